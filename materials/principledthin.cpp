// principledthin: the thin-surface principled BSDF (Burley 2015, section 5.3) in Mitsuba 3's
// parameterisation: a sheet with no inside (leaves, paper, fabric). Both sides alike: seen from
// the back, directions are mirrored through the sheet. Light that refracts leaves on the other
// side without bending.
//
// Parameters (Mitsuba 3; every one but the sampling rates a float or texture):
//   base_color, roughness, anisotropic, spec_tint, sheen, sheen_tint, flatness   as `principled`
//   spec_trans     float     blends the diffuse response (0) into the specular pair (1) (0)
//   eta            float     interior / exterior index of the sheet (1.5)
//   diff_trans     float     share of the diffuse energy transmitted, 0 to 2 (0)
//   specular_reflectance_sampling_rate, specular_transmittance_sampling_rate,
//   diffuse_reflectance_sampling_rate, diffuse_transmittance_sampling_rate   (1 each)
//
// With t = diff_trans / 2, wi turned to +z and wo with it, h = normalize(wi + mirror(wo)):
//   specular reflection     spec_trans F_t D G / (4 cos wi),  F_t = lerp(F, Schlick(tint R0), spec_tint)
//   specular transmission   spec_trans base (1 - F) D' G' / (4 cos wi), D' G' of roughness
//                           (0.65 eta - 0.35) roughness (Burley 2015, fig. 15), wo on the far side
//   diffuse reflection      (1 - spec_trans)(1 - t) [base / pi burley_diffuse + sheen F_d sheen_color]
//   diffuse transmission    (1 - spec_trans) t base / pi
// (times |cos wo|). Without spec_trans there is no specular lobe at all (Mitsuba). Lobes are
// sampled in proportion to spec_trans rate / 2 (each of the pair), (1 - spec_trans)(1 - t) rate
// and (1 - spec_trans) t rate.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/registry.h"
#include "core/warp.h"
#include "materials/fresnel.h"
#include "materials/local_mix.h"
#include "materials/microfacet.h"
#include "materials/principled_lobes.h"

#include <array>

