// hair: the hair fibre model of Chiang et al. 2016 ("A Practical and Controllable Hair and Fur
// Model for Production Path Tracing"), as Mitsuba 3's `hair`: the light paths R, TT, TRT and the
// sum of all longer ones through a dielectric cylinder with absorbing interior, each a product of
// a longitudinal lobe M_p (d'Eon et al. 2011), an attenuation A_p and an azimuthal lobe N_p (a
// trimmed logistic). A "near-field" model: one interaction is the whole walk through the fibre.
//
// Parameters (Mitsuba 3):
//   eumelanin, pheomelanin   float   pigment concentrations (defaults 1.3 and 0.2); sigma_a =
//                                    eumelanin (0.419, 0.697, 1.37) + pheomelanin (0.187, 0.4,
//                                    1.05) per unit fibre radius (d'Eon et al. 2011)
//   sigma_a          rgb or texture  absorption coefficient instead of the pigments (not both)
//   scale            float           factor on sigma_a (default 1)
//   int_ior, ext_ior float or name   indices inside and outside (defaults amber 1.55, air)
//   longitudinal_roughness, azimuthal_roughness
//                    float           beta_m and beta_n in [0, 1] (default 0.3 both)
//   scale_tilt       float           angle alpha of the cuticle scales, degrees (default 2)
//
// The frame (Mitsuba's curves give it): the shading frame's t axis (local y) runs along the
// fibre, its normal (local z) points out of the fibre at the hit, s (local x) goes around it.
// theta is the angle to the normal plane (sin theta = w.y), phi = atan2(w.z, w.x) the azimuth,
// and h = sin(gamma_i) the offset across the fibre, gamma_i the angle between the normal and wi
// in the normal plane.
//
//   f cos = sum_{p<3} M_p(theta_i', theta_o) A_p N_p(phi_o - phi_i) + M_3(theta_i, theta_o) A_3 / 2pi
// with theta_i' tilted by -2 alpha, alpha, 4 alpha for R, TT, TRT; v_0 = (0.726 b_m + 0.812 b_m^2
// + 3.7 b_m^20)^2, v_1 = v_0 / 4, v_2 = v_3 = 4 v_0; s = sqrt(pi / 8)(0.265 b_n + 1.194 b_n^2 +
// 5.372 b_n^22); A_0 = F, A_1 = (1 - F)^2 T, A_2 = A_1 T F, A_3 = A_2 T F / (1 - T F) with F the
// Fresnel reflectance at cos(theta_i) cos(gamma_i) and T = exp(-sigma_a 2 cos(gamma_t) /
// cos(theta_t)). Sampling picks p by the luminance of A_p, then samples M_p exactly and N_p by
// its logistic (p = 3: uniform azimuth). With sigma_a = 0 the fibre loses nothing: sum A_p = 1.
// Unlike Mitsuba's stored version, the remainder term p = 3 samples its longitudinal lobe about
// theta_i itself (Mitsuba leaves theta_i' at zero there, which its pdf does not describe).

#include "core/bsdf.h"
#include "core/registry.h"
#include "core/texture.h"
#include "materials/fresnel.h"
#include "materials/ior.h"

#include <array>

