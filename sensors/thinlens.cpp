// thinlens: a perspective camera with a thin lens at a circular aperture, for depth of field
// (Mitsuba 3's `thinlens` sensor).
//
// Parameters (and those of every projective camera, sensors/projective.h):
//   aperture_radius   float       radius of the aperture in scene units (required; 0 gives a
//                                 pinhole: Mitsuba replaces 0 by a tiny radius)
//   focus_distance    float       distance from the aperture to the plane in focus, measured
//                                 along the view axis (default far_clip)
//   fov, focal_length, fov_axis   as `perspective` (default 50mm)
//   to_world          transform   camera to world, without scaling
//
// A film position chooses the point on the focal plane that a pinhole camera would see there;
// the ray runs from a uniformly sampled point of the aperture disk (concentric map) through it.
// A point at depth z images to a disk of diameter 2 a |z - f| / z on the focal plane (the
// circle of confusion), f the focus distance and a the aperture radius.

#include "core/properties.h"
#include "core/registry.h"
#include "core/warp.h"
#include "sensors/projective.h"

namespace candela {

class ThinLensCamera final : public ProjectiveCamera {
public:
    explicit ThinLensCamera(const Properties& props) : ProjectiveCamera(props) {
        if (to_world_.has_scale()) props.fail("to_world", "the camera's to_world must not scale");
        projection_.to_world = to_world_;
        projection_.tan_half_x = read_tan_half_fov_x(props, aspect_);
        projection_.aspect = aspect_;
        projection_.near_clip = near_clip_;
        projection_.far_clip = far_clip_;
        aperture_radius_ = props.get_float("aperture_radius");
        if (!(aperture_radius_ >= 0.0f) || !std::isfinite(aperture_radius_)) props.fail("aperture_radius", "aperture_radius must be non-negative");
    }

    Ray sample_ray(const Vec2& film_pos, const Vec2& aperture_u) const override {
        Vec3 focus = projection_.direction(film_fraction(film_pos)) * focus_distance_;  // z = focus distance
        Vec2 a = aperture_radius_ * warp::square_to_uniform_disk_concentric(aperture_u);
        Vec3 aperture(a.x, a.y, 0.0f);
        Vec3 d_local = glm::normalize(focus - aperture);
        Ray ray;
        ray.o = to_world_.apply_point(aperture);
        ray.d = glm::normalize(to_world_.apply_vector(d_local));
        float inv_z = 1.0f / d_local.z;
        ray.tmin = near_clip_ * inv_z;
        ray.tmax = far_clip_ * inv_z;
        return ray;
    }

    // With a zero aperture the camera is a pinhole, which the rasterizer can draw.
    std::optional<PinholeProjection> pinhole() const override {
        if (aperture_radius_ > 0.0f) return std::nullopt;
        return projection_;
    }

    std::string to_string() const override { return "thinlens"; }

private:
    PinholeProjection projection_;
    float aperture_radius_ = 0.0f;
};

CANDELA_REGISTER(ThinLensCamera, ObjectKind::Sensor, "thinlens");

}  // namespace candela
