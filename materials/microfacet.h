#pragma once
// Microfacet normal distributions (Beckmann and GGX, isotropic or anisotropic) with Smith's
// masking, and sampling of either the full distribution or the distribution of normals visible
// from the incident direction (Heitz & d'Eon 2014). Local frame: macro-normal +z.
//
//   D(m)        normal distribution; integrates to one as D(m) cos(theta_m) over the hemisphere
//   G1(v, m)    Smith masking, 2 / (1 + Lambda(v)) for the exact Beckmann and GGX Lambda
//   pdf(wi, m)  D(m) G1(wi, m) |wi . m| / cos(theta_i) when sampling visible normals,
//               D(m) cos(theta_m) otherwise

#include "core/properties.h"
#include "core/texture.h"

#include <optional>

namespace candela {

enum class MicrofacetType { Beckmann, GGX };

class MicrofacetDistribution {
public:
    MicrofacetDistribution(MicrofacetType type, float alpha_u, float alpha_v, bool sample_visible = true);
    // Reads distribution (beckmann | ggx, default beckmann), alpha or alpha_u and alpha_v
    // (default 0.1) and sample_visible (default true), Mitsuba's parameters. Like Mitsuba, a
    // roughness below 1e-4 (0 included) is raised to 1e-4: a smooth surface in all but name.
    static MicrofacetDistribution from_properties(const Properties& props, bool allow_anisotropic = true);

    float D(const Vec3& m) const;
    float lambda(const Vec3& v) const;
    float G1(const Vec3& v, const Vec3& m) const;
    float G(const Vec3& wi, const Vec3& wo, const Vec3& m) const { return G1(wi, m) * G1(wo, m); }

    // A microfacet normal for incident direction wi (wi.z > 0), and its density pdf(wi, m).
    Vec3 sample(const Vec3& wi, const Vec2& u, float& pdf) const;
    float pdf(const Vec3& wi, const Vec3& m) const;
    // pdf(wi, m) from D(m) and G1(wi, m) the caller has already computed (eval and pdf of a BSDF
    // share them); the same arithmetic as pdf(wi, m).
    float pdf(const Vec3& wi, const Vec3& m, float D_m, float G1_wi) const;

    MicrofacetType type() const { return type_; }
    float alpha_u() const { return alpha_u_; }
    float alpha_v() const { return alpha_v_; }
    bool sample_visible() const { return sample_visible_; }
    bool is_anisotropic() const { return alpha_u_ != alpha_v_; }

private:
    // GGX's slopes of visible normals for alpha = 1, for an incident direction at cos_theta_i in
    // the x-z plane (Beckmann's are sampled in sample(), which shares Lambda's terms with them).
    Vec2 sample_visible_slope(float cos_theta_i, const Vec2& u) const;
    Vec3 sample_visible_normal(const Vec3& wi, const Vec2& u) const;
    // The normal of alpha = 1 slopes sampled for the stretched incident direction w, rotated to
    // w's azimuth and unstretched.
    Vec3 normal_from_slope(const Vec3& w, const Vec2& slope) const;
    Vec3 sample_all_normals(const Vec2& u) const;

    MicrofacetType type_;
    float alpha_u_, alpha_v_;
    bool sample_visible_;
};

// Roughness as Mitsuba's rough BSDFs read it: distribution (beckmann | ggx, default beckmann),
// alpha or alpha_u and alpha_v (default 0.1), each a float or a texture (looked up as a scalar,
// eval_1), and sample_visible (default true). The distribution is built per shading point;
// constant roughness builds it once.
class MicrofacetRoughness {
public:
    static MicrofacetRoughness from_properties(const Properties& props);
    MicrofacetDistribution at(const SurfaceInteraction& si) const;
    // The mean of (alpha_u + alpha_v) / 2 over the textures (for the local model).
    float mean_alpha() const;

private:
    MicrofacetType type_ = MicrofacetType::Beckmann;
    bool sample_visible_ = true;
    Ref<Texture> alpha_u_, alpha_v_;
    std::optional<MicrofacetDistribution> constant_;
};

// The Phong exponent whose lobe matches a Beckmann distribution of roughness alpha, 2 / alpha^2 - 2
// (Walter et al. 2007), at least 1: the local model's highlight for a microfacet lobe.
inline float phong_exponent(float alpha) { return std::max(2.0f / (alpha * alpha) - 2.0f, 1.0f); }

// Inverse error function in float (Giles 2011's single-precision approximation; relative error
// below 3e-7).
float erf_inv(float x);

}  // namespace candela