namespace candela {

namespace {

constexpr int PMax = 3;  // R, TT, TRT; index 3 is the sum of the rest

// log I_0(x), the modified Bessel function of the first kind: its power series summed until it
// converges for x <= 12, the asymptotic series e^x / sqrt(2 pi x) (1 + 1/(8x) + 9/(128x^2) +
// 225/(3072x^3) + 11025/(98304x^4)) beyond (Abramowitz & Stegun 9.7.1), both to about 1e-6. (A
// ten-term series and a one-term asymptotic correction, as pbrt-v3 and Mitsuba 3 use, err by up to
// 0.5% near x = 12, enough to fail a chi-square test of the sampling.)
double log_bessel_i0(double x) {
    if (x > 12.0) {
        double r = 1.0 / x;
        double series = 1.0 + r * (1.0 / 8.0 + r * (9.0 / 128.0 + r * (225.0 / 3072.0 + r * (11025.0 / 98304.0))));
        return x - 0.5 * std::log(2.0 * 3.14159265358979323846 * x) + std::log(series);
    }
    double sum = 1.0, term = 1.0, q = 0.25 * x * x;
    for (int k = 1; k < 64 && term > 1e-12 * sum; ++k) {
        term *= q / double(k * k);
        sum += term;
    }
    return std::log(sum);
}

// log(1 / (2 v sinh(1/v))) = log(k) - k - log(1 - e^(-2k)), k = 1/v: the normalisation of M_p.
double longitudinal_log_norm(float v) {
    double k = 1.0 / v;
    return std::log(k) - k - std::log1p(-std::exp(-2.0 * k));
}

// d'Eon et al.'s longitudinal lobe M_p = exp(-sin_i sin_o / v) I_0(cos_i cos_o / v) / (2 v sinh(1/v)),
// normalised over theta_o with measure cos(theta_o); in logarithms, since 1/v reaches 10^7.
float longitudinal(float sin_i, float cos_i, float sin_o, float cos_o, float v, double log_norm) {
    double a = double(cos_i) * cos_o / v, b = double(sin_i) * sin_o / v;
    return float(std::exp(log_bessel_i0(a) - b + log_norm));
}

float logistic(float x, float s) {
    x = std::abs(x);
    float e = std::exp(-x / s);
    return e / (s * sqr(1.0f + e));
}
float logistic_cdf(float x, float s) { return 1.0f / (1.0f + std::exp(-x / s)); }
// The logistic restricted to [-pi, pi].
float trimmed_logistic(float x, float s) { return logistic(x, s) / (logistic_cdf(Pi, s) - logistic_cdf(-Pi, s)); }
float sample_trimmed_logistic(float u, float s) {
    float k = logistic_cdf(Pi, s) - logistic_cdf(-Pi, s);
    float x = -s * std::log(1.0f / (u * k + logistic_cdf(-Pi, s)) - 1.0f);
    return std::clamp(x, -Pi, Pi);
}

}  // namespace

class HairBSDF final : public BSDF {
public:
    explicit HairBSDF(const Properties& props) {
        float beta_m = props.get_float("longitudinal_roughness", 0.3f), beta_n = props.get_float("azimuthal_roughness", 0.3f);
        if (!(beta_m >= 0.0f && beta_m <= 1.0f)) props.fail("longitudinal_roughness", "longitudinal_roughness must lie in [0, 1]");
        if (!(beta_n >= 0.0f && beta_n <= 1.0f)) props.fail("azimuthal_roughness", "azimuthal_roughness must lie in [0, 1]");
        float alpha = radians(props.get_float("scale_tilt", 2.0f));
        eta_ = read_ior(props, "int_ior", "amber") / read_ior(props, "ext_ior", "air");
        if (props.has("sigma_a") && (props.has("eumelanin") || props.has("pheomelanin")))
            props.fail("sigma_a", "give either sigma_a or the pigment concentrations, not both");
        float eumelanin = props.get_float("eumelanin", 1.3f), pheomelanin = props.get_float("pheomelanin", 0.2f);
        float scale = props.get_float("scale", 1.0f);
        if (props.has("sigma_a")) {
            sigma_a_ = props.get_texture("sigma_a");
            scale_ = scale;
        } else {
            Spectrum pigments = eumelanin * Spectrum(0.419f, 0.697f, 1.37f) + pheomelanin * Spectrum(0.187f, 0.4f, 1.05f);
            sigma_a_ = std::make_shared<ConstantTexture>(pigments);
        }
        // Tilts: sin and cos of alpha, 2 alpha, 4 alpha.
        sin_2k_alpha_[0] = std::sin(alpha);
        cos_2k_alpha_[0] = safe_sqrt(1.0f - sqr(sin_2k_alpha_[0]));
        for (int i = 1; i < 3; ++i) {
            sin_2k_alpha_[i] = 2.0f * cos_2k_alpha_[i - 1] * sin_2k_alpha_[i - 1];
            cos_2k_alpha_[i] = sqr(cos_2k_alpha_[i - 1]) - sqr(sin_2k_alpha_[i - 1]);
        }
        // (Roughness 0 would make both lobes deltas; the floors keep them finite.)
        v_[0] = std::max(sqr(0.726f * beta_m + 0.812f * sqr(beta_m) + 3.7f * std::pow(beta_m, 20.0f)), 1e-7f);
        v_[1] = 0.25f * v_[0];
        v_[2] = v_[3] = 4.0f * v_[0];
        for (int p = 0; p <= PMax; ++p) log_norm_[p] = longitudinal_log_norm(v_[p]);
        s_ = std::max(std::sqrt(Pi / 8.0f) * (0.265f * beta_n + 1.194f * sqr(beta_n) + 5.372f * std::pow(beta_n, 22.0f)), 1e-5f);
        flags_ = GlossyReflection | GlossyTransmission;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override {
        BSDFSample bs;
        Incidence in;
        if (!ctx.allows(Glossy) || !incidence(si, in)) return bs;
        std::array<float, PMax + 1> pmf = lobe_pmf(in.A);
        int p = 0;
        while (p < PMax && !(u_lobe < pmf[p])) u_lobe -= pmf[p++];
        if (!(pmf[p] > 0.0f)) return bs;
        float u_azimuth = std::clamp(u_lobe / pmf[p], 0.0f, 0.99999994f);

        // M_p about the (tilted) cone of theta_i, exactly (d'Eon et al. 2013).
        float sin_ip = in.sin_theta, cos_ip = in.cos_theta;
        if (p < PMax) tilt(p, sin_ip, cos_ip);
        float v = v_[p], u0 = std::max(u.x, 1e-5f);
        float cos_t = 1.0f + v * std::log(u0 + (1.0f - u0) * std::exp(-2.0f / v));
        float sin_t = safe_sqrt(1.0f - cos_t * cos_t);
        float sin_o = -cos_t * sin_ip + sin_t * std::cos(TwoPi * u.y) * cos_ip;
        float cos_o = safe_sqrt(1.0f - sin_o * sin_o);
        // N_p about the specular azimuth Phi(p), or uniform for the remainder.
        float dphi = p < PMax ? specular_azimuth(p, in) + sample_trimmed_logistic(u_azimuth, s_) : TwoPi * u_azimuth;
        float phi_o = in.phi + dphi;
        bs.wo = glm::normalize(Vec3(cos_o * std::cos(phi_o), sin_o, cos_o * std::sin(phi_o)));
        bs.lobe = bs.wo.z * si.wi.z > 0.0f ? GlossyReflection : GlossyTransmission;
        // As pdf() and eval() compute them, without finding the incidence again.
        std::array<float, PMax + 1> lobes = lobe_values(in, bs.wo);
        Spectrum value(0.0f);
        for (int q = 0; q <= PMax; ++q) {
            bs.pdf += pmf[q] * lobes[q];
            value += in.A[q] * lobes[q];
        }
        if (!(bs.pdf > 0.0f) || !std::isfinite(bs.pdf)) return BSDFSample();
        bs.weight = value / bs.pdf;
        if (!all_finite(bs.weight)) return BSDFSample();
        return bs;
    }

    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        Incidence in;
        if (!ctx.allows(Glossy) || !incidence(si, in)) return Spectrum(0.0f);
        std::array<float, PMax + 1> lobes = lobe_values(in, wo);
        Spectrum value(0.0f);
        for (int p = 0; p <= PMax; ++p) value += in.A[p] * lobes[p];
        return all_finite(value) ? value : Spectrum(0.0f);
    }

    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        Incidence in;
        if (!ctx.allows(Glossy) || !incidence(si, in)) return 0.0f;
        std::array<float, PMax + 1> pmf = lobe_pmf(in.A), lobes = lobe_values(in, wo);
        float result = 0.0f;
        for (int p = 0; p <= PMax; ++p) result += pmf[p] * lobes[p];
        return std::isfinite(result) ? result : 0.0f;
    }

