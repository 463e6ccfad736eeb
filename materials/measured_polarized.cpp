// measured_polarized: a polarimetric BRDF measured by Baek et al. 2020 ("Image-Based Acquisition
// and Modeling of Polarimetric Reflectance", the KAIST pBRDF data set), read from its `.pbsdf`
// tensor file (Mitsuba 3's `measured_polarized`). Isotropic, one-sided (black from below, as in
// Mitsuba: wrap it in `twosided` for two sides), glossy reflection only.
//
// Parameters (Mitsuba 3):
//   filename       string   the .pbsdf file, found like every file a scene names (no default)
//   alpha_sample   float    the roughness of the GGX distribution that importance-samples the
//                           material (default 0.1; any value renders the same picture, the noise
//                           differs); below 1e-4 it is read as 1e-4
//   wavelength     float    render only this wavelength (nm) at every wavelength of the path
//                           (default -1: each path wavelength its own); scalar_rgb needs it
//
// The file (core/tensor_file.h) holds, float32 unless said:
//   phi_d [1, P], theta_d [1, D], theta_h [1, H]   the grid's Rusinkiewicz angles (radians,
//                                     increasing; a first dimension above 1 is read as rows, of
//                                     which only the first is used, as Mitsuba does)
//   wvls uint16 [L]                   the measured wavelengths (nm, increasing; KAIST's five are
//                                     450, 500, ..., 650)
//   M [P, D, H, L, 4, 4]              the BRDF's Mueller matrix (1/sr, row-major) per grid node,
//                                     for light arriving along -wo and leaving along wi,
//                                     expressed in the bases perpendicular to the plane of
//                                     reflection: s = normalize(wo x wi) at both ends (Mitsuba's
//                                     frames, built from its paper's Figure 4; the s/p frame of
//                                     mueller::specular_reflection at the facet h)
//
// eval: h = normalize(wi + wo); theta_h the angle of h from the normal, theta_d of wo from h, and
// phi_d the azimuth of wo about h measured from t = b x h, b = normalize(n x h) (Rusinkiewicz
// 1998); the matrix is interpolated multilinearly in (phi_d, theta_d, theta_h, wavelength), each
// clamped to its grid's range, its (0, 0) element raised to at least 0, turned into the implicit
// Stokes bases of -wo and wi (mueller::facet_to_local_bases with m = h) and multiplied by
// cos(wo). The unpolarised variants use only the (0, 0) element. The path's wavelengths are
// looked up one by one (scalar_spectral and scalar_spectral_polarized); with `wavelength` every
// one takes that wavelength, and scalar_rgb, which has no wavelengths, refuses the plugin
// without it (as Mitsuba does; it renders grey). In importance transport (light paths) wi and wo
// swap roles, as in Mitsuba.
// sample: with probability 0.1 a cosine-weighted direction, else the reflection of wi at a GGX
// visible normal of roughness alpha_sample; pdf() is that mixture's density.
//
// Invalid configurations are marked by NaN in the data (Mitsuba: transmission directions): a
// matrix with any element that is not finite is invalid, and a lookup whose interpolation takes
// an invalid matrix with a non-zero weight, at any of the path's wavelengths, is zero.
//
// Differences from Mitsuba 3: the angles are computed with atan2 rather than acos (accurate at
// the specular peak, theta_h near 0), without first turning both directions so that wi has
// azimuth 0 (they do not change under that turn); at theta_h = 0, where phi_d is undefined, b is
// taken perpendicular to wi's plane of incidence (Mitsuba's normalize(n x h) is NaN there);
// an invalid matrix is invalid whichever element is NaN (Mitsuba tests the (0, 0) element of the
// interpolated matrix, so NaN elsewhere reached the path) and interpolation weights of zero are
// skipped (Mitsuba's 0 * NaN made a lookup on a grid plane next to an invalid node zero); any
// number of wavelengths is read (Mitsuba reads five); every field's type, shape and values are
// checked (a grid that does not increase, a NaN angle or an alpha_sample that is negative or a
// wavelength that is neither -1 nor positive is an error). Local model: a Lambertian of the
// albedo at normal incidence (BSDF::local_shading); albedo() is that constant, computed once at
// the fixed wavelength or else at 550 nm.

