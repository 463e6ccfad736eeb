// area: turns the shape it is nested in into a light that emits on its front side.
//
// Parameters:
//   radiance   rgb or texture   emitted radiance in W m^-2 sr^-1 (default 1); a texture is looked
//                               up at the surface point (by the shape's uv or the texture's mapping)
// Sampling is delegated to the shape: uniform solid angle for spheres seen from outside,
// uniform area (converted to solid angle) otherwise. A textured radiance is evaluated at the
// sampled point's uv, which keeps the estimate unbiased; unlike Mitsuba, the texture is not
// importance-sampled (that needs a uv-to-surface map for every shape), so a high-contrast
// texture costs variance, not correctness.

#include "core/emitter.h"
#include "core/local_model.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"
#include "core/warp.h"

namespace candela {

class AreaEmitter final : public Emitter {
public:
    explicit AreaEmitter(const Properties& props) {
        type_ = EmitterType::Area;
        radiance_ = props.get_texture("radiance", Spectrum(1.0f));
        constant_radiance_ = dynamic_cast<const ConstantTexture*>(radiance_.get());
        if (props.has("to_world")) props.fail("to_world", "an area emitter takes its placement from its shape");
    }

    void set_shape(const Shape* shape) override { shape_ = shape; }

    Spectrum eval(const SurfaceInteraction& si) const override {
        if (Frame::cos_theta(si.wi) <= 0.0f) return Spectrum(0.0f);  // back side
        return radiance_->eval(si);
    }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2& u, Spectrum& weight) const override {
        DirectionSample ds = shape_->sample_direction(ref, u);
        ds.emitter = this;
        // Only the front side emits: the light's normal must face the receiver.
        if (!(ds.pdf > 0.0f) || glm::dot(ds.d, ds.n) >= 0.0f || !std::isfinite(ds.pdf)) {
            ds.pdf = 0.0f;
            weight = Spectrum(0.0f);
            return ds;
        }
        weight = radiance_at(ds) / ds.pdf;
        return ds;
    }

    float pdf_direction(const SurfaceInteraction& ref, const DirectionSample& ds) const override {
        if (glm::dot(ds.d, ds.n) >= 0.0f) return 0.0f;
        return shape_->pdf_direction(ref, ds);
    }

    // Light paths: a point uniform by area, a cosine-weighted direction on the front side; the
    // cosine cancels, leaving the weight pi L(uv) / pdf_area.
    EmitterRay sample_ray(const Vec2& u_position, const Vec2& u_direction) const override {
        EmitterRay r;
        PositionSample ps = shape_->sample_position(u_position);
        if (!(ps.pdf > 0.0f)) return r;
        Vec3 local = warp::square_to_cosine_hemisphere(u_direction);
        r.pdf_direction = warp::square_to_cosine_hemisphere_pdf(local);
        if (!(r.pdf_direction > 0.0f)) return r;
        r.ray = Ray(ps.p, Frame(ps.n).to_world(local));
        r.n = ps.n;
        r.p_error = ps.p_error;
        r.uv = ps.uv;
        r.pdf_position = ps.pdf;
        r.weight = radiance_->eval(ps.uv) * (Pi / ps.pdf);
        return r;
    }

    // Flux of a one-sided Lambertian emitter: pi * area * mean radiance.
    Spectrum power() const override { return Pi * shape_->surface_area() * radiance_->mean(); }
    // Local model: a point light at the shape's centre. A planar shape (rectangle, disk) sends
    // L A cos(theta) along its normal (a Lambertian emitter's intensity); other shapes L A / 4 in
    // every direction (a sphere's projected area is a quarter of its surface).
    std::optional<LocalApproximation> local_approximation() const override {
        LocalApproximation a;
        a.kind = LocalApproximation::Kind::AreaPoint;
        a.radiance = radiance_->mean();
        a.shape = shape_;
        a.position = shape_->bbox().center();
        a.planar = shape_->is_planar(a.normal);
        a.intensity = radiance_->mean() * shape_->surface_area() * (a.planar ? 1.0f : 0.25f);
        return a;
    }
    std::optional<LightBounds> bounds() const override {
        LightBounds b;
        b.box = shape_->bbox();
        shape_->normal_cone(b.axis, b.cos_theta_o);
        b.cos_theta_e = 0.0f;  // Lambertian: a cosine falloff over a further 90 degrees
        b.phi = luminance(power());
        return b;
    }
    std::string to_string() const override { return "area"; }

private:
    // The radiance at a sampled point. A constant radiance (the common case) needs no lookup
    // point: building a SurfaceInteraction per light sample cost about 20 instructions.
    Spectrum radiance_at(const DirectionSample& ds) const {
        if (constant_radiance_) return constant_radiance_->value();
        SurfaceInteraction on_light;  // where the radiance texture is looked up
        on_light.p = ds.p;
        on_light.n = ds.n;
        on_light.uv = ds.uv;
        return radiance_->eval(on_light);
    }

    Ref<Texture> radiance_;
    const ConstantTexture* constant_radiance_ = nullptr;  // radiance_, when it is constant
};

CANDELA_REGISTER(AreaEmitter, ObjectKind::Emitter, "area");

}  // namespace candela
