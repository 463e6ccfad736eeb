// point: an isotropic point light.
//
// Parameters (Mitsuba 3, plus the raster mode's attenuation):
//   intensity                rgb         radiant intensity in W sr^-1 (default 1)
//   position                 point       location (or the translation of to_world)
//   to_world                 transform   alternative to position; or an animation
//                                        <animation name="to_world">: the light takes its
//                                        position at the time of the point it lights (motion
//                                        blur), or of ptracer's light path; the rasterizer: at
//                                        shutter_open
//   attenuation_constant,    float       the received radiance is intensity / (a0 + a1 d + a2 d^2);
//   attenuation_linear,                  defaults 0, 0, 1: the physical inverse-square law
//   attenuation_quadratic

#include "core/emitter.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/texture.h"
#include "core/warp.h"
#include "lights/point_source.h"

namespace candela {

class PointEmitter final : public Emitter {
public:
    explicit PointEmitter(const Properties& props) {
        type_ = EmitterType::DeltaPosition;
        intensity_ = props.get_rgb("intensity", Spectrum(1.0f));
        measured_ = props.measured_spectrum("intensity");
        if (props.has("position") && props.has("to_world")) props.fail("position", "give either position or to_world, not both");
        motion_ = props.has("position") ? AnimatedTransform(Transform::translate(props.get_point("position")))
                                        : props.get_animated_transform("to_world");
        position_ = motion_.first().apply_point(Vec3(0.0f));
        attenuation_ = Attenuation::read(props);
    }

    bool is_animated() const override { return motion_.is_animated(); }
    SourceLocation motion_location() const override { return motion_.where; }
    void set_scene(const Scene& scene) override {
        if (motion_.is_animated()) position_ = motion_.eval(scene.sensor().shutter_open()).apply_point(Vec3(0.0f));
    }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2&, Spectrum& weight) const override {
        const Vec3 position = motion_.is_animated() ? motion_.eval(ref.time).apply_point(Vec3(0.0f)) : position_;
        DirectionSample ds = sample_point_source(position, ref, this);
        weight = ds.dist > 0.0f ? emission_at(intensity_, measured_.get(), ref.wavelengths) * attenuation_(ds.dist) : Spectrum(0.0f);
        return ds;
    }
    float pdf_direction(const SurfaceInteraction&, const DirectionSample&) const override { return 0.0f; }
    // Light paths leave uniformly over the sphere.
    EmitterRay sample_ray(const Vec2&, const Vec2& u_direction, Wavelengths* wavelengths, float time) const override {
        const Vec3 position = motion_.is_animated() ? motion_.eval(time).apply_point(Vec3(0.0f)) : position_;
        return point_source_ray(position, warp::square_to_uniform_sphere(u_direction), InvFourPi,
                                emission_at(intensity_, measured_.get(), wavelengths));
    }
    float ray_attenuation(float dist) const override { return attenuation_.ray_factor(dist); }
    Spectrum eval(const SurfaceInteraction&) const override { return Spectrum(0.0f); }
    Spectrum power() const override { return FourPi * intensity_; }
    std::optional<LightBounds> bounds() const override {
        LightBounds b;
        b.box.expand(position_);
        if (motion_.is_animated()) {  // everywhere the light goes
            BoundingBox point;
            point.expand(Vec3(0.0f));
            b.box = motion_.bounds(point);
        }
        b.phi = luminance(power());
        return b;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override { expose_color(visitor, "intensity.value", intensity_); }
    // An edited colour replaces the measured spectrum the scene gave (the spectral variant uses it).
    void parameters_changed(const std::vector<std::string>&) override { measured_.reset(); }
    std::string to_string() const override { return "point"; }

    const Vec3& position() const { return position_; }
    const Spectrum& intensity() const { return intensity_; }
    const Attenuation& attenuation() const { return attenuation_; }

private:
    Spectrum intensity_;
    std::shared_ptr<const SpectrumTexture> measured_;  // the spectral variant's intensity, if measured
    AnimatedTransform motion_;
    Vec3 position_;  // at shutter_open
    Attenuation attenuation_;
};

CANDELA_REGISTER_SPECTRAL(PointEmitter, ObjectKind::Emitter, "point");

}  // namespace candela
