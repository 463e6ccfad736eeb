#pragma once
// The emitter interface. `sample_direction` picks a point on (or a direction toward) the
// emitter as seen from a reference point; `eval` is the radiance leaving the emitter toward a
// viewer; `power` guides light selection. Area emitters emit on the front side only.

#include "core/object.h"
#include "core/shape.h"
#include "core/spectrum.h"

#include <optional>

namespace candela {

class Scene;
struct LocalApproximation;

enum class EmitterType { DeltaPosition, DeltaDirection, Area, Infinite };

// Where and in which directions an emitter sends its power, for many-light sampling (Conty &
// Kulla 2018; pbrt-v4's LightBounds): it emits `phi` (luminance of its flux) from inside `box`,
// along directions within theta_o of `axis`, falling off to zero over a further theta_e.
struct LightBounds {
    BoundingBox box;
    Vec3 axis{0.0f, 0.0f, 1.0f};
    float cos_theta_o = -1.0f;  // -1: all directions
    float cos_theta_e = 0.0f;   // cos(pi / 2): a cosine falloff
    float phi = 0.0f;
    bool two_sided = false;
};

class Emitter : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Emitter; }

    // `weight` receives radiance / pdf (for delta lights: intensity / dist^2 or irradiance).
    // A failed sample has pdf 0.
    virtual DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2& u, Spectrum& weight) const = 0;
    // Solid-angle density of sampling `ds` (built by an intersection or by sample_direction).
    virtual float pdf_direction(const SurfaceInteraction& ref, const DirectionSample& ds) const = 0;
    // Radiance leaving the emitter toward the viewer at `si.wi_world()`: for area emitters `si`
    // is the surface hit; for infinite ones only the direction matters.
    virtual Spectrum eval(const SurfaceInteraction& si) const = 0;
    // Radiance arriving along a ray that escaped the scene in direction `d` (infinite emitters).
    virtual Spectrum eval_environment(const Vec3& d) const { return Spectrum(0.0f); }
    // Emitted flux in W (approximate where exact is costly); used to pick lights.
    virtual Spectrum power() const = 0;
    // The rasterizer's local-model view (core/local_model.h); delta lights have none (the
    // rasterizer evaluates them exactly through sample_direction), nor do emitters it ignores.
    virtual std::optional<LocalApproximation> local_approximation() const;

    // Spatial and directional bounds of the emission; infinite emitters have none.
    virtual std::optional<LightBounds> bounds() const { return std::nullopt; }

    EmitterType type() const { return type_; }
    bool is_delta() const { return type_ == EmitterType::DeltaPosition || type_ == EmitterType::DeltaDirection; }
    bool is_infinite() const { return type_ == EmitterType::Infinite; }

    // Called by the scene once everything is loaded: infinite lights learn the scene's bounds,
    // area lights their shape.
    virtual void set_scene(const Scene& scene) {}
    virtual void set_shape(const Shape* shape) {}
    const Shape* shape() const { return shape_; }

protected:
    EmitterType type_ = EmitterType::Area;
    const Shape* shape_ = nullptr;
};

}  // namespace candela
