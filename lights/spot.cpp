// spot: a point light emitting into a cone.
//
// Parameters (Mitsuba 3, plus the raster mode's extras):
//   intensity          rgb         radiant intensity on the axis in W sr^-1 (default 1)
//   to_world           transform   apex at the origin, beam along +z (use a lookat); or an
//                      animation   <animation name="to_world">: the light takes its pose at
//                                  the time of the point it lights (motion blur), or of
//                                  ptracer's light path; the rasterizer sees the pose at
//                                  shutter_open
//   cutoff_angle       float       degrees from the axis where emission ends (default 20)
//   beam_width         float       degrees of full intensity; in between it falls off linearly
//                                  in the angle, as in Mitsuba (default 3/4 of cutoff_angle)
//   falloff_exponent   float       optional: OpenGL's falloff cos^e(angle) inside the cutoff
//                                  instead of Mitsuba's linear ramp (beam_width is then unused)
//   texture            texture     optional image projected along the beam (must vary in
//                                  space, e.g. a bitmap, as in Mitsuba): the intensity toward
//                                  local direction (x, y, z) is multiplied by the texture at
//                                  uv = (0.5 + 0.5 x / (z tan cutoff), 0.5 + 0.5 y / (z tan cutoff)),
//                                  so the image's square circumscribes the cone
//   attenuation_*      float       as `point` (default: inverse square)

#include "core/emitter.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/texture.h"
#include "core/warp.h"
#include "lights/point_source.h"

namespace candela {

class SpotEmitter final : public Emitter {
public:
    explicit SpotEmitter(const Properties& props) {
        type_ = EmitterType::DeltaPosition;
        intensity_ = props.get_rgb("intensity", Spectrum(1.0f));
        measured_ = props.measured_spectrum("intensity");
        motion_ = props.get_animated_transform("to_world");
        cutoff_ = radians(props.get_float("cutoff_angle", 20.0f));
        if (!(cutoff_ > 0.0f && cutoff_ < Pi)) props.fail("cutoff_angle", "cutoff_angle must be in (0, 180) degrees");
        if (props.has("falloff_exponent")) {
            if (props.has("beam_width")) props.fail("falloff_exponent", "give either beam_width or falloff_exponent");
            exponent_ = props.get_float("falloff_exponent");
            if (!(exponent_ >= 0.0f)) props.fail("falloff_exponent", "falloff_exponent must be non-negative");
        }
        beam_ = radians(props.get_float("beam_width", degrees(cutoff_) * 0.75f));
        if (!(beam_ >= 0.0f && beam_ <= cutoff_)) props.fail("beam_width", "beam_width must lie between 0 and cutoff_angle");
        cos_cutoff_ = std::cos(cutoff_);
        cos_beam_ = std::cos(beam_);
        if (props.has("texture")) {
            texture_ = props.get_texture("texture");
            if (texture_->is_constant())
                props.fail("texture", "a spot light's texture must vary in space (e.g. a bitmap); use intensity for a colour");
        }
        attenuation_ = Attenuation::read(props);
        set_pose(motion_.first());
        power_ = intensity_ * integrated_profile();
    }

    bool is_animated() const override { return motion_.is_animated(); }
    SourceLocation motion_location() const override { return motion_.where; }
    void set_scene(const Scene& scene) override {
        if (motion_.is_animated()) set_pose(motion_.eval(scene.sensor().shutter_open()));
    }