    // The directional albedo exactly: M_p and N_p are normalised, so it is sum_p A_p.
    Spectrum albedo(const SurfaceInteraction& si) const override {
        Incidence in;
        if (!incidence(si, in)) return Spectrum(0.0f);
        return in.A[0] + in.A[1] + in.A[2] + in.A[3];
    }
    std::string to_string() const override { return "hair"; }

private:
    // What the lobes need of the incident direction.
    struct Incidence {
        float sin_theta, cos_theta, phi, gamma_i, gamma_t;
        std::array<Spectrum, PMax + 1> A;
    };

    bool incidence(const SurfaceInteraction& si, Incidence& in) const {
        const Vec3& wi = si.wi;
        in.sin_theta = std::clamp(wi.y, -1.0f, 1.0f);
        in.cos_theta = safe_sqrt(1.0f - in.sin_theta * in.sin_theta);
        if (in.cos_theta < 1e-6f) return false;  // along the fibre: no cross-section to hit
        in.phi = std::atan2(wi.z, wi.x);
        float proj = std::sqrt(wi.x * wi.x + wi.z * wi.z);
        float gamma = safe_acos(wi.z / proj);
        in.gamma_i = wi.x < 0.0f ? gamma : -gamma;
        float h = std::sin(in.gamma_i);
        // Refraction in the normal plane with the modified index eta' (Bravais).
        float eta_p = safe_sqrt(eta_ * eta_ - in.sin_theta * in.sin_theta) / in.cos_theta;
        float sin_gamma_t = h / eta_p, cos_gamma_t = safe_sqrt(1.0f - sin_gamma_t * sin_gamma_t);
        in.gamma_t = safe_asin(sin_gamma_t);
        float sin_theta_t = in.sin_theta / eta_, cos_theta_t = safe_sqrt(1.0f - sin_theta_t * sin_theta_t);
        Spectrum T = glm::exp(-sigma_a(si) * (2.0f * cos_gamma_t / cos_theta_t));
        float F = fresnel_dielectric(in.cos_theta * safe_sqrt(1.0f - h * h), eta_).F;
        in.A[0] = Spectrum(F);
        in.A[1] = sqr(1.0f - F) * T;
        for (int p = 2; p < PMax; ++p) in.A[p] = in.A[p - 1] * T * F;
        // The remainder's geometric series, sum over k >= PMax of A[PMax - 1] (T F)^(k - PMax + 1). With
        // T F = 1 (a lossless fibre at grazing incidence, F = 1) A[PMax - 1] holds (1 - F)^2 = 0 and so
        // does the sum.
        const Spectrum remainder = in.A[PMax - 1] * F * T, denominator = Spectrum(1.0f) - T * F;
        for (int c = 0; c < 3; ++c) in.A[PMax][c] = denominator[c] > 0.0f ? remainder[c] / denominator[c] : 0.0f;
        return true;
    }

