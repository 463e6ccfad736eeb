// sunsky: the sun and sky of a clear day, infinitely far away (Mitsuba 3's sunsky emitter): the
// Hosek-Wilkie skylight model and its solar radiance function, from their tabulated data
// (lights/sunsky_data.h).
//
// Parameters (Mitsuba 3.8):
//   turbidity      float      haze of the atmosphere, in [1, 10] (default 3)
//   albedo         rgb or spectrum  ground albedo, constant, each value in [0, 1] (default 0.3)
//   sun_direction  vector     direction toward the sun, world space; excludes the time and place
//   latitude       float      degrees (default 35.6894, Tokyo)
//   longitude      float      degrees (default 139.6917)
//   timezone       float      hours east of UTC (default 9)
//   year, month, day  integer (default 2010, 7, 10)
//   hour, minute, second  float  local time (default 15, 0, 0)
//   sun_scale      float      >= 0, multiplies the sun (default 1; 0 turns it off)
//   sky_scale      float      >= 0, multiplies the sky (default 1)
//   sun_aperture   float      apparent diameter of the sun in degrees, in (0, 180) (default 0.5358)
//   complex_sun    boolean    the sun's disk darkened toward its limb and coloured by the
//                             elevation it is seen at (default false: uniform over the disk)
//   to_world       transform  the emitter's frame: +z is the zenith (default identity)
//
// Units are Mitsuba's: spectral radiance in W m^-2 sr^-1 nm^-1 (the RGB variant's values are the
// model's RGB data scaled as Mitsuba scales them). Below the horizon (local z < 0) the emitter is
// black, and all of it is black when the sun is below the horizon.
//
// The model (Hosek and Wilkie 2012, eq. 9): at a view direction with zenith angle theta and
// angle gamma to the sun, per channel or wavelength
//   L = (1 + A exp(B / (cos theta + 0.01))) (C + D exp(E gamma) + F cos^2 gamma + G chi(H, gamma)
//       + I sqrt(cos theta)) L_M,   chi(g, a) = (1 + cos^2 a) / (1 + g^2 - 2 g cos a)^(3/2),
// with the nine coefficients (stored A B C D E F G I H) and L_M interpolated linearly in
// turbidity and in albedo, then along a quintic Bezier curve in the sun's elevation eta at
// x = (eta / (pi / 2))^(1/3). The sun's disk (half-angle h) carries by default a uniform radiance
// E / (2 pi (1 - cos h)), E the tabulated solar irradiance at the sun's elevation and turbidity;
// with complex_sun, the solar radiance function's piecewise cubic in the viewing elevation
// (45 segments, breaks at (k / 45)^3 pi / 2) times the limb-darkening polynomial in
// cos psi = sqrt(1 - sin^2 gamma / sin^2 h). In the RGB variant the sun's colour is the linear
// sRGB of the irradiance spectrum (320-720 nm every 40 nm, the mean of its CIE 1931 weighted
// samples), and RGB values are scaled as Mitsuba scales them (its CIE Y normalisation and its
// solar constant 467.069280386). A sun_aperture other than the default keeps the sun's
// irradiance: its radiance scales by (1 - cos h_default) / (1 - cos h).
//
// The sun's position from a date, time and place: Blanco-Muriel et al., "Computing the solar
// vector", Solar Energy 70(5), 2001 (the PSA algorithm), with its parallax correction; its
// azimuth is measured from north toward east, and the direction is
// (sin theta cos phi, sin theta sin phi, cos theta) at phi = azimuth - pi, as Mitsuba has it.
//
// Sampling (not Mitsuba's truncated Gaussian mixtures, which give the same expected image): the
// sky by a piecewise-constant density over (azimuth, cos theta) whose cells bound the sky's
// luminance, the sun uniformly over its cone, mixed in proportion to their luminous power.

#include "core/distribution.h"
#include "core/emitter.h"
#include "core/error.h"
#include "core/frame.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/spectral.h"
#include "core/texture.h"
#include "core/warning.h"
#include "core/warp.h"
#include "core/wavelengths.h"
#include "lights/scene_disk.h"
#include "lights/sunsky_data.h"

#include <algorithm>
#include <cmath>

