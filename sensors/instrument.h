#pragma once
// What the measuring sensors (radiancemeter, irradiancemeter, distant) share: one value, so a
// film of 1 x 1 pixel, also as a batch's slice; and, for those that point (radiancemeter,
// distant), a direction: to_world's +z, editable as "to_world".

#include "core/sensor.h"

namespace candela {

class Instrument : public Sensor {
public:
    // "to_world" and the film (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override;
    void parameters_changed(const std::vector<std::string>& keys) override;
    void set_film_size(const Vec2i& size) override;

protected:
    // Reads what every sensor reads; the film must be 1 x 1 pixel (else an error at the film),
    // and a filter reaching beyond it (radius above 0.5) is warned about, as in Mitsuba.
    explicit Instrument(const Properties& props);
    // The direction from to_world_ (its +z, normalised); false when to_world collapses it.
    bool aim();

    Vec3 direction_{0.0f, 0.0f, 1.0f};
};

// Mitsuba's math::RayEpsilon for single precision (1500 x 2^-24): where its meters' rays start,
// and the smallest bounding-sphere radius of its distant sensor.
constexpr float InstrumentRayEpsilon = 1500.0f / 16777216.0f;

}  // namespace candela
