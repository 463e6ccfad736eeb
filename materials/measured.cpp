// measured: a BRDF measured by RGL's goniophotometer, read from its `.bsdf` tensor file (Mitsuba
// 3's `measured` plugin; Dupuy & Jakob 2018, "An Adaptive Parameterization for Efficient
// Material Acquisition and Rendering"; the files: rgl.epfl.ch/materials). One-sided (black from
// below, as in Mitsuba: wrap it in `twosided` for two sides), glossy reflection only.
//
// Parameters:
//   filename   string   the .bsdf file, found like every file a scene names (no default)
//
// The file (core/tensor_file.h) holds, all float32 unless said:
//   theta_i [T], phi_i [P]       the incident elevations and azimuths (radians) of the slices
//   ndf [H, W], sigma [H, W]     the microfacet normal distribution D and the projected area
//                                sigma(wi) = integral of D(m) <wi, m>+ dm, on the unit square
//                                u = (sqrt(2 theta / pi), (phi + pi) / 2pi)
//   vndf [P, T, H, W]            per slice, the density of visible normals in that square: the
//                                warp from the "sample space" [0, 1]^2 to half vectors
//   luminance [P, T, N, N]       per slice, a density over the sample space (importance sampling)
//   rgb [P, T, 3, N, N]          per slice, the reflectance at each sample-space node; or else
//   spectra [P, T, L, N, N] with wavelengths [L] (nm), converted here to linear sRGB as Mitsuba's
//                                RGB variants convert a reflectance (D65-weighted CIE 1931)
//   jacobian uint8 [1]           1: the values are reflectance factors, times D(m) / (4 sigma(wi))
//   description uint8 [n]        text
// P <= 2 means isotropic (phi_m is then stored relative to phi_i); otherwise the phi_i slices
// cover 2 pi / r for a reduction r of 1, 2 (the material is symmetric under a half turn) or 4
// (symmetric under mirroring in x and in y), and wi is first turned or mirrored into that range.
//
// eval: h = normalize(wi + wo); s = vndf^-1(u(h)); f cos(wo) = rgb(s) [* D(h) / (4 sigma(wi))].
// sample: s from the luminance density, h from the vndf warp, wo = reflect(wi, h); pdf: the
// density in wo is p_lum(s) p_vndf(u) / (2 pi^2 u_theta sin(theta_h) * 4 <wi, h>) (the Jacobians of
// u -> (theta, phi) -> h -> wo). Every table is interpolated bilinearly and blended linearly
// between the slices (core/distribution.h: Marginal2D).
//
// In the spectral variants a spectral file's table is interpolated at the path's wavelengths
// (clamped at the table's ends), as Mitsuba's spectral variants read it; an RGB file's colour is
// upsampled as a reflectance.
//
// Differences from Mitsuba 3: negative rgb values (colours outside sRGB) are clamped to zero, as
// RGL's own reader (powitacq) does; in RGB, spectral files are converted to RGB instead of refused
// (an RGB variant of Mitsuba refuses them); pdf() takes sin(theta_h) from h's x and y (Mitsuba's
// sqrt(1 - cos^2) in float made it several times too large at the mirror direction); a sample's
// pdf and weight come from pdf() and eval() of its direction (the same values but for rounding);
// negative vndf or luminance values are read as 0 (with a warning), and a slice whose density
// integrates to zero, a non-finite value or slice positions that do not increase are errors
// (Mitsuba would divide by zero). Local model: a Lambertian of the albedo at normal incidence
// (BSDF::local_shading); albedo() is that constant, computed once.

#include "core/bsdf.h"
#include "core/distribution.h"
#include "core/registry.h"
#include "core/spectral.h"
#include "core/tensor_file.h"
#include "core/warning.h"
#include "core/wavelengths.h"
#include "materials/fresnel.h"

#include <cmath>