namespace candela {

namespace {

constexpr int ModelWavelengths = 11;  // 320, 360, ... 720 nm
constexpr double FirstWavelength = 320.0, WavelengthStep = 40.0;
constexpr int Turbidities = 10, Albedos = 2, SkyControlPoints = 6, SkyParams = 9;
constexpr int SunSegments = 45, SunPolynomial = 4, SunLimbTerms = 6;
constexpr int IrradianceElevations = 30;  // sun elevations 2, 5, ... 89 degrees
// The default apparent diameter of the sun, degrees (Mitsuba's SUN_HALF_APERTURE doubled).
constexpr double DefaultSunAperture = 0.5358;
// Mitsuba's factor from the model's solar data to RGB radiance (SPEC_TO_RGB_SUN_CONV).
constexpr double SunRGBScale = 467.069280386;
constexpr double PiD = 3.14159265358979323846;
constexpr float OneMinusEpsilon = 0x1.fffffep-1f;  // the largest float below 1

// The angle between unit vectors, accurate when they are nearly parallel or opposite (Mitsuba's
// unit_angle).
float unit_angle(const Vec3& a, const Vec3& b) {
    float d = glm::dot(a, b);
    if (d >= 0.0f) return 2.0f * std::asin(std::min(1.0f, 0.5f * glm::length(a - b)));
    return Pi - 2.0f * std::asin(std::min(1.0f, 0.5f * glm::length(a + b)));
}

// Linear interpolation along the first axis of a row-major table of `n` blocks of `block`
// values, at the fractional index `position` (clamped to [0, n - 1]): one block.
std::vector<double> interpolate_first_axis(const std::vector<double>& table, int n, size_t block, double position) {
    position = std::clamp(position, 0.0, double(n - 1));
    int i0 = std::min(int(position), n - 2);
    double w = position - i0;
    std::vector<double> out(block);
    for (size_t k = 0; k < block; ++k) out[k] = (1.0 - w) * table[size_t(i0) * block + k] + w * table[size_t(i0 + 1) * block + k];
    return out;
}

// Sky data [turbidity][albedo][control point][channel][values] reduced to [channel][values] for
// the given turbidity, per-channel albedo and sun elevation eta (radians).
std::vector<double> sky_coefficients(const std::vector<double>& table, int channels, int values, double turbidity,
                                     const std::vector<double>& albedo, double eta) {
    const size_t per_albedo = size_t(SkyControlPoints) * channels * values;
    std::vector<double> t = interpolate_first_axis(table, Turbidities, Albedos * per_albedo, turbidity - 1.0);
    // The quintic Bezier weights at x = (2 eta / pi)^(1/3): binomial(5, k) x^k (1 - x)^(5 - k).
    double x = std::min(std::cbrt(2.0 * eta / PiD), 1.0);
    static const double binomial[SkyControlPoints] = {1, 5, 10, 10, 5, 1};
    std::vector<double> out(size_t(channels) * values, 0.0);
    for (int k = 0; k < SkyControlPoints; ++k) {
        double bezier = binomial[k] * std::pow(x, k) * std::pow(1.0 - x, SkyControlPoints - 1 - k);
        for (int c = 0; c < channels; ++c)
            for (int v = 0; v < values; ++v) {
                size_t i = (size_t(k) * channels + c) * values + v;
                double a = std::clamp(albedo[size_t(c)], 0.0, 1.0);
                out[size_t(c) * values + v] += bezier * ((1.0 - a) * t[i] + a * t[per_albedo + i]);
            }
    }
    return out;
}

// Hosek-Wilkie's sky function for one channel: p holds A B C D E F G I H (the data's order).
double sky_function(const double* p, double cos_theta, double gamma, double cos_gamma) {
    double chi = (1.0 + cos_gamma * cos_gamma) / std::pow(1.0 + p[8] * p[8] - 2.0 * p[8] * cos_gamma, 1.5);
    return (1.0 + p[0] * std::exp(p[1] / (cos_theta + 0.01))) *
           (p[2] + p[3] * std::exp(p[4] * gamma) + p[5] * cos_gamma * cos_gamma + p[6] * chi + p[7] * std::sqrt(std::max(cos_theta, 0.0)));
}

// A date, time and place (Mitsuba's DateTimeRecord and LocationRecord).
struct SunRecord {
    float latitude = 35.6894f, longitude = 139.6917f, timezone = 9.0f;
    int year = 2010, month = 7, day = 10;
    float hour = 15.0f, minute = 0.0f, second = 0.0f;
};

// The sun's zenith angle and azimuth - pi (radians) at a date, time and place (the PSA algorithm;
// see the top of the file). In single precision, as Mitsuba's scalar variants compute it: the
// Julian date then rounds to a quarter day, which moves only the slow terms (the daily rotation
// comes from the hours themselves), by up to 0.04 degrees.
Vec2 sun_position(const SunRecord& r) {
    using std::sin, std::cos;
    const float pi = 3.14159265358979323846f;
    float hours_ut = r.hour - r.timezone + (r.minute + r.second / 60.0f) / 60.0f;
    // Julian day number (integer arithmetic, truncating division), then days since 2000-01-01 12:00 UT.
    int a = (r.month - 14) / 12;
    int jdn =
        (1461 * (r.year + 4800 + a)) / 4 + (367 * (r.month - 2 - 12 * a)) / 12 - (3 * ((r.year + 4900 + a) / 100)) / 4 + r.day - 32075;
    float n = (float(jdn) - 0.5f + hours_ut / 24.0f) - 2451545.0f;
    // Ecliptic coordinates.
    float omega = 2.1429f - 0.0010394594f * n;
    float mean_longitude = 4.8950630f + 0.017202791698f * n;
    float anomaly = 6.2400600f + 0.0172019699f * n;
    float ecliptic_longitude =
        mean_longitude + 0.03341607f * sin(anomaly) + 0.00034894f * sin(2.0f * anomaly) - 0.0001134f - 0.0000203f * sin(omega);
    float obliquity = 0.4090928f - 6.2140e-9f * n + 0.0000396f * cos(omega);
    // Celestial coordinates.
    float sin_longitude = sin(ecliptic_longitude);
    float right_ascension = std::atan2(cos(obliquity) * sin_longitude, cos(ecliptic_longitude));
    if (right_ascension < 0.0f) right_ascension += 2.0f * pi;
    float declination = std::asin(sin(obliquity) * sin_longitude);
    // Local coordinates.
    float gmst = 6.6974243242f + 0.0657098283f * n + hours_ut;
    float lmst = (gmst * 15.0f + r.longitude) * (pi / 180.0f);
    float latitude = r.latitude * (pi / 180.0f);
    float hour_angle = lmst - right_ascension;
    float zenith = std::acos(cos(latitude) * cos(hour_angle) * cos(declination) + sin(declination) * sin(latitude));
    float azimuth = std::atan2(-sin(hour_angle), std::tan(declination) * cos(latitude) - sin(latitude) * cos(hour_angle));
    if (azimuth < 0.0f) azimuth += 2.0f * pi;
    // Parallax: the Earth's mean radius over the astronomical unit (km).
    zenith += float(6371.01 / 149597890.0) * sin(zenith);
    return Vec2(zenith, azimuth - pi);
}

Vec3 spherical_direction(float theta, float phi) {
    float s = std::sin(theta);
    return Vec3(s * std::cos(phi), s * std::sin(phi), std::cos(theta));
}

}  // namespace

class SunskyEmitter final : public Emitter {
public:
    explicit SunskyEmitter(const Properties& props) {
        type_ = EmitterType::Infinite;
        turbidity_ = props.get_float("turbidity", 3.0f);
        sun_scale_ = props.get_float("sun_scale", 1.0f);
        sky_scale_ = props.get_float("sky_scale", 1.0f);
        sun_aperture_ = props.get_float("sun_aperture", float(DefaultSunAperture));
        complex_sun_ = props.get_bool("complex_sun", false);
        to_world_ = props.get_transform("to_world");
        if (!props.get_texture("albedo", Spectrum(0.3f))->is_constant())
            props.fail("albedo", "the ground albedo must be constant, not a spatially varying texture");
        albedo_ = props.get_texture("albedo", Spectrum(0.3f))->mean();
        measured_albedo_ = props.measured_spectrum("albedo");

        static const char* record_names[] = {"latitude", "longitude", "timezone", "year", "month", "day", "hour", "minute", "second"};
        has_record_ = !props.has("sun_direction");
        if (!has_record_) {
            for (const char* name : record_names)
                if (props.has(name))
                    props.fail(name, "both sun_direction and a time or place (\"" + std::string(name) +
                                         "\") were given: the sun's position comes from one or the other");
            sun_direction_ = props.get_vector("sun_direction");
            if (!(glm::length(sun_direction_) > 0.0f) || !all_finite(sun_direction_))
                props.fail("sun_direction", "the sun's direction must be a finite, non-zero vector");
        } else {
            record_.latitude = props.get_float("latitude", record_.latitude);
            record_.longitude = props.get_float("longitude", record_.longitude);
            record_.timezone = props.get_float("timezone", record_.timezone);
            record_.year = props.get_int("year", record_.year);
            record_.month = props.get_int("month", record_.month);
            record_.day = props.get_int("day", record_.day);
            record_.hour = props.get_float("hour", record_.hour);
            record_.minute = props.get_float("minute", record_.minute);
            record_.second = props.get_float("second", record_.second);
        }
        try {
            update();
        } catch (const InputError& e) {
            props.fail(e.what());
        }
        if (sun_local_.z < 0.0f) warn(props.location(), "sunsky: the sun is below the horizon, so the sun and the sky are black");
    }

