// null: an invisible surface. Light passes straight through it, unchanged (Mitsuba 3's `null`,
// as used to bound participating media). No parameters.
//
// Its one lobe is Null (wo = -wi, weight 1): the path tracer crosses it without a bounce and
// shadow rays pass it (null_transmission 1), so a null shape renders as if it were absent.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/properties.h"
#include "core/registry.h"

namespace candela {

class NullBSDF final : public BSDF {
public:
    explicit NullBSDF(const Properties&) {
        flags_ = Null;
        reads_lobe_sample_ = false;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float, const Vec2&) const override {
        return ctx.allows(Null) ? null_lobe_sample(si, 1.0f, Spectrum(1.0f)) : BSDFSample();
    }
    Spectrum eval(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return Spectrum(0.0f); }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return 0.0f; }
    Spectrum albedo(const SurfaceInteraction&) const override { return Spectrum(0.0f); }
    Spectrum null_transmission(const SurfaceInteraction&) const override { return Spectrum(1.0f); }
    // Polarized: light passes unchanged (the identity, not a depolariser).
    bool eval_mueller(const BSDFContext&, const SurfaceInteraction&, const Vec3&, uint32_t, MuellerSpectrum& M) const override {
        M = identity_spectrum();
        return true;
    }
    // Local model: nothing but the environment seen straight through.
    LocalShading local_shading() const override {
        LocalShading s;
        s.transmission = Spectrum(1.0f);
        s.two_sided = true;
        return s;
    }
    std::string to_string() const override { return "null"; }
};

CANDELA_REGISTER_SPECTRAL(NullBSDF, ObjectKind::BSDF, "null");

}  // namespace candela
