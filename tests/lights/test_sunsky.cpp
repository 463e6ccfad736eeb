// The sunsky emitter: the sun's position from a date and place against facts of the sky (the
// solstice sun over the tropic, the noon sun due south, the equinox sun rising due east), the
// sun's irradiance kept whatever its aperture, the sky's irradiance by the emitter's own
// sampling against an independent uniform estimate, and its mistakes as errors at their lines;
// timed_sunsky against sunsky at the same instants, its sampling against its pdf.
// Its values against Mitsuba 3 are measured by bench/peers/sunsky.py (the peer is not part of the
// tests). The three statistical tests here share a 1% family-wise level (Sidak).

#include "analysis/statistics.h"
#include "core/error.h"
#include "core/parameters.h"
#include "core/rng.h"
#include "core/scene.h"
#include "core/warp.h"
#include "integrators/estimators.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

const double Alpha = sidak(0.01, 3);
const double DegreesPerRadian = 180.0 / 3.14159265358979323846;

Ref<Scene> load_sky_of(const std::string& plugin, const std::string& emitter_body) {
    return load_scene_xml("sunsky", "<emitter type=\"" + plugin + "\">" + emitter_body + R"(</emitter>
        <shape type="sphere"><float name="radius" value="0.01"/><point name="center" x="0" y="0" z="-100"/></shape>)");
}
Ref<Scene> load_sky(const std::string& emitter_body) { return load_sky_of("sunsky", emitter_body); }

const Emitter& the_sky(const Scene& scene) {
    REQUIRE(scene.emitters().size() == 1);
    return *scene.emitters()[0];
}

// The sun's world direction as the emitter reports it (its read-only sun_direction parameter).
Vec3 sun_direction(Scene& scene) {
    for (const SceneParameter& p : scene_parameters(scene))
        if (p.key == "sun_direction") {
            std::vector<float> v = p.access.get();
            REQUIRE(v.size() == 3);
            return glm::normalize(Vec3(v[0], v[1], v[2]));
        }
    FAIL("no sun_direction parameter");
    return Vec3(0.0f);
}

std::string date_and_place(double latitude, double longitude, int year, int month, int day, double hour_ut) {
    return "<float name=\"latitude\" value=\"" + std::to_string(latitude) + "\"/><float name=\"longitude\" value=\"" +
           std::to_string(longitude) + "\"/><float name=\"timezone\" value=\"0\"/><integer name=\"year\" value=\"" + std::to_string(year) +
           "\"/><integer name=\"month\" value=\"" + std::to_string(month) + "\"/><integer name=\"day\" value=\"" + std::to_string(day) +
           "\"/><float name=\"hour\" value=\"" + std::to_string(hour_ut) + "\"/>";
}

void fails_at(const std::string& emitter_body, int line, const std::string& message, const std::string& plugin = "sunsky") {
    INFO(emitter_body);
    try {
        load_scene_xml("sunsky_errors", "<emitter type=\"" + plugin + "\">\n" + emitter_body + "</emitter>");
        FAIL("expected an error: " << message);
    } catch (const SceneError& e) {
        CHECK_THAT(e.message(), Catch::Contains(message));
        CHECK(e.location.line == line);
    }
}

}  // namespace

