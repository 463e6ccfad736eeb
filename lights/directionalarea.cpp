// directionalarea: turns the shape it is nested in into a light that emits only along its
// normal, a beam with the shape's cross-section (Mitsuba 3's `directionalarea` emitter).
//
// Parameters:
//   radiance   rgb or texture   emitted radiance in W m^-2 sr^-1 (default 1); a texture is looked
//                               up by the shape's uv
//
// Mitsuba's convention: each point emits along its front normal only, with flux L dA, so the
// light's flux is L times the area and a surface in the beam, facing it, receives irradiance L
// (times cos theta when tilted by theta). Cameras and BSDF samples never hit that one direction:
// seen directly the shape is black (eval is 0), as in Mitsuba. Mitsuba's path tracer cannot
// connect to it either and renders it black (its documentation asks for a particle tracer);
// Candela connects exactly, for planar shapes: the only point that lights a receiver p is where
// the line from p against the normal meets the shape, found by tracing that ray, so
// next-event estimation treats the light as a directional one masked by the shape. That is the
// picture Mitsuba's particle tracer converges to. Curved shapes (whose beams cross) are refused.

#include "core/emitter.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/texture.h"

namespace candela {

class DirectionalAreaEmitter final : public Emitter {
public:
    explicit DirectionalAreaEmitter(const Properties& props) : location_(props.location()) {
        type_ = EmitterType::Area;
        radiance_ = props.get_texture("radiance", Spectrum(1.0f));
        if (props.has("to_world")) props.fail("to_world", "a directionalarea emitter takes its placement from its shape");
    }

    void set_shape(const Shape* shape) override { shape_ = shape; }
    // The shape is complete only now (set_shape runs inside its constructor).
    void set_scene(const Scene& scene) override {
        scene_ = &scene;
        if (!shape_->is_planar(normal_))
            throw SceneError(location_,
                             "directionalarea needs a planar shape (rectangle, disk or a flat mesh): the beams of a curved "
                             "shape cross, and only a particle tracer could render them");
    }

    // The point that lights `ref`: trace from ref against the emission direction; it must hit
    // this shape's front side first (which also settles visibility).
    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2&, Spectrum& weight) const override {
        DirectionSample ds;
        ds.emitter = this;
        ds.delta = true;
        ds.d = -normal_;
        weight = Spectrum(0.0f);
        SurfaceInteraction hit;
        if (!scene_ || !scene_->intersect(ref.spawn_ray(-normal_), hit) || hit.shape != shape_) return ds;
        if (!(glm::dot(hit.n, normal_) > 0.0f)) return ds;  // the back side emits nothing
        ds.p = hit.p;
        ds.p_error = hit.p_error;
        ds.n = hit.n;
        ds.uv = hit.uv;
        ds.dist = glm::length(hit.p - ref.p);
        ds.pdf = 1.0f;
        weight = radiance_->eval_as(hit, SpectrumRole::Emission);
        return ds;
    }
    float pdf_direction(const SurfaceInteraction&, const DirectionSample&) const override { return 0.0f; }
    // Light paths: a point uniform by area, leaving along the normal (a delta in direction).
    EmitterRay sample_ray(const Vec2& u_position, const Vec2&, Wavelengths* wavelengths, float) const override {
        EmitterRay r;
        PositionSample ps = shape_->sample_position(u_position);
        if (!(ps.pdf > 0.0f)) return r;
        r.ray = Ray(ps.p, normal_);
        r.n = ps.n;
        r.p_error = ps.p_error;
        r.uv = ps.uv;
        r.pdf_position = ps.pdf;
        r.pdf_direction = 1.0f;
        r.delta_direction = true;
        r.weight = radiance_->eval_at(ps.p, ps.n, ps.uv, SpectrumRole::Emission, wavelengths) / ps.pdf;
        return r;
    }
    Spectrum eval(const SurfaceInteraction&) const override { return Spectrum(0.0f); }
    // Flux: L per unit area, all of it along the normal.
    Spectrum power() const override { return shape_->surface_area() * radiance_->mean(); }
    // Emission within the shape's box along the normal and nowhere else. Every point of the beam
    // lies within the box's bounding sphere as seen from the centre, so the tree's importance
    // (which widens the cone by that sphere) never misses it.
    std::optional<LightBounds> bounds() const override {
        LightBounds b;
        b.box = shape_->bbox();
        b.axis = normal_;
        b.cos_theta_o = 1.0f;
        b.cos_theta_e = 1.0f;
        b.phi = luminance(power());
        return b;
    }
    std::string to_string() const override { return "directionalarea"; }

private:
    SourceLocation location_;
    Ref<Texture> radiance_;
    Vec3 normal_{0.0f, 0.0f, 1.0f};
    const Scene* scene_ = nullptr;
};

CANDELA_REGISTER_SPECTRAL(DirectionalAreaEmitter, ObjectKind::Emitter, "directionalarea");

}  // namespace candela
