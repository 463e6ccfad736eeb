#include "materials/fresnel.h"

namespace candela {

DielectricFresnel fresnel_dielectric(float cos_theta_i, float eta) {
    DielectricFresnel r;
    bool outside = cos_theta_i >= 0.0f;
    r.eta_it = outside ? eta : 1.0f / eta;
    r.eta_ti = outside ? 1.0f / eta : eta;
    if (eta == 1.0f) {
        r.F = 0.0f;
        r.cos_theta_t = -cos_theta_i;
        return r;
    }
    // Snell: sin^2(theta_t) = (n_i / n_t)^2 sin^2(theta_i).
    float cos2_t = 1.0f - r.eta_ti * r.eta_ti * (1.0f - cos_theta_i * cos_theta_i);
    float ci = std::abs(cos_theta_i);
    if (cos2_t <= 0.0f) {  // total internal reflection
        r.F = 1.0f;
        r.cos_theta_t = 0.0f;
        return r;
    }
    float ct = std::sqrt(cos2_t);
    // Amplitude coefficients for s and p polarisation, in terms of eta_it = n_t / n_i.
    float a_s = (ci - r.eta_it * ct) / (ci + r.eta_it * ct);
    float a_p = (ct - r.eta_it * ci) / (ct + r.eta_it * ci);
    r.F = 0.5f * (a_s * a_s + a_p * a_p);
    if (ci == 0.0f) r.F = 1.0f;
    r.cos_theta_t = outside ? -ct : ct;
    return r;
}

void fresnel_dielectric_polarized(float cos_theta_i, float eta, float& r_s, float& r_p) {
    float eta_it = cos_theta_i >= 0.0f ? eta : 1.0f / eta;
    float eta_ti = 1.0f / eta_it;
    float cos2_t = 1.0f - eta_ti * eta_ti * (1.0f - cos_theta_i * cos_theta_i);
    if (cos2_t <= 0.0f) {
        r_s = r_p = 1.0f;
        return;
    }
    float ci = std::abs(cos_theta_i), ct = std::sqrt(cos2_t);
    float a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
    float a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
    r_s = a_s * a_s;
    r_p = a_p * a_p;
}

Spectrum fresnel_conductor(float cos_theta_i, const Spectrum& eta, const Spectrum& k) {
    float c = std::clamp(cos_theta_i, 0.0f, 1.0f);
    float c2 = c * c, s2 = 1.0f - c2, s4 = s2 * s2;
    Spectrum F;
    for (int i = 0; i < 3; ++i) {
        float e = eta[i], kk = k[i];
        float t1 = e * e - kk * kk - s2;
        float a2b2 = std::sqrt(std::max(t1 * t1 + 4.0f * e * e * kk * kk, 0.0f));
        float a = std::sqrt(std::max(0.5f * (a2b2 + t1), 0.0f));
        float rs = (a2b2 + c2 - 2.0f * a * c) / (a2b2 + c2 + 2.0f * a * c);
        float rp = rs * (a2b2 * c2 + s4 - 2.0f * a * c * s2) / (a2b2 * c2 + s4 + 2.0f * a * c * s2);
        float f = 0.5f * (rs + rp);
        F[i] = std::isfinite(f) ? f : 1.0f;
    }
    return F;
}

void fresnel_reflection_mueller(const Vec3& m, const Vec3& wi, const Vec3& wo, const Spectrum& eta, const Spectrum& k, MuellerSpectrum& M) {
    const float cos_i = glm::dot(wo, m);
    const BasisChange to_local = facet_to_local_bases(m, wi, wo);
    // One index at every wavelength (the usual case): one matrix.
    const bool uniform = eta.x == eta.y && eta.y == eta.z && k.x == k.y && k.y == k.z;
    for (int i = 0; i < 3; ++i)
        M.w[i] = uniform && i > 0 ? M.w[0] : to_local.apply(specular_reflection(cos_i, std::complex<float>(eta[i], k[i])));
}

void fresnel_transmission_mueller(const Vec3& m, const Vec3& wi, const Vec3& wo, const Spectrum& eta, MuellerSpectrum& M) {
    const float cos_i = glm::dot(wo, m);
    const BasisChange to_local = facet_to_local_bases(m, wi, wo);
    const bool uniform = eta.x == eta.y && eta.y == eta.z;
    for (int i = 0; i < 3; ++i) M.w[i] = uniform && i > 0 ? M.w[0] : to_local.apply(specular_transmission(cos_i, eta[i]));
}

Mueller coated_diffuse_mueller(const Vec3& wi, const Vec3& wo, float eta) {
    const Mueller in = specular_transmission(std::abs(Frame::cos_theta(wo)), eta);
    // Out through the coating from inside, along the direction that refracts to wi.
    const float cos_inside = std::abs(fresnel_dielectric(Frame::cos_theta(wi), eta).cos_theta_t);
    const Mueller out = specular_transmission(cos_inside, 1.0f / eta);
    // out diag(1, 0, 0, 0) in: the outer product of out's first column and in's first row.
    Mueller diffuse;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) diffuse(i, j) = out(i, 0) * in(0, j);
    return facet_to_local_bases(Vec3(0, 0, 1), wi, wo).apply(diffuse);
}

float fresnel_diffuse_reflectance(float eta) {
    if (eta < 1.0f) return -1.4399f * eta * eta + 0.7099f * eta + 0.6681f + 0.0636f / eta;
    float x = 1.0f / eta;
    return 0.919317f + x * (-3.4793f + x * (6.75335f + x * (-7.80989f + x * (4.98554f + x * -1.36881f))));
}

}  // namespace candela
