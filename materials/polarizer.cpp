// polarizer: an ideal linear polariser (Mitsuba 3's). Light passes straight through, unbent; half
// of unpolarised light passes, times `transmittance`. In scalar_spectral_polarized it is a linear
// polariser turned by theta about the beam, whose absorbing axis is the surface's v direction
// (the local y axis) projected onto the plane normal to the beam (Korger et al. 2013, "The
// polarization properties of a tilted polarizer"), as Mitsuba computes it: two crossed
// polarisers pass nothing, and light through two at an angle a follows Malus' law, cos^2 a. In
// the unpolarised variants (RGB, spectral) the angle has no effect and each passes half, as in
// Mitsuba's.
//
// Parameters (Mitsuba 3):
//   theta           float or texture rotation of the polariser about the beam, in degrees
//                                    (default 0; one number at every wavelength)
//   transmittance   rgb or texture   extra factor on what passes (default 1)
//   polarizing      boolean          false: a neutral-density filter that passes half and keeps
//                                    the polarisation (default true)
//
// Its one lobe is Null with weight 0.5 transmittance: crossed without a bounce, and shadow rays
// keep that fraction (and, polarized, its matrix).

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"

namespace candela {

class PolarizerBSDF final : public BSDF {
public:
    explicit PolarizerBSDF(const Properties& props) {
        theta_ = props.get_texture("theta", Spectrum(0.0f));
        transmittance_ = props.get_texture("transmittance", Spectrum(1.0f));
        polarizing_ = props.get_bool("polarizing", true);
        flags_ = Null;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float, const Vec2&) const override {
        return ctx.allows(Null) ? null_lobe_sample(si, 1.0f, null_transmission(si)) : BSDFSample();
    }
    Spectrum eval(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return Spectrum(0.0f); }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return 0.0f; }
    bool eval_mueller(const BSDFContext&, const SurfaceInteraction& si, const Vec3&, uint32_t lobe, MuellerSpectrum& M) const override {
        if (lobe != Null) return false;
        if (!polarizing_) {
            M = identity_spectrum();
            return true;
        }
        // The light travels along wi; its implicit basis is turned to the effective transmitting
        // axis, perpendicular to the absorbing one.
        const Vec3 forward = si.wi;
        const Vec3 v_axis = Vec3(0, 1, 0) - forward.y * forward;
        if (!(squared_length(v_axis) > 1e-12f)) return false;  // along the absorbing axis: nothing to turn
        const Vec3 absorbing = glm::normalize(v_axis);
        const Vec3 transmitting = glm::cross(forward, absorbing);
        const Mueller R = rotate_stokes_basis(forward, transmitting, stokes_basis(forward));
        // An angle is one number (a colour's luminance), not a spectrum.
        const Mueller m = R * rotated_element(glm::radians(theta_->eval_1(si)), linear_polarizer()) * transpose(R);
        for (Mueller& w : M.w) w = m;
        return true;
    }
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
    Ref<Texture> theta_, transmittance_;
    bool polarizing_ = true;
};

CANDELA_REGISTER_SPECTRAL(PolarizerBSDF, ObjectKind::BSDF, "polarizer");

}  // namespace candela
