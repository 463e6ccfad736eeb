// principled: the Disney principled BSDF (Burley 2012, 2015) in Mitsuba 3's parameterisation:
// a diffuse base with retro-reflection, fake subsurface and sheen, a GGX specular lobe that
// reflects and (with spec_trans) refracts, a metallic blend and a clearcoat. One-sided in
// reflection; the transmission lobe sees both sides.
//
// Parameters (Mitsuba 3; every one but eta, specular and the sampling rates a float or texture,
// scalar parameters looked up as scalars):
//   base_color        rgb or texture   colour of the diffuse, metallic and transmission lobes (0.5)
//   roughness         float            GGX alpha = roughness^2 of the main specular lobes (0.5)
//   anisotropic       float            stretches alpha along the tangent by 1 / sqrt(1 - 0.9 a) (0)
//   metallic          float            blend toward a Schlick metal of colour base_color (0)
//   spec_trans        float            share of the dielectric base that refracts (0)
//   eta               float            interior / exterior index, or instead
//   specular          float            0.08 specular = ((eta - 1) / (eta + 1))^2 (default 0.5)
//   spec_tint         float            tints the dielectric reflection toward base_color (0)
//   sheen, sheen_tint float            grazing sheen lobe and its tint (0, 0)
//   flatness          float            diffuse -> fake subsurface blend (0)
//   clearcoat         float            weight of the GTR1 clearcoat lobe (0)
//   clearcoat_gloss   float            clearcoat alpha = lerp(0.1, 0.001, gloss) (0)
//   main_specular_sampling_rate, clearcoat_sampling_rate, diffuse_reflectance_sampling_rate
//                     float            relative rates of the sampled lobes (1, 1, 1; Mitsuba's
//                                      documentation says 0 for the clearcoat, its code uses 1)
//
// With brdf = (1 - metallic)(1 - spec_trans), bsdf = (1 - metallic) spec_trans, h the half vector
// (generalised for refraction, turned to +z) and F the exact dielectric Fresnel at wi . h:
//   specular reflection   F_p D G / (4 |cos wi|),  F_p = (1 - m)(1 - spec_tint) F + m Schlick(base)
//                         + (1 - m) spec_tint Schlick(tint R0(eta)); from inside F_p = bsdf F
//   transmission          sqrt(base) bsdf (1 - F) D G |wi.h wo.h| / (|cos wi| (wi.h + eta' wo.h)^2)
//   clearcoat             clearcoat / 4 Schlick(0.04) D_GTR1 G_GGX(0.25) |cos wo|  (Mitsuba's form)
//   diffuse               brdf base / pi burley_diffuse(...) |cos wo| + sheen (1 - m) F_d(cos_d)
//                         sheen_color |cos wo|
// (times cos wo, as eval returns). Sampling as Mitsuba: diffuse, clearcoat and the specular pair
// in proportion to brdf * rate, clearcoat / 4 * rate and rate; within the pair, a visible GGX
// normal m, then refraction with probability bsdf (1 - F(wi . m)). From inside only the pair,
// split by F. Values are float32; pdf() is the density sample() draws from.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/registry.h"
#include "core/warp.h"
#include "materials/fresnel.h"
#include "materials/local_mix.h"
#include "materials/microfacet.h"
#include "materials/principled_lobes.h"

