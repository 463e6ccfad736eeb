// directional: a distant light arriving from one direction (the sun, idealised).
//
// Parameters (Mitsuba 3):
//   irradiance   rgb         irradiance in W m^-2 on a surface facing the light (default 1)
//   direction    vector      direction the light travels
//   to_world     transform   alternative: the light travels along to_world's +z

#include "core/emitter.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/texture.h"
#include "lights/scene_disk.h"

namespace candela {

class DirectionalEmitter final : public Emitter {
public:
    explicit DirectionalEmitter(const Properties& props) {
        type_ = EmitterType::DeltaDirection;
        irradiance_ = props.get_rgb("irradiance", Spectrum(1.0f));
        measured_ = props.measured_spectrum("irradiance");
        if (props.has("direction") && props.has("to_world")) props.fail("direction", "give either direction or to_world, not both");
        Vec3 d = props.has("direction") ? props.get_vector("direction") : props.get_transform("to_world").apply_vector(Vec3(0, 0, 1));
        if (!(squared_length(d) > 0.0f)) props.fail("direction", "the light's direction must not be zero");
        direction_ = glm::normalize(d);
    }

    void set_scene(const Scene& scene) override { disk_ = SceneDisk::around(scene.bbox()); }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2&, Spectrum& weight) const override {
        DirectionSample ds;
        ds.d = -direction_;
        ds.dist = Infinity;
        ds.p = ref.p - direction_ * (2.0f * disk_.radius);
        ds.n = direction_;
        ds.pdf = 1.0f;
        ds.delta = true;
        ds.emitter = this;
        weight = emission_at(irradiance_, measured_.get(), ref.wavelengths);
        return ds;
    }
    float pdf_direction(const SurfaceInteraction&, const DirectionSample&) const override { return 0.0f; }
    // Light paths start uniformly on the scene's bounding disk across the beam (lights/scene_disk.h).
    EmitterRay sample_ray(const Vec2& u_position, const Vec2&, Wavelengths* wavelengths, float) const override {
        EmitterRay r;
        r.ray = disk_.ray(direction_, u_position);
        r.pdf_position = 1.0f / disk_.area();
        r.pdf_direction = 1.0f;
        r.delta_direction = true;
        r.weight = emission_at(irradiance_, measured_.get(), wavelengths) * disk_.area();
        return r;
    }
    Spectrum eval(const SurfaceInteraction&) const override { return Spectrum(0.0f); }
    // Flux through the disk the scene presents to the light.
    Spectrum power() const override { return irradiance_ * disk_.area(); }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override { expose_color(visitor, "irradiance.value", irradiance_); }
    // An edited colour replaces the measured spectrum the scene gave (the spectral variant uses it).
    void parameters_changed(const std::vector<std::string>&) override { measured_.reset(); }
    std::string to_string() const override { return "directional"; }

    const Vec3& direction() const { return direction_; }
    const Spectrum& irradiance() const { return irradiance_; }

private:
    Spectrum irradiance_;
    std::shared_ptr<const SpectrumTexture> measured_;  // the spectral variant's irradiance, if measured
    Vec3 direction_;
    SceneDisk disk_;
};

CANDELA_REGISTER_SPECTRAL(DirectionalEmitter, ObjectKind::Emitter, "directional");

}  // namespace candela
