#pragma once
// Fresnel equations and Snell's law, the one place every BSDF gets them from. Directions are in
// the local shading frame (normal +z). eta is the relative index of refraction n_inside /
// n_outside, "inside" being the -z side.

#include "core/mueller.h"
#include "core/spectrum.h"

namespace candela {

struct DielectricFresnel {
    float F = 1.0f;            // unpolarised reflectance (1 under total internal reflection)
    float cos_theta_t = 0.0f;  // cosine of the refracted direction, signed: opposite side to wi
    float eta_it = 1.0f;       // n_transmitted / n_incident
    float eta_ti = 1.0f;       // n_incident / n_transmitted
};

// Exact Fresnel reflectance of a smooth dielectric interface, averaged over s and p
// polarisation. cos_theta_i > 0 means the incident direction is outside (+z side).
DielectricFresnel fresnel_dielectric(float cos_theta_i, float eta);
// The s- and p-polarised reflectances separately (for tests against Brewster's angle).
void fresnel_dielectric_polarized(float cos_theta_i, float eta, float& r_s, float& r_p);
// Unpolarised reflectance of a conductor with complex index eta + i k, per channel (exact form,
// e.g. Born & Wolf; cos_theta_i >= 0).
Spectrum fresnel_conductor(float cos_theta_i, const Spectrum& eta, const Spectrum& k);
// Hemispherical average of the dielectric Fresnel reflectance, 2 int F(mu) mu dmu, by the
// polynomial fits of Egan & Hilgeman (eta < 1) and d'Eon & Irving (eta >= 1), as Mitsuba uses.
float fresnel_diffuse_reflectance(float eta);

// The polarized variant (core/mueller.h): the Mueller matrices, per wavelength and in
// BSDF::eval_mueller's bases, of reflection and refraction at a facet with normal m (local; +z for
// a smooth surface) for light that arrives along -wo and leaves along wi: Mitsuba's
// specular_reflection / specular_transmission at the incidence cosine wo . m, turned from the
// facet's plane of incidence to the implicit bases. eta: relative index (inside over outside),
// k its imaginary part (0 for dielectrics).
void fresnel_reflection_mueller(const Vec3& m, const Vec3& wi, const Vec3& wo, const Spectrum& eta, const Spectrum& k, MuellerSpectrum& M);
void fresnel_transmission_mueller(const Vec3& m, const Vec3& wi, const Vec3& wo, const Spectrum& eta, MuellerSpectrum& M);

// The diffuse base under a smooth coating, polarized (Mitsuba's pplastic): refraction into the
// coating from wo, a depolarising base, refraction out toward wi; in eval_mueller's bases, with
// (0, 0) element (1 - F(cos wo)) (1 - F(cos wi)). eta: the coating's relative index.
Mueller coated_diffuse_mueller(const Vec3& wi, const Vec3& wo, float eta);

// How a delta BSDF splits between reflection (probability R) and transmission: with both lobes
// allowed, pick by R (the weight then needs no Fresnel factor); with one, take it surely and
// weight it by R or 1 - R.
struct FresnelChoice {
    bool reflect = true;
    float pdf = 0.0f;  // 0: nothing can be sampled
    float weight_factor = 1.0f;
};
inline FresnelChoice choose_fresnel_lobe(bool allow_reflection, bool allow_transmission, float R, float u) {
    FresnelChoice c;
    if (!allow_reflection && !allow_transmission) return c;
    c.reflect = allow_reflection && (!allow_transmission || u < R);
    bool both = allow_reflection && allow_transmission;
    c.pdf = both ? (c.reflect ? R : 1.0f - R) : 1.0f;
    c.weight_factor = both ? 1.0f : (c.reflect ? R : 1.0f - R);
    return c;
}

// Mirror reflection about the normal (+z) and about a microfacet normal m.
inline Vec3 reflect(const Vec3& wi) { return Vec3(-wi.x, -wi.y, wi.z); }
inline Vec3 reflect(const Vec3& wi, const Vec3& m) { return 2.0f * glm::dot(wi, m) * m - wi; }
// Refraction by Snell's law about the normal, given fresnel_dielectric's cos_theta_t, eta_ti.
inline Vec3 refract(const Vec3& wi, float cos_theta_t, float eta_ti) { return Vec3(-eta_ti * wi.x, -eta_ti * wi.y, cos_theta_t); }
// Refraction about a microfacet normal m (m on the same side as wi).
inline Vec3 refract(const Vec3& wi, const Vec3& m, float cos_theta_t, float eta_ti) {
    return m * (glm::dot(wi, m) * eta_ti + cos_theta_t) - wi * eta_ti;
}

}  // namespace candela
