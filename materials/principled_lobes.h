#pragma once
// What `principled` and `principledthin` share: Burley's lobes (Burley 2012, "Physically Based
// Shading at Disney"; Burley 2015, "Extending the Disney BRDF to a BSDF with Integrated Subsurface
// Scattering") in Mitsuba 3's parameterisation. Local frame: normal +z.

#include "core/properties.h"
#include "core/texture.h"

namespace candela {

// Mitsuba's test for an optional lobe: the parameter is given, and is not the float 0.
bool principled_lobe_present(const Properties& props, const std::string& name);

// The parameters both BSDFs have (Mitsuba's names and defaults: base_color 0.5, roughness 0.5, the
// rest 0), and their values at a point; scalar ones are looked up as scalars (eval_1).
struct PrincipledCommon {
    struct Values {
        Spectrum base{0.5f};
        // The luminance of base_color's colour: what tints divide by (in the spectral variant,
        // where `base` holds values at wavelengths, the colour's own luminance).
        float base_luminance = luminance(Spectrum(0.5f));
        float roughness = 0.5f, anisotropic = 0.0f, spec_trans = 0.0f, spec_tint = 0.0f, sheen = 0.0f, sheen_tint = 0.0f, flatness = 0.0f;
    };
    explicit PrincipledCommon(const Properties& props);
    // The values at a surface point; spec_trans is 0 unless the parameter was given (and not
    // the float 0).
    void eval(const SurfaceInteraction& si, Values& v) const;

    Ref<Texture> base_color, roughness, anisotropic, spec_trans, spec_tint, sheen, sheen_tint, flatness;
    bool has_spec_trans = false;
};

// Schlick's weight (1 - cos)^5, cos clamped to [0, 1].
inline float schlick_weight(float cos_theta) {
    float m = std::clamp(1.0f - cos_theta, 0.0f, 1.0f);
    return (m * m) * (m * m) * m;
}
// Schlick's reflectance at normal incidence of a relative index eta.
inline float schlick_r0(float eta) { return sqr((eta - 1.0f) / (eta + 1.0f)); }
// Schlick's Fresnel approximation R0 + (1 - R0) (1 - cos)^5 about a facet at cos_theta_i (signed:
// negative from inside, relative index eta = inside / outside). Seen from the denser side the
// cosine of the refracted direction takes the place of cos_theta_i (0 under total reflection).
Spectrum schlick_fresnel(const Spectrum& r0, float cos_theta_i, float eta);

// GGX roughness of the main specular lobes: alpha = roughness^2 along both axes, or with
// anisotropy stretched by aspect = sqrt(1 - 0.9 anisotropic) (Burley 2012), at least 0.001.
void principled_alphas(float roughness, float anisotropic, float& alpha_u, float& alpha_v);

// The directions lie on the sides of the facet m (turned to wi's side of the macro-surface) that
// reflection (wo with wi) or refraction (wo opposite) requires.
bool facet_sides_agree(const Vec3& m, const Vec3& wi, const Vec3& wo, bool reflection);

// Burley's diffuse with retro-reflection, blended toward the Hanrahan-Krueger-like fake
// subsurface term by `flatness` (Burley 2015, eq. 4-5), without albedo or 1/pi:
//   f_d = (1 - F_i / 2)(1 - F_o / 2) + R_R (F_i + F_o + F_i F_o (R_R - 1)),  R_R = 2 r cos_d^2,
// F = schlick_weight(|cos|), cos_d = wo . h (the 2012 form (1 + (F_D90 - 1) F_i)(1 + (F_D90 - 1) F_o)
// expanded, F_D90 = 1/2 + R_R).
float burley_diffuse(float cos_i, float cos_o, float cos_d, float roughness, float flatness);
// The sheen colour: white, tinted toward base / luminance(base) by sheen_tint.
Spectrum sheen_color(const Spectrum& base, float base_luminance, float sheen_tint);
// base / luminance(base) (white for a black base): the hue that tints specular and sheen.
Spectrum tint_color(const Spectrum& base, float base_luminance);

// The clearcoat lobe's normal distribution, Berry's GTR1 (Burley 2012, appendix B), isotropic,
// sampled in proportion to D(m) cos(theta_m).
struct GTR1 {
    float alpha;
    float D(const Vec3& m) const;
    Vec3 sample(const Vec2& u) const;
    float pdf(const Vec3& m) const { return m.z < 0.0f ? 0.0f : m.z * D(m); }
};
// Smith's separable GGX masking of one direction, 2 / (1 + sqrt(1 + alpha^2 tan^2)), as Mitsuba's
// clearcoat uses it (alpha = 0.25); zero when v sees the back of m.
float smith_ggx1(const Vec3& v, const Vec3& m, float alpha);

}  // namespace candela