namespace candela {

class PrincipledThinBSDF final : public BSDF {
public:
    explicit PrincipledThinBSDF(const Properties& props) : common_(props), has_spec_trans_(common_.has_spec_trans) {
        eta_ = props.get_texture("eta", Spectrum(1.5f));
        has_diff_trans_ = principled_lobe_present(props, "diff_trans");
        diff_trans_ = props.get_texture("diff_trans", Spectrum(0.0f));
        rates_[SpecularReflection] = props.get_float("specular_reflectance_sampling_rate", 1.0f);
        rates_[SpecularTransmission] = props.get_float("specular_transmittance_sampling_rate", 1.0f);
        rates_[DiffuseReflect] = props.get_float("diffuse_reflectance_sampling_rate", 1.0f);
        rates_[DiffuseTransmit] = props.get_float("diffuse_transmittance_sampling_rate", 1.0f);
        for (float r : rates_)
            if (r < 0.0f) props.fail("sampling rates must not be negative");
        flags_ = DiffuseReflection | DiffuseTransmission | (has_spec_trans_ ? GlossyReflection | GlossyTransmission : 0u);
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override {
        BSDFSample bs;
        float cos_i = Frame::cos_theta(si.wi);
        if (cos_i == 0.0f) return bs;
        Params p = params(si);
        std::array<float, 4> prob = lobe_probabilities(ctx, p);
        float sign = cos_i > 0.0f ? 1.0f : -1.0f;
        Vec3 wi = si.wi * sign;  // the sheet seen from its front
        int lobe = 0;
        while (lobe < 3 && !(u_lobe < prob[lobe])) u_lobe -= prob[lobe++];
        if (!(prob[lobe] > 0.0f)) return bs;
        Vec3 wo;
        if (lobe == SpecularReflection || lobe == SpecularTransmission) {
            bool transmit = lobe == SpecularTransmission;
            float pdf_m;
            Vec3 m = specular_distribution(p, transmit).sample(wi, u, pdf_m);
            if (!(pdf_m > 0.0f)) return bs;
            wo = reflect(wi, m);
            if (wo.z <= 0.0f) return bs;
            if (transmit) wo.z = -wo.z;  // through the sheet, unbent
            if (!facet_sides_agree(m, wi, wo, !transmit)) return bs;
            bs.lobe = transmit ? GlossyTransmission : GlossyReflection;
        } else {
            wo = warp::square_to_cosine_hemisphere(u);
            if (lobe == DiffuseTransmit) wo.z = -wo.z;
            bs.lobe = lobe == DiffuseTransmit ? DiffuseTransmission : DiffuseReflection;
        }
        bs.wo = wo * sign;
        return weighted_by_pdf(ctx, si, bs);
    }

    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo_in) const override {
        float cos_i = Frame::cos_theta(si.wi);
        if (cos_i == 0.0f || wo_in.z == 0.0f) return Spectrum(0.0f);
        Params p = params(si);
        float sign = cos_i > 0.0f ? 1.0f : -1.0f;
        Vec3 wi = si.wi * sign, wo = wo_in * sign;
        bool reflection = wo.z > 0.0f;
        Vec3 h = glm::normalize(wi + Vec3(wo.x, wo.y, std::abs(wo.z)));
        float ci = wi.z, co = std::abs(wo.z);
        Spectrum value(0.0f);
        if (has_spec_trans_ && p.spec_trans > 0.0f && facet_sides_agree(h, wi, wo, reflection)) {
            float F = fresnel_dielectric(glm::dot(wi, h), p.eta).F;
            MicrofacetDistribution dist = specular_distribution(p, !reflection);
            float DG = dist.D(h) * dist.G(wi, wo, h) / (4.0f * ci);
            if (reflection && ctx.allows(GlossyReflection)) {
                Spectrum tinted = schlick_fresnel(tint_color(p.base, p.base_luminance) * schlick_r0(p.eta), glm::dot(wi, h), p.eta);
                value += (Spectrum(F) + p.spec_tint * (tinted - Spectrum(F))) * (p.spec_trans * DG);
            }
            if (!reflection && ctx.allows(GlossyTransmission)) value += p.base * (p.spec_trans * (1.0f - F) * DG);
        }
        if (reflection && p.spec_trans < 1.0f && p.diff_trans < 1.0f && ctx.allows(DiffuseReflection)) {
            float cos_d = glm::dot(h, wo), scale = (1.0f - p.spec_trans) * (1.0f - p.diff_trans) * co;
            value += p.base * (scale * InvPi * burley_diffuse(ci, co, cos_d, p.roughness, p.flatness));
            if (p.sheen > 0.0f)
                value += sheen_color(p.base, p.base_luminance, p.sheen_tint) * (scale * p.sheen * schlick_weight(std::abs(cos_d)));
        }
        if (!reflection && has_diff_trans_ && p.spec_trans < 1.0f && p.diff_trans > 0.0f && ctx.allows(DiffuseTransmission))
            value += p.base * ((1.0f - p.spec_trans) * p.diff_trans * InvPi * co);
        return value;
    }

    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo_in) const override {
        float cos_i = Frame::cos_theta(si.wi);
        if (cos_i == 0.0f || wo_in.z == 0.0f) return 0.0f;
        Params p = params(si);
        std::array<float, 4> prob = lobe_probabilities(ctx, p);
        float sign = cos_i > 0.0f ? 1.0f : -1.0f;
        Vec3 wi = si.wi * sign, wo = wo_in * sign;
        bool reflection = wo.z > 0.0f;
        Vec3 wo_mirrored(wo.x, wo.y, std::abs(wo.z));
        float result = reflection ? prob[DiffuseReflect] * warp::square_to_cosine_hemisphere_pdf(wo)
                                  : prob[DiffuseTransmit] * warp::square_to_cosine_hemisphere_pdf(wo_mirrored);
        int specular = reflection ? SpecularReflection : SpecularTransmission;
        if (prob[specular] > 0.0f) {
            Vec3 h = glm::normalize(wi + wo_mirrored);
            if (facet_sides_agree(h, wi, wo, reflection))
                result += prob[specular] * specular_distribution(p, !reflection).pdf(wi, h) / (4.0f * std::abs(glm::dot(wo_mirrored, h)));
        }
        return std::isfinite(result) ? result : 0.0f;
    }

