// retarder: an ideal linear retarder (wave plate), Mitsuba 3's. Light passes straight through,
// unbent, times `transmittance`. In scalar_spectral_polarized it delays the field along the slow
// axis by `delta` against the fast axis, which is the surface's u direction (the local x axis)
// turned by theta about the beam: delta = 90 is a quarter-wave plate (linear light at 45 degrees
// becomes circular), 180 a half-wave plate. As in Mitsuba, oblique incidence scales the
// retardance by |cos theta_i|. (Mitsuba takes the x axis as the basis even at oblique incidence;
// here its part normal to the beam, the same at normal incidence.) In the unpolarised variants
// (RGB, spectral) it is clear, as a `null` surface times `transmittance`, as in Mitsuba's.
//
// Parameters (Mitsuba 3):
//   theta           float or texture rotation of the fast axis about the beam, degrees (default 0)
//   delta           float or texture retardance in degrees, 360 a full wavelength (default 90);
//                                    both one number at every wavelength
//   transmittance   rgb or texture   factor on what passes (default 1)
//
// Its one lobe is Null: crossed without a bounce; shadow rays keep `transmittance` (and,
// polarized, its matrix).

#include "core/registry.h"
#include "materials/optical_element.h"

namespace candela {

class RetarderBSDF final : public OpticalElementBSDF {
public:
    explicit RetarderBSDF(const Properties& props) : OpticalElementBSDF(props, 1.0f) {
        theta_ = props.get_texture("theta", Spectrum(0.0f));
        delta_ = props.get_texture("delta", Spectrum(90.0f));
    }

    bool eval_mueller(const BSDFContext&, const SurfaceInteraction& si, const Vec3&, uint32_t lobe, MuellerSpectrum& M) const override {
        if (lobe != Null) return false;
        const Vec3 forward = si.wi;  // the light travels along wi
        const Vec3 u_axis = Vec3(1, 0, 0) - forward.x * forward;
        if (!(squared_length(u_axis) > 1e-12f)) return false;  // along the fast axis
        // Angles are one number each (a colour's luminance), not spectra.
        const float theta = glm::radians(theta_->eval_1(si)), delta = glm::radians(delta_->eval_1(si));
        on_beam(forward, glm::normalize(u_axis), rotated_element(theta, linear_retarder(delta * std::abs(Frame::cos_theta(si.wi)))), M);
        return true;
    }
    std::string to_string() const override { return "retarder"; }

private:
    Ref<Texture> theta_, delta_;
};

CANDELA_REGISTER_SPECTRAL(RetarderBSDF, ObjectKind::BSDF, "retarder");

}  // namespace candela
