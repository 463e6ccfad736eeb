#pragma once
// Phase functions: how a participating medium scatters light at a point, the volumetric
// counterpart of a BSDF. Everything is in world space: `wi` is the unit direction back toward
// where the path came from (minus the ray direction, Mitsuba's mi.wi), `wo` the scattered
// direction. eval gives p(wi, wo) per steradian (it integrates to one over wo); pdf is the
// solid-angle density of sample(); sample gives the direction, its pdf and the weight
// p / pdf (1 for the phase functions here, which are all sampled exactly).

#include "core/frame.h"
#include "core/object.h"

namespace candela {

struct PhaseSample {
    Vec3 wo{0.0f};
    float pdf = 0.0f;     // 0 marks a failed sample
    float weight = 0.0f;  // eval / pdf
    bool valid() const { return pdf > 0.0f; }
};

class PhaseFunction : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Phase; }
    virtual float eval(const Vec3& wi, const Vec3& wo) const = 0;
    virtual float pdf(const Vec3& wi, const Vec3& wo) const = 0;
    virtual PhaseSample sample(const Vec3& wi, const Vec2& u) const = 0;
    // The mean cosine between the incident and scattered propagation directions (HG's g): what
    // approximations such as the raster mode's fog may use.
    virtual float mean_cosine() const { return 0.0f; }
};

// The unit direction at angle acos(cos_theta) from `axis` and azimuth phi around it.
inline Vec3 direction_around(const Vec3& axis, float cos_theta, float phi) {
    Frame frame(axis);
    float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
    return frame.to_world(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta));
}

}  // namespace candela