    void set_scene(const Scene& scene) override {
        disk_.center = scene.bbox().valid() ? scene.bbox().center() : Vec3(0.0f);
        disk_.radius = std::max(scene.bbox().bounding_radius(), 1e-3f);
    }

    Spectrum eval(const SurfaceInteraction& si) const override { return eval_environment(-si.wi_world(), si.wavelengths); }
    Spectrum eval_environment(const Vec3& d, const Wavelengths* w) const override {
        Vec3 local = to_local(d);
        return radiance(local, sees_sun(local), w);
    }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2& u, Spectrum& weight) const override {
        DirectionSample ds;
        ds.emitter = this;
        weight = Spectrum(0.0f);
        const bool pick_sky = u.x < sky_probability_;
        Vec3 local;
        if (pick_sky) {
            float pdf_uv;
            Vec2 uv = sky_distribution_.sample(Vec2(u.x / sky_probability_, u.y), &pdf_uv);
            float phi = TwoPi * uv.x, cos_theta = uv.y, sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
            local = Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
        } else {
            Vec2 v(std::min((u.x - sky_probability_) / (1.0f - sky_probability_), OneMinusEpsilon), u.y);
            local = sun_frame_.to_world(warp::square_to_uniform_cone(v, cos_sun_half_angle_));
        }
        if (local.z < 0.0f) return ds;
        // A direction drawn in the sun's cone is in it, whatever the rounding of the test.
        const bool in_sun = !pick_sky || sees_sun(local);
        ds.pdf = pdf_local(local, in_sun);
        if (!(ds.pdf > 0.0f)) return ds;
        ds.d = glm::normalize(to_world_.apply_vector(local));
        ds.dist = Infinity;
        ds.p = ref.p + ds.d * (2.0f * disk_.radius);
        ds.n = -ds.d;
        weight = radiance(local, in_sun, ref.wavelengths) / ds.pdf;
        return ds;
    }

