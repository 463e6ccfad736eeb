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

#include "core/registry.h"
#include "materials/optical_element.h"

namespace candela {

class PolarizerBSDF final : public OpticalElementBSDF {
public:
    explicit PolarizerBSDF(const Properties& props) : OpticalElementBSDF(props, 0.5f) {
        theta_ = props.get_texture("theta", Spectrum(0.0f));
        polarizing_ = props.get_bool("polarizing", true);
    }

    bool eval_mueller(const BSDFContext&, const SurfaceInteraction& si, const Vec3&, uint32_t lobe, MuellerSpectrum& M) const override {
        if (lobe != Null) return false;
        if (!polarizing_) {
            M = identity_spectrum();
            return true;
        }
        // The light travels along wi; the element's reference axis is the effective transmitting
        // axis, perpendicular to the absorbing one.
        const Vec3 forward = si.wi;
        const Vec3 v_axis = Vec3(0, 1, 0) - forward.y * forward;
        if (!(squared_length(v_axis) > 1e-12f)) return false;  // along the absorbing axis: nothing to turn
        const Vec3 transmitting = glm::cross(forward, glm::normalize(v_axis));
        // An angle is one number (a colour's luminance), not a spectrum.
        on_beam(forward, transmitting, rotated_element(glm::radians(theta_->eval_1(si)), linear_polarizer()), M);
        return true;
    }
    std::string to_string() const override { return "polarizer"; }

private:
    Ref<Texture> theta_;
    bool polarizing_ = true;
};

CANDELA_REGISTER_SPECTRAL(PolarizerBSDF, ObjectKind::BSDF, "polarizer");

}  // namespace candela
