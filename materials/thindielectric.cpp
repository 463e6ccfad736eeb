// thindielectric: a thin sheet of dielectric (a window pane). Light is reflected or passes
// straight through without refraction; the interreflections inside the sheet are summed:
// R = R1 + T1^2 R1 / (1 - R1^2) = 2 R1 / (1 + R1), T = 1 - R, with R1 the Fresnel reflectance.
//
// As in Mitsuba 3, the light that passes through is a Null lobe, not a delta transmission: the
// direction does not change, so the sheet is crossed as a `null` surface is (no scattering event,
// no max_depth step, no change of the vertex MIS refers to) and shadow rays pass it with
// null_transmission = T times specular_transmittance. Inside a medium bounded by a thin sheet,
// next-event estimation thus reaches lights outside it; with a delta lobe it could not, and the
// light would only be found by chance (noise), one depth step lost per crossing (darker).
//
// Parameters (Mitsuba 3):
//   int_ior, ext_ior, specular_reflectance, specular_transmittance   as `dielectric`

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "core/texture.h"
#include "materials/fresnel.h"
#include "materials/ior.h"

namespace candela {

class ThinDielectricBSDF final : public BSDF {
public:
    explicit ThinDielectricBSDF(const Properties& props) {
        eta_ = read_relative_ior(props, "bk7");
        reflectance_ = props.get_reflectance("specular_reflectance", Spectrum(1.0f));
        transmittance_ = props.get_reflectance("specular_transmittance", Spectrum(1.0f));
        flags_ = DeltaReflection | Null;
    }

    // Total reflectance of the sheet at incidence cos_i.
    float sheet_reflectance(float cos_i) const {
        float r1 = fresnel_dielectric(std::abs(cos_i), eta_).F;
        return r1 < 1.0f ? 2.0f * r1 / (1.0f + r1) : 1.0f;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2&) const override {
        BSDFSample bs;
        float R = sheet_reflectance(Frame::cos_theta(si.wi));
        FresnelChoice c = choose_fresnel_lobe(ctx.allows(DeltaReflection), ctx.allows(Null), R, u_lobe);
        if (!(c.pdf > 0.0f)) return bs;
        if (!c.reflect) return null_lobe_sample(si, c.pdf, transmittance_->eval(si) * c.weight_factor);
        bs.pdf = c.pdf;
        bs.wo = reflect(si.wi);
        bs.lobe = DeltaReflection;
        bs.weight = reflectance_->eval(si) * c.weight_factor;
        return bs;
    }

    // What a shadow ray keeps crossing the sheet (si.wi: back along the shadow ray).
    Spectrum null_transmission(const SurfaceInteraction& si) const override {
        return transmittance_->eval(si) * (1.0f - sheet_reflectance(Frame::cos_theta(si.wi)));
    }

    Spectrum eval(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return Spectrum(0.0f); }
    // Polarized (beyond Mitsuba, whose sheet depolarises): the interreflections summed per
    // polarisation, R_s = 2 R1_s / (1 + R1_s) and likewise p, T = 1 - R; a diattenuator, with the
    // first surface's phase (0 or pi) on reflection. One matrix for every wavelength.
    bool eval_mueller(const BSDFContext&, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe, MuellerSpectrum& M) const override {
        if (lobe != DeltaReflection && lobe != Null) return false;
        const FresnelAmplitudes f = fresnel_amplitudes(std::abs(Frame::cos_theta(si.wi)), std::complex<float>(eta_, 0.0f));
        const float r1_s = std::norm(f.a_s), r1_p = std::norm(f.a_p);
        const float r_s = 2.0f * r1_s / (1.0f + r1_s), r_p = 2.0f * r1_p / (1.0f + r1_p);
        Mueller facet = lobe == Null ? diattenuator(1.0f - r_s, 1.0f - r_p) : diattenuator(r_s, r_p);
        if (lobe == DeltaReflection && f.a_s.real() * f.a_p.real() < 0.0f) {
            facet(2, 2) = -facet(2, 2);
            facet(3, 3) = -facet(3, 3);
        }
        const Mueller local = facet_to_local_bases(Vec3(0, 0, 1), si.wi, wo).apply(facet);
        for (Mueller& m : M.w) m = local;
        return true;
    }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return 0.0f; }
    Spectrum albedo(const SurfaceInteraction& si) const override {
        float R = sheet_reflectance(Frame::cos_theta(si.wi));
        return reflectance_->eval(si) * R + transmittance_->eval(si) * (1.0f - R);
    }
    // Local model: environment reflection with the sheet's reflectance R at normal incidence and
    // the environment seen straight through with 1 - R.
    LocalShading local_shading() const override {
        LocalShading s;
        float R = sheet_reflectance(1.0f);
        s.mirror = reflectance_->mean() * R;
        s.transmission = transmittance_->mean() * (1.0f - R);
        s.two_sided = true;
        return s;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        visitor.object("specular_reflectance", reflectance_.get());
        visitor.object("specular_transmittance", transmittance_.get());
    }
    std::string to_string() const override { return "thindielectric"; }

private:
    float eta_;
    Ref<Texture> reflectance_, transmittance_;
};

CANDELA_REGISTER_SPECTRAL(ThinDielectricBSDF, ObjectKind::BSDF, "thindielectric");

}  // namespace candela