    float pdf_direction(const SurfaceInteraction&, const DirectionSample& ds) const override {
        Vec3 local = to_local(ds.d);
        return pdf_local(local, sees_sun(local));
    }

    // Flux through the scene's bounding disk: pi r^2 times the radiance integrated over the sky.
    Spectrum power() const override { return (sky_integral_ + sun_integral_) * disk_.area(); }
    // Light paths: from the bounding disk along directions drawn as for next-event estimation.
    EmitterRay sample_ray(const Vec2& u_position, const Vec2& u_direction, Wavelengths* wavelengths) const override {
        return environment_ray(*this, disk_, u_position, u_direction, wavelengths);
    }
    // Local model: ambient radiance equal to the sun's and sky's average over the sphere.
    std::optional<LocalApproximation> local_approximation() const override {
        LocalApproximation a;
        a.kind = LocalApproximation::Kind::Ambient;
        a.radiance = (sky_integral_ + sun_integral_) / FourPi;
        return a;
    }

    // Mitsuba's parameter names: the sun's position by the parameters it was given.
    void traverse(ParameterVisitor& visitor) override {
        expose_float(visitor, "turbidity", turbidity_);
        expose_float(visitor, "sky_scale", sky_scale_);
        expose_float(visitor, "sun_scale", sun_scale_);
        expose_transform(visitor, "to_world", to_world_);
        expose_color(visitor, "albedo.value", albedo_);
        if (has_record_) {
            expose_float(visitor, "latitude", record_.latitude);
            expose_float(visitor, "longitude", record_.longitude);
            expose_float(visitor, "timezone", record_.timezone);
            expose_integer(visitor, "year", record_.year);
            expose_integer(visitor, "month", record_.month);
            expose_integer(visitor, "day", record_.day);
            expose_float(visitor, "hour", record_.hour);
            expose_float(visitor, "minute", record_.minute);
            expose_float(visitor, "second", record_.second);
        }
        // The sun's world direction; read-only when a time and place give it (as in Mitsuba).
        ParameterAccess sun{ParameterType::Floats,
                            [this] {
                                return std::vector<float>{sun_direction_.x, sun_direction_.y, sun_direction_.z};
                            },
                            nullptr};
        if (!has_record_)
            sun.set = [this](const std::vector<float>& v) {
                if (v.size() != 3) throw InputError("sun_direction takes 3 values");
                sun_direction_ = Vec3(v[0], v[1], v[2]);
            };
        visitor.value("sun_direction", std::move(sun));
    }
    // An edited albedo colour replaces the measured spectrum the scene gave (as for `constant`).
    void parameters_changed(const std::vector<std::string>& keys) override {
        if (std::find(keys.begin(), keys.end(), "albedo.value") != keys.end()) measured_albedo_.reset();
        update();
    }
    std::string to_string() const override { return "sunsky"; }

private:
    // An integer parameter exposed as one float (Mitsuba's year, month and day).
    static void expose_integer(ParameterVisitor& visitor, const std::string& name, int& value) {
        visitor.value(name, ParameterAccess{ParameterType::Float, [&value] { return std::vector<float>{float(value)}; },
                                            [&value, name](const std::vector<float>& v) {
                                                if (v.size() != 1 || !(v[0] == std::round(v[0])) || std::abs(v[0]) > 1e6f)
                                                    throw InputError(name + " must be an integer");
                                                value = int(v[0]);
                                            }});
    }

