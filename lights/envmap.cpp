// envmap: an environment map in latitude-longitude layout, infinitely far away.
//
// Parameters (Mitsuba 3):
//   filename   string      the image (EXR, HDR, ...), relative to the scene file; 8- and
//                          16-bit images (PNG, JPEG, ...) are sRGB-encoded and decoded to linear
//                          radiance, as Mitsuba converts its bitmap to linear float RGB
//   scale      float       radiance multiplier (default 1)
//   to_world   transform   rotation of the environment (default identity)
//
// Orientation as in Mitsuba: +y is up; a direction d (in the map's frame) maps to
//   u = atan2(d.x, -d.z) / 2pi (wrapped to [0, 1)),  v = acos(d.y) / pi,
// so the top image row is the zenith and u = 0.5 looks along +z. Radiance is interpolated
// bilinearly with texel centres at u = (j + 0.5) / W and rows at exactly v = i / (H - 1).
// Importance sampling: a piecewise-constant 2D distribution over luminance times sin(theta),
// giving the solid-angle density pdf(u, v) / (2 pi^2 sin theta).

#include "core/distribution.h"
#include "core/emitter.h"
#include "core/error.h"
#include "core/image.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/wavelengths.h"
#include "lights/scene_disk.h"

namespace candela {

class EnvironmentMap final : public Emitter {
public:
    explicit EnvironmentMap(const Properties& props) {
        type_ = EmitterType::Infinite;
        std::string path = props.get_file_path("filename");
        scale_ = props.get_float("scale", 1.0f);
        to_world_ = props.get_transform("to_world");
        if (!to_world_.all_finite()) props.fail("to_world", "environment map transform is not finite");
        world_to_local_ = to_world_.inverse();
        Image img;
        try {
            img = read_image(path);
        } catch (const InputError& e) {
            props.fail("filename", e.what());
        }
        width_ = img.width();
        height_ = img.height();
        if (width_ < 2 || height_ < 2) props.fail("filename", "environment map must be at least 2x2 pixels");
        texels_.resize(size_t(width_) * height_);
        for (int y = 0; y < height_; ++y)
            for (int x = 0; x < width_; ++x) {
                Spectrum s = img.linear_rgb_at(x, y);
                for (int c = 0; c < 3; ++c)
                    if (!std::isfinite(s[c]) || s[c] < 0.0f) s[c] = 0.0f;
                texels_[size_t(y) * width_ + x] = s * scale_;
            }
        build_distribution();
    }

    void set_scene(const Scene& scene) override { disk_ = SceneDisk::around(scene.bbox()); }

    // In the spectral variant the interpolated colour's emission spectrum (unbounded, times D65).
    Spectrum eval_environment(const Vec3& d, const Wavelengths* w, float) const override {
        return rgb_at_wavelengths(lookup(map_direction(d).uv), SpectrumRole::Emission, w);
    }
    Spectrum eval(const SurfaceInteraction& si) const override { return eval_environment(-si.wi_world(), si.wavelengths, si.time); }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2& u, Spectrum& weight) const override {
        DirectionSample ds;
        float pdf_uv;
        Vec2 uv = distribution_.sample(u, &pdf_uv);
        float theta = Pi * uv.y, phi = TwoPi * uv.x;
        float sin_theta = std::sin(theta);
        ds.emitter = this;
        if (!(pdf_uv > 0.0f) || sin_theta <= 0.0f) {
            weight = Spectrum(0.0f);
            return ds;
        }
        Vec3 local(sin_theta * std::sin(phi), std::cos(theta), -sin_theta * std::cos(phi));
        ds.d = glm::normalize(to_world_.apply_vector(local));
        ds.dist = Infinity;
        ds.p = ref.p + ds.d * (2.0f * disk_.radius);
        ds.n = -ds.d;
        // The density of the direction as pdf_direction computes it: a sample landing exactly on a
        // cell edge may round into the neighbouring cell, and MIS needs both to agree. One
        // computation of the direction's map coordinates serves the density and the radiance.
        const Spectrum radiance = eval_environment_pdf(ref, ds.d, ds.pdf);
        weight = ds.pdf > 0.0f ? radiance / ds.pdf : Spectrum(0.0f);
        return ds;
    }

    float pdf_direction(const SurfaceInteraction&, const DirectionSample& ds) const override { return pdf_at(map_direction(ds.d)); }
    Spectrum eval_environment_pdf(const SurfaceInteraction& ref, const Vec3& d, float& pdf) const override {
        const MapDirection m = map_direction(d);
        pdf = pdf_at(m);
        return rgb_at_wavelengths(lookup(m.uv), SpectrumRole::Emission, ref.wavelengths);
    }