namespace candela {

namespace {

// The unit-square coordinates of the tables (Mitsuba's theta2u, phi2u and their inverses).
float theta_to_u(float theta) { return std::sqrt(theta * (2.0f / Pi)); }
float phi_to_u(float phi) { return (phi + Pi) * InvTwoPi; }
float u_to_theta(float u) { return u * u * (Pi / 2.0f); }
float u_to_phi(float u) { return (2.0f * u - 1.0f) * Pi; }

// The angle between d and +z, accurate near the pole (2 asin(|d - z| / 2)).
float elevation(const Vec3& d) {
    float dist = std::sqrt(d.x * d.x + d.y * d.y + (d.z - 1.0f) * (d.z - 1.0f));
    return 2.0f * std::asin(std::min(0.5f * dist, 1.0f));
}

}  // namespace

class MeasuredBSDF final : public BSDF {
public:
    explicit MeasuredBSDF(const Properties& props) {
        path_ = props.get_file_path("filename");
        SourceLocation where = props.location_of("filename");
        try {
            TensorFile file(path_);
            load(file, where);
        } catch (const InputError& e) {
            throw SceneError(where, e.what());  // at the filename's line, as "file not found" is
        }
        flags_ = GlossyReflection;
        reads_lobe_sample_ = false;
        albedo_ = normal_incidence_albedo();
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float, const Vec2& u) const override {
        BSDFSample bs;
        if (!ctx.allows(GlossyReflection) || Frame::cos_theta(si.wi) <= 0.0f) return bs;
        const Incident at = incident(si.wi);
        float lum_pdf = 1.0f, vndf_pdf = 0.0f;
        Vec2 s = luminance_.sample(Vec2(u.y, u.x), at.slices, &lum_pdf);
        Vec2 u_m = vndf_.sample(s, at.slices, &vndf_pdf);
        float theta_m = u_to_theta(u_m.x), phi_m = u_to_phi(u_m.y) + (isotropic_ ? at.in.phi : 0.0f);
        float sin_theta_m = std::sin(theta_m);
        Vec3 m(std::cos(phi_m) * sin_theta_m, std::sin(phi_m) * sin_theta_m, std::cos(theta_m));
        Vec3 wo = reflect(at.wi, m);
        if (wo.z <= 0.0f || !(vndf_pdf * lum_pdf > 0.0f)) return bs;
        bs.wo = at.sym.apply(wo);  // each flip is its own inverse
        bs.lobe = GlossyReflection;
        // pdf and weight from pdf() and eval() of the direction drawn (Mitsuba computes them from
        // the warp's own values, which equal these but for rounding: near the pole, where
        // theta_m is tiny, the half vector recomputed from wo differs by up to 1% in theta_m).
        // eval_pdf's own checks hold here (glossy allowed, both cosines positive).
        return weighted_by_pdf(bs, eval_pdf_at(at, bs.wo, si.wavelengths));
    }

    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        if (!ctx.allows(GlossyReflection) || Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return Spectrum(0.0f);
        const Incident at = incident(si.wi);
        return reflectance(lookup(at, wo), at.in, si.wavelengths);
    }

    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        if (!ctx.allows(GlossyReflection) || Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return 0.0f;
        const Incident at = incident(si.wi);
        return pdf_of(at, lookup(at, wo));
    }

    // One lookup (the incidence's angles and the warp's inversion) for both: sample() and
    // next-event estimation need the two together.
    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        if (!ctx.allows(GlossyReflection) || Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return BSDFEvalPdf();
        return eval_pdf_at(incident(si.wi), wo, si.wavelengths);
    }

    Spectrum albedo(const SurfaceInteraction&) const override { return albedo_; }
    std::string to_string() const override { return "measured \"" + path_ + "\" (" + description_ + ")"; }

private:
    // The turn (reduction 2) or mirrors (reduction 4) that bring wi into the tabulated range of
    // phi_i, [-pi, -pi + 2 pi / r]: negate x and/or y (Mitsuba's mulsign_neg by wi's signs).
    struct Symmetry {
        bool flip_x = false, flip_y = false;
        Vec3 apply(Vec3 v) const {
            if (flip_x) v.x = -v.x;
            if (flip_y) v.y = -v.y;
            return v;
        }
    };
    Symmetry symmetry(const Vec3& wi) const {
        Symmetry s;
        if (reduction_ >= 2) {
            s.flip_y = !std::signbit(wi.y);
            s.flip_x = reduction_ == 4 ? !std::signbit(wi.x) : s.flip_y;
        }
        return s;
    }

    struct Incidence {
        float theta, phi;
        float params[2];  // the slice parameters (phi_i, theta_i)
        Vec2 u;           // wi on the unit square (sigma's coordinates)
    };
    static Incidence incidence(const Vec3& wi) {
        Incidence in;
        in.theta = elevation(wi);
        in.phi = std::atan2(wi.y, wi.x);
        in.params[0] = in.phi;
        in.params[1] = in.theta;
        in.u = Vec2(theta_to_u(in.theta), phi_to_u(in.phi));
        return in;
    }

    // The half vector m on the unit square; its azimuth is relative to wi's for an isotropic
    // material.
    Vec2 half_vector_u(const Vec3& m, const Incidence& in) const {
        float phi_m = std::atan2(m.y, m.x) - (isotropic_ ? in.phi : 0.0f);
        Vec2 u(theta_to_u(elevation(m)), phi_to_u(phi_m));
        u.y -= std::floor(u.y);
        return u;
    }

