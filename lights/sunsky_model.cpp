#include "lights/sunsky_model.h"

#include "core/error.h"
#include "core/local_model.h"
#include "core/properties.h"
#include "core/scene.h"
#include "core/spectral.h"
#include "core/wavelengths.h"
#include "lights/sunsky_data.h"

#include <algorithm>
#include <cmath>

namespace candela {

namespace {

constexpr double FirstWavelength = 320.0, WavelengthStep = 40.0;
constexpr int Turbidities = 10, Albedos = 2, SkyControlPoints = 6, SkyParams = 9, SkyValues = SkyParams + 1;
constexpr int SunSegments = 45, SunPolynomial = 4, SunLimbTerms = 6;
constexpr int IrradianceElevations = 30;  // sun elevations 2, 5, ... 89 degrees
constexpr double DefaultSunAperture = 0.5358;
// Mitsuba's factor from the model's solar data to RGB radiance (SPEC_TO_RGB_SUN_CONV).
constexpr double SunRGBScale = 467.069280386;
constexpr double PiD = 3.14159265358979323846;

// The angle between unit vectors, accurate when they are nearly parallel or opposite (Mitsuba's
// unit_angle).
float unit_angle(const Vec3& a, const Vec3& b) {
    if (glm::dot(a, b) >= 0.0f) return 2.0f * std::asin(std::min(1.0f, 0.5f * glm::length(a - b)));
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

// The sky's data [turbidity][albedo][control point][channel][values] for one turbidity and
// per-channel albedo, as [control point][channel][9 coefficients, L_M].
std::vector<double> sky_data(const std::vector<double>& params, const std::vector<double>& radiance, int channels, double turbidity,
                             const std::vector<double>& albedo) {
    const size_t params_block = size_t(SkyControlPoints) * channels * SkyParams, radiance_block = size_t(SkyControlPoints) * channels;
    std::vector<double> p = interpolate_first_axis(params, Turbidities, Albedos * params_block, turbidity - 1.0);
    std::vector<double> r = interpolate_first_axis(radiance, Turbidities, Albedos * radiance_block, turbidity - 1.0);
    std::vector<double> out(size_t(SkyControlPoints) * channels * SkyValues);
    for (int k = 0; k < SkyControlPoints; ++k)
        for (int c = 0; c < channels; ++c) {
            const double a = albedo[size_t(c)];
            double* o = &out[(size_t(k) * channels + c) * SkyValues];
            for (int v = 0; v < SkyParams; ++v) {
                size_t i = (size_t(k) * channels + c) * SkyParams + v;
                o[v] = (1.0 - a) * p[i] + a * p[params_block + i];
            }
            size_t i = size_t(k) * channels + c;
            o[SkyParams] = (1.0 - a) * r[i] + a * r[radiance_block + i];
        }
    return out;
}

// The quintic Bezier curve through the control points at the sun's elevation eta (radians):
// weights binomial(5, k) x^k (1 - x)^(5 - k) at x = (2 eta / pi)^(1/3).
void bezier(const std::vector<double>& data, int channels, double eta, double* out) {
    static const double binomial[SkyControlPoints] = {1, 5, 10, 10, 5, 1};
    const double x = std::min(std::cbrt(2.0 * std::max(eta, 0.0) / PiD), 1.0);
    const size_t n = size_t(channels) * SkyValues;
    std::fill(out, out + n, 0.0);
    for (int k = 0; k < SkyControlPoints; ++k) {
        const double w = binomial[k] * std::pow(x, k) * std::pow(1.0 - x, SkyControlPoints - 1 - k);
        for (size_t i = 0; i < n; ++i) out[i] += w * data[size_t(k) * n + i];
    }
}

// Hosek-Wilkie's sky function times L_M for one channel: p holds A B C D E F G I H, L_M.
double sky_radiance(const double* p, double cos_theta, double gamma, double cos_gamma) {
    double chi = (1.0 + cos_gamma * cos_gamma) / std::pow(1.0 + p[8] * p[8] - 2.0 * p[8] * cos_gamma, 1.5);
    return (1.0 + p[0] * std::exp(p[1] / (cos_theta + 0.01))) *
           (p[2] + p[3] * std::exp(p[4] * gamma) + p[5] * cos_gamma * cos_gamma + p[6] * chi + p[7] * std::sqrt(std::max(cos_theta, 0.0))) *
           p[9];
}

// The mean of cmf(l_i) E(l_i) over the model's wavelengths (the 320 nm sample has no weight),
// as Mitsuba converts the irradiance spectrum.
Vec3d model_spectrum_xyz(const double* values) {
    Vec3d xyz(0.0);
    for (int i = 0; i < SunskyWavelengths; ++i) xyz += cie1931_xyz(FirstWavelength + WavelengthStep * i) * (values[i] / SunskyWavelengths);
    return xyz;
}

// complex_sun: the solar radiance function's segment (breaks at (k / 45)^3 pi / 2) and the offset
// into it for the elevation a view direction has.
void sun_segment(const Vec3& local, int& segment, double& x) {
    double elevation = 0.5 * PiD - std::acos(std::clamp(double(local.z), -1.0, 1.0));
    segment = std::clamp(int(std::cbrt(2.0 * elevation / PiD) * SunSegments), 0, SunSegments - 1);
    x = elevation - 0.5 * PiD * std::pow(double(segment) / SunSegments, 3.0);
}

// The irradiance tables' rows are the sun elevations 2, 5, ... 89 degrees: the row below eta
// (radians) and the weight of the row above, clamped to the table.
double irradiance_position(double eta) {
    return std::clamp((std::max(eta, 0.0) * 180.0 / PiD - 2.0) / 3.0, 0.0, double(IrradianceElevations - 1));
}
int irradiance_row(double eta) { return std::min(int(irradiance_position(eta)), IrradianceElevations - 2); }
double irradiance_weight(double eta, int row) { return irradiance_position(eta) - row; }

std::vector<double> to_doubles(const std::vector<float>& v) { return std::vector<double>(v.begin(), v.end()); }

}  // namespace

int julian_day(int year, int month, int day) {
    int a = (month - 14) / 12;
    return (1461 * (year + 4800 + a)) / 4 + (367 * (month - 2 - 12 * a)) / 12 - (3 * ((year + 4900 + a) / 100)) / 4 + day - 32075;
}

// The PSA algorithm (Blanco-Muriel et al., "Computing the solar vector", Solar Energy 70(5),
// 2001), in single precision as Mitsuba's scalar variants compute it: the Julian date then rounds
// to a quarter day, which moves only the slow terms (the daily rotation comes from the hours
// themselves), by up to 0.04 degrees. Azimuth from north toward east; the direction is
// (sin t cos(az - pi), sin t sin(az - pi), cos t).
Vec3 sun_direction_at(const SunRecord& r) {
    using std::cos, std::sin;
    const float pi = 3.14159265358979323846f;
    float hours_ut = r.hour - r.timezone + (r.minute + r.second / 60.0f) / 60.0f;
    // Days since 2000-01-01 12:00 UT.
    float n = (float(julian_day(r.year, r.month, r.day)) - 0.5f + hours_ut / 24.0f) - 2451545.0f;
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
    const float phi = azimuth - pi;
    return Vec3(sin(zenith) * cos(phi), sin(zenith) * sin(phi), cos(zenith));
}

void expose_record(ParameterVisitor& visitor, SunRecord& record, bool with_date) {
    expose_float(visitor, "latitude", record.latitude);
    expose_float(visitor, "longitude", record.longitude);
    expose_float(visitor, "timezone", record.timezone);
    if (!with_date) return;
    expose_int(visitor, "year", record.year);
    expose_int(visitor, "month", record.month);
    expose_int(visitor, "day", record.day);
    expose_float(visitor, "hour", record.hour);
    expose_float(visitor, "minute", record.minute);
    expose_float(visitor, "second", record.second);
}

SunskySettings SunskySettings::read(const Properties& props) {
    SunskySettings s;
    s.turbidity = props.get_float("turbidity", s.turbidity);
    s.sun_scale = props.get_float("sun_scale", s.sun_scale);
    s.sky_scale = props.get_float("sky_scale", s.sky_scale);
    s.sun_aperture = props.get_float("sun_aperture", s.sun_aperture);
    s.complex_sun = props.get_bool("complex_sun", s.complex_sun);
    Ref<Texture> albedo = props.get_texture("albedo", s.albedo);
    if (!albedo->is_constant()) props.fail("albedo", "the ground albedo must be constant, not a spatially varying texture");
    s.albedo = albedo->mean();
    s.measured_albedo = props.measured_spectrum("albedo");
    return s;
}

SunskyModel::SunskyModel(const SunskySettings& settings) : settings_(settings) {
    const SunskySettings& s = settings_;
    if (!(s.turbidity >= 1.0f && s.turbidity <= 10.0f))
        throw InputError("turbidity " + std::to_string(s.turbidity) + " is outside [1, 10]");
    if (!(s.sun_scale >= 0.0f) || !std::isfinite(s.sun_scale)) throw InputError("sun_scale must be finite and >= 0");
    if (!(s.sky_scale >= 0.0f) || !std::isfinite(s.sky_scale)) throw InputError("sky_scale must be finite and >= 0");
    if (!(s.sun_aperture > 0.0f && s.sun_aperture < 180.0f)) throw InputError("sun_aperture must be in (0, 180) degrees");
    for (int c = 0; c < 3; ++c)
        if (!(s.albedo[c] >= 0.0f && s.albedo[c] <= 1.0f)) throw InputError("the albedo must be in [0, 1] in every channel");

    // The sun's half-angle and its cosine in single precision, as Mitsuba evaluates them: the
    // disk's radiance divides the irradiance by the solid angle the hit test really covers.
    const float half_angle = float(s.sun_aperture * 0.5 * PiD / 180.0);
    cos_sun_half_angle_ = std::cos(half_angle);
    sin_sun_half_angle_ = std::sin(half_angle);
    sun_solid_angle_ = 2.0 * PiD * (1.0 - double(cos_sun_half_angle_));
    const double default_solid_angle = 2.0 * PiD * (1.0 - double(std::cos(float(DefaultSunAperture * 0.5 * PiD / 180.0))));
    area_ratio_ = default_solid_angle / sun_solid_angle_;

    // Albedo per RGB channel and per model wavelength.
    std::vector<double> albedo_rgb(3), albedo_spectral(SunskyWavelengths);
    for (int c = 0; c < 3; ++c) albedo_rgb[size_t(c)] = s.albedo[c];
    for (int i = 0; i < SunskyWavelengths; i += 3) {
        Vec3 lambda;
        for (int k = 0; k < 3; ++k) lambda[k] = float(FirstWavelength + WavelengthStep * std::min(i + k, SunskyWavelengths - 1));
        Wavelengths w = Wavelengths::at(lambda);
        Spectrum v = s.measured_albedo ? s.measured_albedo->eval_spectrum(SurfaceInteraction(), w, SpectrumRole::Reflectance)
                                       : rgb_at_wavelengths(s.albedo, SpectrumRole::Reflectance, &w);
        for (int k = 0; k < 3 && i + k < SunskyWavelengths; ++k) albedo_spectral[size_t(i + k)] = std::clamp(double(v[k]), 0.0, 1.0);
    }

    const TensorFile& data = sunsky_datasets();
    const double t = s.turbidity;
    sky_rgb_ = sky_data(data.doubles("sky_params_rgb"), data.doubles("sky_rad_rgb"), 3, t, albedo_rgb);
    sky_spectral_ = sky_data(data.doubles("sky_params_spec"), data.doubles("sky_rad_spec"), SunskyWavelengths, t, albedo_spectral);
    const size_t irradiance_block = size_t(IrradianceElevations) * SunskyWavelengths;
    sun_irradiance_ =
        interpolate_first_axis(to_doubles(sunsky_sampling_data().floats("sun_irradiance")), Turbidities, irradiance_block, t - 1.0);
    sky_irradiance_ =
        interpolate_first_axis(to_doubles(sunsky_sampling_data().floats("sky_irradiance")), Turbidities, irradiance_block, t - 1.0);
    sun_rgb_polynomials_ =
        interpolate_first_axis(data.doubles("sun_rad_rgb"), Turbidities, size_t(SunSegments) * 3 * SunPolynomial * SunLimbTerms, t - 1.0);
    sun_spectral_polynomials_ =
        interpolate_first_axis(data.doubles("sun_rad_spec"), Turbidities, size_t(SunSegments) * SunskyWavelengths * SunPolynomial, t - 1.0);
    sun_limb_ = data.doubles("sun_ld_spec");
}

void SunskyModel::state_at(const Vec3& sun_local, SunskyState& state) const {
    state.sun = sun_local;
    const double eta = 0.5 * PiD - double(unit_angle(sun_local, Vec3(0.0f, 0.0f, 1.0f)));
    state.elevation = eta;
    state.up = eta >= 0.0;
    bezier(sky_rgb_, 3, eta, &state.sky_rgb[0][0]);
    bezier(sky_spectral_, SunskyWavelengths, eta, &state.sky_spectral[0][0]);
    // The sun's irradiance at this elevation, spread uniformly over the disk: E / (2 pi (1 - cos
    // h_default)) times the aperture's area ratio, i.e. E over the disk's own solid angle.
    const int i0 = irradiance_row(eta);
    const double w = irradiance_weight(eta, i0);
    double irradiance[SunskyWavelengths];
    const double scale = double(settings_.sun_scale) / sun_solid_angle_;
    for (int i = 0; i < SunskyWavelengths; ++i) {
        irradiance[i] =
            (1.0 - w) * sun_irradiance_[size_t(i0) * SunskyWavelengths + i] + w * sun_irradiance_[size_t(i0 + 1) * SunskyWavelengths + i];
        state.sun_spectral[i] = irradiance[i] * scale;
    }
    // The RGB variant's colour carries the CIE Y normalisation once, as Mitsuba 3.8's does
    // (measured against it: bench/results/sunsky_2026-12-06.txt).
    Vec3d rgb = xyz_to_linear_srgb(model_spectrum_xyz(irradiance)) * (SunRGBScale * CieYNormalization * scale);
    state.sun_rgb = Spectrum(float(rgb.x), float(rgb.y), float(rgb.z));
}

Spectrum SunskyModel::radiance(const SunskyState& state, const Vec3& local, bool in_sun, const Wavelengths* w) const {
    if (local.z < 0.0f || !state.up) return Spectrum(0.0f);
    const float gamma = unit_angle(state.sun, local);
    const double cos_theta = local.z, cos_gamma = std::cos(double(gamma));
    const double sky_scale = settings_.sky_scale;
    const bool sun = in_sun && settings_.sun_scale > 0.0f;
    if (!w) {
        Spectrum sky(0.0f);
        if (sky_scale > 0.0)
            for (int c = 0; c < 3; ++c)
                sky[c] = float(sky_scale * CieYNormalization * sky_radiance(state.sky_rgb[c], cos_theta, gamma, cos_gamma));
        if (!sun) return sky;
        return sky + (settings_.complex_sun ? complex_sun_rgb(local, gamma) : state.sun_rgb);
    }
    Spectrum out(0.0f);
    for (int k = 0; k < WavelengthSamples; ++k) {
        double n = (double(w->lambda[k]) - FirstWavelength) / WavelengthStep;
        if (!(n >= 0.0 && n <= SunskyWavelengths - 1)) continue;
        int lo = std::min(int(n), SunskyWavelengths - 2);
        double f = n - lo;
        double value = 0.0;
        if (sky_scale > 0.0)
            value += sky_scale * ((1.0 - f) * sky_radiance(state.sky_spectral[lo], cos_theta, gamma, cos_gamma) +
                                  f * sky_radiance(state.sky_spectral[lo + 1], cos_theta, gamma, cos_gamma));
        if (sun)
            value += settings_.complex_sun ? double(settings_.sun_scale) * area_ratio_ * complex_sun_spectral(local, gamma, lo, f)
                                           : (1.0 - f) * state.sun_spectral[lo] + f * state.sun_spectral[lo + 1];
        out[k] = float(value);
    }
    return out;
}

float SunskyModel::sun_share(const SunskyState& state) const {
    if (!state.up) return 0.0f;
    const int i0 = irradiance_row(state.elevation);
    const double w = irradiance_weight(state.elevation, i0);
    double sun[SunskyWavelengths], sky[SunskyWavelengths];
    for (int i = 0; i < SunskyWavelengths; ++i) {
        size_t a = size_t(i0) * SunskyWavelengths + i, b = a + SunskyWavelengths;
        sun[i] = (1.0 - w) * sun_irradiance_[a] + w * sun_irradiance_[b];
        sky[i] = (1.0 - w) * sky_irradiance_[a] + w * sky_irradiance_[b];
    }
    const double sun_y = settings_.sun_scale * model_spectrum_xyz(sun).y, sky_y = settings_.sky_scale * model_spectrum_xyz(sky).y;
    return sun_y + sky_y > 0.0 ? float(sun_y / (sun_y + sky_y)) : 0.0f;
}

Spectrum SunskyModel::sun_integral(const SunskyState& state) const {
    if (!state.up || settings_.sun_scale == 0.0f) return Spectrum(0.0f);
    const Spectrum centre = settings_.complex_sun ? complex_sun_rgb(state.sun, 0.0f) : state.sun_rgb;
    return centre * float(sun_solid_angle_);
}

double SunskyModel::cos_psi(float gamma) const {
    double s = std::sin(double(gamma)) / double(sin_sun_half_angle_);
    return std::sqrt(std::max(1.0 - s * s, 0.0));
}

// RGB: the limb darkening is part of the data (polynomials in x and cos psi).
Spectrum SunskyModel::complex_sun_rgb(const Vec3& local, float gamma) const {
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
        out[c] = float(double(settings_.sun_scale) * area_ratio_ * SunRGBScale * CieYNormalization * sum);
    }
    return out;
}

// Spectral: the cubic in x at model wavelengths lo and lo + 1, interpolated by f, times the
// interpolated limb-darkening polynomial in cos psi.
double SunskyModel::complex_sun_spectral(const Vec3& local, float gamma, int lo, double f) const {
    int segment;
    double x;
    sun_segment(local, segment, x);
    const double c_psi = cos_psi(gamma);
    double radiance[2] = {0.0, 0.0}, limb[2] = {0.0, 0.0};
    for (int e = 0; e < 2; ++e) {
        const double* d = &sun_spectral_polynomials_[(size_t(segment) * SunskyWavelengths + size_t(lo + e)) * SunPolynomial];
        for (int k = 0; k < SunPolynomial; ++k) radiance[e] += std::pow(x, k) * d[k];
        for (int j = 0; j < SunLimbTerms; ++j) limb[e] += std::pow(c_psi, j) * sun_limb_[size_t(lo + e) * SunLimbTerms + size_t(j)];
    }
    return ((1.0 - f) * radiance[0] + f * radiance[1]) * ((1.0 - f) * limb[0] + f * limb[1]);
}

SunskyEmitterBase::SunskyEmitterBase(const Properties& props) : settings_(SunskySettings::read(props)) {
    type_ = EmitterType::Infinite;
    to_world_ = props.get_transform("to_world");
}

void SunskyEmitterBase::initialize(const Properties& props) {
    try {
        update();
    } catch (const InputError& e) {
        props.fail(e.what());
    }
}

void SunskyEmitterBase::update() {
    if (!to_world_.all_finite()) throw InputError("to_world is not finite");
    world_to_local_ = to_world_.inverse();
    model_ = std::make_shared<const SunskyModel>(settings_);
    update_sun();
}

void SunskyEmitterBase::set_scene(const Scene& scene) { disk_ = SceneDisk::around(scene.bbox()); }

std::optional<LocalApproximation> SunskyEmitterBase::local_approximation() const {
    LocalApproximation a;
    a.kind = LocalApproximation::Kind::Ambient;
    a.radiance = radiance_integral_ / FourPi;
    return a;
}

void SunskyEmitterBase::traverse(ParameterVisitor& visitor) {
    expose_float(visitor, "turbidity", settings_.turbidity);
    expose_float(visitor, "sky_scale", settings_.sky_scale);
    expose_float(visitor, "sun_scale", settings_.sun_scale);
    expose_transform(visitor, "to_world", to_world_);
    expose_color(visitor, "albedo.value", settings_.albedo);
}

void SunskyEmitterBase::parameters_changed(const std::vector<std::string>& keys) {
    if (std::find(keys.begin(), keys.end(), "albedo.value") != keys.end()) settings_.measured_albedo.reset();
    update();
}

DirectionSample SunskyEmitterBase::direction_sample(const SurfaceInteraction& ref, const Vec3& local, float pdf) const {
    DirectionSample ds;
    ds.emitter = this;
    ds.pdf = pdf;
    ds.d = glm::normalize(to_world_.apply_vector(local));
    ds.dist = Infinity;
    ds.p = ref.p + ds.d * (2.0f * disk_.radius);
    ds.n = -ds.d;
    return ds;
}

}  // namespace candela
