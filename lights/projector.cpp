// projector: a pinhole that projects an image into the scene, the reciprocal of the
// `perspective` camera (Mitsuba 3's `projector` emitter).
//
// Parameters:
//   irradiance   rgb or texture   the projected image (default 1); a constant is a 1 x 1 image
//   scale        float            factor on the image (default 1)
//   to_world     transform        projector to world, without scaling: the pinhole sits at the
//                                 origin and projects along +z with +y up; camera +x maps to
//                                 the image's left, exactly as for the perspective camera
//   fov, focal_length, fov_axis   the field of view, as `perspective` (default 50mm), for the
//                                 image's aspect ratio (texture width / height)
//
// Mitsuba's convention, kept exactly so that scenes agree: a point p (projector space, z > 0)
// whose film position uv (PinholeProjection::film_position) lies in [0,1]^2 receives, on a
// surface facing the projector, the irradiance
//     E = pi * scale * T(uv) / (z^2 cos theta),   cos theta = z / |p|,
// so a plane perpendicular to the axis at depth z is lit with pi * scale * T(uv) / z^2. The
// intensity is pi scale T / cos^3 (the inverse of a pinhole camera's importance), and the flux is
// pi * scale * mean(T) * (2 tan(fov_x / 2)) * (2 tan(fov_y / 2)), the image plane at z = 1.

#include "core/emitter.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sensor.h"
#include "core/texture.h"
#include "lights/point_source.h"

namespace candela {

class ProjectorEmitter final : public Emitter {
public:
    explicit ProjectorEmitter(const Properties& props) {
        type_ = EmitterType::DeltaPosition;
        image_ = props.get_texture("irradiance", Spectrum(1.0f));
        scale_ = props.get_float("scale", 1.0f);
        if (!(scale_ >= 0.0f) || !std::isfinite(scale_)) props.fail("scale", "scale must be non-negative");
        Transform to_world = props.get_transform("to_world");
        if (to_world.has_scale()) props.fail("to_world", "the projector's to_world must not scale");
        Vec2i res = image_->resolution();
        projection_.to_world = to_world;
        projection_.aspect = float(res.x) / float(res.y);
        projection_.tan_half_x = read_tan_half_fov_x(props, projection_.aspect);
        world_to_local_ = to_world.inverse();
        position_ = to_world.apply_point(Vec3(0.0f));
        axis_ = glm::normalize(to_world.apply_vector(Vec3(0.0f, 0.0f, 1.0f)));
        float tan_x = projection_.tan_half_x, tan_y = tan_x / projection_.aspect;
        cos_corner_ = 1.0f / std::sqrt(1.0f + tan_x * tan_x + tan_y * tan_y);
        power_ = image_->mean() * (Pi * scale_ * 4.0f * tan_x * tan_y);
    }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2&, Spectrum& weight) const override {
        DirectionSample ds = sample_point_source(position_, ref, this);
        ds.n = axis_;
        weight = Spectrum(0.0f);
        Vec3 local = world_to_local_.apply_point(ref.p);
        if (!(local.z > 0.0f) || !(ds.dist > 0.0f)) return ds;
        Vec2 uv = projection_.film_position(local);
        if (!(uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f)) return ds;
        ds.uv = uv;
        float cos_theta = local.z / ds.dist;
        weight =
            rgb_at_wavelengths(image_->eval(uv), SpectrumRole::Emission, ref.wavelengths) * (Pi * scale_ / (local.z * local.z * cos_theta));
        return ds;
    }
    float pdf_direction(const SurfaceInteraction&, const DirectionSample&) const override { return 0.0f; }
    // Light paths leave through a point uniform on the image plane at depth 1 (area 4 tan_x tan_y):
    // solid-angle density 1 / (4 tan_x tan_y cos^3 theta), which the intensity pi scale T / cos^3
    // divides into the constant weight pi scale T(uv) 4 tan_x tan_y.
    EmitterRay sample_ray(const Vec2&, const Vec2& u_direction, Wavelengths* wavelengths, float) const override {
        Vec3 local = projection_.direction(u_direction);  // z = 1
        float len = glm::length(local), cos_theta = 1.0f / len;
        float image_area = 4.0f * projection_.tan_half_x * projection_.tan_half_x / projection_.aspect;
        Vec3 d = glm::normalize(projection_.to_world.apply_vector(local / len));
        EmitterRay r = point_source_ray(position_, d, 1.0f / (image_area * cos_theta * cos_theta * cos_theta), Spectrum(0.0f));
        r.uv = u_direction;
        r.weight = rgb_at_wavelengths(image_->eval(u_direction), SpectrumRole::Emission, wavelengths) * (Pi * scale_ * image_area);
        return r;
    }
    Spectrum eval(const SurfaceInteraction&) const override { return Spectrum(0.0f); }
    Spectrum power() const override { return power_; }
    std::optional<LightBounds> bounds() const override {
        LightBounds b;
        b.box.expand(position_);
        b.axis = axis_;
        b.cos_theta_o = cos_corner_;  // the frustum's corners
        b.cos_theta_e = 1.0f;         // nothing outside it
        b.phi = luminance(power_);
        return b;
    }
    std::string to_string() const override { return "projector"; }

private:
    Ref<Texture> image_;
    float scale_ = 1.0f, cos_corner_ = 0.0f;
    PinholeProjection projection_;
    Transform world_to_local_;
    Vec3 position_{0.0f}, axis_{0.0f, 0.0f, 1.0f};
    Spectrum power_{0.0f};
};

CANDELA_REGISTER_SPECTRAL(ProjectorEmitter, ObjectKind::Emitter, "projector");

}  // namespace candela
