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
// (1 - 2 s.x, (1 - 2 s.y) / aspect, near_clip); every ray runs along camera +z. Light tracers
// connect along that axis with the importance W H / (the viewed rectangle's cross-section).

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
        film_size_changed();
        if (!(cross_section_ > 0.0f)) props.fail("to_world", "the camera's to_world must be invertible");
    }

    void film_size_changed() override { cross_section_ = cross_section(to_world_, direction_); }
    // The viewed rectangle's area across the view direction `direction` of pose `to_world` (it
    // may scale or shear).
    float cross_section(const Transform& to_world, const Vec3& direction) const {
        Vec3 ex = to_world.apply_vector(Vec3(2.0f, 0.0f, 0.0f)), ey = to_world.apply_vector(Vec3(0.0f, 2.0f / aspect_, 0.0f));
        return std::abs(glm::dot(glm::cross(ex, ey), direction));
    }

    Ray sample_ray(const Vec2& film_pos, const Vec2&, float time) const override {
        Vec2 s = film_fraction(film_pos);
        Vec3 local(1.0f - 2.0f * s.x, (1.0f - 2.0f * s.y) / aspect_, near_clip_);
        Ray ray;
        ray.time = time;
        if (motion_.is_animated()) {
            Transform pose = pose_at(time);
            ray.o = pose.apply_point(local);
            ray.d = glm::normalize(pose.apply_vector(Vec3(0.0f, 0.0f, 1.0f)));
        } else {
            ray.o = to_world_.apply_point(local);
            ray.d = direction_;
        }
        ray.tmin = 0.0f;
        ray.tmax = far_clip_ - near_clip_;
        return ray;
    }

    // Light tracing: the one ray that reaches `ref` runs along the view axis; its importance is
    // film pixels per unit area across the beam, W H / (viewed cross-section).
    // An animated camera connects with its pose at `time`: the view axis and the cross-section
    // are that pose's (a still camera's are direction_ and cross_section_, computed alike).
    SensorSample sample_direction(const Vec3& ref, const Vec2&, float time) const override {
        SensorSample s;
        const Transform pose = pose_at(time);
        Vec3 local = pose.inverse().apply_point(ref);
        Vec2 fraction(0.5f - 0.5f * local.x, 0.5f - 0.5f * local.y * aspect_);
        if (!(local.z > near_clip_) || !on_film(fraction)) return s;
        s.p = pose.apply_point(Vec3(local.x, local.y, near_clip_));
        const Vec3 direction = glm::normalize(pose.apply_vector(Vec3(0.0f, 0.0f, 1.0f)));
        const float viewed = cross_section(pose, direction);
        s.dist = glm::length(ref - s.p);
        if (!(s.dist > 0.0f && s.dist < far_clip_ - near_clip_) || !(viewed > 0.0f)) return SensorSample();
        s.d = -direction;
        s.film_pos = film_pixels(fraction);
        s.pdf = 1.0f;
        s.delta = true;
        s.weight = film_area() / viewed;
        return s;
    }

    std::string to_string() const override { return "orthographic"; }

private:
    Vec3 direction_{0.0f, 0.0f, 1.0f};
    float cross_section_ = 4.0f;
};

CANDELA_REGISTER(OrthographicCamera, ObjectKind::Sensor, "orthographic");

}  // namespace candela