    Vec3 to_local(const Vec3& d_world) const { return glm::normalize(world_to_local_.apply_vector(d_world)); }
    bool sees_sun(const Vec3& local) const { return glm::dot(sun_local_, local) >= cos_sun_half_angle_; }

    // Everything derived from the parameters: checks them, places the sun, and interpolates the
    // model's data for this turbidity, albedo and sun elevation. InputError for invalid values.
    void update() {
        if (!(turbidity_ >= 1.0f && turbidity_ <= 10.0f))
            throw InputError("turbidity " + std::to_string(turbidity_) + " is outside [1, 10]");
        if (!(sun_scale_ >= 0.0f) || !std::isfinite(sun_scale_)) throw InputError("sun_scale must be finite and >= 0");
        if (!(sky_scale_ >= 0.0f) || !std::isfinite(sky_scale_)) throw InputError("sky_scale must be finite and >= 0");
        if (!(sun_aperture_ > 0.0f && sun_aperture_ < 180.0f)) throw InputError("sun_aperture must be in (0, 180) degrees");
        if (!to_world_.all_finite()) throw InputError("to_world is not finite");
        world_to_local_ = to_world_.inverse();

        if (has_record_) {
            if (record_.month < 1 || record_.month > 12 || record_.day < 1 || record_.day > 31)
                throw InputError("month and day must be a calendar date (month 1-12, day 1-31)");
            Vec2 angles = sun_position(record_);
            sun_local_ = spherical_direction(angles.x, angles.y);
            sun_direction_ = glm::normalize(to_world_.apply_vector(sun_local_));
        } else {
            if (!(glm::length(sun_direction_) > 0.0f) || !all_finite(sun_direction_))
                throw InputError("the sun's direction must be a finite, non-zero vector");
            sun_local_ = to_local(sun_direction_);
        }
        sun_frame_ = Frame(sun_local_);
        // The sun's half-angle and its cosine in single precision, as Mitsuba evaluates them: the
        // disk's radiance divides the irradiance by the solid angle the hit test really covers.
        const float half_angle = float(sun_aperture_ * 0.5 * PiD / 180.0);
        cos_sun_half_angle_ = std::cos(half_angle);
        sin_sun_half_angle_ = std::sin(half_angle);
        const double default_solid_angle = 2.0 * PiD * (1.0 - double(std::cos(float(DefaultSunAperture * 0.5 * PiD / 180.0))));
        sun_solid_angle_ = 2.0 * PiD * (1.0 - double(cos_sun_half_angle_));
        const double area_ratio = default_solid_angle / sun_solid_angle_;
        const double eta = 0.5 * PiD - double(unit_angle(sun_local_, Vec3(0.0f, 0.0f, 1.0f)));
        sun_up_ = eta >= 0.0;

        // Albedo per RGB channel and per model wavelength.
        std::vector<double> albedo_rgb(3), albedo_spectral(ModelWavelengths);
        for (int c = 0; c < 3; ++c) {
            if (!(albedo_[c] >= 0.0f && albedo_[c] <= 1.0f)) throw InputError("the albedo must be in [0, 1] in every channel");
            albedo_rgb[size_t(c)] = albedo_[c];
        }
        for (int i = 0; i < ModelWavelengths; i += 3) {
            Vec3 lambda;
            for (int k = 0; k < 3; ++k) lambda[k] = float(FirstWavelength + WavelengthStep * std::min(i + k, ModelWavelengths - 1));
            Wavelengths w = Wavelengths::at(lambda);
            Spectrum v = measured_albedo_ ? measured_albedo_->eval_spectrum(SurfaceInteraction(), w, SpectrumRole::Reflectance)
                                          : rgb_at_wavelengths(albedo_, SpectrumRole::Reflectance, &w);
            for (int k = 0; k < 3 && i + k < ModelWavelengths; ++k) albedo_spectral[size_t(i + k)] = std::clamp(double(v[k]), 0.0, 1.0);
        }

        const TensorFile& data = sunsky_datasets();
        const double t = turbidity_;
        const double eta_clamped = std::max(eta, 0.0);
        sky_rgb_params_ = sky_coefficients(data.doubles("sky_params_rgb"), 3, SkyParams, t, albedo_rgb, eta_clamped);
        sky_rgb_radiance_ = sky_coefficients(data.doubles("sky_rad_rgb"), 3, 1, t, albedo_rgb, eta_clamped);
        sky_spectral_params_ =
            sky_coefficients(data.doubles("sky_params_spec"), ModelWavelengths, SkyParams, t, albedo_spectral, eta_clamped);
        sky_spectral_radiance_ = sky_coefficients(data.doubles("sky_rad_spec"), ModelWavelengths, 1, t, albedo_spectral, eta_clamped);

        // The sun: the tabulated irradiance at this turbidity and elevation (the simple disk), and
        // the solar radiance function's coefficients at this turbidity (complex_sun).
        std::vector<double> irradiance_table;
        for (float v : sunsky_sampling_data().floats("sun_irradiance")) irradiance_table.push_back(v);
        std::vector<double> by_elevation =
            interpolate_first_axis(irradiance_table, Turbidities, size_t(IrradianceElevations) * ModelWavelengths, t - 1.0);
        double eta_degrees = eta_clamped * 180.0 / PiD;
        sun_irradiance_ = interpolate_first_axis(by_elevation, IrradianceElevations, ModelWavelengths, (eta_degrees - 2.0) / 3.0);
        Vec3d xyz(0.0);
        for (int i = 0; i < ModelWavelengths; ++i)
            xyz += cie1931_xyz(FirstWavelength + WavelengthStep * i) * (sun_irradiance_[size_t(i)] / ModelWavelengths);
        // The RGB variant's colour carries the CIE Y normalisation once, as Mitsuba 3.8's does
        // (measured against it: bench/results/sunsky_2026-12-06.txt).
        Vec3d sun_rgb = xyz_to_linear_srgb(xyz) * (SunRGBScale * CieYNormalization);
        // Radiance over the disk: E / (2 pi (1 - cos h_default)) times the aperture's area ratio.
        const double simple_scale = double(sun_scale_) * area_ratio / default_solid_angle;
        sun_rgb_radiance_ = Spectrum(float(sun_rgb.x * simple_scale), float(sun_rgb.y * simple_scale), float(sun_rgb.z * simple_scale));
        sun_spectral_scale_ = simple_scale;
        sun_complex_scale_ = double(sun_scale_) * area_ratio;
        sun_rgb_polynomials_ = interpolate_first_axis(data.doubles("sun_rad_rgb"), Turbidities,
                                                      size_t(SunSegments) * 3 * SunPolynomial * SunLimbTerms, t - 1.0);
        sun_spectral_polynomials_ = interpolate_first_axis(data.doubles("sun_rad_spec"), Turbidities,
                                                           size_t(SunSegments) * ModelWavelengths * SunPolynomial, t - 1.0);
        sun_limb_ = data.doubles("sun_ld_spec");

        build_sampling();
    }

