// AnimatedTransform (core/animated_transform.h): the T R S split recomposes the matrix, equal
// keyframes give the static transform, a fixed time gives the pose interpolated there, and the
// rotation follows slerp (Embree's convention; the angle Mitsuba's animation_rotation scene
// states, -40.5 degrees at t = 0.23 between -75 and 75, where nlerp would give -45).

#include "core/animated_transform.h"

#include <catch2/catch.hpp>

using namespace candela;

namespace {

float max_difference(const Mat4& a, const Mat4& b) {
    float worst = 0.0f;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) worst = std::max(worst, std::abs(a[c][r] - b[c][r]));
    return worst;
}

// The rotation angle about +z of a transform's linear part, in degrees.
float angle_about_z(const Transform& t) { return degrees(std::atan2(t.matrix()[0][1], t.matrix()[0][0])); }

Transform general() {
    // Rotation, non-uniform scale, shear and a mirror, then a translation.
    Mat4 shear(1.0f);
    shear[1][0] = 0.3f;
    shear[2][1] = -0.2f;
    return Transform::translate(Vec3(1.5f, -2.0f, 0.25f)) * Transform::rotate(Vec3(1, 2, 3), 37.0f) * Transform(shear) *
           Transform::scale(Vec3(2.0f, 0.5f, -1.25f));
}

}  // namespace

TEST_CASE("animated transform: the T R S split recomposes the matrix", "[animation]") {
    for (const Transform& t : {Transform(), general(), Transform::look_at(Vec3(3, -1, 2), Vec3(0), Vec3(0, 0, 1))}) {
        Vec3 translation;
        Vec4 rotation;
        Mat3 scale_shear;
        AnimatedTransform::decompose(t.matrix(), translation, rotation, scale_shear);
        CHECK(std::abs(glm::length(rotation) - 1.0f) < 1e-6f);
        CHECK(scale_shear[0][1] == 0.0f);  // upper triangular (glm: [column][row])
        CHECK(scale_shear[0][2] == 0.0f);
        CHECK(scale_shear[1][2] == 0.0f);
        // Float rounding of a few products of entries of magnitude ~2.
        CHECK(max_difference(AnimatedTransform::compose(translation, rotation, scale_shear), t.matrix()) < 1e-5f);
    }
}

TEST_CASE("animated transform: equal keyframes are the static transform at every time", "[animation]") {
    const Transform t = general();
    AnimatedTransform still(t), moving({{0.0f, t}, {0.5f, t}, {1.0f, t}});
    CHECK_FALSE(still.is_animated());
    CHECK(moving.is_animated());
    for (float time : {-1.0f, 0.0f, 0.1f, 0.25f, 0.5f, 0.77f, 1.0f, 2.0f}) {
        INFO("time " << time);
        CHECK(still.eval(time).matrix() == t.matrix());
        CHECK(max_difference(moving.eval(time).matrix(), t.matrix()) < 1e-5f);
        CHECK(max_difference(moving.eval(time).inverse_matrix(), t.inverse_matrix()) < 1e-5f);
    }
}

TEST_CASE("animated transform: translation and scale interpolate linearly, outside the keyframes the ends hold", "[animation]") {
    AnimatedTransform a({{1.0f, Transform::translate(Vec3(0, 0, 0)) * Transform::scale(Vec3(1.0f))},
                         {3.0f, Transform::translate(Vec3(4, -2, 6)) * Transform::scale(Vec3(3.0f))}});
    // Halfway (t = 2): translation (2, -1, 3), scale 2.
    Transform mid = a.eval(2.0f);
    Transform expected = Transform::translate(Vec3(2, -1, 3)) * Transform::scale(Vec3(2.0f));
    CHECK(max_difference(mid.matrix(), expected.matrix()) < 1e-6f);
    CHECK(a.eval(0.0f).matrix() == a.keyframes().front().transform.matrix());
    CHECK(a.eval(5.0f).matrix() == a.keyframes().back().transform.matrix());
}

TEST_CASE("animated transform: rotation by slerp, -40.5 degrees at t = 0.23 between -75 and 75 (animation_rotation.xml)", "[animation]") {
    AnimatedTransform a({{0.0f, Transform::rotate(Vec3(0, 0, 1), -75.0f)}, {1.0f, Transform::rotate(Vec3(0, 0, 1), 75.0f)}});
    // slerp turns at a constant rate: -75 + 150 t degrees. nlerp would give -45.0 at 0.23.
    CHECK(angle_about_z(a.eval(0.23f)) == Approx(-40.5f).margin(1e-3));
    CHECK(angle_about_z(a.eval(0.77f)) == Approx(40.5f).margin(1e-3));
    CHECK(angle_about_z(a.eval(0.5f)) == Approx(0.0f).margin(1e-3));
    for (float t = 0.0f; t <= 1.0f; t += 0.125f) CHECK(angle_about_z(a.eval(t)) == Approx(-75.0f + 150.0f * t).margin(1e-3));
    // A rotation stays a rotation (no shrinking between the keyframes, as a matrix lerp would).
    CHECK(glm::determinant(Mat3(a.eval(0.5f).matrix())) == Approx(1.0f).epsilon(1e-5));
}

TEST_CASE("animated transform: bounds cover the box along the whole motion", "[animation]") {
    BoundingBox unit;
    unit.expand(Vec3(-1.0f));
    unit.expand(Vec3(1.0f));
    // A quarter turn about z of a box offset along x: at 45 degrees its corner (2, 1) reaches
    // radius sqrt(5) along the diagonal, beyond both keyframes' boxes.
    AnimatedTransform a({{0.0f, Transform::translate(Vec3(1, 0, 0))},
                         {1.0f, Transform::rotate(Vec3(0, 0, 1), 90.0f) * Transform::translate(Vec3(1, 0, 0))}});
    BoundingBox b = a.bounds(unit);
    for (float t = 0.0f; t <= 1.0f; t += 1.0f / 64.0f) {
        BoundingBox at = AnimatedTransform(a.eval(t)).bounds(unit);
        CHECK(glm::all(glm::lessThanEqual(b.min, at.min + Vec3(1e-2f))));
        CHECK(glm::all(glm::greaterThanEqual(b.max, at.max - Vec3(1e-2f))));
    }
    CHECK(AnimatedTransform({{0.0f, Transform()}, {1.0f, Transform()}, {3.0f, Transform()}}).equally_spaced() == false);
    CHECK(AnimatedTransform({{0.0f, Transform()}, {1.0f, Transform()}, {2.0f, Transform()}}).equally_spaced());
}