    // As Mitsuba's diffuse-reflectance view: the base colour.
    Spectrum albedo(const SurfaceInteraction& si) const override { return common_.base_color->eval(si); }

    // Local model: kd = base_color (1 - spec_trans)(1 - diff_trans / 2), lit from both sides; a
    // highlight and mirror with F0 = R0(eta) spec_trans, shininess 2 / alpha^2 - 2; the
    // environment seen straight through with weight spec_trans (1 - R0) base + diffuse
    // transmission (means of textured parameters).
    LocalShading local_shading() const override {
        LocalShading s;
        float st = luminance(common_.spec_trans->mean()), t = 0.5f * luminance(diff_trans_->mean()),
              r = luminance(common_.roughness->mean());
        float alpha = std::max(0.001f, r * r), r0 = schlick_r0(luminance(eta_->mean()));
        Spectrum base = common_.base_color->mean();
        s.diffuse = scaled_texture(common_.base_color, (1.0f - st) * (1.0f - t));
        s.specular = Spectrum(st * r0);
        s.shininess = phong_exponent(alpha);
        s.mirror = s.specular;
        s.roughness = alpha;
        s.transmission = base * (st * (1.0f - r0) + (1.0f - st) * t);
        s.two_sided = true;
        return s;
    }
    std::string to_string() const override { return "principledthin"; }

private:
    enum Lobe { SpecularReflection = 0, SpecularTransmission = 1, DiffuseReflect = 2, DiffuseTransmit = 3 };
    struct Params : PrincipledCommon::Values {
        float eta, diff_trans;
    };

    Params params(const SurfaceInteraction& si) const {
        Params p;
        common_.eval(si, p);
        p.eta = eta_->eval_1(si);
        p.diff_trans = has_diff_trans_ ? 0.5f * diff_trans_->eval_1(si) : 0.0f;  // 0..2 -> 0..1
        return p;
    }

    std::array<float, 4> lobe_probabilities(const BSDFContext& ctx, const Params& p) const {
        std::array<float, 4> prob{};
        if (has_spec_trans_) {
            if (ctx.allows(GlossyReflection)) prob[SpecularReflection] = 0.5f * p.spec_trans * rates_[SpecularReflection];
            if (ctx.allows(GlossyTransmission)) prob[SpecularTransmission] = 0.5f * p.spec_trans * rates_[SpecularTransmission];
        }
        if (ctx.allows(DiffuseReflection)) prob[DiffuseReflect] = (1.0f - p.spec_trans) * (1.0f - p.diff_trans) * rates_[DiffuseReflect];
        if (has_diff_trans_ && ctx.allows(DiffuseTransmission))
            prob[DiffuseTransmit] = (1.0f - p.spec_trans) * p.diff_trans * rates_[DiffuseTransmit];
        float total = prob[0] + prob[1] + prob[2] + prob[3];
        for (float& x : prob) x = total > 0.0f ? x / total : 0.0f;
        return prob;
    }

    // The specular pair's GGX: roughness scaled by 0.65 eta - 0.35 for transmission.
    MicrofacetDistribution specular_distribution(const Params& p, bool transmission) const {
        float roughness = transmission ? (0.65f * p.eta - 0.35f) * p.roughness : p.roughness;
        float au, av;
        principled_alphas(roughness, p.anisotropic, au, av);
        return MicrofacetDistribution(MicrofacetType::GGX, au, av, true);
    }

    PrincipledCommon common_;
    bool has_spec_trans_;
    Ref<Texture> eta_, diff_trans_;
    bool has_diff_trans_ = false;
    std::array<float, 4> rates_{};
};

CANDELA_REGISTER_SPECTRAL(PrincipledThinBSDF, ObjectKind::BSDF, "principledthin");

}  // namespace candela