#include "core/bsdf.h"
#include "core/error.h"
#include "core/memory_budget.h"
#include "core/registry.h"
#include "core/tensor_file.h"
#include "core/warp.h"
#include "core/wavelengths.h"
#include "materials/fresnel.h"
#include "materials/microfacet.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace candela {

namespace {

// Mitsuba's COSINE_HEMISPHERE_PDF_WEIGHT: the share of cosine-weighted samples.
constexpr float CosineWeight = 0.1f;
// Where a lookup has no wavelengths of the path (the albedo estimate, a test's bare interaction)
// and no fixed `wavelength`.
constexpr float DefaultWavelength = 550.0f;

// One axis of the grid: its node values, increasing.
struct Axis {
    std::vector<float> nodes;
    // The interval [i, i + 1] holding p and its weight t of node i + 1, clamped to the axis (as
    // Mitsuba's Marginal2D clamps its parameters); a NaN p gives the first node.
    void locate(float p, size_t& i, float& t) const {
        if (nodes.size() == 1) {
            i = 0;
            t = 0.0f;
            return;
        }
        size_t k = size_t(std::upper_bound(nodes.begin(), nodes.end(), p) - nodes.begin());
        i = std::min(k > 0 ? k - 1 : 0, nodes.size() - 2);
        float x = (p - nodes[i]) / (nodes[i + 1] - nodes[i]);
        t = x > 0.0f ? std::min(x, 1.0f) : 0.0f;
    }
};

// The Rusinkiewicz angles of light arriving along -wo and leaving along wi (both above the
// surface), and the half vector.
struct HalfDifference {
    Vec3 h;
    float phi_d, theta_h, theta_d;
};

HalfDifference half_difference(const Vec3& wi, const Vec3& wo) {
    HalfDifference r;
    r.h = glm::normalize(wi + wo);
    const float sin_theta_h = std::sqrt(r.h.x * r.h.x + r.h.y * r.h.y);
    r.theta_h = std::atan2(sin_theta_h, r.h.z);
    r.theta_d = std::atan2(glm::length(glm::cross(r.h, wo)), glm::dot(r.h, wo));
    // b = normalize(n x h) = (-h.y, h.x, 0) / sin(theta_h); at the pole, the limit from wi's
    // side: perpendicular to wi's plane of incidence.
    Vec3 b;
    if (sin_theta_h > 1e-6f) {
        b = Vec3(-r.h.y, r.h.x, 0.0f) / sin_theta_h;
    } else {
        const float s = std::sqrt(wi.x * wi.x + wi.y * wi.y);
        b = s > 0.0f ? Vec3(-wi.y / s, wi.x / s, 0.0f) : Vec3(0.0f, 1.0f, 0.0f);
    }
    const Vec3 t = glm::cross(b, r.h);
    // b and t are orthogonal to h: the projection of wo onto their plane changes neither dot.
    r.phi_d = std::atan2(glm::dot(b, wo), glm::dot(t, wo));
    return r;
}

std::string shape_text(const std::vector<uint64_t>& shape) {
    std::string s;
    for (uint64_t v : shape) s += (s.empty() ? "" : ", ") + std::to_string(v);
    return "[" + s + "]";
}

}  // namespace