    // The radiance toward local direction `local` (unit): the sky's, plus the sun's where the
    // direction lies in the sun's disk. At the path's wavelengths in the spectral variant.
    Spectrum radiance(const Vec3& local, bool in_sun, const Wavelengths* w) const {
        if (local.z < 0.0f || !sun_up_) return Spectrum(0.0f);
        const float gamma = unit_angle(sun_local_, local);
        const double cos_theta = local.z, cos_gamma = std::cos(double(gamma));
        if (!w) {
            Spectrum sky(0.0f);
            if (sky_scale_ > 0.0f)
                for (int c = 0; c < 3; ++c)
                    sky[c] = float(double(sky_scale_) * CieYNormalization * sky_rgb_radiance_[size_t(c)] *
                                   sky_function(&sky_rgb_params_[size_t(c) * SkyParams], cos_theta, gamma, cos_gamma));
            if (!in_sun || sun_scale_ == 0.0f) return sky;
            return sky + (complex_sun_ ? complex_sun_rgb(local, gamma) : sun_rgb_radiance_);
        }
        Spectrum out(0.0f);
        for (int k = 0; k < WavelengthSamples; ++k) {
            double n = (double(w->lambda[k]) - FirstWavelength) / WavelengthStep;
            if (!(n >= 0.0 && n <= ModelWavelengths - 1)) continue;
            int lo = std::min(int(n), ModelWavelengths - 2);
            double f = n - lo;
            double value = 0.0;
            if (sky_scale_ > 0.0f) {
                double sky_lo = sky_spectral_radiance_[size_t(lo)] *
                                sky_function(&sky_spectral_params_[size_t(lo) * SkyParams], cos_theta, gamma, cos_gamma);
                double sky_hi = sky_spectral_radiance_[size_t(lo + 1)] *
                                sky_function(&sky_spectral_params_[size_t(lo + 1) * SkyParams], cos_theta, gamma, cos_gamma);
                value += double(sky_scale_) * ((1.0 - f) * sky_lo + f * sky_hi);
            }
            if (in_sun && sun_scale_ > 0.0f) {
                if (!complex_sun_)
                    value += sun_spectral_scale_ * ((1.0 - f) * sun_irradiance_[size_t(lo)] + f * sun_irradiance_[size_t(lo + 1)]);
                else
                    value += sun_complex_scale_ * complex_sun_spectral(local, gamma, lo, f);
            }
            out[k] = float(value);
        }
        return out;
    }

