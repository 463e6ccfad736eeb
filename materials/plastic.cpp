// plastic: a diffuse base under a smooth dielectric coating (Mitsuba 3's model). The coating
// reflects F(cos wi) as a mirror; light that enters scatters diffusely in the base, with the
// internal reflections at the coating summed in closed form. One-sided.
//
// Parameters (Mitsuba 3):
//   int_ior, ext_ior       float or name    coating indices (defaults polypropylene 1.49, air)
//   diffuse_reflectance    rgb or texture   base albedo rho (default 0.5)
//   specular_reflectance   rgb or texture   factor on the mirror term (default 1)
//   nonlinear              boolean          account for colour shifts from repeated bounces in
//                                           the base (default false)
//
//   f_diffuse cos(wo) = rho' (1 - F(cos wi)) (1 - F(cos wo)) cos(wo) / (pi eta^2),
//   rho' = rho / (1 - Fdr_int) (linear) or rho / (1 - rho Fdr_int) (nonlinear),
// with Fdr_int the hemispherical internal reflectance of the coating.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "core/texture.h"
#include "core/warp.h"
#include "materials/coating.h"
#include "materials/fresnel.h"
#include "materials/ior.h"

namespace candela {

class PlasticBSDF final : public CoatedBSDF {
public:
    explicit PlasticBSDF(const Properties& props) : CoatedBSDF(props) {
        eta_ = read_relative_ior(props, "polypropylene");
        nonlinear_ = props.get_bool("nonlinear", false);
        fdr_int_ = fresnel_diffuse_reflectance(1.0f / eta_);
        flags_ = DeltaReflection | DiffuseReflection;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override {
        BSDFSample bs;
        float cos_i = Frame::cos_theta(si.wi);
        if (cos_i <= 0.0f) return bs;
        float Fi = fresnel_dielectric(cos_i, eta_).F;
        float p_spec = specular_probability(ctx, Fi);
        if (u_lobe < p_spec) {
            bs.wo = reflect(si.wi);
            bs.pdf = p_spec;
            bs.lobe = DeltaReflection;
            bs.weight = specular_->eval(si) * (Fi / p_spec);
            return bs;
        }
        if (!ctx.allows(DiffuseReflection)) return bs;
        bs.wo = warp::square_to_cosine_hemisphere(u);
        bs.pdf = (1.0f - p_spec) * warp::square_to_cosine_hemisphere_pdf(bs.wo);
        if (!(bs.pdf > 0.0f)) return BSDFSample();
        bs.lobe = DiffuseReflection;
        bs.weight = diffuse_term(si, Fi, bs.wo) / bs.pdf;
        return bs;
    }

    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        float cos_i = Frame::cos_theta(si.wi);
        if (!ctx.allows(DiffuseReflection) || cos_i <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return Spectrum(0.0f);
        return diffuse_term(si, fresnel_dielectric(cos_i, eta_).F, wo);
    }

    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        float cos_i = Frame::cos_theta(si.wi);
        if (!ctx.allows(DiffuseReflection) || cos_i <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return 0.0f;
        float p_spec = specular_probability(ctx, fresnel_dielectric(cos_i, eta_).F);
        return (1.0f - p_spec) * warp::square_to_cosine_hemisphere_pdf(wo);
    }

    // Both at once for next-event estimation, equal to the two: the coating's Fresnel at wi once.
    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        BSDFEvalPdf result;
        const float cos_i = Frame::cos_theta(si.wi);
        if (!ctx.allows(DiffuseReflection) || cos_i <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return result;
        const float Fi = fresnel_dielectric(cos_i, eta_).F;
        result.value = diffuse_term(si, Fi, wo);
        result.pdf = (1.0f - specular_probability(ctx, Fi)) * warp::square_to_cosine_hemisphere_pdf(wo);
        return result;
    }

    // Polarized: the coating's Fresnel reflection matrix for the mirror lobe and, for the diffuse
    // one, refraction in, a depolarising base and refraction out (as pplastic).
    bool eval_mueller(const BSDFContext&, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe, MuellerSpectrum& M) const override {
        if (Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return false;
        if (lobe == DeltaReflection) {
            fresnel_reflection_mueller(Vec3(0, 0, 1), si.wi, wo, Spectrum(eta_), Spectrum(0.0f), M);
            return true;
        }
        const Mueller diffuse = coated_diffuse_mueller(si.wi, wo, eta_);
        for (Mueller& m : M.w) m = diffuse;
        return true;
    }

    Spectrum albedo(const SurfaceInteraction& si) const override {
        float Fi = fresnel_dielectric(std::max(Frame::cos_theta(si.wi), 0.0f), eta_).F;
        return specular_->eval(si) * Fi + diffuse_->eval(si) * (1.0f - Fi);
    }
    // Local model: kd = diffuse_reflectance (the base under the coating), and the coating as a
    // mirror reflecting the environment with F0 = ((eta - 1) / (eta + 1))^2.
    LocalShading local_shading() const override {
        LocalShading s;
        s.diffuse = diffuse_;
        s.mirror = specular_->mean() * fresnel_dielectric(1.0f, eta_).F;
        return s;
    }
    std::string to_string() const override { return "plastic"; }

private:
    float specular_probability(const BSDFContext& ctx, float Fi) const {
        return specular_lobe_probability(ctx, DeltaReflection, DiffuseReflection, specular_weight_, Fi);
    }

    Spectrum diffuse_term(const SurfaceInteraction& si, float Fi, const Vec3& wo) const {
        float Fo = fresnel_dielectric(Frame::cos_theta(wo), eta_).F;
        const Spectrum rho_p = coated_base_albedo(diffuse_->eval(si), fdr_int_, nonlinear_);
        return rho_p * ((1.0f - Fi) * (1.0f - Fo) * Frame::cos_theta(wo) * InvPi / (eta_ * eta_));
    }

    float eta_, fdr_int_;
    bool nonlinear_;
};

CANDELA_REGISTER_SPECTRAL(PlasticBSDF, ObjectKind::BSDF, "plastic");

}  // namespace candela
