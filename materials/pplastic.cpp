// pplastic: Mitsuba 3's polarised plastic (after Baek et al. 2018) as its RGB (unpolarised)
// variants compute it: a rough specular reflection added to a Lambertian base that light reaches
// and leaves through smooth refractions. Not energy conserving (the two are added, not layered).
// One-sided.
//
// Parameters (Mitsuba 3):
//   diffuse_reflectance    rgb or texture   base albedo rho (default 0.5)
//   specular_reflectance   rgb or texture   factor on the specular term (default 1)
//   int_ior, ext_ior       float or name    indices (defaults polypropylene 1.49, air)
//   distribution, alpha (or alpha_u, alpha_v), sample_visible
//                          as `roughconductor`, floats (default beckmann, 0.1, true)
//
//   f cos(wo) = s F(wi . h) D G / (4 cos wi) + rho (1 - F(cos wi)) (1 - F(cos wo)) cos(wo) / pi
// The specular term is sampled with probability mean(s) / (mean(s) + mean(rho)) (Mitsuba's
// specular_sampling_weight), the diffuse one by the cosine.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "core/texture.h"
#include "core/warp.h"
#include "materials/coating.h"
#include "materials/fresnel.h"
#include "materials/ior.h"
#include "materials/microfacet.h"

namespace candela {

class PolarizedPlasticBSDF final : public CoatedBSDF {
public:
    explicit PolarizedPlasticBSDF(const Properties& props)
        : CoatedBSDF(props), distribution_(MicrofacetDistribution::from_properties(props)) {
        eta_ = read_relative_ior(props, "polypropylene");
        flags_ = GlossyReflection | DiffuseReflection;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override {
        BSDFSample bs;
        if (Frame::cos_theta(si.wi) <= 0.0f) return bs;
        if (!sample_rough_coating(distribution_, ctx, si.wi, specular_probability(ctx), u_lobe, u, bs)) return BSDFSample();
        return weighted_by_pdf(ctx, si, bs);
    }

    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        return eval_pdf(ctx, si, wo, true, false).value;
    }

    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        return eval_pdf(ctx, si, wo, false, true).pdf;
    }

    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        return eval_pdf(ctx, si, wo, true, true);
    }

    Spectrum albedo(const SurfaceInteraction& si) const override {
        float F = fresnel_dielectric(std::max(Frame::cos_theta(si.wi), 0.0f), eta_).F;
        return specular_->eval(si) * F + diffuse_->eval(si) * (1.0f - F);
    }
    // Local model: kd = diffuse_reflectance, a highlight and environment reflection with
    // F0 = ((eta - 1) / (eta + 1))^2, shininess 2 / alpha^2 - 2, blurred by alpha.
    LocalShading local_shading() const override {
        LocalShading s;
        float F0 = fresnel_dielectric(1.0f, eta_).F;
        float alpha = 0.5f * (distribution_.alpha_u() + distribution_.alpha_v());
        s.diffuse = diffuse_;
        s.specular = specular_->mean() * F0;
        s.shininess = phong_exponent(alpha);
        s.mirror = s.specular;
        s.roughness = alpha;
        return s;
    }
    std::string to_string() const override { return "pplastic"; }

    // Polarized (Mitsuba's pplastic): the Fresnel reflection matrix of the microfacet at the half
    // vector for the specular term, plus refraction in, a depolarising base and refraction out for
    // the diffuse one, each times its eval() intensity at each wavelength.
    bool eval_mueller(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t, MuellerSpectrum& M) const override {
        const float cos_i = Frame::cos_theta(si.wi), cos_o = Frame::cos_theta(wo);
        if (cos_i <= 0.0f || cos_o <= 0.0f) return false;
        M = MuellerSpectrum();
        if (ctx.allows(GlossyReflection)) {
            const Vec3 h = glm::normalize(si.wi + wo);
            const float value = distribution_.D(h) * distribution_.G1(si.wi, h) * distribution_.G1(wo, h) / (4.0f * cos_i);
            MuellerSpectrum F;
            fresnel_reflection_mueller(h, si.wi, wo, Spectrum(eta_), Spectrum(0.0f), F);
            const Spectrum s = specular_->eval(si) * value;
            for (int k = 0; k < 3; ++k) M.w[k] = M.w[k] + s[k] * F.w[k];
        }
        if (ctx.allows(DiffuseReflection)) {
            const Mueller diffuse = coated_diffuse_mueller(si.wi, wo, eta_);
            const Spectrum d = diffuse_->eval(si) * (cos_o * InvPi);
            for (int k = 0; k < 3; ++k) M.w[k] = M.w[k] + d[k] * diffuse;
        }
        return true;
    }

private:
    // eval() and pdf(), either or both: one half vector, D(h) and G1(wi).
    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, bool with_value, bool with_pdf) const {
        BSDFEvalPdf result;
        float cos_i = Frame::cos_theta(si.wi), cos_o = Frame::cos_theta(wo);
        if (cos_i <= 0.0f || cos_o <= 0.0f) return result;
        const bool specular = ctx.allows(GlossyReflection);
        Vec3 h = glm::normalize(si.wi + wo);
        float D = 0.0f, G1_wi = 0.0f;
        if (specular) {
            D = distribution_.D(h);
            G1_wi = distribution_.G1(si.wi, h);
        }
        if (with_value) {
            if (specular) {
                float F = fresnel_dielectric(glm::dot(si.wi, h), eta_).F;
                result.value += specular_->eval(si) * (F * D * (G1_wi * distribution_.G1(wo, h)) / (4.0f * cos_i));
            }
            if (ctx.allows(DiffuseReflection)) {
                float Fi = fresnel_dielectric(cos_i, eta_).F, Fo = fresnel_dielectric(cos_o, eta_).F;
                result.value += diffuse_->eval(si) * ((1.0f - Fi) * (1.0f - Fo) * cos_o * InvPi);
            }
        }
        if (with_pdf) {
            // specular_probability is 0 unless `specular`.
            float p_spec = specular_probability(ctx);
            if (p_spec > 0.0f && glm::dot(si.wi, h) > 0.0f && glm::dot(wo, h) > 0.0f)
                result.pdf += p_spec * distribution_.pdf(si.wi, h, D, G1_wi) / (4.0f * glm::dot(wo, h));
            if (ctx.allows(DiffuseReflection)) result.pdf += (1.0f - p_spec) * warp::square_to_cosine_hemisphere_pdf(wo);
        }
        return result;
    }

    float specular_probability(const BSDFContext& ctx) const {
        return specular_lobe_probability(ctx, GlossyReflection, DiffuseReflection, specular_weight_);
    }

    MicrofacetDistribution distribution_;
    float eta_;
};

CANDELA_REGISTER_SPECTRAL(PolarizedPlasticBSDF, ObjectKind::BSDF, "pplastic");

}  // namespace candela
