// perspective: a pinhole camera (Mitsuba 3's `perspective` sensor).
//
// Parameters:
//   to_world       transform   camera to world; the camera looks down +z with +y up, and camera
//                              +x maps to the left of the image (Mitsuba's convention)
//   fov            float       field of view in degrees along fov_axis
//   focal_length   string      alternative to fov: 35mm-equivalent focal length, e.g. "50mm",
//                              measured on the 36x24 mm diagonal (default when neither is
//                              given: 50mm; fov_axis then defaults to diagonal)
//   fov_axis       string      x (default), y, diagonal, smaller or larger
//   near_clip      float       distance of the near plane (default 0.01)
//   far_clip       float       distance of the far plane (default 10000)
//   film, sampler  nested      default: hdrfilm and independent
//
// A film position (sx, sy) in [0,1]^2 (top-left origin) looks along the camera-space direction
// ((1 - 2 sx) tan(fov_x / 2), (1 - 2 sy) tan(fov_x / 2) / aspect, 1), aspect = width / height.

#include "core/properties.h"
#include "core/registry.h"
#include "core/sensor.h"

namespace candela {

class PerspectiveCamera final : public Sensor {
public:
    explicit PerspectiveCamera(const Properties& props) {
        to_world_ = props.get_transform("to_world", Transform());
        auto films = props.get_objects(ObjectKind::Film);
        auto samplers = props.get_objects(ObjectKind::Sampler);
        if (films.size() > 1 || samplers.size() > 1) props.fail("a sensor has at most one film and one sampler");
        film_ = films.empty() ? create_plugin_as<Film>(ObjectKind::Film, Properties("hdrfilm", props.location()))
                              : std::static_pointer_cast<Film>(films[0]);
        sampler_ = samplers.empty() ? create_plugin_as<Sampler>(ObjectKind::Sampler, Properties("independent", props.location()))
                                    : std::static_pointer_cast<Sampler>(samplers[0]);

        Vec2i size = film_->full_size();
        aspect_ = float(size.x) / float(size.y);

        float fov;
        std::string default_axis = "x";
        if (props.has("fov")) {
            if (props.has("focal_length")) props.fail("focal_length", "give either fov or focal_length, not both");
            fov = props.get_float("fov");
        } else {
            std::string f = props.get_string("focal_length", "50mm");
            float mm = 0.0f;
            try {
                size_t used = 0;
                mm = std::stof(f, &used);
                std::string unit = f.substr(used);
                if (!(unit.empty() || unit == "mm")) throw std::invalid_argument(f);
            } catch (const std::exception&) {
                props.fail("focal_length", "focal_length must look like \"50mm\", not \"" + f + "\"");
            }
            // As Mitsuba: the focal length fixes the fov along the 36x24 mm frame's diagonal.
            fov = degrees(2.0f * std::atan(std::sqrt(36.0f * 36.0f + 24.0f * 24.0f) / (2.0f * mm)));
            default_axis = "diagonal";
        }
        if (!(fov > 0.0f && fov < 180.0f)) props.fail("fov", "fov must be in (0, 180) degrees");
        float t = std::tan(radians(fov) * 0.5f);
        std::string axis = props.get_string("fov_axis", default_axis);
        if (axis == "smaller") axis = aspect_ > 1.0f ? "y" : "x";
        if (axis == "larger") axis = aspect_ > 1.0f ? "x" : "y";
        if (axis == "x") tan_half_x_ = t;
        else if (axis == "y") tan_half_x_ = t * aspect_;
        else if (axis == "diagonal") tan_half_x_ = t * aspect_ / std::sqrt(1.0f + aspect_ * aspect_);
        else props.fail("fov_axis", "fov_axis must be x, y, diagonal, smaller or larger, not \"" + axis + "\"");

        if (to_world_.has_scale()) props.fail("to_world", "the camera's to_world must not scale");
        near_clip_ = props.get_float("near_clip", 0.01f);
        far_clip_ = props.get_float("far_clip", 10000.0f);
        if (!(near_clip_ > 0.0f && far_clip_ > near_clip_)) props.fail("near_clip", "need 0 < near_clip < far_clip");
        inv_size_ = Vec2(1.0f / float(size.x), 1.0f / float(size.y));
        origin_ = to_world_.apply_point(Vec3(0.0f));
    }

    Ray sample_ray(const Vec2& film_pos, const Vec2&) const override {
        Vec2 s = film_pos * inv_size_;
        Vec3 local((1.0f - 2.0f * s.x) * tan_half_x_, (1.0f - 2.0f * s.y) * tan_half_x_ / aspect_, 1.0f);
        Vec3 d_local = glm::normalize(local);
        Ray ray;
        ray.o = origin_;
        ray.d = glm::normalize(to_world_.apply_vector(d_local));
        // Clip planes are at camera-space depths, so the ray parameter depends on the angle.
        float inv_z = 1.0f / d_local.z;
        ray.tmin = near_clip_ * inv_z;
        ray.tmax = far_clip_ * inv_z;
        return ray;
    }

    std::optional<PinholeProjection> pinhole() const override {
        PinholeProjection p;
        p.to_world = to_world_;
        p.tan_half_x = tan_half_x_;
        p.aspect = aspect_;
        p.near_clip = near_clip_;
        p.far_clip = far_clip_;
        return p;
    }

    std::string to_string() const override { return "perspective"; }

private:
    float aspect_ = 1.0f, tan_half_x_ = 1.0f, near_clip_ = 0.01f, far_clip_ = 1e4f;
    Vec2 inv_size_{1.0f};
    Vec3 origin_{0.0f};
};

CANDELA_REGISTER(PerspectiveCamera, ObjectKind::Sensor, "perspective");

}  // namespace candela
