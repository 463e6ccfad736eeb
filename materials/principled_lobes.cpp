#include "materials/principled_lobes.h"

namespace candela {

bool principled_lobe_present(const Properties& props, const std::string& name) {
    if (!props.has(name)) return false;
    Properties::Type type;
    const Properties::Value& value = props.get_raw(name, &type);
    if (type == Properties::Type::Float) return std::get<double>(value) != 0.0;
    if (type == Properties::Type::Integer) return std::get<int64_t>(value) != 0;
    return true;
}

PrincipledCommon::PrincipledCommon(const Properties& props) {
    base_color = props.get_reflectance("base_color", Spectrum(0.5f));
    roughness = props.get_texture("roughness", Spectrum(0.5f));
    anisotropic = props.get_texture("anisotropic", Spectrum(0.0f));
    has_spec_trans = principled_lobe_present(props, "spec_trans");
    spec_trans = props.get_texture("spec_trans", Spectrum(0.0f));
    spec_tint = props.get_texture("spec_tint", Spectrum(0.0f));
    sheen = props.get_texture("sheen", Spectrum(0.0f));
    sheen_tint = props.get_texture("sheen_tint", Spectrum(0.0f));
    flatness = props.get_texture("flatness", Spectrum(0.0f));
}

void PrincipledCommon::eval(const SurfaceInteraction& si, Values& v) const {
    v.base = base_color->eval(si);
    v.base_luminance = luminance(si.wavelengths ? base_color->eval_rgb(si) : v.base);
    v.roughness = roughness->eval_1(si);
    v.anisotropic = anisotropic->eval_1(si);
    v.spec_trans = has_spec_trans ? spec_trans->eval_1(si) : 0.0f;
    v.spec_tint = spec_tint->eval_1(si);
    v.sheen = sheen->eval_1(si);
    v.sheen_tint = sheen_tint->eval_1(si);
    v.flatness = flatness->eval_1(si);
}

Spectrum schlick_fresnel(const Spectrum& r0, float cos_theta_i, float eta) {
    bool outside = cos_theta_i >= 0.0f;
    float eta_it = outside ? eta : 1.0f / eta, eta_ti = 1.0f / eta_it;
    float cos_t = safe_sqrt(1.0f - (1.0f - cos_theta_i * cos_theta_i) * eta_ti * eta_ti);
    float w = schlick_weight(eta_it > 1.0f ? std::abs(cos_theta_i) : cos_t);
    return r0 + (Spectrum(1.0f) - r0) * w;
}

void principled_alphas(float roughness, float anisotropic, float& alpha_u, float& alpha_v) {
    float r2 = roughness * roughness;
    float aspect = std::sqrt(std::max(1.0f - 0.9f * anisotropic, 0.0f));
    alpha_u = std::max(0.001f, r2 / aspect);
    alpha_v = std::max(0.001f, r2 * aspect);
}

bool facet_sides_agree(const Vec3& m, const Vec3& wi, const Vec3& wo, bool reflection) {
    Vec3 mi = wi.z >= 0.0f ? m : -m;
    float wo_m = glm::dot(wo, mi);
    return glm::dot(wi, mi) > 0.0f && (reflection ? wo_m > 0.0f : wo_m < 0.0f);
}

float burley_diffuse(float cos_i, float cos_o, float cos_d, float roughness, float flatness) {
    float Fi = schlick_weight(std::abs(cos_i)), Fo = schlick_weight(std::abs(cos_o));
    float lambert = (1.0f - 0.5f * Fi) * (1.0f - 0.5f * Fo);
    float Rr = 2.0f * roughness * cos_d * cos_d;
    float retro = Rr * (Fo + Fi + Fo * Fi * (Rr - 1.0f));
    if (flatness == 0.0f) return lambert + retro;
    // Fake subsurface (Burley 2015 after Hanrahan-Krueger): F_ss90 = R_R / 2.
    float Fss = lerp(Fo, 1.0f, 0.5f * Rr) * lerp(Fi, 1.0f, 0.5f * Rr);
    float subsurface = 1.25f * (Fss * (1.0f / (std::abs(cos_o) + std::abs(cos_i)) - 0.5f) + 0.5f);
    return lerp(flatness, lambert + retro, subsurface);
}

Spectrum tint_color(const Spectrum& base, float base_luminance) { return base_luminance > 0.0f ? base / base_luminance : Spectrum(1.0f); }

Spectrum sheen_color(const Spectrum& base, float base_luminance, float sheen_tint) {
    return Spectrum(1.0f) + sheen_tint * (tint_color(base, base_luminance) - Spectrum(1.0f));
}

float GTR1::D(const Vec3& m) const {
    float a2 = alpha * alpha, c2 = m.z * m.z;
    float d = (a2 - 1.0f) / (Pi * std::log(a2) * (1.0f + (a2 - 1.0f) * c2));
    return d * m.z > 1e-20f ? d : 0.0f;
}

Vec3 GTR1::sample(const Vec2& u) const {
    // Inverting the CDF of D cos: cos^2 = (1 - alpha^(2 (1 - u))) / (1 - alpha^2).
    float a2 = alpha * alpha;
    float phi = TwoPi * u.x;
    float cos2 = (1.0f - std::pow(a2, 1.0f - u.y)) / (1.0f - a2);
    float cos_t = safe_sqrt(cos2), sin_t = safe_sqrt(1.0f - cos2);
    return Vec3(std::cos(phi) * sin_t, std::sin(phi) * sin_t, cos_t);
}

float smith_ggx1(const Vec3& v, const Vec3& m, float alpha) {
    if (glm::dot(v, m) * v.z <= 0.0f) return 0.0f;
    if (v.z == 1.0f) return 1.0f;
    float c2 = v.z * v.z, tan2 = (1.0f - c2) / c2;
    return 2.0f / (1.0f + std::sqrt(1.0f + alpha * alpha * tan2));
}

}  // namespace candela
