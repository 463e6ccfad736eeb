// distant: the radiance leaving the scene in one direction, as seen from infinitely far away
// (Mitsuba 3's `distant` sensor, the adjoint of the `directional` emitter).
//
// Parameters:
//   to_world    transform   its rays travel along to_world's +z (default identity: along +z)
//   direction   vector      an alternative to to_world (giving both is an error): the direction
//                           its rays travel, into the scene
//   target      point or    where the rays aim: a point (every ray passes through it), or a
//               shape       nested shape (a point of it uniform by area per ray, the radiance
//                           averaged over the shape); default the cross-section of the scene's
//                           bounding sphere (rays that miss see the environment, or black)
//   srf         spectrum    the spectral variant's sensor response (as every sensor's)
//   film, sampler           nested, as every sensor's; the film must be 1 x 1 pixel, and a filter
//                           wider than the pixel (radius above 0.5) is warned about
//
// Rays start outside the scene, two bounding-sphere radii before their target point (Mitsuba's
// placement), and each draws its point from the aperture sample. A delta in direction: light
// paths cannot reach it, and the particle tracer refuses it.

#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/shape.h"
#include "core/warp.h"
#include "sensors/instrument.h"

namespace candela {

class DistantSensor final : public Instrument {
public:
    explicit DistantSensor(const Properties& props) : Instrument(props) {
        if (props.has("direction")) {
            if (props.has("to_world")) props.fail("direction", "give either direction or to_world, not both");
            Vec3 d = props.get_vector("direction");
            if (!(squared_length(d) > 0.0f)) props.fail("direction", "the direction must not be zero");
            to_world_ = Transform::look_at(Vec3(0.0f), d, Vec3(0.0f));
        } else {
            to_world_ = props.get_transform("to_world", Transform());
        }
        if (!aim()) props.fail("to_world", "the sensor's to_world must be finite and keep its +z direction");
        if (props.has("target")) {
            Properties::Type type;
            props.get_raw("target", &type);
            if (type == Properties::Type::Point) {
                target_point_ = props.get_point("target");
                target_ = Target::Point;
            } else if (type == Properties::Type::Object) {
                target_shape_ = std::dynamic_pointer_cast<Shape>(props.get_object("target"));
                if (!target_shape_ || target_shape_->is_shape_group()) props.fail("target", "target must be a point or a shape");
                if (!(target_shape_->surface_area() > 0.0f)) props.fail("target", "the target shape has no area to aim at");
                target_ = Target::Shape;
            } else {
                props.fail("target", "target must be a point or a shape");
            }
        }
    }

    // Mitsuba's bounding sphere: the scene box's, a little larger, never of zero radius.
    void set_scene(const Scene& scene) override {
        const BoundingBox& box = scene.bbox();
        centre_ = box.valid() ? box.center() : Vec3(0.0f);
        radius_ = std::max(InstrumentRayEpsilon, box.bounding_radius() * (1.0f + InstrumentRayEpsilon));
    }

    Ray sample_ray(const Vec2&, const Vec2& aperture_u, float time) const override {
        Ray ray;
        ray.d = direction_;
        ray.time = time;
        switch (target_) {
            case Target::Point: ray.o = target_point_ - 2.0f * radius_ * direction_; break;
            case Target::Shape: ray.o = target_shape_->sample_position(aperture_u).p - 2.0f * radius_ * direction_; break;
            case Target::BoundingSphere: {
                Vec2 offset = warp::square_to_uniform_disk_concentric(aperture_u);
                ray.o = centre_ + radius_ * (to_world_.apply_vector(Vec3(offset.x, offset.y, 0.0f)) - direction_);
                break;
            }
        }
        return ray;
    }

    std::string to_string() const override { return "distant"; }

private:
    enum class Target { BoundingSphere, Point, Shape };
    Target target_ = Target::BoundingSphere;
    Vec3 target_point_{0.0f};
    Ref<Shape> target_shape_;
    Vec3 centre_{0.0f};
    float radius_ = InstrumentRayEpsilon;
};

CANDELA_REGISTER(DistantSensor, ObjectKind::Sensor, "distant");

}  // namespace candela
