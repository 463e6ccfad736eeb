#pragma once
// The emitter interface. `sample_direction` picks a point on (or a direction toward) the
// emitter as seen from a reference point; `sample_ray` starts a light path (a position and a
// direction of emission); `eval` is the radiance leaving the emitter toward a viewer; `power`
// guides light selection. Area emitters emit on the front side only.

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

// A ray of emitted light, sampled by position and direction (Mitsuba's Emitter::sample_ray,
// pbrt-v4's SampleLe), to start the light paths of particle tracing and photon mapping.
struct EmitterRay {
    Ray ray;                     // starts exactly on the emitter (not offset); unit direction
    Vec3 n{0.0f};                // the emitter's normal at the origin (zero for point and infinite emitters)
    float p_error = 0.0f;        // bound on the error of each coordinate of the origin
    Vec2 uv{0.0f};               // surface uv of the origin (area emitters)
    float pdf_position = 0.0f;   // per unit area (1 for a delta in position; infinite emitters:
                                 // per unit area of the disk the rays start from)
    float pdf_direction = 0.0f;  // per unit solid angle (1 for a delta in direction)
    bool delta_position = false, delta_direction = false;
    // Le |cos| / (pdf_position pdf_direction): the flux this ray carries, in W. Its mean over the
    // samples is power(); infinite emitters send their flux through the scene's bounding disk.
    Spectrum weight{0.0f};
    bool valid() const { return pdf_position > 0.0f && pdf_direction > 0.0f; }
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
    // Radiance arriving along a ray that escaped the scene in direction `d` (infinite emitters), at
    // the ray's time (an environment that changes over the shutter: timed_sunsky).
    virtual Spectrum eval_environment(const Vec3& d, const Wavelengths* wavelengths, float time) const { return Spectrum(0.0f); }
    // eval_environment(d) and the pdf_direction() of direction `d` from `ref` together (MIS at a ray
    // that escaped): an emitter whose two share work (an environment map's coordinates of `d`)
    // overrides it to do that work once.
    virtual Spectrum eval_environment_pdf(const SurfaceInteraction& ref, const Vec3& d, float& pdf) const {
        DirectionSample ds;
        ds.d = d;
        ds.dist = Infinity;
        pdf = pdf_direction(ref, ds);
        return eval_environment(d, ref.wavelengths, ref.time);
    }
    // Emitted flux in W (approximate where exact is costly); used to pick lights.
    virtual Spectrum power() const = 0;
    // A ray leaving the emitter: the origin from `u_position`, the direction from `u_direction`.
    // A failed sample is not valid().
    // `wavelengths`: the light path's, in the spectral variant (null in RGB): the weight is at them.
    // `time`: the light path's shutter time (Mitsuba's sample_ray(time, ...)): a moving emitter
    // takes its pose then. The returned ray's own time is the caller's to set.
    virtual EmitterRay sample_ray(const Vec2& u_position, const Vec2& u_direction, Wavelengths* wavelengths, float time) const = 0;
    // The factor on the flux of a sample_ray ray where it first meets a surface at distance
    // `dist`: 1 for physical emitters; point and spot lights with the lecture's distance
    // attenuation give d^2 / (a0 + a1 d + a2 d^2), the ratio of their law to the inverse square.
    virtual float ray_attenuation(float dist) const { return 1.0f; }
    // The rasterizer's local-model view (core/local_model.h); delta lights have none (the
    // rasterizer evaluates them exactly through sample_direction), nor do emitters it ignores.
    virtual std::optional<LocalApproximation> local_approximation() const;

    // Spatial and directional bounds of the emission; infinite emitters have none.
    virtual std::optional<LightBounds> bounds() const { return std::nullopt; }

    // Whether the emitter moves (an animated to_world: point and spot lights, and area lights on
    // a moving shape); it then takes its pose at the reference point's time
    // (SurfaceInteraction::time).
    virtual bool is_animated() const { return false; }
    virtual SourceLocation motion_location() const { return {}; }

    // An area emitter on a shape with an animated to_world: the loader builds the shape still, as
    // the only member of a shape group moved by an instance (create_moving_shape in
    // core/xml.cpp). move_with_instance() lets that group hold it (shape groups refuse emitters
    // otherwise); set_motion gives it the instance's motion, by which it places its shape, which
    // lives in the group's space, at each reference point's time.
    void move_with_instance() { moves_with_instance_ = true; }
    bool moves_with_instance() const { return moves_with_instance_; }
    virtual void set_motion(const AnimatedTransform* motion) {}

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
    bool moves_with_instance_ = false;
};

}  // namespace candela