    // The solar radiance function's segment and offset for the elevation a view direction has.
    static void sun_segment(const Vec3& local, int& segment, double& x) {
        double elevation = 0.5 * PiD - std::acos(std::clamp(double(local.z), -1.0, 1.0));
        segment = std::min(int(std::cbrt(2.0 * elevation / PiD) * SunSegments), SunSegments - 1);
        segment = std::max(segment, 0);
        x = elevation - 0.5 * PiD * std::pow(double(segment) / SunSegments, 3.0);
    }
    double cos_psi(float gamma) const {
        double s = std::sin(double(gamma)) / double(sin_sun_half_angle_);
        return std::sqrt(std::max(1.0 - s * s, 0.0));
    }
    // RGB: the limb darkening is part of the data (polynomials in x and cos psi).
    Spectrum complex_sun_rgb(const Vec3& local, float gamma) const {
        int segment;
        double x;
        sun_segment(local, segment, x);
        const double c_psi = cos_psi(gamma);
        Spectrum out(0.0f);
        for (int c = 0; c < 3; ++c) {
            const double* d = &sun_rgb_polynomials_[(size_t(segment) * 3 + c) * SunPolynomial * SunLimbTerms];
            double sum = 0.0;
            for (int k = 0; k < SunPolynomial; ++k)
                for (int j = 0; j < SunLimbTerms; ++j) sum += std::pow(x, k) * std::pow(c_psi, j) * d[k * SunLimbTerms + j];
            out[c] = float(sun_complex_scale_ * SunRGBScale * CieYNormalization * sum);
        }
        return out;
    }
    // Spectral: the cubic in x at model wavelengths lo and lo + 1, interpolated by f, times the
    // interpolated limb-darkening polynomial in cos psi.
    double complex_sun_spectral(const Vec3& local, float gamma, int lo, double f) const {
        int segment;
        double x;
        sun_segment(local, segment, x);
        const double c_psi = cos_psi(gamma);
        double radiance[2] = {0.0, 0.0}, limb[2] = {0.0, 0.0};
        for (int e = 0; e < 2; ++e) {
            const double* d = &sun_spectral_polynomials_[(size_t(segment) * ModelWavelengths + size_t(lo + e)) * SunPolynomial];
            for (int k = 0; k < SunPolynomial; ++k) radiance[e] += std::pow(x, k) * d[k];
            for (int j = 0; j < SunLimbTerms; ++j) limb[e] += std::pow(c_psi, j) * sun_limb_[size_t(lo + e) * SunLimbTerms + size_t(j)];
        }
        return ((1.0 - f) * radiance[0] + f * radiance[1]) * ((1.0 - f) * limb[0] + f * limb[1]);
    }

    // The solid-angle density of the mixture at a local direction.
    float pdf_local(const Vec3& local, bool in_sun) const {
        if (local.z < 0.0f) return 0.0f;
        float phi = std::atan2(local.y, local.x) * InvTwoPi;
        phi -= std::floor(phi);
        // (u, v) = (phi / 2 pi, cos theta) has Jacobian d omega = 2 pi du dv.
        float pdf_sky = sky_distribution_.pdf(Vec2(std::min(phi, OneMinusEpsilon), std::min(local.z, OneMinusEpsilon))) * InvTwoPi;
        float pdf_sun = in_sun ? float(1.0 / sun_solid_angle_) : 0.0f;
        return sky_probability_ * pdf_sky + (1.0f - sky_probability_) * pdf_sun;
    }

