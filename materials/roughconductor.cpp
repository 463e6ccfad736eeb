// roughconductor: a rough metal (microfacet model of Walter et al. 2007 with conductor Fresnel).
// One-sided.
//
// Parameters (Mitsuba 3):
//   distribution           string           beckmann (default) or ggx
//   alpha                  float or texture roughness (default 0.1); or alpha_u and alpha_v for
//                                           an anisotropic surface (textures: scalar lookups)
//   sample_visible         boolean          sample visible normals (default true)
//   material, eta, k       as `conductor`
//   specular_reflectance   rgb or texture   extra factor (default 1)
//
// f(wi, wo) cos(wo) = F(wi . h) D(h) G1(wi) G1(wo) / (4 cos(wi)), h = normalize(wi + wo).
// With visible normals sampled (pdf D(m) G1(wi) (wi . m) / cos(wi) / (4 wo . m)) the weight of a
// sample is F(wi . m) G1(wo) (wo . m = wi . m), as Mitsuba 3 computes it.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "materials/fresnel.h"
#include "materials/ior.h"
#include "materials/microfacet.h"

namespace candela {

class RoughConductorBSDF final : public BSDF {
public:
    explicit RoughConductorBSDF(const Properties& props) : roughness_(MicrofacetRoughness::from_properties(props)) {
        read_conductor_ior(props, eta_, k_);
        specular_ = props.get_reflectance("specular_reflectance", Spectrum(1.0f));
        flags_ = GlossyReflection;
        reads_lobe_sample_ = false;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float, const Vec2& u) const override {
        BSDFSample bs;
        if (!ctx.allows(GlossyReflection) || Frame::cos_theta(si.wi) <= 0.0f) return bs;
        MicrofacetDistribution distribution = roughness_.at(si);
        float pdf_m;
        Vec3 m = distribution.sample(si.wi, u, pdf_m);
        Vec3 wo = reflect(si.wi, m);
        if (wo.z <= 0.0f || !(pdf_m > 0.0f)) return bs;
        bs.wo = wo;
        bs.pdf = pdf_m / (4.0f * glm::dot(wo, m));
        bs.lobe = GlossyReflection;
        if (distribution.sample_visible())
            bs.weight = specular_->eval(si) *
                        fresnel_conductor(glm::dot(si.wi, m), eta_->eval_as(si, SpectrumRole::Unbounded),
                                          k_->eval_as(si, SpectrumRole::Unbounded)) *
                        distribution.G1(wo, m);
        else
            bs.weight = eval(ctx, si, wo) / bs.pdf;
        if (!all_finite(bs.weight)) return BSDFSample();
        return bs;
    }

    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        return eval_pdf(ctx, si, wo, false).value;
    }

    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        if (!ctx.allows(GlossyReflection) || Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return 0.0f;
        Vec3 h = glm::normalize(si.wi + wo);
        return roughness_.at(si).pdf(si.wi, h) / (4.0f * glm::dot(wo, h));
    }

    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        return eval_pdf(ctx, si, wo, true);
    }

    Spectrum albedo(const SurfaceInteraction& si) const override {
        return specular_->eval(si) * fresnel_conductor(std::max(Frame::cos_theta(si.wi), 0.0f), eta_->eval_as(si, SpectrumRole::Unbounded),
                                                       k_->eval_as(si, SpectrumRole::Unbounded));
    }
    // Local model: highlight ks = F0 (conductor Fresnel at normal incidence) with shininess
    // 2 / alpha^2 - 2 (the Phong exponent whose lobe matches a Beckmann distribution of
    // roughness alpha, Walter et al. 2007), and the environment reflected with the same F0,
    // blurred by alpha.
    LocalShading local_shading() const override {
        LocalShading s;
        Spectrum F0 = specular_->mean() * fresnel_conductor(1.0f, eta_->mean(), k_->mean());
        float alpha = roughness_.mean_alpha();
        s.specular = F0;
        s.shininess = phong_exponent(alpha);
        s.mirror = F0;
        s.roughness = alpha;
        return s;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        visitor.object("eta", eta_.get());
        visitor.object("k", k_.get());
        visitor.object("specular_reflectance", specular_.get());
    }
    std::string to_string() const override { return "roughconductor"; }

    // Polarized: the Fresnel matrix of the microfacet at the half vector (Mitsuba's); D, G and
    // the specular factor are eval()'s intensity.
    bool eval_mueller(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t, MuellerSpectrum& M) const override {
        if (!ctx.allows(GlossyReflection) || Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return false;
        fresnel_reflection_mueller(glm::normalize(si.wi + wo), si.wi, wo, eta_->eval_as(si, SpectrumRole::Unbounded),
                                   k_->eval_as(si, SpectrumRole::Unbounded), M);
        return true;
    }

private:
    // eval(), and with `with_pdf` pdf() too: one roughness lookup, one D(h) and G1(wi).
    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, bool with_pdf) const {
        BSDFEvalPdf result;
        float cos_i = Frame::cos_theta(si.wi), cos_o = Frame::cos_theta(wo);
        if (!ctx.allows(GlossyReflection) || cos_i <= 0.0f || cos_o <= 0.0f) return result;
        Vec3 h = glm::normalize(si.wi + wo);
        MicrofacetDistribution distribution = roughness_.at(si);
        float D = distribution.D(h), G1_wi = distribution.G1(si.wi, h);
        if (with_pdf) result.pdf = distribution.pdf(si.wi, h, D, G1_wi) / (4.0f * glm::dot(wo, h));
        if (D == 0.0f) return result;
        float G = G1_wi * distribution.G1(wo, h);
        Spectrum F =
            fresnel_conductor(glm::dot(si.wi, h), eta_->eval_as(si, SpectrumRole::Unbounded), k_->eval_as(si, SpectrumRole::Unbounded));
        result.value = specular_->eval(si) * F * (D * G / (4.0f * cos_i));
        return result;
    }

    MicrofacetRoughness roughness_;
    Ref<Texture> eta_, k_, specular_;
};

CANDELA_REGISTER_SPECTRAL(RoughConductorBSDF, ObjectKind::BSDF, "roughconductor");

}  // namespace candela
