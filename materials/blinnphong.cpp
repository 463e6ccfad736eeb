// blinnphong: the energy-normalised Blinn-Phong BRDF (half-vector lobe). Not in Mitsuba 3.
//
// Parameters:
//   kd         rgb or texture   diffuse weight (default 0.5)
//   ks         rgb or texture   specular weight (default 0.2); kd + ks <= 1 per channel
//   exponent   float            Blinn-Phong exponent n (default 30)
//
//   f = kd / pi + ks (n + 2) / (8 pi) cos^n(theta_h) / max(cos wi, cos wo)
// i.e. the normalised half-vector distribution (n + 2) / (2 pi) cos^n(theta_h) with the
// microfacet Jacobian 1 / (4 cos) and the cheapest visibility term that keeps the albedo at most
// ks (Neumann et al. 1999 use max(cos wi, cos wo) for this). The half vector is sampled with
// density (n + 1) / (2 pi) cos^n(theta_h).

#include "core/registry.h"
#include "materials/fresnel.h"
#include "materials/phong_lobe.h"

namespace candela {

class BlinnPhongBSDF final : public PhongFamilyBSDF {
public:
    explicit BlinnPhongBSDF(const Properties& props) : PhongFamilyBSDF(props) {}
    std::string to_string() const override { return "blinnphong"; }

protected:
    float lobe(const Vec3& wi, const Vec3& wo) const override {
        Vec3 h = glm::normalize(wi + wo);
        if (h.z <= 0.0f) return 0.0f;
        return (exponent_ + 2.0f) / (8.0f * Pi) * std::pow(h.z, exponent_) / std::max(wi.z, wo.z);
    }
    Vec3 sample_lobe(const Vec3& wi, const Vec2& u) const override {
        float cos_h = std::pow(u.x, 1.0f / (exponent_ + 1.0f)), sin_h = safe_sqrt(1.0f - cos_h * cos_h);
        float phi = TwoPi * u.y;
        Vec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
        return reflect(wi, h);
    }
    float lobe_pdf(const Vec3& wi, const Vec3& wo) const override {
        Vec3 h = glm::normalize(wi + wo);
        float wo_h = glm::dot(wo, h);
        if (h.z <= 0.0f || wo_h <= 0.0f) return 0.0f;
        return (exponent_ + 1.0f) * InvTwoPi * std::pow(h.z, exponent_) / (4.0f * wo_h);
    }
};

CANDELA_REGISTER_SPECTRAL(BlinnPhongBSDF, ObjectKind::BSDF, "blinnphong");

}  // namespace candela
