#include "materials/microfacet.h"

#include "core/frame.h"
#include "core/warp.h"

namespace candela {

float erf_inv(float x) {
    x = std::clamp(x, -0.99999994f, 0.99999994f);
    // Giles, "Approximating the erfinv function" (GPU Computing Gems Jade, 2011), single precision:
    // relative error below 3e-7 on (-1, 1) against a double-precision inverse (measured), so no
    // refinement is needed.
    float w = -std::log((1.0f - x) * (1.0f + x)), p;
    if (w < 5.0f) {
        w -= 2.5f;
        p = 2.81022636e-08f;
        p = 3.43273939e-07f + p * w;
        p = -3.5233877e-06f + p * w;
        p = -4.39150654e-06f + p * w;
        p = 0.00021858087f + p * w;
        p = -0.00125372503f + p * w;
        p = -0.00417768164f + p * w;
        p = 0.246640727f + p * w;
        p = 1.50140941f + p * w;
    } else {
        w = std::sqrt(w) - 3.0f;
        p = -0.000200214257f;
        p = 0.000100950558f + p * w;
        p = 0.00134934322f + p * w;
        p = -0.00367342844f + p * w;
        p = 0.00573950773f + p * w;
        p = -0.0076224613f + p * w;
        p = 0.00943887047f + p * w;
        p = 1.00167406f + p * w;
        p = 2.83297682f + p * w;
    }
    return p * x;
}

namespace {
constexpr float InvSqrtPi = 0.564189583547756287f;

// Beckmann's Lambda from a = 1 / (alpha tan theta), erf(a) and exp(-a^2):
// (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)).
float beckmann_lambda(float a, float erf_a, float exp_a2) { return 0.5f * (erf_a - 1.0f) + exp_a2 / (2.0f * a * std::sqrt(Pi)); }

// Slopes of the Beckmann normals (alpha = 1) visible from a direction in the x-z plane at
// tan(theta_i) = tan_i, given erf(cot theta_i) and exp(-cot^2 theta_i) (which Lambda needs too).
// Slopes are N(0, 1/2) per axis and visibility weights x by (cot theta_i - x) on x < cot theta_i
// (Heitz & d'Eon 2014), so y is erf^-1(2 u_y - 1) and x inverts the CDF
//   F(x) = (1 + erf(x) + tan_i exp(-x^2) / sqrt(pi)) / (1 + erf(cot) + tan_i exp(-cot^2) / sqrt(pi)).
// As Jakob 2014 ("An Improved Visible Normal Sampling Routine for the Beckmann Distribution"),
// solve F = u_x for b = erf(x), where F is smooth (dF/db = (1 - x tan_i) / norm), from his fitted
// initial guess, keeping a bracket for bisection; here with Halley's steps (d2F/db2 =
// -tan_i sqrt(pi) exp(x^2) / (2 norm)) until |F - u_x| < 1e-6, in float. What it samples is F
// within 1.2e-6 (tests/materials/test_fresnel.cpp measures it against a double inversion).
Vec2 beckmann_visible_slope(float tan_i, float erf_cot, float exp_cot2, const Vec2& u) {
    const float ux = std::clamp(u.x, 1e-6f, 1.0f - 1e-6f), uy = std::clamp(u.y, 1e-6f, 1.0f - 1e-6f);
    const float theta = std::atan(tan_i);
    const float fit = 1.0f + theta * (-0.876f + theta * (0.4265f - 0.0594f * theta));
    const float inv_norm = 1.0f / (1.0f + erf_cot + tan_i * exp_cot2 * InvSqrtPi);
    float lo = -1.0f, hi = erf_cot;
    float b = hi - (1.0f + hi) * std::pow(1.0f - ux, fit), x = 0.0f;
    for (int i = 0;; ++i) {
        if (!(b >= lo && b <= hi)) b = 0.5f * (lo + hi);  // also catches NaN
        x = erf_inv(b);
        const float e = std::exp(-x * x);
        const float f = inv_norm * (1.0f + b + tan_i * e * InvSqrtPi) - ux;
        if (std::abs(f) < 1e-6f || i == 5) break;
        if (f > 0.0f)
            hi = b;
        else
            lo = b;
        const float d1 = inv_norm * (1.0f - x * tan_i), d2 = -inv_norm * tan_i * (0.5f / InvSqrtPi) / e;
        b -= 2.0f * f * d1 / (2.0f * d1 * d1 - f * d2);
    }
    return Vec2(x, erf_inv(2.0f * uy - 1.0f));
}
}  // namespace

MicrofacetDistribution::MicrofacetDistribution(MicrofacetType type, float au, float av, bool sample_visible)
    : type_(type), alpha_u_(std::max(au, 1e-4f)), alpha_v_(std::max(av, 1e-4f)), sample_visible_(sample_visible) {}

namespace {
MicrofacetType read_type(const Properties& props) {
    std::string name = props.get_string("distribution", "beckmann");
    if (name == "beckmann") return MicrofacetType::Beckmann;
    if (name == "ggx") return MicrofacetType::GGX;
    props.fail("distribution", "distribution must be beckmann or ggx, not \"" + name + "\"");
}

// Mitsuba's rule: alpha, or both alpha_u and alpha_v, never both forms.
bool anisotropic_roughness(const Properties& props) {
    if (!props.has("alpha_u") && !props.has("alpha_v")) return false;
    if (props.has("alpha")) props.fail("alpha", "give either alpha or alpha_u and alpha_v");
    if (!props.has("alpha_u") || !props.has("alpha_v"))
        props.fail(props.has("alpha_u") ? "alpha_u" : "alpha_v", "give both alpha_u and alpha_v");
    return true;
}
}  // namespace

MicrofacetDistribution MicrofacetDistribution::from_properties(const Properties& props, bool allow_anisotropic) {
    MicrofacetType type = read_type(props);
    float au, av;
    if (anisotropic_roughness(props)) {
        if (!allow_anisotropic) props.fail("alpha_u", props.plugin_type() + " is isotropic: use alpha");
        au = props.get_float("alpha_u");
        av = props.get_float("alpha_v");
    } else {
        au = av = props.get_float("alpha", 0.1f);
    }
    if (!(au >= 0.0f && av >= 0.0f)) props.fail("alpha", "roughness alpha must not be negative");
    return MicrofacetDistribution(type, au, av, props.get_bool("sample_visible", true));
}

MicrofacetRoughness MicrofacetRoughness::from_properties(const Properties& props) {
    MicrofacetRoughness r;
    r.type_ = read_type(props);
    if (anisotropic_roughness(props)) {
        r.alpha_u_ = props.get_texture("alpha_u");
        r.alpha_v_ = props.get_texture("alpha_v");
    } else {
        r.alpha_u_ = r.alpha_v_ = props.get_texture("alpha", Spectrum(0.1f));
    }
    for (const char* name : {"alpha", "alpha_u", "alpha_v"}) {
        const Ref<Texture>& t = std::string(name) == "alpha_v" ? r.alpha_v_ : r.alpha_u_;
        if (props.has(name) && t->is_constant() && !(t->eval_1(Vec2(0.0f)) >= 0.0f))
            props.fail(name, "roughness " + std::string(name) + " must not be negative");
    }
    r.sample_visible_ = props.get_bool("sample_visible", true);
    if (r.alpha_u_->is_constant() && r.alpha_v_->is_constant())
        r.constant_ = MicrofacetDistribution(r.type_, r.alpha_u_->eval_1(Vec2(0.0f)), r.alpha_v_->eval_1(Vec2(0.0f)), r.sample_visible_);
    return r;
}

MicrofacetDistribution MicrofacetRoughness::at(const SurfaceInteraction& si) const {
    if (constant_) return *constant_;
    float au = alpha_u_->eval_1(si);
    float av = alpha_v_ == alpha_u_ ? au : alpha_v_->eval_1(si);
    return MicrofacetDistribution(type_, au, av, sample_visible_);
}

float MicrofacetRoughness::mean_alpha() const { return 0.5f * (luminance(alpha_u_->mean()) + luminance(alpha_v_->mean())); }

float MicrofacetDistribution::D(const Vec3& m) const {
    float cos_theta = m.z;
    if (cos_theta <= 0.0f) return 0.0f;
    float cos2 = cos_theta * cos_theta;
    float xu = m.x / alpha_u_, yv = m.y / alpha_v_;
    float result;
    if (type_ == MicrofacetType::Beckmann) {
        result = std::exp(-(xu * xu + yv * yv) / cos2) / (Pi * alpha_u_ * alpha_v_ * cos2 * cos2);
    } else {
        float d = xu * xu + yv * yv + cos2;
        result = 1.0f / (Pi * alpha_u_ * alpha_v_ * d * d);
    }
    return result * cos_theta > 1e-20f ? result : 0.0f;
}

float MicrofacetDistribution::lambda(const Vec3& v) const {
    // Projected roughness along v: alpha^2 tan^2(theta) = ((au vx)^2 + (av vy)^2) / vz^2.
    float a2_tan2 = (sqr(alpha_u_ * v.x) + sqr(alpha_v_ * v.y)) / (v.z * v.z);
    if (!(a2_tan2 > 0.0f)) return 0.0f;
    if (!std::isfinite(a2_tan2)) return Infinity;
    if (type_ == MicrofacetType::GGX) return 0.5f * (-1.0f + std::sqrt(1.0f + a2_tan2));
    // Beckmann, exact: Lambda = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)), a = 1 / (alpha tan).
    float a = 1.0f / std::sqrt(a2_tan2);
    return beckmann_lambda(a, std::erf(a), std::exp(-a * a));
}

float MicrofacetDistribution::G1(const Vec3& v, const Vec3& m) const {
    // A facet is never seen from behind, nor from below the macro-surface on its side.
    if (glm::dot(v, m) * v.z <= 0.0f) return 0.0f;
    float l = lambda(v);
    return std::isinf(l) ? 0.0f : 1.0f / (1.0f + l);
}

Vec2 MicrofacetDistribution::sample_visible_slope(float cos_theta_i, const Vec2& u) const {
    // GGX: Heitz 2018 ("Sampling the GGX distribution of visible normals"), written for a view
    // direction in the x-z plane: sample the projected hemisphere, then read off slopes.
    float sin_theta_i = safe_sqrt(1.0f - cos_theta_i * cos_theta_i);
    Vec2 p = warp::square_to_uniform_disk_concentric(u);
    float s = 0.5f * (1.0f + cos_theta_i);
    p.y = lerp(s, safe_sqrt(1.0f - p.x * p.x), p.y);
    float z = safe_sqrt(1.0f - p.x * p.x - p.y * p.y);
    // Basis around wi = (sin, 0, cos): T1 = (0, 1, 0), T2 = wi x T1 = (-cos, 0, sin); the
    // visible normal is p.x T1 + p.y T2 + z wi.
    float nx = -p.y * cos_theta_i + z * sin_theta_i;
    float ny = p.x;
    float nz = p.y * sin_theta_i + z * cos_theta_i;
    nz = std::max(nz, 1e-7f);
    return Vec2(-nx / nz, -ny / nz);
}

Vec3 MicrofacetDistribution::sample_visible_normal(const Vec3& wi, const Vec2& u) const {
    // Stretch to the alpha = 1 configuration, sample slopes there, rotate back and unstretch.
    Vec3 w = glm::normalize(Vec3(alpha_u_ * wi.x, alpha_v_ * wi.y, wi.z));
    return normal_from_slope(w, sample_visible_slope(w.z, u));
}

Vec3 MicrofacetDistribution::normal_from_slope(const Vec3& w, const Vec2& slope) const {
    float sin_theta = Frame::sin_theta(w);
    float cos_phi = sin_theta > 0.0f ? std::clamp(w.x / sin_theta, -1.0f, 1.0f) : 1.0f;
    float sin_phi = sin_theta > 0.0f ? std::clamp(w.y / sin_theta, -1.0f, 1.0f) : 0.0f;
    Vec2 rotated(cos_phi * slope.x - sin_phi * slope.y, sin_phi * slope.x + cos_phi * slope.y);
    rotated.x *= alpha_u_;
    rotated.y *= alpha_v_;
    return glm::normalize(Vec3(-rotated.x, -rotated.y, 1.0f));
}

Vec3 MicrofacetDistribution::sample_all_normals(const Vec2& u) const {
    // pdf D(m) cos(theta_m): the azimuth from the anisotropic ellipse, then theta by inversion.
    float phi = TwoPi * u.y;
    float alpha2 = alpha_u_ * alpha_v_;
    if (is_anisotropic()) {
        phi = std::atan2(alpha_v_ * std::sin(phi), alpha_u_ * std::cos(phi));
        float c = std::cos(phi), s = std::sin(phi);
        alpha2 = 1.0f / (c * c / (alpha_u_ * alpha_u_) + s * s / (alpha_v_ * alpha_v_));
    }
    float ux = std::min(u.x, 1.0f - 1e-7f);
    float tan2 = type_ == MicrofacetType::Beckmann ? -alpha2 * std::log(1.0f - ux) : alpha2 * ux / (1.0f - ux);
    float cos_theta = 1.0f / std::sqrt(1.0f + tan2), sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
    return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}

Vec3 MicrofacetDistribution::sample(const Vec3& wi, const Vec2& u, float& pdf_out) const {
    if (!sample_visible_ || type_ == MicrofacetType::GGX) {
        Vec3 m = sample_visible_ ? sample_visible_normal(wi, u) : sample_all_normals(u);
        pdf_out = pdf(wi, m);
        return m;
    }
    // Beckmann's visible normals: erf(a) and exp(-a^2) at a = cot of the stretched wi serve both
    // the slope sampling and Lambda(wi) in the pdf (the arithmetic of lambda() and G1()).
    float a2_tan2 = (sqr(alpha_u_ * wi.x) + sqr(alpha_v_ * wi.y)) / (wi.z * wi.z);
    if (!(wi.z > 0.0f) || !std::isfinite(a2_tan2)) {
        pdf_out = 0.0f;
        return Vec3(0.0f, 0.0f, 1.0f);
    }
    float tan_i = 0.0f, a = Infinity, erf_a = 1.0f, exp_a2 = 0.0f, lambda_i = 0.0f;
    if (a2_tan2 > 0.0f) {
        tan_i = std::sqrt(a2_tan2);
        a = 1.0f / std::sqrt(a2_tan2);
        erf_a = std::erf(a);
        exp_a2 = std::exp(-a * a);
        lambda_i = beckmann_lambda(a, erf_a, exp_a2);
    }
    Vec3 w = glm::normalize(Vec3(alpha_u_ * wi.x, alpha_v_ * wi.y, wi.z));
    Vec3 m = normal_from_slope(w, beckmann_visible_slope(tan_i, erf_a, exp_a2, u));
    float G1_wi = glm::dot(wi, m) * wi.z <= 0.0f || std::isinf(lambda_i) ? 0.0f : 1.0f / (1.0f + lambda_i);
    pdf_out = pdf(wi, m, D(m), G1_wi);
    return m;
}

float MicrofacetDistribution::pdf(const Vec3& wi, const Vec3& m) const {
    if (!sample_visible_) return D(m) * m.z;
    if (wi.z <= 0.0f) return 0.0f;
    return pdf(wi, m, D(m), G1(wi, m));
}

float MicrofacetDistribution::pdf(const Vec3& wi, const Vec3& m, float D_m, float G1_wi) const {
    if (!sample_visible_) return D_m * m.z;
    if (wi.z <= 0.0f) return 0.0f;
    return D_m * G1_wi * std::max(0.0f, glm::dot(wi, m)) / wi.z;
}

}  // namespace candela