namespace candela {

class PrincipledBSDF final : public BSDF {
public:
    explicit PrincipledBSDF(const Properties& props) : common_(props), has_spec_trans_(common_.has_spec_trans) {
        metallic_ = props.get_texture("metallic", Spectrum(0.0f));
        has_clearcoat_ = principled_lobe_present(props, "clearcoat");
        clearcoat_ = props.get_texture("clearcoat", Spectrum(0.0f));
        clearcoat_gloss_ = props.get_texture("clearcoat_gloss", Spectrum(0.0f));
        specular_rate_ = props.get_float("main_specular_sampling_rate", 1.0f);
        clearcoat_rate_ = props.get_float("clearcoat_sampling_rate", 1.0f);
        diffuse_rate_ = props.get_float("diffuse_reflectance_sampling_rate", 1.0f);
        if (specular_rate_ < 0.0f || clearcoat_rate_ < 0.0f || diffuse_rate_ < 0.0f) props.fail("sampling rates must not be negative");
        // Mitsuba: eta or specular, and neither may make the interface vanish when it refracts.
        if (props.has("eta") && props.has("specular")) props.fail("eta", "give either eta or specular, not both");
        if (props.has("eta")) {
            eta_ = props.get_float("eta");
            if (!(eta_ > 0.0f)) props.fail("eta", "eta must be positive");
            if (has_spec_trans_ && eta_ == 1.0f) eta_ = 1.001f;
        } else {
            float specular = props.get_float("specular", 0.5f);
            if (!(specular >= 0.0f && 0.08f * specular < 1.0f)) props.fail("specular", "specular must lie in [0, 12.5)");
            if (has_spec_trans_ && specular == 0.0f) specular = 1e-3f;
            eta_ = 2.0f / (1.0f - std::sqrt(0.08f * specular)) - 1.0f;
        }
        flags_ = DiffuseReflection | GlossyReflection | (has_spec_trans_ ? GlossyTransmission : 0u);
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override {
        BSDFSample bs;
        float cos_i = Frame::cos_theta(si.wi);
        if (cos_i == 0.0f) return bs;
        Params p = params(si);
        Lobes lobes = lobe_choice(ctx, p, cos_i > 0.0f);
        if (!lobes.valid()) return bs;
        Vec3 wi_up = cos_i > 0.0f ? si.wi : -si.wi;
        if (u_lobe < lobes.diffuse) {
            bs.wo = warp::square_to_cosine_hemisphere(u);
            bs.lobe = DiffuseReflection;
        } else if (u_lobe < lobes.diffuse + lobes.clearcoat) {
            Vec3 m = GTR1{clearcoat_alpha(p)}.sample(u);
            bs.wo = reflect(si.wi, m);
            bs.lobe = GlossyReflection;
            if (!facet_sides_agree(m, si.wi, bs.wo, true)) return BSDFSample();
        } else {
            float u_pair = (u_lobe - lobes.diffuse - lobes.clearcoat) / lobes.specular;
            float pdf_m;
            Vec3 m = specular_distribution(p).sample(wi_up, u, pdf_m);
            if (!(pdf_m > 0.0f)) return bs;
            DielectricFresnel fr = fresnel_dielectric(glm::dot(si.wi, m), eta_);
            bool refract_ = u_pair < 1.0f - reflect_probability(lobes, p, cos_i > 0.0f, fr.F);
            bs.wo = refract_ ? refract(si.wi, m, fr.cos_theta_t, fr.eta_ti) : reflect(si.wi, m);
            bs.lobe = refract_ ? GlossyTransmission : GlossyReflection;
            if (refract_) bs.eta = fr.eta_it;
            if (!facet_sides_agree(m, si.wi, bs.wo, !refract_)) return BSDFSample();
        }
        bool same_side = bs.wo.z * cos_i > 0.0f;
        if (same_side != ((bs.lobe & Reflection) != 0)) return BSDFSample();
        return weighted_by_pdf(ctx, si, bs);
    }

    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        float cos_i = Frame::cos_theta(si.wi), cos_o = Frame::cos_theta(wo);
        if (cos_i == 0.0f || cos_o == 0.0f) return Spectrum(0.0f);
        Params p = params(si);
        bool front = cos_i > 0.0f, reflection = cos_i * cos_o > 0.0f;
        float brdf = (1.0f - p.metallic) * (1.0f - p.spec_trans), bsdf = (1.0f - p.metallic) * p.spec_trans;
        float eta_path = front ? eta_ : 1.0f / eta_;
        Vec3 h = half_vector(si.wi, wo, reflection, eta_path);
        float F = fresnel_dielectric(glm::dot(si.wi, h), eta_).F;
        bool sides = facet_sides_agree(h, si.wi, wo, reflection);
        MicrofacetDistribution dist = specular_distribution(p);
        Spectrum value(0.0f);
        if (reflection && sides && F > 0.0f && ctx.allows(GlossyReflection)) {
            Spectrum Fp = front ? principled_fresnel(p, F, glm::dot(si.wi, h)) : Spectrum(bsdf * F);
            value += Fp * (dist.D(h) * dist.G(si.wi, wo, h) / (4.0f * std::abs(cos_i)));
        }
        if (!reflection && sides && has_spec_trans_ && bsdf > 0.0f && F < 1.0f && ctx.allows(GlossyTransmission)) {
            float wi_h = glm::dot(si.wi, h), wo_h = glm::dot(wo, h), denom = wi_h + eta_path * wo_h;
            float t = (1.0f - F) * dist.D(h) * dist.G(si.wi, wo, h) * std::abs(wi_h * wo_h) / (std::abs(cos_i) * denom * denom);
            if (ctx.mode == TransportMode::Importance) t *= eta_path * eta_path;
            value += glm::sqrt(p.base) * (bsdf * t);
        }
        if (reflection && sides && front && has_clearcoat_ && p.clearcoat > 0.0f && ctx.allows(GlossyReflection)) {
            float Fcc = schlick_fresnel(Spectrum(0.04f), glm::dot(si.wi, h), eta_).x;
            float G = smith_ggx1(si.wi, h, 0.25f) * smith_ggx1(wo, h, 0.25f);
            value += Spectrum(0.25f * p.clearcoat * Fcc * GTR1{clearcoat_alpha(p)}.D(h) * G * std::abs(cos_o));
        }
        if (reflection && front && brdf > 0.0f && ctx.allows(DiffuseReflection)) {
            float cos_d = glm::dot(h, wo);
            value += p.base * (brdf * InvPi * burley_diffuse(cos_i, cos_o, cos_d, p.roughness, p.flatness) * std::abs(cos_o));
            if (p.sheen > 0.0f && p.metallic < 1.0f)
                value += sheen_color(p.base, p.base_luminance, p.sheen_tint) *
                         (p.sheen * (1.0f - p.metallic) * schlick_weight(std::abs(cos_d)) * std::abs(cos_o));
        }
        return value;
    }

    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        float cos_i = Frame::cos_theta(si.wi), cos_o = Frame::cos_theta(wo);
        if (cos_i == 0.0f || cos_o == 0.0f) return 0.0f;
        Params p = params(si);
        bool front = cos_i > 0.0f, reflection = cos_i * cos_o > 0.0f;
        Lobes lobes = lobe_choice(ctx, p, front);
        if (!lobes.valid()) return 0.0f;
        float eta_path = front ? eta_ : 1.0f / eta_;
        Vec3 h = half_vector(si.wi, wo, reflection, eta_path);
        float wi_h = glm::dot(si.wi, h), wo_h = glm::dot(wo, h);
        bool sides = facet_sides_agree(h, si.wi, wo, reflection);
        float result = 0.0f;
        if (reflection) {
            result += lobes.diffuse * warp::square_to_cosine_hemisphere_pdf(wo);  // front only
            if (sides) {
                float dwh_dwo = 1.0f / (4.0f * std::abs(wo_h));
                float F = fresnel_dielectric(wi_h, eta_).F;
                Vec3 wi_up = front ? si.wi : -si.wi;
                result += lobes.specular * reflect_probability(lobes, p, front, F) * specular_distribution(p).pdf(wi_up, h) * dwh_dwo;
                if (lobes.clearcoat > 0.0f) result += lobes.clearcoat * GTR1{clearcoat_alpha(p)}.pdf(h) * dwh_dwo;
            }
        } else if (sides) {
            float denom = wi_h + eta_path * wo_h;
            float dwh_dwo = eta_path * eta_path * std::abs(wo_h) / (denom * denom);
            float F = fresnel_dielectric(wi_h, eta_).F;
            Vec3 wi_up = front ? si.wi : -si.wi;
            result += lobes.specular * (1.0f - reflect_probability(lobes, p, front, F)) * specular_distribution(p).pdf(wi_up, h) * dwh_dwo;
        }
        return std::isfinite(result) ? result : 0.0f;
    }