    // Flux through the scene's bounding disk: pi r^2 times the radiance integrated over the sphere.
    Spectrum power() const override { return integral_ * disk_.area(); }
    // Light paths: from the bounding disk along directions drawn as for next-event estimation.
    EmitterRay sample_ray(const Vec2& u_position, const Vec2& u_direction, Wavelengths* wavelengths, float time) const override {
        return environment_ray(*this, disk_, u_position, u_direction, wavelengths, time);
    }
    // Local model: ambient radiance equal to the map's average over the sphere (reflections and
    // refractions still look the map up through eval_environment).
    std::optional<LocalApproximation> local_approximation() const override {
        LocalApproximation a;
        a.kind = LocalApproximation::Kind::Ambient;
        a.radiance = integral_ / FourPi;
        return a;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        // The texels hold radiance times scale: a new scale rescales them (and their distribution,
        // which is proportional to them, stays as it is).
        visitor.value("scale", ParameterAccess{ParameterType::Float, [this] { return std::vector<float>{scale_}; },
                                               [this](const std::vector<float>& v) {
                                                   if (!(v.at(0) > 0.0f) || !std::isfinite(v.at(0)))
                                                       throw InputError("scale must be positive and finite");
                                                   for (Spectrum& t : texels_) t *= v.at(0) / scale_;
                                                   scale_ = v.at(0);
                                               }});
    }
    std::string to_string() const override { return "envmap"; }

private:
    // A world direction in the map's frame: its texture coordinates (the mapping at the top) and
    // sin(theta), which the density over directions divides by.
    struct MapDirection {
        Vec2 uv;
        float sin_theta = 0.0f;
    };
    MapDirection map_direction(const Vec3& d_world) const {
        Vec3 d = glm::normalize(world_to_local_.apply_vector(d_world));
        float u = std::atan2(d.x, -d.z) * InvTwoPi;
        u -= std::floor(u);
        return {Vec2(u, safe_acos(d.y) * InvPi), safe_sqrt(1.0f - d.y * d.y)};
    }
    // The density over solid angle of a direction: the map's density over (u, v) times the
    // Jacobian 1 / (2 pi^2 sin(theta)) of (u, v) -> direction.
    float pdf_at(const MapDirection& m) const {
        if (m.sin_theta <= 0.0f) return 0.0f;
        return distribution_.pdf(m.uv) / (2.0f * Pi * Pi * m.sin_theta);
    }

    const Spectrum& texel(int x, int y) const {
        x %= width_;
        if (x < 0) x += width_;
        y = std::clamp(y, 0, height_ - 1);
        return texels_[size_t(y) * width_ + x];
    }

    Spectrum lookup(const Vec2& uv) const {
        float x = uv.x * float(width_) - 0.5f, y = uv.y * float(height_ - 1);
        float fx = std::floor(x), fy = std::min(std::floor(y), float(height_ - 2));
        int ix = int(fx), iy = int(fy);
        float wx = x - fx, wy = std::clamp(y - fy, 0.0f, 1.0f);
        return (texel(ix, iy) * (1.0f - wx) + texel(ix + 1, iy) * wx) * (1.0f - wy) +
               (texel(ix, iy + 1) * (1.0f - wx) + texel(ix + 1, iy + 1) * wx) * wy;
    }

    void build_distribution() {
        // One cell per texel column and row band; a cell's weight bounds the bilinear radiance
        // inside it (the largest luminance of the texels it touches) times sin(theta), so that
        // no direction with radiance gets zero density.
        std::vector<float> weights(size_t(width_) * height_);
        double total[3] = {0, 0, 0};
        for (int i = 0; i < height_; ++i) {
            float v0 = float(i) / height_, v1 = float(i + 1) / height_;
            int row0 = int(std::floor(v0 * (height_ - 1))), row1 = std::min(int(std::ceil(v1 * (height_ - 1))), height_ - 1);
            float sin_max = (v0 <= 0.5f && v1 >= 0.5f) ? 1.0f : std::max(std::sin(Pi * v0), std::sin(Pi * v1));
            float sin_mid = std::sin(Pi * 0.5f * (v0 + v1));
            for (int j = 0; j < width_; ++j) {
                float lum = 0.0f;
                for (int r = row0; r <= row1; ++r)
                    for (int dx = -1; dx <= 1; ++dx) lum = std::max(lum, luminance(texel(j + dx, r)));
                weights[size_t(i) * width_ + j] = lum * sin_max;
                Spectrum mid = lookup(Vec2((j + 0.5f) / width_, 0.5f * (v0 + v1)));
                for (int c = 0; c < 3; ++c) total[c] += double(mid[c]) * sin_mid;
            }
        }
        distribution_ = Distribution2D(weights, width_, height_);
        // Integral over the sphere: sum of L sin(theta) dtheta dphi with dtheta dphi = 2 pi^2 / (W H).
        double cell = 2.0 * 3.14159265358979323846 * 3.14159265358979323846 / (double(width_) * height_);
        integral_ = Spectrum(float(total[0] * cell), float(total[1] * cell), float(total[2] * cell));
    }

    int width_ = 0, height_ = 0;
    std::vector<Spectrum> texels_;
    float scale_ = 1.0f;
    SceneDisk disk_;
    Transform to_world_, world_to_local_;
    Distribution2D distribution_;
    Spectrum integral_{0.0f};
};

CANDELA_REGISTER_SPECTRAL(EnvironmentMap, ObjectKind::Emitter, "envmap");

}  // namespace candela
