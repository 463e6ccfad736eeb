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
//
// On a shape with an animated to_world (motion blur) the shape is built still, in the space of
// the shape group an instance moves (core/xml.cpp), and the emitter places it by the instance's
// motion at the reference point's time: the reference point is taken into the group's space,
// the shape samples there as usual, and the sample comes back by to_world(t), its density per
// unit area divided by the area Jacobian |det M| |M^-T n| of the affine map (so any keyframe
// transform, not only rigid ones, keeps the pdf exact). pdf_direction undoes the same steps.
// Views without a time (light paths, the rasterizer, power and bounds for light selection) take
// the pose at the shutter's opening; the light-path integrators refuse moving scenes anyway.

#include "core/emitter.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
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
    void set_motion(const AnimatedTransform* motion) override { motion_ = motion; }
    void set_scene(const Scene& scene) override {
        if (motion_) open_pose_ = motion_->eval(scene.sensor().shutter_open());
    }
    bool is_animated() const override { return motion_ && motion_->is_animated(); }
    SourceLocation motion_location() const override { return motion_ ? motion_->where : SourceLocation{}; }

    Spectrum eval(const SurfaceInteraction& si) const override {
        if (Frame::cos_theta(si.wi) <= 0.0f) return Spectrum(0.0f);  // back side
        return radiance_->eval_as(si, SpectrumRole::Emission);
    }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2& u, Spectrum& weight) const override {
        DirectionSample ds = motion_ ? sample_moving(ref, u) : shape_->sample_direction(ref, u);
        ds.emitter = this;
        // Only the front side emits: the light's normal must face the receiver.
        if (!(ds.pdf > 0.0f) || glm::dot(ds.d, ds.n) >= 0.0f || !std::isfinite(ds.pdf)) {
            ds.pdf = 0.0f;
            weight = Spectrum(0.0f);
            return ds;
        }
        weight = radiance_at(ds, ref.wavelengths) / ds.pdf;
        return ds;
    }

    float pdf_direction(const SurfaceInteraction& ref, const DirectionSample& ds) const override {
        if (glm::dot(ds.d, ds.n) >= 0.0f) return 0.0f;
        return motion_ ? pdf_moving(ref, ds) : shape_->pdf_direction(ref, ds);
    }

    // Light paths: a point uniform by area, a cosine-weighted direction on the front side; the
    // cosine cancels, leaving the weight pi L(uv) / pdf_area.
    EmitterRay sample_ray(const Vec2& u_position, const Vec2& u_direction, Wavelengths* wavelengths, float time) const override {
        EmitterRay r;
        PositionSample ps = shape_->sample_position(u_position);
        if (motion_) ps = to_world_sample(motion_->eval(time), ps);
        if (!(ps.pdf > 0.0f)) return r;
        Vec3 local = warp::square_to_cosine_hemisphere(u_direction);
        r.pdf_direction = warp::square_to_cosine_hemisphere_pdf(local);
        if (!(r.pdf_direction > 0.0f)) return r;
        r.ray = Ray(ps.p, Frame(ps.n).to_world(local));
        r.n = ps.n;
        r.p_error = ps.p_error;
        r.uv = ps.uv;
        r.pdf_position = ps.pdf;
        r.weight = radiance_->eval_at(ps.p, ps.n, ps.uv, SpectrumRole::Emission, wavelengths) * (Pi / ps.pdf);
        return r;
    }

    // Flux of a one-sided Lambertian emitter: pi * area * mean radiance.
    Spectrum power() const override { return Pi * surface_area() * radiance_->mean(); }
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
        if (motion_) {
            a.position = open_pose_.apply_point(a.position);
            a.normal = glm::normalize(open_pose_.apply_normal(a.normal));
        }
        a.intensity = radiance_->mean() * surface_area() * (a.planar ? 1.0f : 0.25f);
        return a;
    }
    std::optional<LightBounds> bounds() const override {
        LightBounds b;
        b.box = shape_->bbox();
        shape_->normal_cone(b.axis, b.cos_theta_o);
        if (motion_) {  // everywhere the shape goes, facing any way (the motion turns the cone)
            b.box = motion_->bounds(b.box);
            b.axis = Vec3(0.0f, 0.0f, 1.0f);
            b.cos_theta_o = -1.0f;
        }
        b.cos_theta_e = 0.0f;  // Lambertian: a cosine falloff over a further 90 degrees
        b.phi = luminance(power());
        return b;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override { visitor.object("radiance", radiance_.get()); }
    std::string to_string() const override { return "area"; }

private:
    // The area in world space; on a moving shape at the shutter's opening, as |det M|^(2/3) times
    // the still area (exact for rotations, translations and uniform scales; only light
    // selection reads it).
    float surface_area() const {
        float area = shape_->surface_area();
        return motion_ ? area * std::pow(std::abs(open_pose_.determinant3()), 2.0f / 3.0f) : area;
    }

    // A point on the still shape moved by to_world: the density per unit area divided by the
    // Jacobian |det M| |M^-T n| of the surface element (n the still unit normal). Embree moves
    // its own copy of the pose, a few roundings away: the error bound covers that.
    static PositionSample to_world_sample(const Transform& to_world, const PositionSample& local) {
        PositionSample ps = local;
        Vec3 n = to_world.apply_normal(local.n);
        float jacobian = std::abs(to_world.determinant3()) * glm::length(n);
        ps.p = to_world.apply_point(local.p);
        ps.n = n / glm::length(n);
        ps.p_error = transformed_point_error(to_world, local.p, local.p_error) + gamma_bound(16) * max_abs_component(ps.p);
        ps.pdf = jacobian > 0.0f ? local.pdf / jacobian : 0.0f;
        return ps;
    }

    // The reference point in the group's space at its time.
    static SurfaceInteraction local_reference(const Transform& to_world, const SurfaceInteraction& ref) {
        SurfaceInteraction local = ref;
        local.p = to_world.inverse().apply_point(ref.p);
        return local;
    }

    // A solid-angle density seen from `ref` at a point p (normal n) as a density per unit area.
    static float area_density(float pdf_solid_angle, const Vec3& ref, const Vec3& p, const Vec3& n) {
        Vec3 to = p - ref;
        float dist2 = squared_length(to);
        if (!(dist2 > 0.0f)) return 0.0f;
        return pdf_solid_angle * std::abs(glm::dot(n, to)) / (dist2 * std::sqrt(dist2));
    }

    DirectionSample sample_moving(const SurfaceInteraction& ref, const Vec2& u) const {
        Transform to_world = motion_->eval(ref.time);
        SurfaceInteraction local_ref = local_reference(to_world, ref);
        DirectionSample local = shape_->sample_direction(local_ref, u);
        if (!(local.pdf > 0.0f)) return local;
        PositionSample ps = local;
        ps.pdf = area_density(local.pdf, local_ref.p, local.p, local.n);
        return Shape::direction_from_position(ref, to_world_sample(to_world, ps));
    }

    float pdf_moving(const SurfaceInteraction& ref, const DirectionSample& ds) const {
        Transform to_world = motion_->eval(ref.time), to_local = to_world.inverse();
        SurfaceInteraction local_ref = local_reference(to_world, ref);
        DirectionSample local = ds;
        local.p = to_local.apply_point(ds.p);
        local.n = glm::normalize(to_local.apply_normal(ds.n));
        Vec3 to = local.p - local_ref.p;
        local.dist = glm::length(to);
        if (!(local.dist > 0.0f)) return 0.0f;
        local.d = to / local.dist;
        PositionSample ps;
        ps.n = local.n;
        ps.pdf = area_density(shape_->pdf_direction(local_ref, local), local_ref.p, local.p, local.n);
        float pdf_area = to_world_sample(to_world, ps).pdf;
        float cos_light = std::abs(glm::dot(ds.n, ds.d));
        return cos_light > 0.0f ? pdf_area * ds.dist * ds.dist / cos_light : 0.0f;
    }

    // The radiance at a sampled point. A constant radiance (the common case) needs no lookup
    // point: building a SurfaceInteraction per light sample cost about 20 instructions.
    Spectrum radiance_at(const DirectionSample& ds, Wavelengths* wavelengths) const {
        if (constant_radiance_ && !wavelengths) return constant_radiance_->value();
        return radiance_->eval_at(ds.p, ds.n, ds.uv, SpectrumRole::Emission, wavelengths);
    }

    Ref<Texture> radiance_;
    const ConstantTexture* constant_radiance_ = nullptr;  // radiance_, when it is constant
    const AnimatedTransform* motion_ = nullptr;           // the instance's motion, on a moving shape
    Transform open_pose_;                                 // its pose at the shutter's opening
};

CANDELA_REGISTER_SPECTRAL(AreaEmitter, ObjectKind::Emitter, "area");

}  // namespace candela