    // The sky's sampling density: cells of (azimuth, cos theta), each weighted by the largest
    // luminance among 3 x 3 points over it (corners, edge midpoints, centre) so that the
    // density follows the sky's peaks near the sun and the horizon, plus a floor that leaves no
    // cell of the upper hemisphere at zero. Also the sky's and sun's radiance integrated over
    // directions (power, mixture weights, the rasterizer's ambient).
    void build_sampling() {
        constexpr int Azimuths = 128, Cosines = 64;
        const int nx = 2 * Azimuths + 1, ny = 2 * Cosines + 1;
        std::vector<Spectrum> lattice(size_t(nx) * ny);
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                float phi = TwoPi * float(i) / float(nx - 1), cos_theta = float(j) / float(ny - 1);
                float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
                Vec3 local(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
                lattice[size_t(j) * nx + i] = radiance(local, false, nullptr);
            }
        std::vector<float> weights(size_t(Azimuths) * Cosines);
        double sum_weights = 0.0, integral[3] = {0.0, 0.0, 0.0};
        const double cell_solid_angle = 2.0 * PiD / Azimuths / Cosines;
        for (int y = 0; y < Cosines; ++y)
            for (int x = 0; x < Azimuths; ++x) {
                float largest = 0.0f;
                for (int dj = 0; dj <= 2; ++dj)
                    for (int di = 0; di <= 2; ++di)
                        largest = std::max(largest, luminance(lattice[size_t(2 * y + dj) * nx + size_t(2 * x + di)]));
                weights[size_t(y) * Azimuths + x] = largest;
                sum_weights += largest;
                const Spectrum& centre = lattice[size_t(2 * y + 1) * nx + size_t(2 * x + 1)];
                for (int c = 0; c < 3; ++c) integral[c] += double(centre[c]) * cell_solid_angle;
            }
        const float floor = sum_weights > 0.0 ? float(1e-3 * sum_weights / double(weights.size())) : 1.0f;
        for (float& w : weights) w += floor;
        sky_distribution_ = Distribution2D(weights, Azimuths, Cosines);
        sky_integral_ = Spectrum(float(integral[0]), float(integral[1]), float(integral[2]));

        // The sun: its radiance at the disk's centre times its solid angle.
        sun_integral_ = Spectrum(0.0f);
        if (sun_up_ && sun_scale_ > 0.0f)
            sun_integral_ = (complex_sun_ ? complex_sun_rgb(sun_local_, 0.0f) : sun_rgb_radiance_) * float(sun_solid_angle_);
        const float sky_power = std::max(luminance(sky_integral_), 0.0f), sun_power = std::max(luminance(sun_integral_), 0.0f);
        if (sun_power <= 0.0f)
            sky_probability_ = 1.0f;
        else if (sky_power <= 0.0f)
            sky_probability_ = 0.0f;
        else
            sky_probability_ = std::clamp(sky_power / (sky_power + sun_power), 0.05f, 0.95f);
    }

    // Parameters.
    float turbidity_ = 3.0f, sun_scale_ = 1.0f, sky_scale_ = 1.0f, sun_aperture_ = float(DefaultSunAperture);
    bool complex_sun_ = false, has_record_ = true;
    SunRecord record_;
    Vec3 sun_direction_{0.0f, 0.0f, 1.0f};                    // world space
    Spectrum albedo_{0.3f};                                   // RGB, each in [0, 1]
    std::shared_ptr<const SpectrumTexture> measured_albedo_;  // the spectral variant's, if measured
    Transform to_world_, world_to_local_;

    // Derived.
    Vec3 sun_local_{0.0f, 0.0f, 1.0f};
    Frame sun_frame_;
    bool sun_up_ = true;
    float cos_sun_half_angle_ = 1.0f, sin_sun_half_angle_ = 0.0f;
    double sun_solid_angle_ = 0.0;
    std::vector<double> sky_rgb_params_, sky_rgb_radiance_, sky_spectral_params_, sky_spectral_radiance_;
    std::vector<double> sun_irradiance_;  // W m^-2 nm^-1 at the 11 model wavelengths
    Spectrum sun_rgb_radiance_{0.0f};
    double sun_spectral_scale_ = 0.0, sun_complex_scale_ = 0.0;
    std::vector<double> sun_rgb_polynomials_, sun_spectral_polynomials_, sun_limb_;
    Distribution2D sky_distribution_;
    float sky_probability_ = 1.0f;
    Spectrum sky_integral_{0.0f}, sun_integral_{0.0f};
    SceneDisk disk_;
};

CANDELA_REGISTER_SPECTRAL(SunskyEmitter, ObjectKind::Emitter, "sunsky");

}  // namespace candela
