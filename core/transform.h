#pragma once
// Affine transforms as 4x4 matrices with their inverses. Composition follows Mitsuba's XML: each
// new operation multiplies on the left, so `a then b` is `b * a`.

#include "core/math.h"

namespace candela {

class Transform {
public:
    Transform() = default;
    explicit Transform(const Mat4& m) : m_(m), inv_(glm::inverse(m)) {}
    Transform(const Mat4& m, const Mat4& inv) : m_(m), inv_(inv) {}

    static Transform translate(const Vec3& t);
    static Transform scale(const Vec3& s);
    // Rotation by `angle_deg` degrees about `axis`, counter-clockwise looking down the axis.
    static Transform rotate(const Vec3& axis, float angle_deg);
    // Mitsuba's camera/light look-at: columns [left, up, dir, origin] with left = up x dir.
    // An `up` of zero length is replaced by one from coordinate_system(dir), as Mitsuba does.
    static Transform look_at(const Vec3& origin, const Vec3& target, const Vec3& up);

    const Mat4& matrix() const { return m_; }
    const Mat4& inverse_matrix() const { return inv_; }
    Transform inverse() const { return Transform(inv_, m_); }
    Transform operator*(const Transform& other) const { return Transform(m_ * other.m_, other.inv_ * inv_); }

    Vec3 apply_point(const Vec3& p) const {
        Vec4 r = m_ * Vec4(p, 1.0f);
        return r.w == 1.0f ? Vec3(r) : Vec3(r) / r.w;
    }
    Vec3 apply_vector(const Vec3& v) const { return Vec3(m_ * Vec4(v, 0.0f)); }
    // Normals transform by the inverse transpose; the result is not normalised.
    Vec3 apply_normal(const Vec3& n) const { return Vec3(glm::transpose(inv_) * Vec4(n, 0.0f)); }

    bool is_identity() const { return m_ == Mat4(1.0f); }
    bool has_scale() const;
    bool all_finite() const;
    // Determinant of the linear part; negative when the transform mirrors.
    float determinant3() const { return glm::determinant(Mat3(m_)); }

private:
    Mat4 m_{1.0f};
    Mat4 inv_{1.0f};
};

// A bound on the error of each coordinate of to_world applied to a point p that already
// carries error `p_error`: a few roundings of sum_j |M_ij p_j| + |t_i|, plus sum_j |M_ij| e.
inline float transformed_point_error(const Transform& to_world, const Vec3& p, float p_error) {
    const Mat4& m = to_world.matrix();
    Mat3 abs_m(glm::abs(Vec3(m[0])), glm::abs(Vec3(m[1])), glm::abs(Vec3(m[2])));
    Vec3 magnitude = abs_m * glm::abs(p) + glm::abs(Vec3(m[3]));
    return gamma_bound(4) * max_component(magnitude) + max_component(abs_m * Vec3(p_error)) * (1.0f + gamma_bound(4));
}

}  // namespace candela
