// polarizer: an ideal linear polariser, as Mitsuba 3's RGB (unpolarised) variants render it: a
// neutral filter that lets half the light pass straight through, unbent, times `transmittance`.
// Polarisation itself is not tracked, so the angle has no effect (two crossed polarisers pass a
// quarter, not nothing, exactly as in Mitsuba's RGB variants).
//
// Parameters (Mitsuba 3):
//   theta           rgb or texture   rotation of the absorbing axis in degrees (default 0; read,
//                                    no effect without polarisation)
//   transmittance   rgb or texture   extra factor on what passes (default 1)
//   polarizing      boolean          false: a plain neutral-density filter (default true; the same
//                                    here, 0.5 transmittance either way)
//
// Its one lobe is Null with weight 0.5 transmittance: crossed without a bounce, and shadow rays
// keep that fraction.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"

namespace candela {

class PolarizerBSDF final : public BSDF {
public:
    explicit PolarizerBSDF(const Properties& props) {
        props.get_texture("theta", Spectrum(0.0f));
        transmittance_ = props.get_texture("transmittance", Spectrum(1.0f));
        props.get_bool("polarizing", true);
        flags_ = Null;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float, const Vec2&) const override {
        return ctx.allows(Null) ? null_lobe_sample(si, 1.0f, null_transmission(si)) : BSDFSample();
    }
    Spectrum eval(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return Spectrum(0.0f); }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return 0.0f; }
    Spectrum albedo(const SurfaceInteraction& si) const override { return null_transmission(si); }
    Spectrum null_transmission(const SurfaceInteraction& si) const override { return 0.5f * transmittance_->eval(si); }
    // Local model: the environment seen straight through, at half strength.
    LocalShading local_shading() const override {
        LocalShading s;
        s.transmission = 0.5f * transmittance_->mean();
        s.two_sided = true;
        return s;
    }
    std::string to_string() const override { return "polarizer"; }

private:
    Ref<Texture> transmittance_;
};

CANDELA_REGISTER_SPECTRAL(PolarizerBSDF, ObjectKind::BSDF, "polarizer");

}  // namespace candela