    // The falloff for a local direction (unit, beam along +z).
    float falloff(const Vec3& d) const {
        if (d.z <= cos_cutoff_) return 0.0f;
        return falloff_angle(safe_acos(d.z));
    }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2&, Spectrum& weight) const override {
        if (motion_.is_animated()) {  // the pose at the reference point's time
            Transform pose = motion_.eval(ref.time);
            return sample_from(pose.apply_point(Vec3(0.0f)), pose.inverse(), ref, weight);
        }
        return sample_from(position_, world_to_local_, ref, weight);
    }
    // The sample toward the apex at `position`, with the falloff of the pose `world_to_local`.
    DirectionSample sample_from(const Vec3& position, const Transform& world_to_local, const SurfaceInteraction& ref,
                                Spectrum& weight) const {
        DirectionSample ds = sample_point_source(position, ref, this);
        Vec3 local = glm::normalize(world_to_local.apply_vector(-ds.d));
        float f = ds.dist > 0.0f ? falloff(local) : 0.0f;
        weight = f > 0.0f ? intensity_ * (f * attenuation_(ds.dist)) : Spectrum(0.0f);
        if (texture_ && f > 0.0f) weight *= texture_->eval(texture_uv(local));
        if (ref.wavelengths && f > 0.0f)  // textured: the emission spectrum of that colour
            weight = texture_ ? rgb_at_wavelengths(weight, SpectrumRole::Emission, ref.wavelengths)
                              : emission_at(intensity_, measured_.get(), ref.wavelengths) * (f * attenuation_(ds.dist));
        return ds;
    }
    float pdf_direction(const SurfaceInteraction&, const DirectionSample&) const override { return 0.0f; }
    // Light paths leave uniformly over the cone (as in Mitsuba), weighted by the falloff and the
    // texture. The density is carried through to_world (its Jacobian |det M| / |M v|^3), so a
    // scaled spot stays correct.
    EmitterRay sample_ray(const Vec2&, const Vec2& u_direction, Wavelengths* wavelengths, float time) const override {
        const Transform pose = motion_.is_animated() ? motion_.eval(time) : to_world_;
        Vec3 local = warp::square_to_uniform_cone(u_direction, cos_cutoff_);
        Vec3 world = pose.apply_vector(local);
        float len = glm::length(world);
        float pdf = warp::square_to_uniform_cone_pdf(local, cos_cutoff_) * len * len * len / std::abs(pose.determinant3());
        Spectrum intensity = intensity_ * falloff(local);
        if (texture_) intensity *= texture_->eval(texture_uv(local));
        if (wavelengths)  // textured: the emission spectrum of that colour
            intensity = texture_ ? rgb_at_wavelengths(intensity, SpectrumRole::Emission, wavelengths)
                                 : emission_at(intensity_, measured_.get(), wavelengths) * falloff(local);
        EmitterRay r = point_source_ray(pose.apply_point(Vec3(0.0f)), world / len, std::isfinite(pdf) ? pdf : 0.0f, intensity);
        return r;
    }
    float ray_attenuation(float dist) const override { return attenuation_.ray_factor(dist); }
    Spectrum eval(const SurfaceInteraction&) const override { return Spectrum(0.0f); }
    Spectrum power() const override { return power_; }
    std::optional<LightBounds> bounds() const override {
        LightBounds b;
        b.box.expand(position_);
        b.axis = axis_;
        b.cos_theta_o = cos_cutoff_;
        if (motion_.is_animated()) {  // everywhere the apex goes, lighting any direction
            BoundingBox apex;
            apex.expand(Vec3(0.0f));
            b.box = motion_.bounds(apex);
            b.cos_theta_o = -1.0f;
        }
        b.cos_theta_e = 1.0f;  // nothing beyond the cutoff
        b.phi = luminance(power_);
        return b;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override { expose_color(visitor, "intensity.value", intensity_); }
    // An edited colour replaces the measured spectrum the scene gave (the spectral variant uses it).
    void parameters_changed(const std::vector<std::string>&) override {
        power_ = intensity_ * integrated_profile();
        measured_.reset();
    }
    std::string to_string() const override { return "spot"; }

    const Vec3& position() const { return position_; }
    const Vec3& axis() const { return axis_; }
    const Spectrum& intensity() const { return intensity_; }
    float cutoff() const { return cutoff_; }
    float beam_width() const { return beam_; }
    float exponent() const { return exponent_; }  // < 0: Mitsuba's linear falloff
    const Attenuation& attenuation() const { return attenuation_; }

private:
    void set_pose(const Transform& to_world) {
        to_world_ = to_world;
        position_ = to_world_.apply_point(Vec3(0.0f));
        axis_ = glm::normalize(to_world_.apply_vector(Vec3(0, 0, 1)));
        world_to_local_ = to_world_.inverse();
    }

    // The falloff (times the texture) integrated over solid angle, by the midpoint rule in theta
    // and, with a texture, in phi: the power is the intensity times this.
    Spectrum integrated_profile() const {
        const int n_theta = texture_ ? 256 : 4096, n_phi = texture_ ? 256 : 1;
        const double d_theta = cutoff_ / n_theta, d_phi = TwoPi / n_phi;
        Spectrum sum(0.0f);
        for (int i = 0; i < n_theta; ++i) {
            double theta = (i + 0.5) * d_theta;
            double ring = falloff_angle(float(theta)) * std::sin(theta) * d_theta * d_phi;
            for (int j = 0; j < n_phi; ++j) {
                double phi = (j + 0.5) * d_phi;
                Vec3 d(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)));
                sum += (texture_ ? texture_->eval(texture_uv(d)) : Spectrum(1.0f)) * float(ring);
            }
        }
        return sum;
    }
    // Where a local direction inside the cone reads the texture (Mitsuba's direction_to_uv).
    Vec2 texture_uv(const Vec3& local) const {
        float t = std::tan(cutoff_);
        return Vec2(0.5f + 0.5f * local.x / (local.z * t), 0.5f + 0.5f * local.y / (local.z * t));
    }
    float falloff_angle(float theta) const {
        if (theta >= cutoff_) return 0.0f;
        if (exponent_ >= 0.0f) return std::pow(std::cos(theta), exponent_);
        if (theta <= beam_) return 1.0f;
        return (cutoff_ - theta) / (cutoff_ - beam_);  // linear in the angle, Mitsuba's ramp
    }

    Spectrum intensity_, power_;
    std::shared_ptr<const SpectrumTexture> measured_;  // the spectral variant's intensity, if measured
    AnimatedTransform motion_;
    Transform to_world_, world_to_local_;  // the pose at shutter_open
    float cutoff_, beam_, cos_cutoff_, cos_beam_, exponent_ = -1.0f;
    Ref<Texture> texture_;
    Attenuation attenuation_;
    Vec3 position_, axis_;
};

CANDELA_REGISTER_SPECTRAL(SpotEmitter, ObjectKind::Emitter, "spot");

}  // namespace candela
