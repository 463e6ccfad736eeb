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
        refuse_scaling(props);
        projection_ = pinhole_projection(props);
        aperture_radius_ = props.get_float("aperture_radius");
        if (!(aperture_radius_ >= 0.0f) || !std::isfinite(aperture_radius_))
            props.fail("aperture_radius", "aperture_radius must be non-negative");
    }

    Ray sample_ray(const Vec2& film_pos, const Vec2& aperture_u, float time) const override {
        Vec3 focus = projection_.direction(film_fraction(film_pos)) * focus_distance_;  // z = focus distance
        Vec2 a = aperture_radius_ * warp::square_to_uniform_disk_concentric(aperture_u);
        Vec3 aperture(a.x, a.y, 0.0f);
        Vec3 d_local = glm::normalize(focus - aperture);
        Transform pose = pose_at(time);
        Ray ray;
        ray.time = time;
        ray.o = pose.apply_point(aperture);
        ray.d = glm::normalize(pose.apply_vector(d_local));
        float inv_z = 1.0f / d_local.z;
        ray.tmin = near_clip_ * inv_z;
        ray.tmax = far_clip_ * inv_z;
        return ray;
    }

    // Light tracing: a lens point uniform on the aperture, then the film position whose ray from
    // that lens point passes through `ref` (where the line meets the focal plane). The lens
    // density 1 / (pi a^2) cancels against the camera's own averaging over the aperture, so the
    // weight is the pinhole's, measured from the lens point.
    SensorSample sample_direction(const Vec3& ref, const Vec2& aperture_u, float time) const override {
        const Transform pose = pose_at(time);
        Vec3 local = pose.inverse().apply_point(ref);
        if (!(local.z > near_clip_ && local.z < far_clip_)) return SensorSample();
        Vec2 a = aperture_radius_ * warp::square_to_uniform_disk_concentric(aperture_u);
        Vec3 lens(a.x, a.y, 0.0f);
        Vec3 focus = lens + (local - lens) * (focus_distance_ / local.z);
        Vec2 fraction = projection_.film_position(focus);
        if (!on_film(fraction)) return SensorSample();
        SensorSample s = lens_connection(ref, local, lens, fraction, projection_.tan_half_x, pose);
        if (aperture_radius_ > 0.0f && s.pdf > 0.0f) {
            // Solid-angle density at ref of the lens point: (1 / (pi a^2)) r^2 / cos theta.
            Vec3 v = local - lens;
            float r2 = squared_length(v);
            s.pdf = r2 / (Pi * aperture_radius_ * aperture_radius_ * (v.z / std::sqrt(r2)));
            s.delta = false;
        }
        return s;
    }

    // With a zero aperture the camera is a pinhole, which the rasterizer can draw.
    std::optional<PinholeProjection> pinhole() const override {
        if (aperture_radius_ > 0.0f) return std::nullopt;
        return projection_;
    }

    // to_world, x_fov (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        ProjectiveCamera::traverse(visitor);
        expose_x_fov(visitor, projection_);
    }
    void pose_changed() override { projection_.to_world = to_world_; }
    void film_size_changed() override { projection_.aspect = aspect_; }

    std::string to_string() const override { return "thinlens"; }

private:
    PinholeProjection projection_;
    float aperture_radius_ = 0.0f;
};

CANDELA_REGISTER(ThinLensCamera, ObjectKind::Sensor, "thinlens");

}  // namespace candela
