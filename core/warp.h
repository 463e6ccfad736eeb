#pragma once
// Warps from the unit square to common domains, each with its density. Formulas follow
// pbrt-v4 (chapter A.5) and Shirley & Chiu's concentric disk mapping.

#include "core/math.h"

namespace candela::warp {

// Inline, as the two below: BSDF sampling calls them once per bounce, and out of line their
// results went through memory.
inline Vec2 square_to_uniform_disk_concentric(const Vec2& u) {
    float x = 2.0f * u.x - 1.0f, y = 2.0f * u.y - 1.0f;
    if (x == 0.0f && y == 0.0f) return Vec2(0.0f);
    // phi = (pi/4) y/x with radius x, or pi/2 - (pi/4) x/y with radius y: both angles within
    // pi/4 of an axis, so cos and sin come from sincos_quarter_pi (cos(pi/2 - a) = sin a).
    // Which case applies is a coin flip for uniform u, so it is chosen by bit masks, not a
    // branch: a mispredicted branch here, resolved only when the sampler's number arrives,
    // discarded the next-event estimation that surface_step runs after it.
    const uint32_t x_major = 0u - uint32_t(std::abs(x) > std::abs(y));
    const float r = select_float(x_major, x, y), across = select_float(x_major, y, x);
    float s, c;
    sincos_quarter_pi((Pi / 4.0f) * (across / r), s, c);
    return Vec2(r * select_float(x_major, c, s), r * select_float(x_major, s, c));
}

Vec3 square_to_uniform_sphere(const Vec2& u);
inline float square_to_uniform_sphere_pdf() { return InvFourPi; }

Vec3 square_to_uniform_hemisphere(const Vec2& u);
inline float square_to_uniform_hemisphere_pdf(const Vec3& v) { return v.z >= 0.0f ? InvTwoPi : 0.0f; }

// Density cos(theta) / pi over the upper hemisphere (Malley's method).
inline Vec3 square_to_cosine_hemisphere(const Vec2& u) {
    Vec2 d = square_to_uniform_disk_concentric(u);
    float z = safe_sqrt(1.0f - d.x * d.x - d.y * d.y);
    return Vec3(d.x, d.y, z);
}
inline float square_to_cosine_hemisphere_pdf(const Vec3& v) { return v.z > 0.0f ? v.z * InvPi : 0.0f; }

// Uniform over the cone of directions within acos(cos_cutoff) of +z.
Vec3 square_to_uniform_cone(const Vec2& u, float cos_cutoff);
inline float square_to_uniform_cone_pdf(const Vec3& v, float cos_cutoff) {
    return v.z >= cos_cutoff ? 1.0f / (TwoPi * (1.0f - cos_cutoff)) : 0.0f;
}

// Barycentric coordinates (b1, b2) uniform over a triangle (Heitz 2019, low-distortion map).
Vec2 square_to_uniform_triangle(const Vec2& u);

// Uniform on the unit disk by polar mapping (radius sqrt(u.x)); used where the mapping's
// continuity does not matter.
Vec2 square_to_uniform_disk(const Vec2& u);

}  // namespace candela::warp