class MeasuredPolarizedBSDF final : public BSDF {
public:
    explicit MeasuredPolarizedBSDF(const Properties& props)
        : distribution_(MicrofacetType::GGX, read_alpha(props), read_alpha(props), true) {
        wavelength_ = props.get_float("wavelength", -1.0f);
        if (!(wavelength_ == -1.0f || (wavelength_ > 0.0f && std::isfinite(wavelength_))))
            props.fail("wavelength", "wavelength must be a positive number of nm, or -1 for every wavelength of the path");
        if (props.variant() == Variant::ScalarRGB && wavelength_ == -1.0f)
            props.fail(
                "measured_polarized renders in scalar_rgb only at one wavelength: give `wavelength` (nm), as Mitsuba 3 "
                "requires, or render in scalar_spectral or scalar_spectral_polarized");
        path_ = props.get_file_path("filename");
        try {
            load(TensorFile(path_));
        } catch (const InputError& e) {
            throw SceneError(props.location_of("filename"), e.what());  // at the filename's line
        }
        flags_ = GlossyReflection;
        albedo_ = normal_incidence_albedo();
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override {
        BSDFSample bs;
        if (!ctx.allows(GlossyReflection) || Frame::cos_theta(si.wi) <= 0.0f) return bs;
        if (u_lobe < CosineWeight) {
            bs.wo = warp::square_to_cosine_hemisphere(u);
        } else {
            float unused;
            bs.wo = reflect(si.wi, distribution_.sample(si.wi, u, unused));
        }
        if (Frame::cos_theta(bs.wo) <= 0.0f) return BSDFSample();
        bs.lobe = GlossyReflection;
        return weighted_by_pdf(ctx, si, bs);
    }

    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        if (!ctx.allows(GlossyReflection) || Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return Spectrum(0.0f);
        Mueller m[3];
        if (!lookup(ctx, si, wo, 1, m, nullptr)) return Spectrum(0.0f);
        const float cos_o = Frame::cos_theta(wo);
        return Spectrum(std::max(m[0](0, 0), 0.0f), std::max(m[1](0, 0), 0.0f), std::max(m[2](0, 0), 0.0f)) * cos_o;
    }

    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        if (!ctx.allows(GlossyReflection) || Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return 0.0f;
        const Vec3 h = glm::normalize(si.wi + wo);
        const float p = CosineWeight * warp::square_to_cosine_hemisphere_pdf(wo) +
                        (1.0f - CosineWeight) * distribution_.pdf(si.wi, h) / (4.0f * glm::dot(wo, h));
        return p > 0.0f && std::isfinite(p) ? p : 0.0f;
    }

    // The measured matrix per wavelength, in the implicit bases of -wo and wi, times cos(wo). The
    // directions are always the light's (it arrives along -wo, BSDF::eval_mueller's contract; light
    // paths pass them swapped), so the lookup is the radiance one whatever ctx.mode says.
    bool eval_mueller(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t, MuellerSpectrum& M) const override {
        if (!ctx.allows(GlossyReflection) || Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return false;
        M = MuellerSpectrum();
        HalfDifference hd;
        Mueller m[3];
        BSDFContext light_order = ctx;
        light_order.mode = TransportMode::Radiance;
        if (!lookup(light_order, si, wo, 16, m, &hd)) return true;
        const Vec3& wo_hat = wo;
        const Vec3& wi_hat = si.wi;
        const float cos_o = Frame::cos_theta(wo);
        // The stored bases, normalize(wo x wi) at both ends, are those of a reflection at the
        // facet h in its s/p frame.
        const BasisChange to_local = facet_to_local_bases(hd.h, wi_hat, wo_hat);
        for (int k = 0; k < 3; ++k) {
            m[k](0, 0) = std::max(m[k](0, 0), 0.0f);
            M.w[k] = cos_o * to_local.apply(m[k]);
        }
        return true;
    }

    Spectrum albedo(const SurfaceInteraction&) const override { return albedo_; }
    std::string to_string() const override { return "measured_polarized \"" + path_ + "\""; }

private:
    static float read_alpha(const Properties& props) {
        const float alpha = props.get_float("alpha_sample", 0.1f);
        if (!(alpha >= 0.0f && std::isfinite(alpha))) props.fail("alpha_sample", "alpha_sample must be a finite roughness >= 0");
        return alpha;  // raised to 1e-4 by MicrofacetDistribution
    }

    // The interpolated matrices (their first `elements` elements in row-major order) at the
    // path's three wavelengths; false when the lookup meets an invalid node. `hd`, when given,
    // receives the configuration.
    bool lookup(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, int elements, Mueller m[3],
                HalfDifference* hd) const {
        const bool radiance = ctx.mode == TransportMode::Radiance;
        const HalfDifference c = half_difference(radiance ? si.wi : wo, radiance ? wo : si.wi);
        if (hd) *hd = c;
        // The 8 corners of the angular cell, as matrix indices without the wavelength.
        size_t index[3];
        float t[3];
        phi_d_.locate(c.phi_d, index[0], t[0]);
        theta_d_.locate(c.theta_d, index[1], t[1]);
        theta_h_.locate(c.theta_h, index[2], t[2]);
        std::array<size_t, 8> corner{};
        std::array<float, 8> weight{};
        for (int k = 0; k < 8; ++k) {
            size_t ip = index[0] + ((k >> 2) & 1), id = index[1] + ((k >> 1) & 1), ih = index[2] + (k & 1);
            corner[size_t(k)] = ((ip * theta_d_.nodes.size() + id) * theta_h_.nodes.size() + ih) * wavelengths_.nodes.size();
            weight[size_t(k)] = ((k >> 2) & 1 ? t[0] : 1.0f - t[0]) * ((k >> 1) & 1 ? t[1] : 1.0f - t[1]) * (k & 1 ? t[2] : 1.0f - t[2]);
        }
        const Vec3 lambda = wavelength_ > 0.0f ? Vec3(wavelength_) : si.wavelengths ? si.wavelengths->lambda : Vec3(DefaultWavelength);
        for (int w = 0; w < 3; ++w) {
            if (w > 0 && lambda[w] == lambda[w - 1]) {
                m[w] = m[w - 1];
                continue;
            }
            size_t il;
            float tl;
            wavelengths_.locate(lambda[w], il, tl);
            Mueller sum;
            for (int k = 0; k < 16; ++k) {
                const float wk = weight[size_t(k >> 1)] * (k & 1 ? tl : 1.0f - tl);
                if (wk == 0.0f) continue;
                const size_t node = corner[size_t(k >> 1)] + il + size_t(k & 1);
                if (!valid_[node]) return false;
                const float* v = &data_[node * 16];
                for (int e = 0; e < elements; ++e) sum.m[e / 4][e % 4] += wk * v[e];
            }
            m[w] = sum;
        }
        return true;
    }

    void load(const TensorFile& file);

    Spectrum normal_incidence_albedo() const {
        // The mean sample weight over a 32 x 32 grid of stratum centres for each lobe choice: a
        // deterministic estimate of the directional albedo at normal incidence.
        const int n = 32;
        BSDFContext ctx;
        SurfaceInteraction si;
        si.wi = Vec3(0.0f, 0.0f, 1.0f);
        Spectrum sum(0.0f);
        for (float u_lobe : {0.5f * CosineWeight, 0.5f * (1.0f + CosineWeight)})
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    BSDFSample bs = sample(ctx, si, u_lobe, Vec2((float(i) + 0.5f) / n, (float(j) + 0.5f) / n));
                    if (bs.valid()) sum += bs.weight * (u_lobe < CosineWeight ? CosineWeight : 1.0f - CosineWeight);
                }
        return sum / float(n * n);
    }

    std::string path_;
    MicrofacetDistribution distribution_;
    float wavelength_ = -1.0f;
    Axis phi_d_, theta_d_, theta_h_, wavelengths_;
    std::vector<float> data_;     // [P][D][H][L][4][4]
    std::vector<uint8_t> valid_;  // per matrix: every element finite
    Spectrum albedo_{0.0f};
};

void MeasuredPolarizedBSDF::load(const TensorFile& file) {
    // An angle field: float32 [rows, n] (Mitsuba's files store MATLAB row vectors, [1, n]).
    auto angles = [&](const char* name, float lo, float hi) {
        const TensorField& f = file.field(name);
        if (f.shape.size() != 2 || f.shape[0] < 1 || f.shape[1] < 1)
            file.fail(std::string("field \"") + name + "\" has shape " + shape_text(f.shape) + ", expected [1, n] (n >= 1)");
        std::vector<float> v = file.floats(name);
        v.resize(size_t(f.shape[1]));  // the first row
        for (size_t i = 0; i < v.size(); ++i) {
            if (!(v[i] >= lo && v[i] <= hi))
                file.fail(std::string("field \"") + name + "\" value " + std::to_string(i) + " (" + std::to_string(v[i]) +
                          ") is not an angle in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] radians");
            if (i > 0 && !(v[i] > v[i - 1]))
                file.fail(std::string("field \"") + name + "\" must increase (value " + std::to_string(i) + " does not)");
        }
        return Axis{v};
    };
    // phi_d within a turn either way (KAIST's range is not documented), theta_h and theta_d
    // within [0, pi] (a little past pi / 2 is allowed for the grid's last node).
    phi_d_ = angles("phi_d", -2.0f * Pi - 1e-3f, 2.0f * Pi + 1e-3f);
    theta_d_ = angles("theta_d", -1e-3f, Pi + 1e-3f);
    theta_h_ = angles("theta_h", -1e-3f, Pi + 1e-3f);

    const TensorField& wf = file.field("wvls");
    if (wf.shape.size() != 1 || wf.shape[0] < 1)
        file.fail("field \"wvls\" has shape " + shape_text(wf.shape) + ", expected [n] (n >= 1 wavelengths)");
    std::vector<uint16_t> wvls = file.uint16s("wvls");
    for (size_t i = 0; i < wvls.size(); ++i) {
        if (wvls[i] == 0) file.fail("field \"wvls\" value " + std::to_string(i) + " is 0 nm");
        if (i > 0 && !(wvls[i] > wvls[i - 1])) file.fail("field \"wvls\" must increase (value " + std::to_string(i) + " does not)");
        wavelengths_.nodes.push_back(float(wvls[i]));
    }

    const TensorField& mf = file.field("M");
    const std::vector<uint64_t> expected = {
        phi_d_.nodes.size(), theta_d_.nodes.size(), theta_h_.nodes.size(), wavelengths_.nodes.size(), 4, 4};
    if (mf.shape != expected)
        file.fail("field \"M\" has shape " + shape_text(mf.shape) + ", expected " + shape_text(expected) +
                  " (phi_d, theta_d, theta_h, wvls, then a 4 x 4 Mueller matrix)");
    // The shape matches the axes, whose sizes the file's length bounds (core/tensor_file.h): the
    // copy is the field's size, checked against the budget as the file was.
    check_memory(saturating_mul(mf.count(), uint64_t(sizeof(float) + 1)), "the Mueller matrices of \"" + file.path() + "\"");
    if (mf.dtype != TensorType::Float32) file.fail(std::string("field \"M\" is ") + tensor_type_name(mf.dtype) + ", expected float32");
    data_ = file.floats("M");
    const size_t matrices = data_.size() / 16;
    valid_.assign(matrices, 1);
    size_t invalid = 0;
    for (size_t i = 0; i < matrices; ++i)
        for (int e = 0; e < 16; ++e)
            if (!std::isfinite(data_[i * 16 + size_t(e)])) {
                valid_[i] = 0;
                ++invalid;
                break;
            }
    if (invalid == matrices) file.fail("field \"M\" holds no finite matrix (all " + std::to_string(matrices) + " have a NaN or infinity)");
}

CANDELA_REGISTER_SPECTRAL(MeasuredPolarizedBSDF, ObjectKind::BSDF, "measured_polarized");

}  // namespace candela
