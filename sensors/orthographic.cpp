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

    // The viewed rectangle's area across the view direction (to_world may scale or shear).
    void film_size_changed() override {
        Vec3 ex = to_world_.apply_vector(Vec3(2.0f, 0.0f, 0.0f)), ey = to_world_.apply_vector(Vec3(0.0f, 2.0f / aspect_, 0.0f));
        cross_section_ = std::abs(glm::dot(glm::cross(ex, ey), direction_));
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
    SensorSample sample_direction(const Vec3& ref, const Vec2&) const override {
        SensorSample s;
        Vec3 local = world_to_local_.apply_point(ref);
        Vec2 fraction(0.5f - 0.5f * local.x, 0.5f - 0.5f * local.y * aspect_);
        if (!(local.z > near_clip_) || !on_film(fraction)) return s;
        s.p = to_world_.apply_point(Vec3(local.x, local.y, near_clip_));
        s.dist = glm::length(ref - s.p);
        if (!(s.dist > 0.0f && s.dist < far_clip_ - near_clip_)) return SensorSample();
        s.d = -direction_;
        s.film_pos = film_pixels(fraction);
        s.pdf = 1.0f;
        s.delta = true;
        s.weight = film_area() / cross_section_;
        return s;
    }

    std::string to_string() const override { return "orthographic"; }

private:
    Vec3 direction_{0.0f, 0.0f, 1.0f};
    float cross_section_ = 4.0f;
};

CANDELA_REGISTER(OrthographicCamera, ObjectKind::Sensor, "orthographic");

}  // namespace candela
