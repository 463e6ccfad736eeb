#pragma once
// Phase functions: how a participating medium scatters light at a point, the volumetric
// counterpart of a BSDF. Everything is in world space. A phase function is asked at a
// `MediumInteraction` (Mitsuba's mi): the point `p` (for parameters that vary in space, such as
// SGGX's S or a blendphase weight volume) and `wi`, the unit direction back toward where the
// path came from (minus the ray direction); `wo` is the scattered direction. eval gives
// p(wi, wo) per steradian (it integrates to one over wo); pdf is the solid-angle density of
// sample(); sample gives the direction, its pdf and the weight p / pdf (1 for the phase
// functions here, which are all sampled exactly).
//
// Microflake phase functions (sggx) also set the medium's extinction: a medium scales sigma_t
// at p by projected_area(mi), the flakes' area seen along wi (Jakob et al. 2010; Mitsuba 3's
// PhaseFunctionFlags::Microflake), which max_projected_area bounds for the majorants.

#include "core/frame.h"
#include "core/object.h"

namespace candela {

struct MediumInteraction {
    Vec3 p{0.0f};
    Vec3 wi{0.0f, 0.0f, 1.0f};
};

struct PhaseSample {
    Vec3 wo{0.0f};
    float pdf = 0.0f;     // 0 marks a failed sample
    float weight = 0.0f;  // eval / pdf
    bool valid() const { return pdf > 0.0f; }
};

class PhaseFunction : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Phase; }
    virtual float eval(const MediumInteraction& mi, const Vec3& wo) const = 0;
    virtual float pdf(const MediumInteraction& mi, const Vec3& wo) const = 0;
    virtual PhaseSample sample(const MediumInteraction& mi, const Vec2& u) const = 0;
    // The mean cosine between the incident and scattered propagation directions (HG's g): what
    // approximations such as the raster mode's fog may use (0 where it varies, as for sggx).
    virtual float mean_cosine() const { return 0.0f; }

    // Microflakes: whether the phase function scales the medium's extinction, by how much at
    // mi (the projected area along mi.wi, symmetric in wi), and a bound on that factor for
    // every point along direction d (the majorants' factor; d matters only for a constant S).
    virtual bool is_microflake() const { return false; }
    virtual float projected_area(const MediumInteraction&) const { return 1.0f; }
    virtual float max_projected_area(const Vec3& /*d*/) const { return 1.0f; }
    // Whether eval or projected_area depend on mi.p (a volume-valued parameter that is not
    // constant): a homogeneous medium then cannot use its closed-form transmittance.
    virtual bool varies_in_space() const { return false; }
};

// The unit direction at angle acos(cos_theta) from `axis` and azimuth phi around it.
inline Vec3 direction_around(const Vec3& axis, float cos_theta, float phi) {
    Frame frame(axis);
    float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
    return frame.to_world(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta));
}

}  // namespace candela
