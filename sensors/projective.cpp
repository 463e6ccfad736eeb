#include "sensors/projective.h"

#include "core/error.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/registry.h"

namespace candela {

ProjectiveCamera::ProjectiveCamera(const Properties& props) : Sensor(props) {
    motion_ = props.get_animated_transform("to_world", Transform());
    to_world_ = motion_.is_animated() ? motion_.eval(shutter_open_) : motion_.first();
    take_size(film_->full_size());

    near_clip_ = props.get_float("near_clip", 0.01f);
    far_clip_ = props.get_float("far_clip", 10000.0f);
    if (!(near_clip_ > 0.0f)) props.fail("near_clip", "near_clip must be greater than zero");
    if (!(far_clip_ > near_clip_)) props.fail("far_clip", "far_clip must be greater than near_clip");
    focus_distance_ = props.get_float("focus_distance", far_clip_);
    if (!(focus_distance_ > 0.0f)) props.fail("focus_distance", "focus_distance must be positive");

    jitter_ = props.get_bool("jitter", true);
    if (!(props.get_float("cone_scale", 1.0f) > 0.0f)) props.fail("cone_scale", "cone_scale must be positive");
}

void ProjectiveCamera::set_film_size(const Vec2i& size) {
    take_size(size);
    film_size_changed();
}

void ProjectiveCamera::take_size(const Vec2i& size) {
    aspect_ = float(size.x) / float(size.y);
    inv_size_ = Vec2(1.0f / float(size.x), 1.0f / float(size.y));
}

PinholeProjection ProjectiveCamera::pinhole_projection(const Properties& props) const {
    PinholeProjection p;
    p.to_world = to_world_;
    p.tan_half_x = read_tan_half_fov_x(props, aspect_);
    p.aspect = aspect_;
    p.near_clip = near_clip_;
    p.far_clip = far_clip_;
    return p;
}

void ProjectiveCamera::refuse_scaling(const Properties& props) const {
    for (const auto& key : motion_.keyframes())
        if (key.transform.has_scale()) props.fail("to_world", "the camera's to_world must not scale");
}

SensorSample ProjectiveCamera::lens_connection(const Vec3& ref, const Vec3& local, const Vec3& lens, const Vec2& fraction, float tan_half_x,
                                               const Transform& pose) const {
    SensorSample s;
    Vec3 v = local - lens;  // camera space, from the lens point toward the reference point
    float r2 = squared_length(v), r = std::sqrt(r2);
    float cos_theta = v.z / r;
    if (!(cos_theta > 0.0f) || !(r > 0.0f)) return s;
    float image_area = 4.0f * tan_half_x * tan_half_x / aspect_;
    s.weight = film_area() / (image_area * cos_theta * cos_theta * cos_theta * r2);
    // The camera ray starts where it crosses the near plane (z = near_clip).
    s.p = pose.apply_point(lens + v * (near_clip_ / v.z));
    Vec3 to_sensor = s.p - ref;
    s.dist = glm::length(to_sensor);
    if (!(s.dist > 0.0f)) return SensorSample();
    s.d = to_sensor / s.dist;
    s.film_pos = film_pixels(fraction);
    s.pdf = 1.0f;
    s.delta = true;
    return s;
}

void ProjectiveCamera::traverse(ParameterVisitor& visitor) {
    if (!motion_.is_animated()) expose_transform(visitor, "to_world", to_world_);
    visitor.object("film", film_.get());
}

void ProjectiveCamera::parameters_changed(const std::vector<std::string>& keys) {
    if (std::find(keys.begin(), keys.end(), "to_world") == keys.end()) return;
    motion_ = AnimatedTransform(to_world_);
    pose_changed();
}

void ProjectiveCamera::expose_x_fov(ParameterVisitor& visitor, PinholeProjection& projection) {
    visitor.value("x_fov", ParameterAccess{ParameterType::Float,
                                           [&projection] { return std::vector<float>{degrees(2.0f * std::atan(projection.tan_half_x))}; },
                                           [&projection](const std::vector<float>& v) {
                                               if (!(v.at(0) > 0.0f && v.at(0) < 180.0f))
                                                   throw InputError("x_fov must lie between 0 and 180 degrees");
                                               projection.tan_half_x = std::tan(radians(v.at(0)) * 0.5f);
                                           }});
}

}  // namespace candela
