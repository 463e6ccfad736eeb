// sunsky: the sun and sky of a clear day, infinitely far away (Mitsuba 3's sunsky emitter): the
// Hosek-Wilkie skylight model and its solar radiance function, from their tabulated data
// (lights/sunsky_data.h), evaluated by lights/sunsky_model.h (shared with timed_sunsky).
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
#include "core/error.h"
#include "core/frame.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/warning.h"
#include "core/warp.h"
#include "lights/sunsky_model.h"

#include <algorithm>
#include <cmath>

namespace candela {

namespace {
constexpr float OneMinusEpsilon = 0x1.fffffep-1f;  // the largest float below 1
}  // namespace

class SunskyEmitter final : public SunskyEmitterBase {
public:
    explicit SunskyEmitter(const Properties& props) : SunskyEmitterBase(props) {
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
        initialize(props);
        if (!state_.up) warn(props.location(), "sunsky: the sun is below the horizon, so the sun and the sky are black");
    }

    Spectrum eval_environment(const Vec3& d, const Wavelengths* w, float) const override {
        Vec3 local = to_local(d);
        return model_->radiance(state_, local, model_->sees_sun(state_, local), w);
    }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2& u, Spectrum& weight) const override {
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
            local = sun_frame_.to_world(warp::square_to_uniform_cone(v, model_->cos_sun_half_angle()));
        }
        // A direction drawn in the sun's cone is in it, whatever the rounding of the test.
        const bool in_sun = !pick_sky || model_->sees_sun(state_, local);
        const float pdf = pdf_local(local, in_sun);
        if (!(pdf > 0.0f)) return DirectionSample{};
        weight = model_->radiance(state_, local, in_sun, ref.wavelengths) / pdf;
        return direction_sample(ref, local, pdf);
    }

    float pdf_direction(const SurfaceInteraction&, const DirectionSample& ds) const override {
        Vec3 local = to_local(ds.d);
        return pdf_local(local, model_->sees_sun(state_, local));
    }

    // The sun's position by the parameters it was given.
    void traverse(ParameterVisitor& visitor) override {
        SunskyEmitterBase::traverse(visitor);
        if (has_record_) expose_record(visitor, record_, true);
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
    std::string to_string() const override { return "sunsky"; }

private:
    // The sun's place, the model finished for it, and the sampling.
    void update_sun() override {
        Vec3 sun_local;
        if (has_record_) {
            if (record_.month < 1 || record_.month > 12 || record_.day < 1 || record_.day > 31)
                throw InputError("month and day must be a calendar date (month 1-12, day 1-31)");
            sun_local = sun_direction_at(record_);
            sun_direction_ = glm::normalize(to_world_.apply_vector(sun_local));
        } else {
            if (!(glm::length(sun_direction_) > 0.0f) || !all_finite(sun_direction_))
                throw InputError("the sun's direction must be a finite, non-zero vector");
            sun_local = to_local(sun_direction_);
        }
        model_->state_at(sun_local, state_);
        sun_frame_ = Frame(sun_local);
        build_sampling();
    }
    // The solid-angle density of the mixture at a local direction.
    float pdf_local(const Vec3& local, bool in_sun) const {
        if (local.z < 0.0f) return 0.0f;
        float phi = std::atan2(local.y, local.x) * InvTwoPi;
        phi -= std::floor(phi);
        // (u, v) = (phi / 2 pi, cos theta) has Jacobian d omega = 2 pi du dv.
        float pdf_sky = sky_distribution_.pdf(Vec2(std::min(phi, OneMinusEpsilon), std::min(local.z, OneMinusEpsilon))) * InvTwoPi;
        float pdf_sun = in_sun ? float(1.0 / model_->sun_solid_angle()) : 0.0f;
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
                lattice[size_t(j) * nx + i] = model_->radiance(state_, local, false, nullptr);
            }
        std::vector<float> weights(size_t(Azimuths) * Cosines);
        double sum_weights = 0.0, integral[3] = {0.0, 0.0, 0.0};
        const double cell_solid_angle = 2.0 * 3.14159265358979323846 / Azimuths / Cosines;
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
        const Spectrum sky_integral = Spectrum(float(integral[0]), float(integral[1]), float(integral[2]));

        const Spectrum sun_integral = model_->sun_integral(state_);
        radiance_integral_ = sky_integral + sun_integral;
        const float sky_power = std::max(luminance(sky_integral), 0.0f), sun_power = std::max(luminance(sun_integral), 0.0f);
        if (sun_power <= 0.0f)
            sky_probability_ = 1.0f;
        else if (sky_power <= 0.0f)
            sky_probability_ = 0.0f;
        else
            sky_probability_ = std::clamp(sky_power / (sky_power + sun_power), 0.05f, 0.95f);
    }

    bool has_record_ = true;
    SunRecord record_;
    Vec3 sun_direction_{0.0f, 0.0f, 1.0f};  // world space
    SunskyState state_;
    Frame sun_frame_;
    Distribution2D sky_distribution_;
    float sky_probability_ = 1.0f;
};

CANDELA_REGISTER_SPECTRAL(SunskyEmitter, ObjectKind::Emitter, "sunsky");

}  // namespace candela
