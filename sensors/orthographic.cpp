// orthographic: a camera without perspective, measuring radiance along its view axis over a
// rectangle (Mitsuba 3's `orthographic` sensor).
//
// Parameters (and those of every projective camera, sensors/projective.h):
//   to_world    transform   camera to world; unlike the perspective cameras it may scale: the
//                           viewed rectangle is [-1, 1] x [-1/aspect, 1/aspect] in camera space
//                           (aspect = width / height), so a scale of 10 views 20 units across
//   near_clip   float       the rays start on the plane z = near_clip of camera space
//                           (default 0.01)
//   far_clip    float       and run a distance far_clip - near_clip in scene units (default
//                           10000), as Mitsuba does
//
// Film position s in [0,1]^2 (top-left origin) starts at camera-space point
// (1 - 2 s.x, (1 - 2 s.y) / aspect, near_clip); every ray runs along camera +z.

#include "core/properties.h"
#include "core/registry.h"
#include "sensors/projective.h"

namespace candela {

class OrthographicCamera final : public ProjectiveCamera {
public:
    explicit OrthographicCamera(const Properties& props) : ProjectiveCamera(props) {
        Vec3 d = to_world_.apply_vector(Vec3(0.0f, 0.0f, 1.0f));
        if (!(squared_length(d) > 0.0f) || !to_world_.all_finite()) props.fail("to_world", "the camera's to_world must be invertible");
        direction_ = glm::normalize(d);
    }

    Ray sample_ray(const Vec2& film_pos, const Vec2&) const override {
        Vec2 s = film_fraction(film_pos);
        Vec3 local(1.0f - 2.0f * s.x, (1.0f - 2.0f * s.y) / aspect_, near_clip_);
        Ray ray;
        ray.o = to_world_.apply_point(local);
        ray.d = direction_;
        ray.tmin = 0.0f;
        ray.tmax = far_clip_ - near_clip_;
        return ray;
    }

    std::string to_string() const override { return "orthographic"; }

private:
    Vec3 direction_{0.0f, 0.0f, 1.0f};
};

CANDELA_REGISTER(OrthographicCamera, ObjectKind::Sensor, "orthographic");

}  // namespace candela