// The emitter's frame (Mitsuba's): azimuth is measured from north toward east and the direction
// is (sin t cos(az - pi), sin t sin(az - pi), cos t), so +x is south, -y east, +z the zenith.
TEST_CASE("sunsky: the sun stands where the sky puts it", "[lights][sunsky]") {
    // 2024-06-20, the June solstice (declination 23.44 degrees), at local solar noon on the
    // meridian of Greenwich (12:02 UT: the equation of time is about -1.7 minutes): overhead at
    // the Tropic of Cancer.
    Ref<Scene> solstice = load_sky(date_and_place(23.44, 0.0, 2024, 6, 20, 12.0 + 2.0 / 60.0));
    CHECK(std::acos(sun_direction(*solstice).z) * DegreesPerRadian < 0.5);
    // 2024-03-21 at Lausanne (46.5 N, 6.6 E), local solar noon at 11:40 UT (longitude 26.4
    // minutes, equation of time about -7 minutes): due south, at 46.5 - 0.6 (declination)
    // degrees from the zenith.
    Ref<Scene> noon = load_sky(date_and_place(46.5, 6.6, 2024, 3, 21, 11.0 + 40.0 / 60.0));
    Vec3 s = sun_direction(*noon);
    CHECK(std::abs(std::atan2(s.y, s.x)) * DegreesPerRadian < 1.0);
    CHECK(std::abs(std::acos(s.z) * DegreesPerRadian - 45.9) < 1.0);
    // The equinox on the equator, 7:00 local solar time (7:07 UT at longitude 0): the sun has
    // risen due east and climbed 15 degrees.
    Ref<Scene> morning = load_sky(date_and_place(0.0, 0.0, 2024, 3, 20, 7.0 + 7.0 / 60.0));
    Vec3 m = sun_direction(*morning);
    CHECK(std::abs(std::atan2(m.y, m.x) * DegreesPerRadian + 90.0) < 1.5);
    CHECK(std::abs(std::asin(m.z) * DegreesPerRadian - 15.0) < 1.5);
    // A sun given by direction is reported as given; to_world turns the frame, not the sun.
    Ref<Scene> given = load_sky(R"(<vector name="sun_direction" x="1" y="2" z="2"/>
        <transform name="to_world"><rotate x="1" angle="-90"/></transform>)");
    Vec3 g = sun_direction(*given);
    CHECK(glm::length(g - Vec3(1.0f, 2.0f, 2.0f) / 3.0f) < 1e-6f);
}

TEST_CASE("sunsky: the sun's irradiance does not depend on its aperture", "[lights][sunsky]") {
    // The sun alone, facing a point whose normal points at it: E = L * Omega * (1 + cos h) / 2 (the
    // mean cosine over a uniform cone of half-angle h), and L * Omega is held fixed.
    const std::string sun = R"(<vector name="sun_direction" x="0.3" y="-0.5" z="0.6"/><float name="sky_scale" value="0"/>)";
    const Vec3 n = glm::normalize(Vec3(0.3f, -0.5f, 0.6f));
    EstimatorOptions o;
    o.samples = uint64_t(effort_scaled(100000, 20000));
    o.seed = 11;
    Ref<Scene> narrow = load_sky(sun);
    Ref<Scene> wide = load_sky(sun + R"(<float name="sun_aperture" value="8"/>)");
    Estimate a = estimate_irradiance(*narrow, Vec3(0.0f), n, o);
    Estimate b = estimate_irradiance(*wide, Vec3(0.0f), n, o);
    const double h0 = 0.5358 / 2.0 / DegreesPerRadian, h1 = 4.0 / DegreesPerRadian;
    const double expected_ratio = (1.0 + std::cos(h1)) / (1.0 + std::cos(h0));
    INFO("narrow " << a.mean.x << " +- " << a.std_error.x << ", wide " << b.mean.x << " +- " << b.std_error.x << ", expected ratio "
                   << expected_ratio);
    REQUIRE(a.mean.x > 0.0f);
    for (int c = 0; c < 3; ++c) {
        double difference = double(b.mean[c]) - expected_ratio * double(a.mean[c]);
        double se = std::hypot(double(b.std_error[c]), expected_ratio * double(a.std_error[c]));
        CHECK(std::abs(difference) <= two_sided_z(Alpha) * se + 1e-5 * double(a.mean[c]));
    }
    CHECK(a.nonfinite + b.nonfinite == 0);
}