    // As Mitsuba's diffuse-reflectance view: the base colour.
    Spectrum albedo(const SurfaceInteraction& si) const override { return common_.base_color->eval(si); }

    // Local model: kd = base_color (1 - metallic)(1 - spec_trans); a highlight and environment
    // reflection with F0 = (1 - metallic) R0(eta) + metallic base_color, shininess 2 / alpha^2 - 2
    // for alpha = roughness^2; refraction with weight (1 - metallic) spec_trans (1 - R0) sqrt(base)
    // (means of textured parameters).
    LocalShading local_shading() const override {
        LocalShading s;
        float m = luminance(metallic_->mean()), st = luminance(common_.spec_trans->mean()), r = luminance(common_.roughness->mean());
        float alpha = std::max(0.001f, r * r), r0 = schlick_r0(eta_);
        Spectrum base = common_.base_color->mean();
        s.diffuse = scaled_texture(common_.base_color, (1.0f - m) * (1.0f - st));
        s.specular = (1.0f - m) * Spectrum(r0) + m * base;
        s.shininess = phong_exponent(alpha);
        s.mirror = s.specular;
        s.roughness = alpha;
        if (has_spec_trans_) {
            s.transmission = glm::sqrt(base) * ((1.0f - m) * st * (1.0f - r0));
            s.eta = eta_;
            s.two_sided = true;
        }
        return s;
    }
    std::string to_string() const override { return "principled"; }

private:
    struct Params : PrincipledCommon::Values {
        float metallic, clearcoat, clearcoat_gloss;
    };
    // Probabilities of the diffuse lobe, the clearcoat and the specular pair; they sum to one.
    struct Lobes {
        float diffuse = 0.0f, clearcoat = 0.0f, specular = 0.0f;
        bool reflect = true, refract = true;  // which of the pair the context allows
        bool valid() const { return diffuse + clearcoat + specular > 0.0f; }
    };

