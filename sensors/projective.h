#pragma once
// What perspective, thinlens and orthographic share (Mitsuba's Sensor and ProjectiveCamera):
//   to_world           transform   camera to world (default identity)
//   near_clip          float       distance of the near plane (default 0.01)
//   far_clip           float       distance of the far plane (default 10000)
//   focus_distance     float       distance of the focal plane (default far_clip); only thinlens
//                                  uses it, the others accept it, as in Mitsuba
//   shutter_open,      float       the exposure interval (default 0, 0); accepted and unused, as
//   shutter_close                  nothing in a Candela scene moves
//   srf                spectrum    rejected: a sensor response needs a spectral variant, and
//                                  Candela renders in RGB (Mitsuba's RGB variants reject it too)
//   film, sampler      nested      default: hdrfilm and independent

#include "core/sensor.h"

namespace candela {

class ProjectiveCamera : public Sensor {
protected:
    explicit ProjectiveCamera(const Properties& props);
    // Film position in pixels of the full film -> fractions in [0,1]^2.
    Vec2 film_fraction(const Vec2& film_pos) const { return film_pos * inv_size_; }

    float aspect_ = 1.0f;  // width / height of the full film
    float near_clip_ = 0.01f, far_clip_ = 1e4f, focus_distance_ = 1e4f;

private:
    Vec2 inv_size_{1.0f};
};

}  // namespace candela
