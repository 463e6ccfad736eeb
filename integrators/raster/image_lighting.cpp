// Building the image-based lighting (image_lighting.h). Both the nine SH coefficients and the
// prefiltered maps come from one deterministic set of directions: each infinite emitter's own
// importance sampling (sample_direction) at the midpoints of a 512 x 512 grid of strata, so a
// small bright sun is integrated with its full energy however small it is. The coefficients are
// the estimate L_lm = 1/N sum L(w) Y_lm(w) / pdf(w); the same samples, splatted into a 256 x 128
// lat-long grid, give the energy (radiance times solid angle) of every texel, which each
// roughness level sums under its Phong lobe, normalised by the lobe's own discrete integral.

#include "integrators/raster/image_lighting.h"

#include "core/parallel.h"
#include "materials/microfacet.h"

namespace candela::raster {

namespace {

constexpr int StrataPerSide = 512;
constexpr int BaseWidth = 256, BaseHeight = 128;
// Output widths of the roughness levels (heights are half): at least two texels per lobe width,
// and never coarser than 64 x 32, whose rows next to the poles lie 2.8 degrees from them (16 x 8
// put them 11 degrees off, which cost the widest lobe 8% at the zenith of a sky). Source grids:
// twice as fine for the narrow lobes, as fine for the wide ones.
constexpr int LevelWidths[ImageBasedLighting::LevelCount] = {128, 64, 64, 64, 64};
constexpr int SourceWidths[ImageBasedLighting::LevelCount] = {256, 128, 64, 64, 64};
// The lobe is cut where it falls below this fraction of its peak.
constexpr float LobeCutoff = 1e-4f;

float theta_of_row(int j, int height) { return (float(j) + 0.5f) * Pi / float(height); }
float phi_of_column(int i, int width) { return (float(i) + 0.5f) * TwoPi / float(width); }
Vec3 latlong_direction(float theta, float phi) {
    return Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
}
void latlong_angles(const Vec3& d, float& theta, float& phi) {
    theta = safe_acos(d.y);
    phi = std::atan2(d.z, d.x);
    if (phi < 0.0f) phi += TwoPi;
}
// Solid angle of a texel of row j.
float texel_solid_angle(int j, int width, int height) {
    return (std::cos(float(j) * Pi / float(height)) - std::cos(float(j + 1) * Pi / float(height))) * TwoPi / float(width);
}

// The sampled directions of every infinite emitter with their weights L / (pdf N).
struct EnvironmentSamples {
    std::vector<Vec3> directions;
    std::vector<Spectrum> weights;
};

EnvironmentSamples sample_environment(const Scene& scene) {
    const size_t per_emitter = size_t(StrataPerSide) * StrataPerSide;
    EnvironmentSamples s;
    s.directions.resize(per_emitter * scene.infinite_emitters().size());
    s.weights.resize(s.directions.size());
    SurfaceInteraction ref;
    ref.p = scene.bbox().valid() ? 0.5f * (scene.bbox().min + scene.bbox().max) : Vec3(0.0f);
    for (size_t e = 0; e < scene.infinite_emitters().size(); ++e) {
        const Emitter& emitter = *scene.infinite_emitters()[e];
        parallel_for(size_t(StrataPerSide), [&](int row) {
            for (int col = 0; col < StrataPerSide; ++col) {
                size_t k = e * per_emitter + size_t(row) * StrataPerSide + size_t(col);
                Vec2 u((float(col) + 0.5f) / float(StrataPerSide), (float(row) + 0.5f) / float(StrataPerSide));
                Spectrum weight;
                DirectionSample ds = emitter.sample_direction(ref, u, weight);
                bool ok = ds.pdf > 0.0f && all_finite(weight);
                s.directions[k] = ok ? ds.d : Vec3(0.0f, 1.0f, 0.0f);
                s.weights[k] = ok ? weight / float(per_emitter) : Spectrum(0.0f);
            }
        });
    }
    return s;
}

// Sums 2^k x 2^k blocks of an energy grid.
std::vector<Spectrum> downsample_energy(const std::vector<Spectrum>& energy, int factor) {
    const int w = BaseWidth / factor, h = BaseHeight / factor;
    std::vector<Spectrum> out(size_t(w) * size_t(h), Spectrum(0.0f));
    for (int y = 0; y < BaseHeight; ++y)
        for (int x = 0; x < BaseWidth; ++x)
            out[size_t(y / factor) * size_t(w) + size_t(x / factor)] += energy[size_t(y) * BaseWidth + size_t(x)];
    return out;
}

// The columns of a source row within angle `reach` of direction (theta_r, phi_r), as a first
// column and a count (possibly wrapping); count 0 when the row lies out of reach.
void columns_in_reach(float theta_row, float theta_r, float phi_r, float cos_reach, int width, int& first, int& count) {
    float s = std::sin(theta_row) * std::sin(theta_r);
    float c = s > 1e-6f ? (cos_reach - std::cos(theta_row) * std::cos(theta_r)) / s : -2.0f;
    if (s <= 1e-6f && std::cos(theta_row - theta_r) < cos_reach) c = 2.0f;
    if (c > 1.0f) {
        count = 0;
        return;
    }
    if (c <= -1.0f) {
        first = 0;
        count = width;
        return;
    }
    float half = std::acos(c) + TwoPi / float(width);  // one texel of margin
    count = std::min(width, 2 * int(std::ceil(half * float(width) / TwoPi)) + 1);
    first = int(std::floor(phi_r * float(width) / TwoPi)) - count / 2;
}

// A source grid of a prefiltered level: its energy per texel, and per row and column what the
// lobe sums need (solid angle, sines and cosines), computed once.
struct SourceGrid {
    int w = 0, h = 0;
    std::vector<Spectrum> energy;
    std::vector<float> solid_angle, sin_theta, cos_theta, cos_phi, sin_phi;
    SourceGrid(std::vector<Spectrum> e, int width, int height) : w(width), h(height), energy(std::move(e)) {
        for (int j = 0; j < h; ++j) {
            solid_angle.push_back(texel_solid_angle(j, w, h));
            sin_theta.push_back(std::sin(theta_of_row(j, h)));
            cos_theta.push_back(std::cos(theta_of_row(j, h)));
        }
        for (int i = 0; i < w; ++i) {
            cos_phi.push_back(std::cos(phi_of_column(i, w)));
            sin_phi.push_back(std::sin(phi_of_column(i, w)));
        }
    }
};

// One texel of a prefiltered level: the energy under the lobe max(w.r, 0)^n over the lobe's
// integral on the same texels.
Spectrum prefiltered_texel(const SourceGrid& src, float theta_r, float phi_r, float exponent) {
    const int w = src.w, h = src.h;
    const std::vector<Spectrum>& energy = src.energy;
    const std::vector<float>& solid_angle = src.solid_angle;
    const Vec3 r = latlong_direction(theta_r, phi_r);
    const float cos_reach = std::max(std::exp(std::log(LobeCutoff) / exponent), 0.0f);
    const float reach = std::acos(cos_reach) + Pi / float(h);
    Spectrum sum(0.0f);
    double norm = 0.0;
    int j0 = std::max(0, int((theta_r - reach) / Pi * float(h))), j1 = std::min(h - 1, int((theta_r + reach) / Pi * float(h)));
    for (int j = j0; j <= j1; ++j) {
        int first = 0, count = 0;
        float theta = theta_of_row(j, h);
        columns_in_reach(theta, theta_r, phi_r, std::cos(reach), w, first, count);
        for (int k = 0; k < count; ++k) {
            int i = ((first + k) % w + w) % w;
            float c =
                src.sin_theta[size_t(j)] * (src.cos_phi[size_t(i)] * r.x + src.sin_phi[size_t(i)] * r.z) + src.cos_theta[size_t(j)] * r.y;
            if (c <= 0.0f) continue;
            float lobe = std::pow(c, exponent);
            sum += lobe * energy[size_t(j) * size_t(w) + size_t(i)];
            norm += double(lobe) * solid_angle[size_t(j)];
        }
    }
    if (norm <= 0.0) {
        int j = std::min(h - 1, int(theta_r / Pi * float(h))), i = std::min(w - 1, int(phi_r / TwoPi * float(w)));
        return energy[size_t(j) * size_t(w) + size_t(i)] / solid_angle[size_t(j)];
    }
    return sum / float(norm);
}

}  // namespace

void ImageBasedLighting::sh_basis(const Vec3& d, float out[9]) {
    const float x = d.x, y = d.y, z = d.z;
    out[0] = 0.282095f;
    out[1] = 0.488603f * y;
    out[2] = 0.488603f * z;
    out[3] = 0.488603f * x;
    out[4] = 1.092548f * x * y;
    out[5] = 1.092548f * y * z;
    out[6] = 0.315392f * (3.0f * z * z - 1.0f);
    out[7] = 1.092548f * x * z;
    out[8] = 0.546274f * (x * x - y * y);
}

ImageBasedLighting::ImageBasedLighting(const Scene& scene) : scene_(scene) {
    EnvironmentSamples samples = sample_environment(scene);
    // Coefficients and energy grid, accumulated in a fixed order (deterministic).
    std::array<double, 27> sh{};
    std::vector<Spectrum> energy(size_t(BaseWidth) * BaseHeight, Spectrum(0.0f));
    float y[9];
    for (size_t k = 0; k < samples.directions.size(); ++k) {
        const Spectrum& w = samples.weights[k];
        if (is_black(w)) continue;
        sh_basis(samples.directions[k], y);
        for (int i = 0; i < 9; ++i)
            for (int c = 0; c < 3; ++c) sh[size_t(3 * i + c)] += double(w[c]) * y[i];
        float theta, phi;
        latlong_angles(samples.directions[k], theta, phi);
        int j = std::min(BaseHeight - 1, int(theta / Pi * BaseHeight)), i = std::min(BaseWidth - 1, int(phi / TwoPi * BaseWidth));
        energy[size_t(j) * BaseWidth + size_t(i)] += w;
    }
    for (int i = 0; i < 9; ++i)
        coefficients_[size_t(i)] = Spectrum(float(sh[size_t(3 * i)]), float(sh[size_t(3 * i + 1)]), float(sh[size_t(3 * i + 2)]));

    for (int level = 0; level < LevelCount; ++level) {
        const int out_w = LevelWidths[level], out_h = out_w / 2, src_w = SourceWidths[level], src_h = src_w / 2;
        const SourceGrid source(downsample_energy(energy, BaseWidth / src_w), src_w, src_h);
        const float exponent = phong_exponent(LevelAlphas[level]);
        LatLong& map = levels_[size_t(level)];
        map.width = out_w;
        map.height = out_h;
        map.texels.assign(size_t(out_w) * size_t(out_h), Spectrum(0.0f));
        parallel_for(size_t(out_h), [&](int j) {
            for (int i = 0; i < out_w; ++i)
                map.texels[size_t(j) * size_t(out_w) + size_t(i)] =
                    prefiltered_texel(source, theta_of_row(j, out_h), phi_of_column(i, out_w), exponent);
        });
        map.poles[0] = prefiltered_texel(source, 0.0f, 0.0f, exponent);
        map.poles[1] = prefiltered_texel(source, Pi, 0.0f, exponent);
    }
}

Spectrum ImageBasedLighting::irradiance(const Vec3& n) const {
    // A_l for l = 0, 1, 1, 1, 2, 2, 2, 2, 2 (Ramamoorthi & Hanrahan, eq. 8).
    static const float A[9] = {Pi, TwoPi / 3.0f, TwoPi / 3.0f, TwoPi / 3.0f, Pi / 4.0f, Pi / 4.0f, Pi / 4.0f, Pi / 4.0f, Pi / 4.0f};
    float y[9];
    sh_basis(n, y);
    Spectrum E(0.0f);
    for (int i = 0; i < 9; ++i) E += coefficients_[size_t(i)] * (A[i] * y[i]);
    return glm::max(E, Spectrum(0.0f));
}

Spectrum ImageBasedLighting::LatLong::bilinear(const Vec3& d) const {
    float theta, phi;
    latlong_angles(d, theta, phi);
    float x = phi / TwoPi * float(width) - 0.5f, y = theta / Pi * float(height) - 0.5f;
    int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    float fx = x - float(x0), fy = y - float(y0);
    auto at = [&](int i, int j) {
        i = (i % width + width) % width;
        j = std::clamp(j, 0, height - 1);
        return texels[size_t(j) * size_t(width) + size_t(i)];
    };
    auto row = [&](int j) { return (1.0f - fx) * at(x0, j) + fx * at(x0 + 1, j); };
    // Between a pole and the row next to it: toward the pole's own value.
    if (y < 0.0f) return (1.0f + y * 2.0f) * row(0) - y * 2.0f * poles[0];
    if (y > float(height - 1)) {
        float t = (y - float(height - 1)) * 2.0f;
        return (1.0f - t) * row(height - 1) + t * poles[1];
    }
    return (1.0f - fy) * row(y0) + fy * row(y0 + 1);
}

Spectrum ImageBasedLighting::glossy(const Vec3& r, float alpha) const {
    if (!(alpha > 0.0f)) return scene_.eval_environment(r);
    if (alpha < LevelAlphas[0]) {
        float t = alpha / LevelAlphas[0];
        return (1.0f - t) * scene_.eval_environment(r) + t * levels_[0].bilinear(r);
    }
    for (int k = 0; k + 1 < LevelCount; ++k)
        if (alpha < LevelAlphas[k + 1]) {
            float t = (alpha - LevelAlphas[k]) / (LevelAlphas[k + 1] - LevelAlphas[k]);
            return (1.0f - t) * levels_[size_t(k)].bilinear(r) + t * levels_[size_t(k + 1)].bilinear(r);
        }
    return levels_[LevelCount - 1].bilinear(r);
}

}  // namespace candela::raster
