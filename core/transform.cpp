#include "core/transform.h"

#include "core/frame.h"

namespace candela {

Transform Transform::translate(const Vec3& t) {
    Mat4 m(1.0f), inv(1.0f);
    m[3] = Vec4(t, 1.0f);
    inv[3] = Vec4(-t, 1.0f);
    return Transform(m, inv);
}

Transform Transform::scale(const Vec3& s) {
    Mat4 m(1.0f), inv(1.0f);
    for (int i = 0; i < 3; ++i) {
        m[i][i] = s[i];
        inv[i][i] = 1.0f / s[i];
    }
    return Transform(m, inv);
}

Transform Transform::rotate(const Vec3& axis, float angle_deg) {
    // Rodrigues' rotation formula; the inverse of a rotation is its transpose.
    Vec3 a = glm::normalize(axis);
    float s = std::sin(radians(angle_deg)), c = std::cos(radians(angle_deg));
    // Exact values at multiples of 90 degrees keep axis-aligned scenes axis-aligned.
    if (std::abs(s) < 1e-7f) s = 0.0f;
    if (std::abs(c) < 1e-7f) c = 0.0f;
    float k = 1.0f - c;
    Mat4 m(1.0f);
    // glm is column-major: m[col][row].
    m[0][0] = a.x * a.x * k + c;
    m[1][0] = a.x * a.y * k - a.z * s;
    m[2][0] = a.x * a.z * k + a.y * s;
    m[0][1] = a.y * a.x * k + a.z * s;
    m[1][1] = a.y * a.y * k + c;
    m[2][1] = a.y * a.z * k - a.x * s;
    m[0][2] = a.z * a.x * k - a.y * s;
    m[1][2] = a.z * a.y * k + a.x * s;
    m[2][2] = a.z * a.z * k + c;
    return Transform(m, glm::transpose(m));
}

Transform Transform::look_at(const Vec3& origin, const Vec3& target, const Vec3& up_in) {
    Vec3 dir = glm::normalize(target - origin);
    Vec3 up = up_in;
    if (squared_length(up) == 0.0f) {
        Vec3 unused;
        coordinate_system(dir, up, unused);
    }
    Vec3 left = glm::normalize(glm::cross(glm::normalize(up), dir));
    Vec3 new_up = glm::cross(dir, left);
    Mat4 m(1.0f);
    m[0] = Vec4(left, 0.0f);
    m[1] = Vec4(new_up, 0.0f);
    m[2] = Vec4(dir, 0.0f);
    m[3] = Vec4(origin, 1.0f);
    // Inverse of a rigid transform: transpose the rotation, rotate the negated translation.
    Mat4 inv(1.0f);
    Mat3 rt = glm::transpose(Mat3(m));
    for (int c = 0; c < 3; ++c) inv[c] = Vec4(rt[c], 0.0f);
    inv[3] = Vec4(-(rt * origin), 1.0f);
    return Transform(m, inv);
}

bool Transform::has_scale() const {
    for (int i = 0; i < 3; ++i)
        if (std::abs(glm::length(Vec3(m_[i])) - 1.0f) > 1e-4f) return true;
    return false;
}

bool Transform::all_finite() const {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m_[c][r]) || !std::isfinite(inv_[c][r])) return false;
    return true;
}

}  // namespace candela
