#pragma once
// What point and spot lights share: the direction sample toward a point source, and the
// lecture's distance attenuation 1 / (a0 + a1 d + a2 d^2), kept as optional parameters whose
// defaults (0, 0, 1) are the physical inverse-square law. Path tracer and rasterizer use the
// same values, so changing them changes both images alike.

#include "core/emitter.h"
#include "core/properties.h"

namespace candela {

struct Attenuation {
    float constant = 0.0f, linear = 0.0f, quadratic = 1.0f;

    static Attenuation read(const Properties& props) {
        Attenuation a;
        a.constant = props.get_float("attenuation_constant", 0.0f);
        a.linear = props.get_float("attenuation_linear", 0.0f);
        a.quadratic = props.get_float("attenuation_quadratic", 1.0f);
        if (a.constant < 0.0f || a.linear < 0.0f || a.quadratic < 0.0f || a.constant + a.linear + a.quadratic <= 0.0f)
            props.fail("attenuation_constant", "attenuation coefficients must be non-negative and not all zero");
        return a;
    }
    bool physical() const { return constant == 0.0f && linear == 0.0f && quadratic == 1.0f; }
    float operator()(float d) const { return 1.0f / (constant + linear * d + quadratic * d * d); }
    // A light path's flux where it first meets a surface at distance d already falls as 1 / d^2:
    // this is the factor that turns that into the law above (Emitter::ray_attenuation).
    float ray_factor(float d) const { return physical() ? 1.0f : d * d * (*this)(d); }
};

// A ray from a point source at `position` along unit direction `d`, drawn with solid-angle density
// `pdf_direction`, carrying the radiant intensity `intensity` toward d.
inline EmitterRay point_source_ray(const Vec3& position, const Vec3& d, float pdf_direction, const Spectrum& intensity) {
    EmitterRay r;
    r.ray = Ray(position, d);
    r.pdf_position = 1.0f;
    r.delta_position = true;
    r.pdf_direction = pdf_direction;
    if (pdf_direction > 0.0f) r.weight = intensity / pdf_direction;
    return r;
}

// The sample toward a point source at `position` (a delta in position: pdf 1, no normal).
inline DirectionSample sample_point_source(const Vec3& position, const SurfaceInteraction& ref, const Emitter* emitter) {
    DirectionSample ds;
    ds.p = position;
    ds.n = Vec3(0.0f);
    Vec3 to = position - ref.p;
    ds.dist = glm::length(to);
    ds.d = to / ds.dist;
    ds.pdf = 1.0f;
    ds.delta = true;
    ds.emitter = emitter;
    return ds;
}

}  // namespace candela