TEST_CASE("sunsky: the sky's irradiance by its own sampling matches a uniform estimate", "[lights][sunsky]") {
    // The sky alone (its luminance peaks toward the sun and the horizon): the path tracer's
    // estimate (the emitter's sampling with MIS) against the mean of 2 pi L cos(theta) over
    // directions uniform on the hemisphere, drawn here from the emitter's eval alone.
    Ref<Scene> scene = load_sky(R"(<float name="sun_scale" value="0"/><float name="turbidity" value="4"/>
        <vector name="sun_direction" x="0.2" y="0.6" z="0.25"/>)");
    const Emitter& sky = the_sky(*scene);
    const Vec3 n(0.0f, 0.0f, 1.0f);
    EstimatorOptions o;
    o.samples = uint64_t(effort_scaled(200000, 40000));
    o.seed = 5;
    Estimate e = estimate_irradiance(*scene, Vec3(0.0f), n, o);
    PCG32 rng(17, 3);
    const int m = effort_scaled(400000, 80000);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < m; ++i) {
        Vec3 d = warp::square_to_uniform_hemisphere(Vec2(rng.next_float(), rng.next_float()));
        double v = 2.0 * 3.14159265358979323846 * double(sky.eval_environment(d, nullptr, 0.0f).y) * d.z;
        sum += v;
        sum2 += v * v;
    }
    double mean = sum / m, se = std::sqrt(std::max(sum2 / m - mean * mean, 0.0) / (m - 1));
    INFO("emitter sampling " << e.mean.y << " +- " << e.std_error.y << ", uniform " << mean << " +- " << se);
    REQUIRE(mean > 0.0);
    CHECK(std::abs(double(e.mean.y) - mean) <= two_sided_z(Alpha) * std::hypot(double(e.std_error.y), se));
    CHECK(e.nonfinite == 0);
}

TEST_CASE("sunsky: below the horizon it is black, and all of it when the sun has set", "[lights][sunsky]") {
    Ref<Scene> day = load_sky(R"(<vector name="sun_direction" x="0" y="1" z="1"/>)");
    CHECK(max_component(the_sky(*day).eval_environment(Vec3(0.3f, 0.0f, -0.5f), nullptr, 0.0f)) == 0.0f);
    const Spectrum above = the_sky(*day).eval_environment(Vec3(0.3f, 0.0f, 0.5f), nullptr, 0.0f);
    CHECK(std::min(above.x, std::min(above.y, above.z)) > 0.0f);
    Ref<Scene> night = load_sky(R"(<vector name="sun_direction" x="0" y="1" z="-0.1"/>)");
    CHECK(max_component(the_sky(*night).eval_environment(Vec3(0.0f, 0.0f, 1.0f), nullptr, 0.0f)) == 0.0f);
    CHECK(max_component(the_sky(*night).power()) == 0.0f);
}

TEST_CASE("sunsky: its mistakes are errors at their lines", "[lights][sunsky][errors]") {
    // Lines count from scene_xml's <scene> line (1); the emitter opens on line 2, its body on 3.
    fails_at("<vector name=\"sun_direction\" x=\"0\" y=\"0\" z=\"1\"/>\n<float name=\"hour\" value=\"9\"/>\n", 4,
             "both sun_direction and a time or place");
    fails_at("<float name=\"turbidity\" value=\"12\"/>\n", 2, "outside [1, 10]");
    fails_at("<rgb name=\"albedo\" value=\"0.2, 1.5, 0.2\"/>\n", 2, "albedo must be in [0, 1]");
    fails_at("<texture name=\"albedo\" type=\"checkerboard\"/>\n", 3, "must be constant");
    fails_at("<float name=\"sun_aperture\" value=\"0\"/>\n", 2, "sun_aperture must be in (0, 180)");
    fails_at("<vector name=\"sun_direction\" x=\"0\" y=\"0\" z=\"0\"/>\n", 3, "finite, non-zero");
}

