// roughdielectric: a rough interface between two dielectrics (frosted glass), the microfacet
// BTDF of Walter et al. 2007 ("Microfacet Models for Refraction through Rough Surfaces").
//
// Parameters (Mitsuba 3):
//   distribution, alpha (or alpha_u, alpha_v), sample_visible   as `roughconductor` (alphas may
//                                                                be textures)
//   int_ior, ext_ior, specular_reflectance, specular_transmittance   as `dielectric`
//
// With eta' = n_other_side / n_wi_side and the half vector m of the pair (m.z > 0):
//   reflection:    f cos(wo) = F D G / (4 |cos wi|)
//   transmission:  f cos(wo) = (1 - F) D G |wi.m| |wo.m| / (|cos wi| (wi.m + eta' wo.m)^2)
// in radiance mode; importance transport multiplies transmission by eta'^2. Reflection is
// sampled with probability F(wi . m), refraction with 1 - F. With visible normals sampled the
// weight of a sample is G1(wo) (as Mitsuba 3), times F or 1 - F when only that lobe may be
// sampled, and 1 / eta'^2 for refraction in radiance mode.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "core/texture.h"
#include "materials/fresnel.h"
#include "materials/ior.h"
#include "materials/microfacet.h"

namespace candela {

class RoughDielectricBSDF final : public BSDF {
public:
    explicit RoughDielectricBSDF(const Properties& props) : roughness_(MicrofacetRoughness::from_properties(props)) {
        eta_ = read_relative_ior(props, "bk7");
        reflectance_ = props.get_reflectance("specular_reflectance", Spectrum(1.0f));
        transmittance_ = props.get_reflectance("specular_transmittance", Spectrum(1.0f));
        flags_ = GlossyReflection | GlossyTransmission;
        // An index-matched interface (eta = 1) neither reflects (F = 0) nor bends light, however
        // rough: every microfacet refracts wo = -wi, where the half-vector model degenerates
        // (wi + eta' wo = 0). It is a smooth straight transmission, as `dielectric` gives.
        if (eta_ == 1.0f) flags_ = DeltaTransmission;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override {
        BSDFSample bs;
        float cos_i = Frame::cos_theta(si.wi);
        bool has_r = ctx.allows(GlossyReflection), has_t = ctx.allows(GlossyTransmission);
        if (eta_ == 1.0f) {
            if (cos_i == 0.0f || !ctx.allows(DeltaTransmission)) return bs;
            bs.wo = -si.wi;
            bs.lobe = DeltaTransmission;
            bs.pdf = 1.0f;
            bs.weight = transmittance_->eval(si);
            return bs;
        }
        if (cos_i == 0.0f || (!has_r && !has_t)) return bs;
        // Sample a normal visible from wi mirrored into the upper hemisphere.
        Vec3 wi_up = cos_i > 0.0f ? si.wi : -si.wi;
        MicrofacetDistribution distribution = roughness_.at(si);
        float pdf_m;
        Vec3 m = distribution.sample(wi_up, u, pdf_m);
        if (!(pdf_m > 0.0f)) return bs;
        DielectricFresnel fr = fresnel_dielectric(glm::dot(si.wi, m), eta_);
        FresnelChoice choice = choose_fresnel_lobe(has_r, has_t, fr.F, u_lobe);
        if (choice.reflect) {
            bs.wo = reflect(si.wi, m);
            bs.lobe = GlossyReflection;
            if (bs.wo.z * cos_i <= 0.0f) return BSDFSample();
        } else {
            if (fr.F >= 1.0f) return bs;
            bs.wo = refract(si.wi, m, fr.cos_theta_t, fr.eta_ti);
            bs.lobe = GlossyTransmission;
            bs.eta = fr.eta_it;
            if (bs.wo.z * cos_i >= 0.0f) return BSDFSample();
        }
        if (!distribution.sample_visible()) return weighted_by_pdf(ctx, si, bs);
        // The weight in closed form, eval / pdf = G1(wo) times the lobe's factor (D, G1(wi), the
        // Jacobian and the lobe's probability cancel); the pdf is pdf()'s, through the half vector
        // of wi and wo as next-event estimation sees it (through the sampled m it can differ by
        // 0.2% near total internal reflection, where that half vector is ill-conditioned).
        float G1_wo = distribution.G1(bs.wo, m);
        if (!(G1_wo > 0.0f)) return BSDFSample();
        bs.pdf = pdf(ctx, si, bs.wo);
        if (bs.lobe == GlossyReflection) {
            bs.weight = reflectance_->eval(si) * (choice.weight_factor * G1_wo);
        } else {
            float radiance = ctx.mode == TransportMode::Radiance ? fr.eta_ti * fr.eta_ti : 1.0f;
            bs.weight = transmittance_->eval(si) * (choice.weight_factor * G1_wo * radiance);
        }
        if (!(bs.pdf > 0.0f) || !all_finite(bs.weight)) return BSDFSample();
        return bs;
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
        float F = fresnel_dielectric(Frame::cos_theta(si.wi), eta_).F;
        return reflectance_->eval(si) * F + transmittance_->eval(si) * (1.0f - F);
    }
    // Local model: as `dielectric`, plus a highlight ks = F0 with shininess 2 / alpha^2 - 2, and
    // both environment lookups blurred by alpha.
    LocalShading local_shading() const override {
        LocalShading s;
        float F0 = fresnel_dielectric(1.0f, eta_).F;
        float alpha = roughness_.mean_alpha();
        s.specular = reflectance_->mean() * F0;
        s.shininess = phong_exponent(alpha);
        s.mirror = reflectance_->mean() * F0;
        s.transmission = transmittance_->mean() * (1.0f - F0);
        s.eta = eta_;
        s.roughness = alpha;
        s.two_sided = true;
        return s;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        visitor.object("specular_reflectance", reflectance_.get());
        visitor.object("specular_transmittance", transmittance_.get());
    }
    std::string to_string() const override { return "roughdielectric"; }

    // Polarized: Fresnel's reflection or refraction matrix of the microfacet at the generalised
    // half vector (Mitsuba's); D, G and the rest are eval()'s intensity.
    bool eval_mueller(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe,
                      MuellerSpectrum& M) const override {
        if (eta_ == 1.0f) {
            if (lobe != DeltaTransmission) return false;
            fresnel_transmission_mueller(Vec3(0, 0, 1), si.wi, wo, Spectrum(eta_), M);
            return true;
        }
        Geometry g;
        if (!half_vector(si.wi, wo, g)) return false;
        if (g.reflect)
            fresnel_reflection_mueller(g.m, si.wi, wo, Spectrum(eta_), Spectrum(0.0f), M);
        else
            fresnel_transmission_mueller(g.m, si.wi, wo, Spectrum(eta_), M);
        return true;
    }

private:
    struct Geometry {
        bool reflect;
        float eta_p;  // n of the wo medium / n of the wi medium
        Vec3 m;       // half vector, m.z > 0
        float wi_m, wo_m;
    };

    // eval() and pdf(), either or both: one half vector, roughness lookup, D, G1(wi) and Fresnel.
    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, bool with_value, bool with_pdf) const {
        BSDFEvalPdf result;
        Geometry g;
        if (eta_ == 1.0f || !half_vector(si.wi, wo, g)) return result;
        bool has_r = ctx.allows(GlossyReflection), has_t = ctx.allows(GlossyTransmission);
        if (g.reflect ? !has_r : !has_t) return result;
        MicrofacetDistribution distribution = roughness_.at(si);
        float D = distribution.D(g.m);
        float G1_wi = distribution.G1(si.wi, g.m);
        float F = fresnel_dielectric(g.wi_m, eta_).F;
        float cos_i = std::abs(Frame::cos_theta(si.wi));
        float denom = g.wi_m + g.eta_p * g.wo_m;
        if (with_pdf) {
            // G1 is even in its direction: G1(wi_up) = G1(wi).
            Vec3 wi_up = Frame::cos_theta(si.wi) > 0.0f ? si.wi : -si.wi;
            float pdf_m = distribution.pdf(wi_up, g.m, D, G1_wi);
            float lobe = (has_r && has_t) ? (g.reflect ? F : 1.0f - F) : 1.0f;
            // Jacobian of the refraction half vector: eta'^2 |wo.m| / (wi.m + eta' wo.m)^2.
            result.pdf = g.reflect ? pdf_m * lobe / (4.0f * std::abs(g.wo_m))
                                   : pdf_m * lobe * g.eta_p * g.eta_p * std::abs(g.wo_m) / (denom * denom);
        }
        if (!with_value || D == 0.0f) return result;
        float G = G1_wi * distribution.G1(wo, g.m);
        if (g.reflect) {
            result.value = reflectance_->eval(si) * (F * D * G / (4.0f * cos_i));
            return result;
        }
        float value = (1.0f - F) * D * G * std::abs(g.wi_m * g.wo_m) / (cos_i * denom * denom);
        if (ctx.mode == TransportMode::Importance) value *= g.eta_p * g.eta_p;
        result.value = transmittance_->eval(si) * value;
        return result;
    }

    // The generalised half vector of (wi, wo) and the side checks of Walter et al.
    bool half_vector(const Vec3& wi, const Vec3& wo, Geometry& g) const {
        float cos_i = wi.z, cos_o = wo.z;
        if (cos_i == 0.0f || cos_o == 0.0f) return false;
        g.reflect = cos_i * cos_o > 0.0f;
        g.eta_p = g.reflect ? 1.0f : (cos_i > 0.0f ? eta_ : 1.0f / eta_);
        Vec3 m = wi + wo * g.eta_p;
        float len2 = squared_length(m);
        if (!(len2 > 0.0f)) return false;
        m /= std::sqrt(len2);
        if (m.z < 0.0f) m = -m;
        g.m = m;
        g.wi_m = glm::dot(wi, m);
        g.wo_m = glm::dot(wo, m);
        // Both directions must lie on the same side of the microfacet as of the macro-surface.
        return g.wi_m * cos_i > 0.0f && g.wo_m * cos_o > 0.0f;
    }

    MicrofacetRoughness roughness_;
    float eta_;
    Ref<Texture> reflectance_, transmittance_;
};

CANDELA_REGISTER_SPECTRAL(RoughDielectricBSDF, ObjectKind::BSDF, "roughdielectric");

}  // namespace candela
