// constant: a uniform environment, the same radiance from every direction.
//
// Parameters:
//   radiance   rgb   radiance in W m^-2 sr^-1 (default 1)
// Sampled uniformly over the sphere (pdf 1 / 4pi), as in Mitsuba 3.

#include "core/emitter.h"
#include "core/local_model.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/warp.h"

namespace candela {

class ConstantEmitter final : public Emitter {
public:
    explicit ConstantEmitter(const Properties& props) {
        type_ = EmitterType::Infinite;
        radiance_ = props.get_rgb("radiance", Spectrum(1.0f));
    }

    void set_scene(const Scene& scene) override { scene_radius_ = std::max(scene.bbox().bounding_radius(), 1e-3f); }

    Spectrum eval(const SurfaceInteraction&) const override { return radiance_; }
    Spectrum eval_environment(const Vec3&) const override { return radiance_; }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2& u, Spectrum& weight) const override {
        DirectionSample ds;
        ds.d = warp::square_to_uniform_sphere(u);
        ds.dist = Infinity;
        ds.p = ref.p + ds.d * (2.0f * scene_radius_);
        ds.n = -ds.d;
        ds.pdf = InvFourPi;
        ds.emitter = this;
        weight = radiance_ * FourPi;
        return ds;
    }

    float pdf_direction(const SurfaceInteraction&, const DirectionSample&) const override { return InvFourPi; }

    // Flux through the scene's bounding sphere: L * 4pi * (pi r^2).
    Spectrum power() const override { return radiance_ * (FourPi * Pi * scene_radius_ * scene_radius_); }
    // Local model: uniform ambient radiance.
    std::optional<LocalApproximation> local_approximation() const override {
        LocalApproximation a;
        a.kind = LocalApproximation::Kind::Ambient;
        a.radiance = radiance_;
        return a;
    }
    std::string to_string() const override { return "constant"; }

private:
    Spectrum radiance_;
    float scene_radius_ = 1.0f;
};

CANDELA_REGISTER(ConstantEmitter, ObjectKind::Emitter, "constant");

}  // namespace candela
