// roughplastic: a diffuse base under a rough dielectric coating (Mitsuba 3's model).
// One-sided, isotropic.
//
// Parameters (Mitsuba 3):
//   distribution, alpha, sample_visible   as `roughconductor`, but isotropic and alpha a float (as
//                                         in Mitsuba 3: the coating's tables depend on it)
//   int_ior, ext_ior, diffuse_reflectance, specular_reflectance, nonlinear   as `plastic`
//
//   specular:  F(wi . h) D(h) G(wi, wo) / (4 cos wi)
//   diffuse:   rho' T(cos wi) T(cos wo) cos(wo) / (pi eta^2),
//              rho' = rho / (1 - R_int) (or rho / (1 - rho R_int) when nonlinear)
// T(mu) is the total transmittance of the rough coating at incidence mu and R_int its
// hemispherically averaged internal reflectance. Both are tabulated once, as Mitsuba does: T at
// 64 cosines j/63 (interpolated linearly), R_int as 2 * mean_j(R(mu_j) mu_j) over the same 64
// cosines; the integrals over visible normals are evaluated with Gauss-Legendre quadrature.

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
#include "materials/quadrature.h"

#include <array>

namespace candela {

class RoughPlasticBSDF final : public CoatedBSDF {
public:
    explicit RoughPlasticBSDF(const Properties& props)
        : CoatedBSDF(props), distribution_(MicrofacetDistribution::from_properties(props, false)) {
        eta_ = read_relative_ior(props, "polypropylene");
        nonlinear_ = props.get_bool("nonlinear", false);
        build_tables();
        flags_ = GlossyReflection | DiffuseReflection;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override {
        BSDFSample bs;
        float cos_i = Frame::cos_theta(si.wi);
        if (cos_i <= 0.0f) return bs;
        if (!sample_rough_coating(distribution_, ctx, si.wi, specular_probability(ctx, cos_i), u_lobe, u, bs)) return BSDFSample();
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
        float T = transmittance(std::max(Frame::cos_theta(si.wi), 0.0f));
        return specular_->eval(si) * (1.0f - T) + diffuse_->eval(si) * T;
    }
    // Local model: kd = diffuse_reflectance, a highlight ks = F0 with shininess 2 / alpha^2 - 2,
    // and the environment reflected with F0, blurred by alpha.
    LocalShading local_shading() const override {
        LocalShading s;
        float F0 = fresnel_dielectric(1.0f, eta_).F;
        float alpha = distribution_.alpha_u();
        s.diffuse = diffuse_;
        s.specular = specular_->mean() * F0;
        s.shininess = phong_exponent(alpha);
        s.mirror = specular_->mean() * F0;
        s.roughness = alpha;
        return s;
    }
    std::string to_string() const override { return "roughplastic"; }

    float transmittance(float cos_theta) const {
        float x = std::clamp(cos_theta, 0.0f, 1.0f) * float(TableSize - 1);
        int i = std::min(int(x), TableSize - 2);
        float t = x - float(i);
        return transmittance_[i] * (1.0f - t) + transmittance_[i + 1] * t;
    }

private:
    static constexpr int TableSize = 64;

    // eval() and pdf(), either or both: one half vector, D(h) and G1(wi).
    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, bool with_value, bool with_pdf) const {
        BSDFEvalPdf result;
        float cos_i = Frame::cos_theta(si.wi), cos_o = Frame::cos_theta(wo);
        if (cos_i <= 0.0f || cos_o <= 0.0f) return result;
        const bool specular = ctx.allows(GlossyReflection);
        Vec3 h(0.0f);
        float D = 0.0f, G1_wi = 0.0f;
        if (specular) {
            h = glm::normalize(si.wi + wo);
            D = distribution_.D(h);
            G1_wi = distribution_.G1(si.wi, h);
        }
        if (with_value) {
            if (specular && D > 0.0f) {
                float F = fresnel_dielectric(glm::dot(si.wi, h), eta_).F;
                result.value += specular_->eval(si) * (F * D * (G1_wi * distribution_.G1(wo, h)) / (4.0f * cos_i));
            }
            if (ctx.allows(DiffuseReflection)) {
                const Spectrum rho_p = coated_base_albedo(diffuse_->eval(si), internal_reflectance_, nonlinear_);
                result.value += rho_p * (transmittance(cos_i) * transmittance(cos_o) * cos_o * InvPi / (eta_ * eta_));
            }
        }
        if (with_pdf) {
            // specular_probability is 0 unless `specular`.
            float p_spec = specular_probability(ctx, cos_i);
            if (p_spec > 0.0f) result.pdf += p_spec * distribution_.pdf(si.wi, h, D, G1_wi) / (4.0f * glm::dot(wo, h));
            if (p_spec < 1.0f) result.pdf += (1.0f - p_spec) * warp::square_to_cosine_hemisphere_pdf(wo);
        }
        return result;
    }

    float specular_probability(const BSDFContext& ctx, float cos_i) const {
        return specular_lobe_probability(ctx, GlossyReflection, DiffuseReflection, specular_weight_, 1.0f - transmittance(cos_i));
    }

    // Expected value over normals visible from wi of g(m): an integral over [0, 1]^2 through the
    // visible-normal sampling map, by n x n Gauss-Legendre quadrature.
    template <typename G>
    double over_visible_normals(const Vec3& wi, int n, G g) const {
        std::vector<double> x, w;
        gauss_legendre(n, x, w);
        double sum = 0.0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                float pdf_m;
                Vec3 m = visible_.sample(wi, Vec2(float(0.5 * (x[i] + 1.0)), float(0.5 * (x[j] + 1.0))), pdf_m);
                sum += 0.25 * w[i] * w[j] * g(m);
            }
        return sum;
    }

    void build_tables() {
        visible_ = MicrofacetDistribution(distribution_.type(), distribution_.alpha_u(), distribution_.alpha_v(), true);
        double r_sum = 0.0;
        for (int j = 0; j < TableSize; ++j) {
            float mu = std::max(1e-6f, float(j) / float(TableSize - 1));
            Vec3 wi(safe_sqrt(1.0f - mu * mu), 0.0f, mu);
            // Transmission into the coating: refract about m; unmasked fraction G1(wo).
            double T = over_visible_normals(wi, eta_ > 1.0f ? 32 : 128, [&](const Vec3& m) {
                DielectricFresnel fr = fresnel_dielectric(glm::dot(wi, m), eta_);
                if (fr.F >= 1.0f) return 0.0;
                Vec3 wo = refract(wi, m, fr.cos_theta_t, fr.eta_ti);
                if (wo.z * wi.z >= 0.0f) return 0.0;
                return double(visible_.G1(wo, m) * (1.0f - fr.F));
            });
            transmittance_[j] = float(T);
            // Reflection from inside the coating (relative index 1 / eta), for R_int.
            double R = over_visible_normals(wi, 128, [&](const Vec3& m) {
                Vec3 wo = reflect(wi, m);
                if (wo.z <= 0.0f) return 0.0;
                return double(visible_.G1(wo, m) * fresnel_dielectric(glm::dot(wi, m), 1.0f / eta_).F);
            });
            r_sum += R * mu;
        }
        internal_reflectance_ = float(2.0 * r_sum / TableSize);
    }

    MicrofacetDistribution distribution_, visible_{MicrofacetType::GGX, 0.1f, 0.1f, true};
    float eta_, internal_reflectance_ = 0.0f;
    bool nonlinear_;
    std::array<float, TableSize> transmittance_{};
};

CANDELA_REGISTER_SPECTRAL(RoughPlasticBSDF, ObjectKind::BSDF, "roughplastic");

}  // namespace candela
