#pragma once
// The BSDF interface. Everything happens in the local shading frame (normal = +z): `wi` points
// back toward where the path came from (the camera side) and `wo` is the sampled or queried
// direction. eval returns f * |cos(wo)|; pdf is per unit solid angle; eval_pdf both at once;
// sample returns the weight f * |cos(wo)| / pdf (for a delta lobe, the weight alone). Every BSDF
// is one-sided unless wrapped in `twosided`; transmissive ones are two-sided by nature.

#include "core/mueller.h"
#include "core/object.h"
#include "core/ray.h"
#include "core/spectrum.h"

#include <cstdint>

namespace candela {

enum BSDFFlags : uint32_t {
    BSDFNone = 0,
    DiffuseReflection = 1u << 0,
    DiffuseTransmission = 1u << 1,
    GlossyReflection = 1u << 2,
    GlossyTransmission = 1u << 3,
    DeltaReflection = 1u << 4,
    DeltaTransmission = 1u << 5,
    // The ray passes on unchanged, as if the surface were not there (`null`, the transparent part
    // of `mask`, `polarizer`): wo = -wi. A delta lobe, but no scattering: the path tracer crosses
    // it without counting a bounce, and shadow rays pass with null_transmission().
    Null = 1u << 6,

    Reflection = DiffuseReflection | GlossyReflection | DeltaReflection,
    Transmission = DiffuseTransmission | GlossyTransmission | DeltaTransmission,
    Diffuse = DiffuseReflection | DiffuseTransmission,
    Glossy = GlossyReflection | GlossyTransmission,
    Smooth = Diffuse | Glossy,
    Delta = DeltaReflection | DeltaTransmission | Null,
    AllLobes = Reflection | Transmission | Null,
};

// Radiance: paths traced from the camera (the usual case). Importance: paths from the lights,
// where the eta^2 radiance scaling on refraction must not be applied.
enum class TransportMode { Radiance, Importance };

struct BSDFContext {
    TransportMode mode = TransportMode::Radiance;
    uint32_t lobes = AllLobes;  // lobes that may be sampled or evaluated
    bool allows(uint32_t lobe) const { return (lobes & lobe) != 0; }
};

struct BSDFSample {
    Vec3 wo{0.0f};
    float pdf = 0.0f;          // 0 marks a failed sample
    float eta = 1.0f;          // relative IOR along the sampled direction (1 for reflection)
    uint32_t lobe = BSDFNone;  // the one lobe that was chosen
    Spectrum weight{0.0f};     // f * |cos wo| / pdf
    // The direction depends on the wavelength (dispersion): it was sampled for the first (hero)
    // wavelength only, and the path must terminate the others (Wavelengths::terminate_secondary).
    bool dispersed = false;
    bool valid() const { return pdf > 0.0f; }
};

// eval() and pdf() of one direction, as BSDF::eval_pdf returns them.
struct BSDFEvalPdf {
    Spectrum value{0.0f};  // f * |cos wo|
    float pdf = 0.0f;
};

struct LocalShading;

class BSDF : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::BSDF; }

    virtual BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u_dir) const = 0;
    virtual Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const = 0;
    virtual float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const = 0;
    // eval() and pdf() together, equal to the two calls (as Mitsuba's eval_pdf): for next-event
    // estimation and MIS, which need both. BSDFs whose two share work (texture lookups, the half
    // vector, D and G1) override it to do that work once.
    // The default writes its result field by field: built as one aggregate from the two calls, the
    // caller read it back as one block across two smaller stores (a store-forwarding stall).
    virtual BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const {
        BSDFEvalPdf result;
        result.value = eval(ctx, si, wo);
        result.pdf = pdf(ctx, si, wo);
        return result;
    }

    // The polarized variant (core/mueller.h): the Mueller matrix, at the path's wavelengths, of
    // light that arrives along -wo and leaves along wi, in the implicit Stokes bases of those two
    // local directions (Mitsuba's convention). For a delta `lobe` (what sample() chose, wo its
    // direction) the matrix of that lobe; for any other `lobe` the smooth lobes at wo, as eval()
    // sums them. Only its polarising part is used: the path divides it by its (0, 0) element per
    // wavelength and keeps eval()'s and sample()'s values as the intensity, so a BSDF may return
    // it times any positive factor per wavelength. False for a BSDF that depolarises (the matrix
    // diag(1, 0, 0, 0), `M` untouched): the default, and Mitsuba's for every BSDF without a
    // polarised model.
    virtual bool eval_mueller(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe,
                              MuellerSpectrum& M) const {
        return false;
    }

    // Directional albedo estimate for AOVs and light-path heuristics (not used for rendering).
    virtual Spectrum albedo(const SurfaceInteraction& si) const = 0;

    // The fraction of light that passes straight through at si (the weight of the Null lobe times
    // the probability with which sample() picks it): what a shadow ray keeps when it crosses this
    // surface. 0 for every BSDF without a Null lobe.
    virtual Spectrum null_transmission(const SurfaceInteraction& si) const { return Spectrum(0.0f); }

    // The rasterizer's local-model view (core/local_model.h). By default a Lambertian of the
    // albedo at normal incidence, two-sided when the BSDF transmits.
    virtual LocalShading local_shading() const;
    // The frame the BSDF evaluates in at si: the shading frame, unless a bump or normal map
    // perturbs it (the rasterizer shades with this frame too).
    virtual Frame shading_frame(const SurfaceInteraction& si) const { return si.shading; }

    uint32_t flags() const { return flags_; }
    bool has_smooth_lobe() const { return (flags_ & Smooth) != 0; }
    bool has_null_lobe() const { return (flags_ & Null) != 0; }
    // False for a BSDF whose sample() never reads u_lobe (one lobe, or a choice made otherwise):
    // the path integrator then skips drawing it (Sampler::skip_1d). True unless a BSDF says so.
    bool reads_lobe_sample() const { return reads_lobe_sample_; }

protected:
    // Completes a sample whose direction, lobe and eta a smooth lobe has drawn: its pdf is pdf()
    // (the density of the whole BSDF, as MIS needs) and its weight eval / pdf, both from one
    // eval_pdf(); invalid when the pdf is not positive or the weight not finite.
    BSDFSample weighted_by_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, BSDFSample bs) const {
        return weighted_by_pdf(bs, eval_pdf(ctx, si, bs.wo));
    }
    // The same from eval_pdf's result `e` of bs.wo, for a BSDF that computes it from what sample()
    // already has.
    static BSDFSample weighted_by_pdf(BSDFSample bs, const BSDFEvalPdf& e) {
        bs.pdf = e.pdf;
        if (!(bs.pdf > 0.0f)) return BSDFSample();
        bs.weight = e.value / bs.pdf;
        if (!all_finite(bs.weight)) return BSDFSample();
        return bs;
    }

    uint32_t flags_ = BSDFNone;
    bool reads_lobe_sample_ = true;
};

inline bool is_delta(uint32_t lobe) { return (lobe & Delta) != 0; }

// A sample of the Null lobe: straight on (wo = -wi), chosen with probability `pdf`.
inline BSDFSample null_lobe_sample(const SurfaceInteraction& si, float pdf, const Spectrum& weight) {
    BSDFSample bs;
    bs.wo = -si.wi;
    bs.pdf = pdf;
    bs.lobe = Null;
    bs.weight = weight;
    return bs;
}

}  // namespace candela
