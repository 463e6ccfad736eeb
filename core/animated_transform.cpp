#include "core/animated_transform.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>

namespace candela {

namespace {
AnimatedTransform::Keyframe make_keyframe(float time, const Transform& t) {
    AnimatedTransform::Keyframe k;
    k.time = time;
    k.transform = t;
    AnimatedTransform::decompose(t.matrix(), k.translation, k.rotation, k.scale_shear);
    return k;
}
}  // namespace

AnimatedTransform::AnimatedTransform(const Transform& fixed) { keys_.push_back(make_keyframe(0.0f, fixed)); }

AnimatedTransform::AnimatedTransform(const std::vector<std::pair<float, Transform>>& keyframes) {
    for (const auto& [time, t] : keyframes) {
        keys_.push_back(make_keyframe(time, t));
        // q and -q are the same rotation: keep neighbours on the same side (a . b >= 0), so that
        // any slerp, with or without its own shorter-arc flip (Embree's), turns the short way.
        if (keys_.size() > 1 && glm::dot(keys_[keys_.size() - 2].rotation, keys_.back().rotation) < 0.0f)
            keys_.back().rotation = -keys_.back().rotation;
    }
    if (keys_.empty()) keys_.push_back(make_keyframe(0.0f, Transform()));
}

void AnimatedTransform::decompose(const Mat4& m, Vec3& translation, Vec4& rotation, Mat3& scale_shear) {
    translation = Vec3(m[3]);
    // Gram-Schmidt on the columns a0, a1, a2 of the linear part A gives A = Q S with Q
    // orthonormal and S upper triangular (S[j][i] = q_i . a_j in glm's column-major indexing).
    glm::dvec3 a[3] = {glm::dvec3(Vec3(m[0])), glm::dvec3(Vec3(m[1])), glm::dvec3(Vec3(m[2]))};
    glm::dvec3 q[3];
    glm::dmat3 s(0.0);
    for (int j = 0; j < 3; ++j) {
        glm::dvec3 v = a[j];
        for (int i = 0; i < j; ++i) {
            s[j][i] = glm::dot(q[i], a[j]);
            v -= s[j][i] * q[i];
        }
        s[j][j] = glm::length(v);
        q[j] = v / s[j][j];
    }
    // A mirroring A gives det Q = -1; a rotation needs +1, so the mirror moves into S's last row.
    if (glm::dot(glm::cross(q[0], q[1]), q[2]) < 0.0) {
        q[2] = -q[2];
        for (int j = 0; j < 3; ++j) s[j][2] = -s[j][2];
    }
    glm::dquat r = glm::quat_cast(glm::dmat3(q[0], q[1], q[2]));
    rotation = Vec4(float(r.x), float(r.y), float(r.z), float(r.w));
    scale_shear = Mat3(s);
}

Mat4 AnimatedTransform::compose(const Vec3& translation, const Vec4& rotation, const Mat3& scale_shear) {
    glm::quat r(rotation.w, rotation.x, rotation.y, rotation.z);
    Mat3 linear = glm::mat3_cast(glm::normalize(r)) * scale_shear;
    Mat4 m(linear);
    m[3] = Vec4(translation, 1.0f);
    return m;
}

Vec4 AnimatedTransform::slerp(const Vec4& a, const Vec4& b_in, float t) {
    // q(t) = (sin((1 - t) theta) a + sin(t theta) b) / sin(theta), cos(theta) = a . b, with b
    // negated when a . b < 0 (the same rotation, the shorter arc).
    Vec4 b = b_in;
    float cos_theta = glm::dot(a, b);
    if (cos_theta < 0.0f) {
        b = -b;
        cos_theta = -cos_theta;
    }
    if (cos_theta > 0.9995f) return glm::normalize(a + t * (b - a));  // nearly equal: sin(theta) -> 0
    float theta = std::acos(std::min(cos_theta, 1.0f));
    float sin_theta = std::sin(theta);
    return (std::sin((1.0f - t) * theta) * a + std::sin(t * theta) * b) / sin_theta;
}

Transform AnimatedTransform::eval(float time) const {
    if (keys_.size() == 1 || !(time > keys_.front().time)) return keys_.front().transform;
    if (time >= keys_.back().time) return keys_.back().transform;
    size_t i = 0;
    while (time >= keys_[i + 1].time) ++i;  // keys_[i].time <= time < keys_[i + 1].time
    const Keyframe &a = keys_[i], &b = keys_[i + 1];
    float alpha = (time - a.time) / (b.time - a.time);
    Vec3 translation = a.translation + alpha * (b.translation - a.translation);
    Mat3 scale_shear = a.scale_shear + alpha * (b.scale_shear - a.scale_shear);
    return Transform(compose(translation, slerp(a.rotation, b.rotation, alpha), scale_shear));
}

bool AnimatedTransform::equally_spaced() const {
    if (keys_.size() <= 2) return true;
    float step = (end_time() - begin_time()) / float(keys_.size() - 1);
    for (size_t i = 1; i < keys_.size(); ++i)
        if (std::abs(keys_[i].time - keys_[i - 1].time - step) > 1e-4f * step) return false;
    return true;
}

bool AnimatedTransform::resampled_equally(int max_keyframes, AnimatedTransform& out) const {
    float shortest = end_time() - begin_time();
    for (size_t i = 1; i < keys_.size(); ++i) shortest = std::min(shortest, keys_[i].time - keys_[i - 1].time);
    for (int divisor = 1; divisor < max_keyframes; ++divisor) {
        double step = double(shortest) / divisor;
        if ((double(end_time()) - begin_time()) / step + 1.0 > max_keyframes + 0.5) return false;
        bool divides = true;
        for (size_t i = 1; i < keys_.size() && divides; ++i) {
            double n = (double(keys_[i].time) - keys_[i - 1].time) / step;
            divides = std::abs(n - std::round(n)) <= 1e-4 * n;
        }
        if (!divides) continue;
        out = *this;
        out.keys_.clear();
        for (size_t i = 1; i < keys_.size(); ++i) {
            const Keyframe &a = keys_[i - 1], &b = keys_[i];
            int n = int(std::round((double(b.time) - a.time) / step));
            for (int j = 0; j < n; ++j) {
                float alpha = float(j) / float(n);
                Keyframe k;
                k.time = a.time + alpha * (b.time - a.time);
                k.translation = a.translation + alpha * (b.translation - a.translation);
                k.rotation = j == 0 ? a.rotation : slerp(a.rotation, b.rotation, alpha);
                k.scale_shear = a.scale_shear + alpha * (b.scale_shear - a.scale_shear);
                k.transform = j == 0 ? a.transform : Transform(compose(k.translation, k.rotation, k.scale_shear));
                out.keys_.push_back(k);
            }
        }
        out.keys_.push_back(keys_.back());
        return true;
    }
    return false;
}

BoundingBox AnimatedTransform::bounds(const BoundingBox& local) const {
    BoundingBox out;
    auto add_pose = [&](const Transform& t) {
        for (int corner = 0; corner < 8; ++corner)
            out.expand(t.apply_point(Vec3(corner & 1 ? local.max.x : local.min.x, corner & 2 ? local.max.y : local.min.y,
                                          corner & 4 ? local.max.z : local.min.z)));
    };
    add_pose(keys_.front().transform);
    const int Steps = 32;
    for (size_t i = 1; i < keys_.size(); ++i)
        for (int s = 1; s <= Steps; ++s) add_pose(eval(keys_[i - 1].time + (keys_[i].time - keys_[i - 1].time) * float(s) / Steps));
    return out;
}

}  // namespace candela
