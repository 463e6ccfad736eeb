#pragma once
// What the sunsky and timed_sunsky emitters share: the Hosek-Wilkie sky and sun (lights/sunsky.cpp
// states the model and its sources), the sun's position from a date, time and place, and the
// parameters both read. The model is split where the sun's position enters: SunskyModel holds the
// data interpolated for one turbidity and ground albedo, and state_at() finishes it for one sun
// (sunsky once; timed_sunsky at every ray's time, without allocating).

#include "core/emitter.h"
#include "core/parameters.h"
#include "core/texture.h"
#include "lights/scene_disk.h"

#include <memory>
#include <vector>

namespace candela {

class Properties;

constexpr int SunskyWavelengths = 11;  // the model's: 320, 360, ... 720 nm

// A date, time and place (Mitsuba's DateTimeRecord and LocationRecord; its defaults: Tokyo,
// 2010-07-10 15:00 local time).
struct SunRecord {
    float latitude = 35.6894f, longitude = 139.6917f, timezone = 9.0f;  // degrees, degrees, hours east of UTC
    int year = 2010, month = 7, day = 10;
    float hour = 15.0f, minute = 0.0f, second = 0.0f;
};

// The Julian day number of a calendar date (Fliegel and Van Flandern's integer formula, with
// truncating division; a day past the month's end counts on into the next month).
int julian_day(int year, int month, int day);

// The direction toward the sun at a date, time and place, in the emitter's frame (+z the zenith,
// +x south, -y east; Mitsuba's convention).
Vec3 sun_direction_at(const SunRecord& record);

// The place's parameters, as Mitsuba names them (latitude, longitude, timezone), and with
// `with_date` the date and time's (year, month, day, hour, minute, second).
void expose_record(ParameterVisitor& visitor, SunRecord& record, bool with_date);

// The parameters both emitters read (lights/sunsky.cpp lists them), checked by SunskyModel.
struct SunskySettings {
    float turbidity = 3.0f, sun_scale = 1.0f, sky_scale = 1.0f;
    float sun_aperture = 0.5358f;  // degrees: the apparent diameter
    bool complex_sun = false;
    Spectrum albedo{0.3f};                                   // RGB
    std::shared_ptr<const SpectrumTexture> measured_albedo;  // the spectral variant's, if measured
    // From a scene's properties; a spatially varying albedo fails at its line.
    static SunskySettings read(const Properties& props);
};

// The model finished for one sun position: what depends on the sun's elevation.
struct SunskyState {
    Vec3 sun{0.0f, 0.0f, 1.0f};  // toward the sun, local
    double elevation = 0.0;      // of the sun, radians
    bool up = false;             // above the horizon: else everything is black
    // The sky's nine coefficients (A B C D E F G I H) and mean radiance L_M, per RGB channel and
    // per model wavelength.
    double sky_rgb[3][10] = {};
    double sky_spectral[SunskyWavelengths][10] = {};
    // The uniform sun disk's radiance (sun_scale and the aperture's area ratio included).
    Spectrum sun_rgb{0.0f};
    double sun_spectral[SunskyWavelengths] = {};
};

class SunskyModel {
public:
    // InputError for settings out of range.
    explicit SunskyModel(const SunskySettings& settings);

    void state_at(const Vec3& sun_local, SunskyState& state) const;
    // Radiance toward unit local direction `local`: the sky's, plus the sun's when `in_sun`. At
    // the path's wavelengths in the spectral variant.
    Spectrum radiance(const SunskyState& state, const Vec3& local, bool in_sun, const Wavelengths* w) const;
    bool sees_sun(const SunskyState& state, const Vec3& local) const { return glm::dot(state.sun, local) >= cos_sun_half_angle_; }
    float cos_sun_half_angle() const { return cos_sun_half_angle_; }
    double sun_solid_angle() const { return sun_solid_angle_; }
    // The sun's share of the luminous irradiance a surface facing it receives, from the model's
    // irradiance tables (sun_scale and sky_scale applied): for choosing between sun and sky.
    float sun_share(const SunskyState& state) const;
    // The sun's radiance integrated over its disk, taken as its centre's (RGB).
    Spectrum sun_integral(const SunskyState& state) const;

private:
    Spectrum complex_sun_rgb(const Vec3& local, float gamma) const;
    double complex_sun_spectral(const Vec3& local, float gamma, int lo, double f) const;
    double cos_psi(float gamma) const;

    SunskySettings settings_;
    float cos_sun_half_angle_ = 1.0f, sin_sun_half_angle_ = 0.0f;
    double sun_solid_angle_ = 0.0, area_ratio_ = 1.0;
    // Interpolated in turbidity and albedo: [control point][channel][A..H, L_M].
    std::vector<double> sky_rgb_, sky_spectral_;
    // [elevation][wavelength], W m^-2 nm^-1, for sun and sky, at this turbidity.
    std::vector<double> sun_irradiance_, sky_irradiance_;
    // complex_sun: the solar radiance function's polynomials at this turbidity, and the limb
    // darkening per wavelength.
    std::vector<double> sun_rgb_polynomials_, sun_spectral_polynomials_, sun_limb_;
};

// What both emitters share besides the sun's place. A derived constructor reads its own
// parameters, then calls initialize(); update() (again after edits) makes the model and calls
// the derived update_sun().
class SunskyEmitterBase : public Emitter {
public:
    // Reads the shared parameters (SunskySettings::read) and to_world.
    explicit SunskyEmitterBase(const Properties& props);

    void set_scene(const Scene& scene) override;
    Spectrum eval(const SurfaceInteraction& si) const override { return eval_environment(-si.wi_world(), si.wavelengths, si.time); }
    // Flux through the scene's bounding disk: pi r^2 times the radiance integrated over directions.
    Spectrum power() const override { return radiance_integral_ * disk_.area(); }
    // Light paths: from the bounding disk along directions drawn as for next-event estimation.
    EmitterRay sample_ray(const Vec2& u_position, const Vec2& u_direction, Wavelengths* wavelengths, float time) const override {
        return environment_ray(*this, disk_, u_position, u_direction, wavelengths, time);
    }
    // Local model: ambient radiance equal to the radiance's average over the sphere.
    std::optional<LocalApproximation> local_approximation() const override;
    // Mitsuba's names: turbidity, sky_scale, sun_scale, to_world, albedo.value.
    void traverse(ParameterVisitor& visitor) override;
    // An edited albedo colour replaces the measured spectrum the scene gave (as for `constant`).
    void parameters_changed(const std::vector<std::string>& keys) override;

protected:
    // update(), its InputError turned into an error at the emitter's line.
    void initialize(const Properties& props);
    void update();
    // What depends on the derived emitter's own parameters; InputError for invalid ones. Sets
    // radiance_integral_.
    virtual void update_sun() = 0;

    Vec3 to_local(const Vec3& d_world) const { return glm::normalize(world_to_local_.apply_vector(d_world)); }
    // The direction sample toward unit local direction `local`, of solid-angle density `pdf` (> 0).
    DirectionSample direction_sample(const SurfaceInteraction& ref, const Vec3& local, float pdf) const;

    SunskySettings settings_;
    Transform to_world_, world_to_local_;
    std::shared_ptr<const SunskyModel> model_;
    SceneDisk disk_;
    Spectrum radiance_integral_{0.0f};
};

}  // namespace candela
