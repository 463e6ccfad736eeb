// constant: a uniform environment, the same radiance from every direction.
//
// Parameters:
//   radiance   rgb   radiance in W m^-2 sr^-1 (default 1)
// Sampled uniformly over the sphere (pdf 1 / 4pi), as in Mitsuba 3.

#include "core/emitter.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/texture.h"
#include "core/warp.h"
#include "lights/scene_disk.h"

namespace candela {

class ConstantEmitter final : public Emitter {
public:
    explicit ConstantEmitter(const Properties& props) {
        type_ = EmitterType::Infinite;
        radiance_ = props.get_rgb("radiance", Spectrum(1.0f));
        measured_ = props.measured_spectrum("radiance");
    }

    void set_scene(const Scene& scene) override { disk_ = SceneDisk::around(scene.bbox()); }

    Spectrum eval(const SurfaceInteraction& si) const override { return emission_at(radiance_, measured_.get(), si.wavelengths); }
    Spectrum eval_environment(const Vec3&, const Wavelengths* w, float) const override {
        return emission_at(radiance_, measured_.get(), w);
    }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2& u, Spectrum& weight) const override {
        DirectionSample ds;
        ds.d = warp::square_to_uniform_sphere(u);
        ds.dist = Infinity;
        ds.p = ref.p + ds.d * (2.0f * disk_.radius);
        ds.n = -ds.d;
        ds.pdf = InvFourPi;
        ds.emitter = this;
        weight = emission_at(radiance_, measured_.get(), ref.wavelengths) * FourPi;
        return ds;
    }

    float pdf_direction(const SurfaceInteraction&, const DirectionSample&) const override { return InvFourPi; }

    // Flux through the scene's bounding disk: L * 4pi * (pi r^2).
    Spectrum power() const override { return radiance_ * (FourPi * disk_.area()); }
    // Light paths: a direction uniform over the sphere, then a point on the bounding disk across it.
    EmitterRay sample_ray(const Vec2& u_position, const Vec2& u_direction, Wavelengths* wavelengths, float) const override {
        EmitterRay r;
        r.ray = disk_.ray(warp::square_to_uniform_sphere(u_direction), u_position);
        r.pdf_position = 1.0f / disk_.area();
        r.pdf_direction = InvFourPi;
        r.weight = emission_at(radiance_, measured_.get(), wavelengths) * (FourPi * disk_.area());
        return r;
    }
    // Local model: uniform ambient radiance.
    std::optional<LocalApproximation> local_approximation() const override {
        LocalApproximation a;
        a.kind = LocalApproximation::Kind::Ambient;
        a.radiance = radiance_;
        return a;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override { expose_color(visitor, "radiance.value", radiance_); }
    // An edited colour replaces the measured spectrum the scene gave (the spectral variant uses it).
    void parameters_changed(const std::vector<std::string>&) override { measured_.reset(); }
    std::string to_string() const override { return "constant"; }

private:
    Spectrum radiance_;
    std::shared_ptr<const SpectrumTexture> measured_;  // the spectral variant's radiance, if measured
    SceneDisk disk_;
};

CANDELA_REGISTER_SPECTRAL(ConstantEmitter, ObjectKind::Emitter, "constant");

}  // namespace candela
