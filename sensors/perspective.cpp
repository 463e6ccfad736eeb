// perspective: a pinhole camera (Mitsuba 3's `perspective` sensor).
//
// Parameters (and those of every projective camera, sensors/projective.h):
//   to_world                   transform   camera to world, without scaling; the camera looks
//                                          down +z with +y up, and camera +x maps to the left of
//                                          the image (Mitsuba's convention)
//   fov                        float       field of view in degrees along fov_axis
//   focal_length               string      alternative to fov: 35mm-equivalent focal length, e.g.
//                                          "50mm", spanning the 36x24 mm frame's diagonal (the
//                                          default, 50mm, when neither is given)
//   fov_axis                   string      with fov: x (default), y, diagonal, smaller or larger
//   principal_point_offset_x,  float       shift of the image centre in fractions of the film's
//   principal_point_offset_y               width and height (default 0): film position s looks
//                                          where s + offset would look unshifted
//   focus_distance             float       accepted, no effect (a pinhole has no focus)
//
// A film position s in [0,1]^2 (top-left origin), t = s + offset, looks along the camera-space
// direction ((1 - 2 t.x) tan(fov_x / 2), (1 - 2 t.y) tan(fov_x / 2) / aspect, 1). Light tracers
// connect to the pinhole (sample_direction) with the importance of that map: film pixels per
// solid angle, W H / (4 tan(fov_x / 2) tan(fov_y / 2) cos^3 theta).

#include "core/properties.h"
#include "core/registry.h"
#include "sensors/projective.h"

namespace candela {

class PerspectiveCamera final : public ProjectiveCamera {
public:
    explicit PerspectiveCamera(const Properties& props) : ProjectiveCamera(props) {
        refuse_scaling(props);
        projection_ = pinhole_projection(props);
        projection_.principal_point_offset =
            Vec2(props.get_float("principal_point_offset_x", 0.0f), props.get_float("principal_point_offset_y", 0.0f));
        origin_ = to_world_.apply_point(Vec3(0.0f));
    }

    Ray sample_ray(const Vec2& film_pos, const Vec2&, float time) const override {
        // Camera space, scaled to depth 1: one normalisation, after to_world (which may scale).
        Vec3 d_local = projection_.direction(film_fraction(film_pos));
        Ray ray;
        ray.time = time;
        if (motion_.is_animated()) {
            Transform pose = pose_at(time);
            ray.o = pose.apply_point(Vec3(0.0f));
            ray.d = glm::normalize(pose.apply_vector(d_local));
        } else {
            ray.o = origin_;
            ray.d = glm::normalize(to_world_.apply_vector(d_local));
        }
        // Clip planes are at camera-space depths, so the ray parameter depends on the angle: depth
        // z lies at distance z |d_local| along the ray, as d_local has depth 1.
        float length_per_depth = glm::length(d_local);
        ray.tmin = near_clip_ * length_per_depth;
        ray.tmax = far_clip_ * length_per_depth;
        return ray;
    }

    SensorSample sample_direction(const Vec3& ref, const Vec2&, float time) const override {
        const Transform pose = pose_at(time);
        Vec3 local = pose.inverse().apply_point(ref);
        if (!(local.z > near_clip_ && local.z < far_clip_)) return SensorSample();
        Vec2 fraction = projection_.film_position(local);
        if (!on_film(fraction)) return SensorSample();
        return lens_connection(ref, local, Vec3(0.0f), fraction, projection_.tan_half_x, pose);
    }

    std::optional<PinholeProjection> pinhole() const override { return projection_; }
    void film_size_changed() override { projection_.aspect = aspect_; }

    // to_world, x_fov (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        ProjectiveCamera::traverse(visitor);
        expose_x_fov(visitor, projection_);
    }
    void pose_changed() override {
        projection_.to_world = to_world_;
        origin_ = to_world_.apply_point(Vec3(0.0f));
    }

    std::string to_string() const override { return "perspective"; }

private:
    PinholeProjection projection_;
    Vec3 origin_{0.0f};
};

CANDELA_REGISTER(PerspectiveCamera, ObjectKind::Sensor, "perspective");

}  // namespace candela