    Params params(const SurfaceInteraction& si) const {
        Params p;
        common_.eval(si, p);
        p.metallic = metallic_->eval_1(si);
        p.clearcoat = has_clearcoat_ ? clearcoat_->eval_1(si) : 0.0f;
        p.clearcoat_gloss = clearcoat_gloss_->eval_1(si);
        return p;
    }

    Lobes lobe_choice(const BSDFContext& ctx, const Params& p, bool front) const {
        Lobes l;
        l.reflect = ctx.allows(GlossyReflection);
        l.refract = has_spec_trans_ && ctx.allows(GlossyTransmission);
        float bsdf = (1.0f - p.metallic) * p.spec_trans;
        if (!front) {
            // From inside only the specular pair, and only when the base refracts at all.
            l.specular = (bsdf > 0.0f && (l.reflect || l.refract)) ? 1.0f : 0.0f;
            return l;
        }
        if (ctx.allows(DiffuseReflection)) l.diffuse = (1.0f - p.metallic) * (1.0f - p.spec_trans) * diffuse_rate_;
        if (has_clearcoat_ && l.reflect) l.clearcoat = 0.25f * p.clearcoat * clearcoat_rate_;
        if (l.reflect || l.refract) l.specular = specular_rate_;
        float total = l.diffuse + l.clearcoat + l.specular;
        if (total > 0.0f) {
            l.diffuse /= total;
            l.clearcoat /= total;
            l.specular /= total;
        }
        return l;
    }

    // Within the specular pair: reflection with 1 - bsdf (1 - F) outside (F inside), unless the
    // context allows only one of the two.
    float reflect_probability(const Lobes& l, const Params& p, bool front, float F) const {
        if (!l.refract) return 1.0f;
        if (!l.reflect) return 0.0f;
        return front ? 1.0f - (1.0f - p.metallic) * p.spec_trans * (1.0f - F) : F;
    }

    static Vec3 half_vector(const Vec3& wi, const Vec3& wo, bool reflection, float eta_path) {
        Vec3 h = glm::normalize(wi + wo * (reflection ? 1.0f : eta_path));
        return h.z < 0.0f ? -h : h;
    }

    MicrofacetDistribution specular_distribution(const Params& p) const {
        float au, av;
        principled_alphas(p.roughness, p.anisotropic, au, av);
        return MicrofacetDistribution(MicrofacetType::GGX, au, av, true);
    }
    static float clearcoat_alpha(const Params& p) { return lerp(p.clearcoat_gloss, 0.1f, 0.001f); }

    // F_p of the front side: the dielectric Fresnel blended with Schlick metal and tint.
    Spectrum principled_fresnel(const Params& p, float F, float cos_ih) const {
        float eta_it = cos_ih >= 0.0f ? eta_ : 1.0f / eta_;
        Spectrum metal = p.metallic * schlick_fresnel(p.base, cos_ih, eta_);
        Spectrum tinted =
            (1.0f - p.metallic) * p.spec_tint * schlick_fresnel(tint_color(p.base, p.base_luminance) * schlick_r0(eta_it), cos_ih, eta_);
        return Spectrum((1.0f - p.metallic) * (1.0f - p.spec_tint) * F) + metal + tinted;
    }

    PrincipledCommon common_;
    bool has_spec_trans_;
    Ref<Texture> metallic_, clearcoat_, clearcoat_gloss_;
    bool has_clearcoat_ = false;
    float eta_ = 1.5f, specular_rate_ = 1.0f, clearcoat_rate_ = 1.0f, diffuse_rate_ = 1.0f;
};

CANDELA_REGISTER_SPECTRAL(PrincipledBSDF, ObjectKind::BSDF, "principled");

}  // namespace candela