    // What sample(), eval() and pdf() share for one wi: the symmetry that turns it into the
    // tabulated range, the turned wi, its incidence, and the blend of the vndf_ and luminance_
    // slices there (both take the same slice parameters).
    struct Incident {
        Symmetry sym;
        Vec3 wi;
        Incidence in;
        Marginal2D::Blend slices;
    };
    Incident incident(const Vec3& wi_local) const {
        Incident at;
        at.sym = symmetry(wi_local);
        at.wi = at.sym.apply(wi_local);
        at.in = incidence(at.wi);
        at.slices = vndf_.blend(at.in.params);
        return at;
    }
    // What eval() and pdf() of (wi, wo) share: the half vector (on the unit square too) and the
    // sample-space point the warp maps to it.
    struct Lookup {
        Vec3 m;
        Vec2 u_m, s;
        float vndf_pdf = 0.0f;
    };
    Lookup lookup(const Incident& at, const Vec3& wo_local) const {
        Lookup l;
        l.m = glm::normalize(at.wi + at.sym.apply(wo_local));
        l.u_m = half_vector_u(l.m, at.in);
        l.s = vndf_.invert(l.u_m, at.slices, &l.vndf_pdf);
        return l;
    }
    float pdf_of(const Incident& at, const Lookup& l) const {
        // sin(theta_m) from m's x and y: Mitsuba's sqrt(1 - cos^2) loses all precision near the
        // pole (the mirror direction), where it made pdf() several times too large.
        const float sin_theta_m = std::sqrt(l.m.x * l.m.x + l.m.y * l.m.y);
        const float pdf = l.vndf_pdf * luminance_.eval(l.s, at.slices) / jacobian(l.u_m.x, sin_theta_m, glm::dot(at.wi, l.m));
        return pdf > 0.0f && std::isfinite(pdf) ? pdf : 0.0f;
    }
    BSDFEvalPdf eval_pdf_at(const Incident& at, const Vec3& wo_local, const Wavelengths* wavelengths) const {
        const Lookup l = lookup(at, wo_local);
        BSDFEvalPdf result;
        result.value = reflectance(l, at.in, wavelengths);
        result.pdf = pdf_of(at, l);
        return result;
    }

    // d(wo) / d(u): 2 pi^2 u_theta sin(theta_m) from the square to half vectors (theta = u^2 pi / 2,
    // phi = (2 u - 1) pi), times 4 <wi, m> from half vectors to reflected directions. Mitsuba's
    // floor of 1e-6 keeps the pole finite.
    static float jacobian(float u_theta, float sin_theta_m, float cos_im) {
        return std::max(2.0f * Pi * Pi * u_theta * sin_theta_m, 1e-6f) * 4.0f * cos_im;
    }

    // f cos(wo) at the lookup's sample-space point and half vector: in RGB, or at the path's wavelengths
    // (a spectral file's table interpolated in wavelength, clamped at its ends; an RGB file's
    // colour upsampled as a reflectance).
    Spectrum reflectance(const Lookup& l, const Incidence& in, const Wavelengths* wavelengths) const {
        Spectrum f;
        if (wavelengths && has_spectra_) {
            for (int k = 0; k < 3; ++k) {
                float params[3] = {in.params[0], in.params[1], wavelengths->lambda[k]};
                f[k] = std::max(spectra_.eval(l.s, params), 0.0f);
            }
        } else {
            const Marginal2D::Blend slices = rgb_.blend_leading(in.params);  // the channel is the last parameter
            for (int c = 0; c < 3; ++c) f[c] = std::max(rgb_.eval(l.s, rgb_.at_node(slices, c)), 0.0f);
            if (wavelengths) f = rgb_at_wavelengths(f, SpectrumRole::Reflectance, wavelengths);
        }
        if (jacobian_) {
            float sigma = sigma_.eval(in.u);
            if (!(sigma > 0.0f)) return Spectrum(0.0f);
            f *= ndf_.eval(l.u_m) / (4.0f * sigma);
        }
        return f;
    }

    void load(const TensorFile& file, const SourceLocation& where);
    Spectrum normal_incidence_albedo() const;

