// phong: the energy-normalised (modified) Phong BRDF of Lafortune & Willems 1994, the lecture's
// reflection model made physically plausible. Not in Mitsuba 3.
//
// Parameters:
//   kd         rgb or texture   diffuse weight (default 0.5)
//   ks         rgb or texture   specular weight (default 0.2); kd + ks <= 1 per channel
//   exponent   float            Phong exponent n (default 30)
//
//   f = kd / pi + ks (n + 2) / (2 pi) max(0, cos alpha)^n,  alpha = angle(wo, mirror(wi))
// The (n + 2) / (2 pi) factor makes the lobe's albedo ks at normal incidence and less elsewhere.
// The glossy lobe is sampled around the mirror direction with density (n + 1) / (2 pi) cos^n.

#include "core/registry.h"
#include "materials/fresnel.h"
#include "materials/phong_lobe.h"

namespace candela {

class PhongBSDF final : public PhongFamilyBSDF {
public:
    explicit PhongBSDF(const Properties& props) : PhongFamilyBSDF(props) {}
    std::string to_string() const override { return "phong"; }

protected:
    float lobe(const Vec3& wi, const Vec3& wo) const override {
        float c = glm::dot(wo, reflect(wi));
        return c > 0.0f ? (exponent_ + 2.0f) * InvTwoPi * std::pow(c, exponent_) : 0.0f;
    }
    Vec3 sample_lobe(const Vec3& wi, const Vec2& u) const override {
        float cos_a = std::pow(u.x, 1.0f / (exponent_ + 1.0f)), sin_a = safe_sqrt(1.0f - cos_a * cos_a);
        float phi = TwoPi * u.y;
        return Frame(reflect(wi)).to_world(Vec3(sin_a * std::cos(phi), sin_a * std::sin(phi), cos_a));
    }
    float lobe_pdf(const Vec3& wi, const Vec3& wo) const override {
        float c = glm::dot(wo, reflect(wi));
        return c > 0.0f ? (exponent_ + 1.0f) * InvTwoPi * std::pow(c, exponent_) : 0.0f;
    }
};

CANDELA_REGISTER_SPECTRAL(PhongBSDF, ObjectKind::BSDF, "phong");

}  // namespace candela
