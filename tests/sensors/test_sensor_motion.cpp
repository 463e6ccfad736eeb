// Animated sensors (camera motion blur) and the shutter: keyframes that are all equal give the
// static camera's rays, a closed shutter at t gives the camera interpolated at t, every camera
// ray carries its time, and the pixel loop draws times uniform over the exposure.

#include "core/integrator.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

Ref<Scene> camera_scene(const std::string& name, const std::string& type, const std::string& sensor_body) {
    return load_scene_xml(name, "<sensor type=\"" + type + "\">" + sensor_body + R"(
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="24"/></film></sensor>)");
}

std::string lookat(const std::string& origin, const std::string& target) {
    return "<lookat origin=\"" + origin + "\" target=\"" + target + "\" up=\"0, 0, 1\"/>";
}

void check_same_rays(const Sensor& a, const Sensor& b, float time_a, float time_b, float tolerance) {
    for (Vec2 film : {Vec2(0.5f), Vec2(16.0f, 12.0f), Vec2(31.2f, 3.7f), Vec2(4.0f, 23.0f)})
        for (Vec2 lens : {Vec2(0.5f), Vec2(0.1f, 0.9f)}) {
            Ray ra = a.sample_ray(film, lens, time_a), rb = b.sample_ray(film, lens, time_b);
            INFO("film " << film.x << ", " << film.y);
            CHECK(glm::length(ra.o - rb.o) <= tolerance);
            CHECK(glm::length(ra.d - rb.d) <= tolerance);
            CHECK(ra.time == time_a);
        }
}

}  // namespace

TEST_CASE("sensor motion: equal keyframes give the static camera's rays", "[camera][animation]") {
    for (const char* type : {"perspective", "thinlens", "orthographic"}) {
        INFO(type);
        std::string extra =
            std::string(type) == "thinlens" ? R"(<float name="aperture_radius" value="0.2"/><float name="focus_distance" value="4"/>)" : "";
        std::string pose = lookat("1, -5, 2", "0, 0, 0.5");
        Ref<Scene> still = camera_scene("sensor-still", type, extra + "<transform name=\"to_world\">" + pose + "</transform>");
        Ref<Scene> moving = camera_scene("sensor-moving", type,
                                         extra + "<animation name=\"to_world\"><transform time=\"0\">" + pose +
                                             "</transform><transform time=\"1\">" + pose + "</transform></animation>");
        CHECK(moving->sensor().is_animated());
        CHECK_FALSE(still->sensor().is_animated());
        // The recomposed pose differs from the matrix by float rounding (coordinates ~5).
        for (float t : {0.0f, 0.3f, 1.0f}) check_same_rays(still->sensor(), moving->sensor(), t, t, 1e-5f);
    }
}

TEST_CASE("sensor motion: at time t the camera is the pose interpolated at t", "[camera][animation]") {
    // A dolly: origin and target move together by (2, 1, 0) from time 0 to 2. At t = 0.5 the
    // camera has moved a quarter of the way.
    Ref<Scene> moving =
        camera_scene("sensor-dolly", "perspective",
                     "<animation name=\"to_world\"><transform time=\"0\">" + lookat("1, -5, 2", "0, 0, 0.5") +
                         "</transform><transform time=\"2\">" + lookat("3, -4, 2", "2, 1, 0.5") + "</transform></animation>");
    Ref<Scene> quarter = camera_scene("sensor-quarter", "perspective",
                                      "<transform name=\"to_world\">" + lookat("1.5, -4.75, 2", "0.5, 0.25, 0.5") + "</transform>");
    check_same_rays(quarter->sensor(), moving->sensor(), 0.0f, 0.5f, 1e-5f);
    // The rasterizer's pose (to_world) is the one at shutter_open.
    CHECK(glm::length(Vec3(moving->sensor().to_world().matrix()[3]) - Vec3(1, -5, 2)) < 1e-6f);
}

TEST_CASE("sensor motion: the shutter gives each camera sample a time uniform over the exposure", "[camera][animation]") {
    // An integrator that returns the camera ray's time as its radiance: the film's mean is the
    // mean time. A box filter over 8 x 8 pixels of 64 independent samples: 4096 times uniform in
    // [open, close], mean (open + close) / 2 within z (close - open) / sqrt(12 n) at 1%.
    class TimeIntegrator final : public SamplingIntegrator {
    public:
        Spectrum sample_radiance(const Scene&, Sampler&, const Ray& ray, SampleRecord& record) const override {
            record.valid = true;
            return Spectrum(ray.time);
        }
        std::string to_string() const override { return "time"; }
    };
    Ref<Scene> scene = load_scene_xml("sensor-shutter", R"(<sensor type="perspective">
        <float name="shutter_open" value="2"/><float name="shutter_close" value="5"/>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/><rfilter type="box"/>
            <string name="component_format" value="float32"/></film></sensor>)");
    CHECK(scene->sensor().shutter_open() == 2.0f);
    CHECK(scene->sensor().shutter_open_time() == 3.0f);
    TimeIntegrator integrator;
    RenderOptions options;
    options.seed = 7;
    Image img = integrator.render(*scene, options).image;
    double mean = 0.0, lowest = 1e9, highest = -1e9;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            double v = img.rgb_at(x, y).x;
            mean += v / 64.0;
            lowest = std::min(lowest, v);
            highest = std::max(highest, v);
        }
    double sigma = 3.0 / std::sqrt(12.0 * 4096.0);
    INFO("mean time " << mean << " +- " << sigma);
    CHECK(std::abs(mean - 3.5) <= two_sided_z(0.01) * sigma);
    CHECK(lowest >= 2.0);
    CHECK(highest <= 5.0);
    // A closed shutter draws nothing: every ray at shutter_open.
    Ref<Scene> closed = load_scene_xml("sensor-closed", R"(<sensor type="perspective">
        <float name="shutter_open" value="0.25"/><float name="shutter_close" value="0.25"/>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/><rfilter type="box"/>
            <string name="component_format" value="float32"/></film></sensor>)");
    Image fixed = integrator.render(*closed, options).image;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) CHECK(fixed.rgb_at(x, y).x == 0.25f);
}
