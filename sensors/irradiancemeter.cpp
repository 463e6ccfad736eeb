// irradiancemeter: the irradiance on a shape, averaged over its area (Mitsuba 3's
// `irradiancemeter` sensor): power arriving per unit area, E = integral of L cos(theta) over the
// hemisphere on the side its normals face.
//
// It is nested in the shape it measures on, and has no pose of its own (to_world is an error:
// the shape's places it):
//     <shape type="rectangle"> <sensor type="irradiancemeter"> <film .../> </sensor> </shape>
//
// Parameters:
//   srf             spectrum   the spectral variant's sensor response (as every sensor's)
//   film, sampler              nested, as every sensor's; the film must be 1 x 1 pixel, and a
//                              filter wider than the pixel (radius above 0.5) is warned about
//
// A sample picks a point uniformly by area (the film position's sample, Mitsuba's position
// sample) and a cosine-distributed direction about its normal (the aperture sample); the
// radiance coming back along it is weighted by pi, so its mean is the area-averaged irradiance
// (cosine sampling: pdf cos / pi). Light tracers connect to a point of the shape sampled as seen
// from theirs (Shape::sample_direction), with importance 1 / area per unit area.

#include "core/error.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/shape.h"
#include "core/warp.h"
#include "sensors/instrument.h"

namespace candela {

class IrradianceMeter final : public Instrument {
public:
    explicit IrradianceMeter(const Properties& props) : Instrument(props), where_(props.location()) {
        if (props.has("to_world"))
            props.fail("to_world", "an irradiancemeter takes no to_world: it measures on the shape it is nested in, which places it");
    }

    void attach_to_shape(const Shape& shape, const Properties& shape_props) override {
        if (shape_) shape_props.fail("this irradiancemeter is already nested in another shape");
        shape_ = &shape;
    }
    void set_scene(const Scene&) override {
        if (!shape_)
            throw SceneError(
                where_,
                "an irradiancemeter must be nested in the shape it measures on (<shape><sensor type=\"irradiancemeter\"/></shape>)");
        if (!(shape_->surface_area() > 0.0f)) throw SceneError(where_, "the irradiancemeter's shape has no area to measure on");
    }

    Ray sample_ray(const Vec2& film_pos, const Vec2& aperture_u, float time) const override {
        PositionSample ps = shape_->sample_position(glm::clamp(film_pos, Vec2(0.0f), Vec2(1.0f)));
        Vec3 d = Frame(ps.n).to_world(warp::square_to_cosine_hemisphere(aperture_u));
        Ray ray(offset_ray_origin(ps.p, ps.p_error, ps.n, d), d);
        ray.time = time;
        return ray;
    }
    float sample_weight(const Vec2&) const override { return Pi; }

    // The importance is 1 / area per unit area on the front side; a point sampled with
    // solid-angle density p as seen from `ref` weighs cos / (dist^2 area p_area) = 1 / (area p).
    SensorSample sample_direction(const Vec3& ref, const Vec2& u, float) const override {
        SurfaceInteraction at;
        at.p = ref;
        DirectionSample ds = shape_->sample_direction(at, u);
        SensorSample s;
        if (!(ds.pdf > 0.0f) || !(ds.dist > 0.0f) || !(glm::dot(ds.n, ds.d) < 0.0f)) return s;
        // Just off the surface, on ref's side: the shadow ray toward it stops before the shape,
        // and a ray leaving it does not hit the shape at its start.
        s.p = offset_ray_origin(ds.p, ds.p_error, ds.n, -ds.d);
        s.dist = glm::length(s.p - ref);
        if (!(s.dist > 0.0f)) return s;
        s.d = (s.p - ref) / s.dist;
        s.film_pos = Vec2(0.5f);
        s.pdf = ds.pdf;
        s.weight = 1.0f / (shape_->surface_area() * ds.pdf);
        return s;
    }
    bool reached_by_light_paths() const override { return true; }

    // Only the film: the shape places the meter.
    void traverse(ParameterVisitor& visitor) override { visitor.object("film", film_.get()); }

    std::string to_string() const override { return "irradiancemeter"; }

private:
    SourceLocation where_;
    const Shape* shape_ = nullptr;
};

CANDELA_REGISTER(IrradianceMeter, ObjectKind::Sensor, "irradiancemeter");

}  // namespace candela