    std::string path_, description_;
    Marginal2D ndf_, sigma_, vndf_, luminance_, rgb_;
    Marginal2D spectra_;  // a spectral file's table, parametrised by wavelength too (the spectral variant)
    bool has_spectra_ = false;
    bool isotropic_ = true, jacobian_ = false;
    int reduction_ = 1;
    Spectrum albedo_{0.0f};
};

namespace {

std::string shape_text(const std::vector<uint64_t>& shape) {
    std::string s;
    for (uint64_t v : shape) s += (s.empty() ? "" : ", ") + std::to_string(v);
    return "[" + s + "]";
}

// A float32 field of `ndim` dimensions whose values are all finite.
std::vector<float> read_floats(const TensorFile& file, const std::string& name, size_t ndim) {
    const TensorField& f = file.field(name);
    if (f.shape.size() != ndim)
        file.fail("field \"" + name + "\" has shape " + shape_text(f.shape) + ", expected " + std::to_string(ndim) + " dimensions");
    std::vector<float> v = file.floats(name);
    for (float x : v)
        if (!std::isfinite(x)) file.fail("field \"" + name + "\" has a value that is not finite");
    return v;
}

void expect_dim(const TensorFile& file, const std::string& name, size_t dim, uint64_t expected, const std::string& why) {
    const TensorField& f = file.field(name);
    if (f.shape[dim] != expected)
        file.fail("field \"" + name + "\" has shape " + shape_text(f.shape) + ": dimension " + std::to_string(dim) + " should be " +
                  std::to_string(expected) + " (" + why + ")");
}

void expect_grid(const TensorFile& file, const std::string& name, size_t first) {
    const TensorField& f = file.field(name);
    if (f.shape[first] < 2 || f.shape[first + 1] < 2 || f.shape[first] > 65536 || f.shape[first + 1] > 65536)
        file.fail("field \"" + name + "\" has shape " + shape_text(f.shape) + ": its last two dimensions must be between 2 and 65536");
}

// Strictly increasing values (the slices' positions).
void expect_increasing(const TensorFile& file, const std::string& name, const std::vector<float>& v) {
    if (v.empty()) file.fail("field \"" + name + "\" is empty");
    for (size_t i = 1; i < v.size(); ++i)
        if (!(v[i] > v[i - 1])) file.fail("field \"" + name + "\" must increase (value " + std::to_string(i) + " does not)");
}

// A density table's negative values (fitting noise in a measurement) are read as zero.
void clamp_negative(std::vector<float>& v, const std::string& name, const std::string& path, const SourceLocation& where) {
    size_t count = 0;
    for (float& x : v)
        if (x < 0.0f) {
            x = 0.0f;
            ++count;
        }
    if (count > 0) warn(where, path + ": " + std::to_string(count) + " negative values of \"" + name + "\" read as 0");
}

}  // namespace

void MeasuredBSDF::load(const TensorFile& file, const SourceLocation& where) {
    std::vector<uint8_t> text = file.bytes("description");
    if (file.field("description").shape.size() != 1) file.fail("field \"description\" must have one dimension");
    description_.assign(text.begin(), text.end());
    std::vector<uint8_t> jacobian = file.bytes("jacobian");
    if (file.field("jacobian").shape != std::vector<uint64_t>{1}) file.fail("field \"jacobian\" must hold one value");
    jacobian_ = jacobian[0] != 0;

    std::vector<float> theta_i = read_floats(file, "theta_i", 1), phi_i = read_floats(file, "phi_i", 1);
    expect_increasing(file, "theta_i", theta_i);
    expect_increasing(file, "phi_i", phi_i);
    uint64_t n_theta = theta_i.size(), n_phi = phi_i.size();
    isotropic_ = n_phi <= 2;
    if (!isotropic_) {
        // The slices cover 2 pi / reduction of azimuth (Mitsuba: rint(2 pi / (last - first))).
        double r = std::rint(2.0 * Pi / (double(phi_i.back()) - double(phi_i.front())));
        if (r != 1.0 && r != 2.0 && r != 4.0)
            file.fail("phi_i spans " + std::to_string(phi_i.back() - phi_i.front()) + " radians: expected 2 pi, pi or pi / 2");
        reduction_ = int(r);
    }

    std::vector<float> ndf = read_floats(file, "ndf", 2), sigma = read_floats(file, "sigma", 2);
    std::vector<float> vndf = read_floats(file, "vndf", 4), luminance = read_floats(file, "luminance", 4);
    expect_grid(file, "ndf", 0);
    expect_grid(file, "sigma", 0);
    for (const char* name : {"vndf", "luminance"}) {
        expect_dim(file, name, 0, n_phi, "the size of phi_i");
        expect_dim(file, name, 1, n_theta, "the size of theta_i");
        expect_grid(file, name, 2);
    }
    const std::vector<uint64_t>& ls = file.field("luminance").shape;
    expect_dim(file, "luminance", 3, ls[2], "the sample space is square");
    std::vector<float> rgb = file.has_field("rgb") ? read_floats(file, "rgb", 5) : std::vector<float>();
    const std::string colour = file.has_field("rgb") ? "rgb" : "spectra";
    std::vector<float> wavelengths, spectra;  // kept for the spectral variant
    if (colour == "spectra") {
        wavelengths = read_floats(file, "wavelengths", 1);
        spectra = read_floats(file, "spectra", 5);
        expect_dim(file, "spectra", 2, wavelengths.size(), "the size of wavelengths");
        std::vector<double> w(wavelengths.begin(), wavelengths.end());
        std::vector<Vec3d> weights;
        try {
            weights = spectrum_to_rgb_weights(w, true);
        } catch (const SpectrumFormatError& e) {
            file.fail(std::string("field \"wavelengths\": ") + e.what());
        }
        // Linear, so converting the nodes equals converting the interpolated spectrum.
        size_t nodes = size_t(ls[2] * ls[3]), slices = size_t(n_phi * n_theta);
        if (spectra.size() == slices * w.size() * nodes) {
            rgb.assign(slices * 3 * nodes, 0.0f);
            for (size_t s = 0; s < slices; ++s)
                for (size_t i = 0; i < nodes; ++i) {
                    Vec3d c(0.0);
                    for (size_t j = 0; j < w.size(); ++j) c += weights[j] * double(spectra[(s * w.size() + j) * nodes + i]);
                    for (int k = 0; k < 3; ++k) rgb[(s * 3 + size_t(k)) * nodes + i] = float(c[k]);
                }
        }
    } else {
        expect_dim(file, "rgb", 2, 3, "three colour channels");
    }
    expect_dim(file, colour, 0, n_phi, "the size of phi_i");
    expect_dim(file, colour, 1, n_theta, "the size of theta_i");
    expect_dim(file, colour, 3, ls[2], "the luminance's resolution");
    expect_dim(file, colour, 4, ls[3], "the luminance's resolution");

    clamp_negative(vndf, "vndf", path_, where);
    clamp_negative(luminance, "luminance", path_, where);
    auto grid = [&](const char* name, size_t first) {
        const std::vector<uint64_t>& s = file.field(name).shape;
        return std::pair<int, int>(int(s[first + 1]), int(s[first]));  // width, height
    };
    // vndf_ and luminance_ take the same slice parameters, so that one Blend serves both.
    std::vector<std::vector<float>> slice_params = {phi_i, theta_i};
    try {
        auto [wn, hn] = grid("ndf", 0);
        ndf_ = Marginal2D(ndf.data(), wn, hn, {}, Marginal2D::Mode::Interpolant);
        auto [ws, hs] = grid("sigma", 0);
        sigma_ = Marginal2D(sigma.data(), ws, hs, {}, Marginal2D::Mode::Interpolant);
        auto [wv, hv] = grid("vndf", 2);
        vndf_ = Marginal2D(vndf.data(), wv, hv, slice_params, Marginal2D::Mode::Distribution);
        auto [wl, hl] = grid("luminance", 2);
        luminance_ = Marginal2D(luminance.data(), wl, hl, slice_params, Marginal2D::Mode::Distribution);
        rgb_ = Marginal2D(rgb.data(), wl, hl, {phi_i, theta_i, {0.0f, 1.0f, 2.0f}}, Marginal2D::Mode::Interpolant);
    } catch (const std::invalid_argument& e) {
        file.fail(std::string("the vndf or luminance tables: ") + e.what());
    }
    if (colour == "spectra") {
        try {
            auto [width, height] = grid("luminance", 2);  // the spectra's nodes are the luminance's
            spectra_ = Marginal2D(spectra.data(), width, height, {phi_i, theta_i, wavelengths}, Marginal2D::Mode::Interpolant);
            has_spectra_ = true;
        } catch (const std::invalid_argument& e) {
            file.fail(std::string("field \"spectra\": ") + e.what());
        }
    }
}

Spectrum MeasuredBSDF::normal_incidence_albedo() const {
    // The mean sample weight over a 32 x 32 grid of stratum centres: a deterministic estimate of
    // the directional albedo at normal incidence.
    const int n = 32;
    BSDFContext ctx;
    SurfaceInteraction si;
    si.wi = Vec3(0.0f, 0.0f, 1.0f);
    Spectrum sum(0.0f);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            BSDFSample bs = sample(ctx, si, 0.5f, Vec2((float(i) + 0.5f) / n, (float(j) + 0.5f) / n));
            if (bs.valid()) sum += bs.weight;
        }
    return sum / float(n * n);
}

CANDELA_REGISTER_SPECTRAL(MeasuredBSDF, ObjectKind::BSDF, "measured");

}  // namespace candela