    // M_p N_p of each lobe for wo (the remainder: M_3 / 2pi), without A_p.
    std::array<float, PMax + 1> lobe_values(const Incidence& in, const Vec3& wo) const {
        float sin_o = std::clamp(wo.y, -1.0f, 1.0f), cos_o = safe_sqrt(1.0f - sin_o * sin_o);
        float dphi = std::atan2(wo.z, wo.x) - in.phi;
        std::array<float, PMax + 1> values{};
        for (int p = 0; p < PMax; ++p) {
            float sin_ip = in.sin_theta, cos_ip = in.cos_theta;
            tilt(p, sin_ip, cos_ip);
            values[p] = longitudinal(sin_ip, cos_ip, sin_o, cos_o, v_[p], log_norm_[p]) *
                        trimmed_logistic(wrap_angle(dphi - specular_azimuth(p, in)), s_);
        }
        values[PMax] = longitudinal(in.sin_theta, in.cos_theta, sin_o, cos_o, v_[PMax], log_norm_[PMax]) * InvTwoPi;
        return values;
    }

    // Probabilities of the lobes: the luminance of A_p, normalised.
    static std::array<float, PMax + 1> lobe_pmf(const std::array<Spectrum, PMax + 1>& A) {
        std::array<float, PMax + 1> pmf;
        float total = 0.0f;
        for (int p = 0; p <= PMax; ++p) total += pmf[p] = luminance(A[p]);
        for (float& x : pmf) x = total > 0.0f ? x / total : 0.0f;
        return pmf;
    }

    // The cuticle tilt of lobe p applied to theta_i: -2 alpha (R), alpha (TT), 4 alpha (TRT).
    void tilt(int p, float& sin_t, float& cos_t) const {
        float s = sin_t, c = cos_t;
        if (p == 0) {
            sin_t = s * cos_2k_alpha_[1] - c * sin_2k_alpha_[1];
            cos_t = c * cos_2k_alpha_[1] + s * sin_2k_alpha_[1];
        } else if (p == 1) {
            sin_t = s * cos_2k_alpha_[0] + c * sin_2k_alpha_[0];
            cos_t = c * cos_2k_alpha_[0] - s * sin_2k_alpha_[0];
        } else {
            sin_t = s * cos_2k_alpha_[2] + c * sin_2k_alpha_[2];
            cos_t = c * cos_2k_alpha_[2] - s * sin_2k_alpha_[2];
        }
        cos_t = std::abs(cos_t);
    }

    // The azimuth change of the perfectly specular path p: 2 p gamma_t - 2 gamma_i + p pi.
    static float specular_azimuth(int p, const Incidence& in) { return 2.0f * p * in.gamma_t - 2.0f * in.gamma_i + p * Pi; }
    static float wrap_angle(float phi) {
        phi = std::fmod(phi, TwoPi);
        if (phi < -Pi) phi += TwoPi;
        if (phi > Pi) phi -= TwoPi;
        return phi;
    }

    // An absorption coefficient: unbounded in the spectral variant (the pigments' RGB too, as pbrt-v4 upsamples them).
    Spectrum sigma_a(const SurfaceInteraction& si) const { return scale_ * sigma_a_->eval_as(si, SpectrumRole::Unbounded); }

    float eta_ = 1.55f, s_ = 0.0f, scale_ = 1.0f;
    std::array<float, PMax + 1> v_{};
    std::array<double, PMax + 1> log_norm_{};
    float sin_2k_alpha_[3], cos_2k_alpha_[3];
    Ref<Texture> sigma_a_;
};

CANDELA_REGISTER_SPECTRAL(HairBSDF, ObjectKind::BSDF, "hair");

}  // namespace candela
