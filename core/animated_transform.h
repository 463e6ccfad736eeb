#pragma once
// A transform that moves over time: Mitsuba 3's <animation name="to_world"> with keyframed
// <transform time="..."> children (motion blur). Between two keyframes it interpolates as Embree's
// instance motion does (rtcSetGeometryTransformQuaternion): each keyframe's matrix is split into
// T R S (translation, rotation, an upper-triangular scale/shear), T and S are interpolated
// linearly and R by slerp (constant angular rate, the shortest way round). Outside the keyframes
// the first or last pose holds. A single keyframe (or a plain <transform>) is static.

#include "core/error.h"
#include "core/transform.h"

#include <vector>

namespace candela {

class AnimatedTransform {
public:
    // One keyframe, with the parts it interpolates by.
    struct Keyframe {
        float time = 0.0f;
        Transform transform;
        Vec3 translation{0.0f};
        Vec4 rotation{0.0f, 0.0f, 0.0f, 1.0f};  // unit quaternion (x, y, z, w)
        Mat3 scale_shear{1.0f};                 // upper triangular
    };

    AnimatedTransform() : AnimatedTransform(Transform()) {}
    explicit AnimatedTransform(const Transform& fixed);
    // Keyframes as (time, transform), times strictly increasing (the loader checks); at least one.
    explicit AnimatedTransform(const std::vector<std::pair<float, Transform>>& keyframes);

    // More than one keyframe: the pose depends on the time.
    bool is_animated() const { return keys_.size() > 1; }
    // The transform at `time` (the keyframe itself at a keyframe's time when static).
    Transform eval(float time) const;
    // The static transform, or the first keyframe's.
    const Transform& first() const { return keys_.front().transform; }
    const std::vector<Keyframe>& keyframes() const { return keys_; }
    float begin_time() const { return keys_.front().time; }
    float end_time() const { return keys_.back().time; }
    // Whether the keyframes are equally spaced in time (within a relative 1e-4), as Embree's time
    // steps are.
    bool equally_spaced() const;
    // The same motion with keyframes at equal steps, for Embree: the step is the shortest
    // interval divided by 1, 2, 3 ... until it divides every interval (within a relative 1e-4),
    // and the keyframes added inside an interval are its interpolation there (linear parts and a
    // slerp along one arc are unchanged by subdividing them). False when that needs more than
    // `max_keyframes` keyframes (incommensurate times).
    bool resampled_equally(int max_keyframes, AnimatedTransform& out) const;
    // A box around `local` carried through the motion: the union of its corners' boxes at the
    // keyframes and at 32 instants within each interval (a rotation sweeps beyond the keyframes'
    // poses; the sampled instants bound that within a small fraction of the box).
    BoundingBox bounds(const BoundingBox& local) const;

    // Split of an affine matrix into translation, rotation and upper-triangular scale/shear
    // (M = T R S: QR of the linear part by Gram-Schmidt on its columns, R with det +1).
    static void decompose(const Mat4& m, Vec3& translation, Vec4& rotation, Mat3& scale_shear);
    // The inverse of decompose.
    static Mat4 compose(const Vec3& translation, const Vec4& rotation, const Mat3& scale_shear);
    // Spherical linear interpolation of unit quaternions along the shorter arc.
    static Vec4 slerp(const Vec4& a, const Vec4& b, float t);

    // Where the <animation> stands in the scene file (empty when static), for messages.
    SourceLocation where;

private:
    std::vector<Keyframe> keys_;
};

}  // namespace candela
