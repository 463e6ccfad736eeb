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

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"

namespace candela {

class RetarderBSDF final : public BSDF {
public:
    explicit RetarderBSDF(const Properties& props) {
        theta_ = props.get_texture("theta", Spectrum(0.0f));
        delta_ = props.get_texture("delta", Spectrum(90.0f));
        transmittance_ = props.get_texture("transmittance", Spectrum(1.0f));
        flags_ = Null;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float, const Vec2&) const override {
        return ctx.allows(Null) ? null_lobe_sample(si, 1.0f, null_transmission(si)) : BSDFSample();
    }
    Spectrum eval(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return Spectrum(0.0f); }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return 0.0f; }
    bool eval_mueller(const BSDFContext&, const SurfaceInteraction& si, const Vec3&, uint32_t lobe, MuellerSpectrum& M) const override {
        if (lobe != Null) return false;
        const Vec3 forward = si.wi;  // the light travels along wi
        const Vec3 u_axis = Vec3(1, 0, 0) - forward.x * forward;
        if (!(squared_length(u_axis) > 1e-12f)) return false;  // along the fast axis
        const Mueller R = rotate_stokes_basis(forward, glm::normalize(u_axis), stokes_basis(forward));
        // Angles are one number each (a colour's luminance), not spectra.
        const float theta = glm::radians(theta_->eval_1(si)), delta = glm::radians(delta_->eval_1(si));
        const Mueller m = R * rotated_element(theta, linear_retarder(delta * std::abs(Frame::cos_theta(si.wi)))) * transpose(R);
        for (Mueller& w : M.w) w = m;
        return true;
    }
    Spectrum albedo(const SurfaceInteraction& si) const override { return null_transmission(si); }
    Spectrum null_transmission(const SurfaceInteraction& si) const override { return transmittance_->eval(si); }
    // Local model: the environment seen straight through.
    LocalShading local_shading() const override {
        LocalShading s;
        s.transmission = transmittance_->mean();
        s.two_sided = true;
        return s;
    }
    std::string to_string() const override { return "retarder"; }

private:
    Ref<Texture> theta_, delta_, transmittance_;
};

CANDELA_REGISTER_SPECTRAL(RetarderBSDF, ObjectKind::BSDF, "retarder");

}  // namespace candela
