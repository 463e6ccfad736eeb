// radiancemeter: the radiance arriving at one point from one direction (Mitsuba 3's
// `radiancemeter` sensor): the limit of a perspective camera whose field of view shrinks to zero.
//
// Parameters:
//   to_world    transform   the meter's pose: it stands at to_world's origin and looks along its
//                           +z (default identity: at the origin, looking along +z)
//   origin,     point,      an alternative to to_world, given together: where it stands and where
//   direction   vector      it looks (world space); to_world wins when both are given, as in
//                           Mitsuba
//   srf         spectrum    the spectral variant's sensor response (as every sensor's)
//   film, sampler           nested, as every sensor's; the film must be 1 x 1 pixel, and a filter
//                           wider than the pixel (radius above 0.5) is warned about
//
// Every sample traces the same ray, from the meter's position (after Mitsuba's ray epsilon,
// 1500 x 2^-24, so that a meter lying on a surface does not see that surface) along its
// direction; the pixel is the mean radiance it carries back. Light paths cannot reach it (a delta
// in position and direction): the particle tracer refuses it.

#include "core/properties.h"
#include "core/registry.h"
#include "sensors/instrument.h"

namespace candela {

class RadianceMeter final : public Instrument {
public:
    explicit RadianceMeter(const Properties& props) : Instrument(props) {
        if (props.has("to_world")) {
            to_world_ = props.get_transform("to_world");
            if (props.has("origin")) props.get_point("origin");  // to_world wins, as in Mitsuba
            if (props.has("direction")) props.get_vector("direction");
        } else if (props.has("origin") != props.has("direction")) {
            props.fail(props.has("origin") ? "origin" : "direction", "a radiancemeter given by origin and direction needs both");
        } else if (props.has("origin")) {
            Vec3 origin = props.get_point("origin"), direction = props.get_vector("direction");
            if (!(squared_length(direction) > 0.0f)) props.fail("direction", "the direction must not be zero");
            to_world_ = Transform::look_at(origin, origin + direction, Vec3(0.0f));
        }
        if (!aim()) props.fail("to_world", "the meter's to_world must be finite and keep its +z direction");
    }

    Ray sample_ray(const Vec2&, const Vec2&, float time) const override {
        Ray ray(to_world_.apply_point(Vec3(0.0f)), direction_);
        ray.tmin = InstrumentRayEpsilon;
        ray.time = time;
        return ray;
    }

    bool rays_coherent() const override { return true; }  // one ray, again and again

    std::string to_string() const override { return "radiancemeter"; }
};

CANDELA_REGISTER(RadianceMeter, ObjectKind::Sensor, "radiancemeter");

}  // namespace candela
