#pragma once
// Orthonormal frames: the local shading frame in which BSDFs work has its normal along +z.

#include "core/math.h"

namespace candela {

// Builds two unit vectors s, t so that (s, t, n) is right-handed and orthonormal, without a
// branch on the normal's direction: Duff et al., "Building an Orthonormal Basis, Revisited",
// JCGT 2017. Mitsuba 3 uses the same construction, which matters where the choice is visible
// (a lookat without an `up`).
inline void coordinate_system(const Vec3& n, Vec3& s, Vec3& t) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    s = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = Vec3(b, sign + n.y * n.y * a, -n.y);
}

struct Frame {
    Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

    Frame() = default;
    explicit Frame(const Vec3& normal) : n(normal) { coordinate_system(n, s, t); }
    Frame(const Vec3& s_, const Vec3& t_, const Vec3& n_) : s(s_), t(t_), n(n_) {}

    // The frame around normal n whose s axis is the tangent's part orthogonal to n (Gram-Schmidt),
    // as Mitsuba builds shading frames from dp/du; falls back to Frame(n) for a degenerate tangent.
    static Frame from_normal_tangent(const Vec3& n, const Vec3& tangent) {
        Vec3 s = tangent - n * glm::dot(n, tangent);
        float len2 = glm::dot(s, s);
        if (!(len2 > 1e-20f) || !std::isfinite(len2)) return Frame(n);
        s /= std::sqrt(len2);
        return Frame(s, glm::cross(n, s), n);
    }

    Vec3 to_local(const Vec3& v) const { return Vec3(glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)); }
    Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }

    // Trigonometry of a direction given in this local frame.
    static float cos_theta(const Vec3& v) { return v.z; }
    static float sin2_theta(const Vec3& v) { return std::max(0.0f, 1.0f - v.z * v.z); }
    static float sin_theta(const Vec3& v) { return std::sqrt(sin2_theta(v)); }
    static float tan_theta(const Vec3& v) { return sin_theta(v) / v.z; }
    static float cos_phi(const Vec3& v) {
        float st = sin_theta(v);
        return st == 0.0f ? 1.0f : std::clamp(v.x / st, -1.0f, 1.0f);
    }
    static float sin_phi(const Vec3& v) {
        float st = sin_theta(v);
        return st == 0.0f ? 0.0f : std::clamp(v.y / st, -1.0f, 1.0f);
    }
};

}  // namespace candela