TEST_CASE("timed_sunsky: at each instant it is the sunsky of that day and hour", "[lights][sunsky]") {
    // Eight days from 2025-03-01, hours 10:30 to 14:30, over the default shutter [0, 1]: time
    // 0.25 is the third day's 10:30, time 0.3125 its 12:30 (day = t (8 - 2^-24), hour = 10.5 +
    // 4 frac(day), both exact in single precision here).
    const std::string place =
        R"(<float name="latitude" value="46.5"/><float name="longitude" value="6.6"/><float name="timezone" value="1"/>
        <float name="turbidity" value="4"/><rgb name="albedo" value="0.2, 0.3, 0.4"/>)";
    Ref<Scene> timed =
        load_sky_of("timed_sunsky", place + R"(<integer name="start_year" value="2025"/><integer name="start_month" value="3"/>
        <integer name="end_year" value="2025"/><integer name="end_month" value="3"/><integer name="end_day" value="9"/>
        <float name="window_start_time" value="10.5"/><float name="window_end_time" value="14.5"/>)");
    for (auto [time, hour] : {std::pair<float, float>{0.25f, 10.5f}, {0.3125f, 12.5f}}) {
        Ref<Scene> fixed =
            load_sky(place + R"(<integer name="year" value="2025"/><integer name="month" value="3"/><integer name="day" value="3"/>
            <float name="hour" value=")" +
                     std::to_string(hour) + R"("/>)");
        const Vec3 sun = sun_direction(*fixed);
        INFO("time " << time);
        for (const Vec3& d :
             {sun, Vec3(0.0f, 0.0f, 1.0f), glm::normalize(Vec3(1.0f, 0.2f, 0.1f)), glm::normalize(Vec3(-0.3f, 0.8f, 0.4f))}) {
            const Spectrum a = the_sky(*timed).eval_environment(d, nullptr, time), b = the_sky(*fixed).eval_environment(d, nullptr, 0.0f);
            INFO("direction " << d.x << " " << d.y << " " << d.z << ": timed " << a.x << " " << a.y << " " << a.z << ", sunsky " << b.x
                              << " " << b.y << " " << b.z);
            CHECK(max_component(b) > 0.0f);
            CHECK(max_component(glm::abs(a - b)) <= 1e-6f * max_component(b));
        }
    }
}

TEST_CASE("timed_sunsky: its mistakes are errors at their lines", "[lights][sunsky][errors]") {
    fails_at("<integer name=\"start_year\" value=\"2026\"/>\n<integer name=\"end_year\" value=\"2025\"/>\n", 2,
             "start date is after the end date", "timed_sunsky");
    fails_at("<float name=\"window_start_time\" value=\"15\"/>\n<float name=\"window_end_time\" value=\"9\"/>\n", 2,
             "window_start_time is after window_end_time", "timed_sunsky");
    fails_at("<float name=\"shutter_open\" value=\"1\"/>\n<float name=\"shutter_close\" value=\"0.5\"/>\n", 2,
             "shutter_open must not be after", "timed_sunsky");
    fails_at("<integer name=\"start_month\" value=\"13\"/>\n", 2, "months run from 1 to 12", "timed_sunsky");
    fails_at("<float name=\"turbidity\" value=\"0\"/>\n", 2, "outside [1, 10]", "timed_sunsky");
}

TEST_CASE("timed_sunsky: its sampling gathers the same light as sunsky's at the same instant", "[lights][sunsky]") {
    // Sun and sky at noon of 2025-01-01 (time 0: the window opens at 12:00), on a plane facing
    // up: the path tracer's irradiance through each emitter's own sampling (timed: sun cone,
    // cosine and aureole cone; sunsky: sun cone and tabulated sky), z-tested per channel.
    Ref<Scene> timed = load_sky_of("timed_sunsky", R"(<float name="window_start_time" value="12"/>)");
    Ref<Scene> fixed = load_sky(R"(<integer name="year" value="2025"/><integer name="month" value="1"/><integer name="day" value="1"/>
        <float name="hour" value="12"/>)");
    EstimatorOptions o;
    o.samples = uint64_t(effort_scaled(200000, 40000));
    o.seed = 23;
    Estimate a = estimate_irradiance(*timed, Vec3(0.0f), Vec3(0.0f, 0.0f, 1.0f), o);
    o.seed = 29;
    Estimate b = estimate_irradiance(*fixed, Vec3(0.0f), Vec3(0.0f, 0.0f, 1.0f), o);
    INFO("timed " << a.mean.y << " +- " << a.std_error.y << ", sunsky " << b.mean.y << " +- " << b.std_error.y);
    REQUIRE(b.mean.y > 0.0f);
    CHECK(std::abs(double(a.luminance) - double(b.luminance)) <=
          two_sided_z(Alpha) * std::hypot(a.luminance_std_error, b.luminance_std_error));
    CHECK(a.nonfinite + b.nonfinite == 0);
}
