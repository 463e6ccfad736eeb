// Animated instances (motion blur through Embree's instance motion): keyframes that are all equal
// render the static instance, a closed shutter at time t renders the pose interpolated at t, and
// an open shutter gives the time average: a black bar sweeping across a white environment covers
// each pixel for the fraction of the exposure it passes over it, seen directly (camera rays) and
// in its shadow (shadow rays carry the camera ray's time). Any other shape with an animated
// to_world moves the same way (the loader wraps it in a one-shape group and animates an instance
// of it): at a closed shutter each analytic shape and a mesh render as the same shape placed
// statically at the interpolated pose.

#include "core/image.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

Image render_body(const std::string& name, const std::string& body) {
    auto dir = scratch_dir(name);
    write_text(dir / "scene.xml", scene_xml(body));
    return render_file((dir / "scene.xml").string(), {}).image;
}

// A lit stage around a shapegroup "group" of a sphere and a box, placed by `instance_transform`
// (a <transform> or an <animation> named to_world), seen by a perspective camera whose shutter
// is [open, close].
std::string stage(const std::string& instance_transform, float open, float close) {
    return R"(<shape type="shapegroup" id="group">
        <shape type="sphere"><float name="radius" value="0.7"/>
            <bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0.7, 0.2, 0.1"/><float name="alpha" value="0.2"/></bsdf></shape>
        <shape type="cube"><transform name="to_world"><scale value="0.4"/><translate x="0.9" y="0.3"/></transform></shape>
    </shape>
    <shape type="instance"><ref id="group"/>)" +
           instance_transform + R"(</shape>
    <shape type="rectangle"><transform name="to_world"><scale value="6"/><translate z="-1.3"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></shape>
    <emitter type="directional"><vector name="direction" x="-1" y="1" z="-2"/><rgb name="irradiance" value="3"/></emitter>
    <emitter type="constant"><rgb name="radiance" value="0.3"/></emitter>
    <integrator type="path"><integer name="max_depth" value="4"/></integrator>
    <sensor type="perspective"><float name="fov" value="50"/>
        <float name="shutter_open" value=")" +
           std::to_string(open) + R"("/><float name="shutter_close" value=")" + std::to_string(close) + R"("/>
        <transform name="to_world"><lookat origin="1, -5, 2" target="0, 0, 0" up="0, 0, 1"/></transform>
        <sampler type="independent"><integer name="sample_count" value="8"/></sampler>
        <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="40"/><rfilter type="box"/></film></sensor>)";
}

// The largest relative difference of two images' pixel luminances.
float worst_relative_difference(const Image& a, const Image& b) {
    float worst = 0.0f;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            float u = luminance(a.rgb_at(x, y)), v = luminance(b.rgb_at(x, y));
            worst = std::max(worst, std::abs(u - v) / std::max(std::max(u, v), 1e-6f));
        }
    return worst;
}

const char* Pose = R"(<rotate z="1" angle="20"/><translate x="0.2" y="-0.1" z="0.1"/>)";

// The fraction of the exposure [0, 1] during which a bar of half-width 0.25 whose centre moves
// from -0.75 to 0.75 covers coordinate u.
double covered_fraction(double u) {
    double lo = std::max(u - 0.25, -0.75), hi = std::min(u + 0.25, 0.75);
    return std::max(hi - lo, 0.0) / 1.5;
}

// The sweeping bar: a black rectangle 0.5 wide (along x) and 20 long, at height `z`, its centre
// moving along x from -0.75 at time 0 to 0.75 at time 1.
std::string sweeping_bar(float z) {
    std::string zs = std::to_string(z);
    return R"(<shape type="shapegroup" id="bar"><shape type="rectangle"><transform name="to_world"><scale x="0.25" y="10"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf></shape></shape>
        <shape type="instance"><ref id="bar"/><animation name="to_world">
            <transform time="0"><translate x="-0.75" z=")" +
           zs + R"("/></transform>
            <transform time="1"><translate x="0.75" z=")" +
           zs + R"("/></transform></animation></shape>)";
}

// An orthographic camera with an open shutter [0, 1] and a box-filtered 16 x 4 film, placed by
// `transform`, taking `spp` independent samples per pixel.
std::string exposing_camera(const std::string& transform, int spp) {
    return R"(<sensor type="orthographic"><float name="shutter_open" value="0"/><float name="shutter_close" value="1"/>)" + transform +
           R"(<sampler type="independent"><integer name="sample_count" value=")" + std::to_string(spp) + R"("/></sampler>
            <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="4"/><rfilter type="box"/>
                <string name="component_format" value="float32"/></film></sensor>)";
}

// Every sample is 0 or 1 (blocked or not), so a column of 4 pixels of n samples each is a mean
// of 4n Bernoulli draws of mean p = 1 - covered: within z sqrt(p (1 - p) / 4n) of p, z for a 1%
// family-wise level over the 16 columns and both tests of this file (Sidak).
void check_columns(const Image& img, int spp, const std::function<double(int)>& expected_covered) {
    const int Columns = 16, Tests = 2;
    const double z = two_sided_z(sidak(0.01, Columns * Tests));
    for (int x = 0; x < Columns; ++x) {
        double mean = 0.0;
        for (int y = 0; y < img.height(); ++y) mean += img.rgb_at(x, y).x / double(img.height());
        double p = 1.0 - expected_covered(x);
        double n = double(spp) * img.height();
        double sigma = std::sqrt(p * (1.0 - p) / n);
        INFO("column " << x << ": mean " << mean << ", expected " << p << " +- " << sigma);
        CHECK(std::abs(mean - p) <= z * sigma + 1e-6);
    }
}

// The covered fraction averaged over the width of column x, whose camera rays span world x in
// [x0 + x w, x0 + (x + 1) w] (midpoint rule on 4096 points: error below 1e-6).
double column_average(int x, double x0, double w) {
    const int N = 4096;
    double sum = 0.0;
    for (int i = 0; i < N; ++i) sum += covered_fraction(x0 + w * (x + (i + 0.5) / N));
    return sum / N;
}

}  // namespace

TEST_CASE("instance motion: equal keyframes render the static instance", "[instance][animation][render]") {
    std::string fixed = std::string("<transform name=\"to_world\">") + Pose + "</transform>";
    std::string moving = std::string("<animation name=\"to_world\"><transform time=\"0\">") + Pose + "</transform><transform time=\"1\">" +
                         Pose + "</transform></animation>";
    // Shutter [0, 1] in both: the same time draws, the same random numbers. The animated pose is
    // the decomposition recomposed (float rounding, 1e-6 relative): hit points agree to rounding,
    // amplified along a few bounces (1e-4 allows a factor 100).
    Image a = render_body("motion-equal-static", stage(fixed, 0.0f, 1.0f));
    Image b = render_body("motion-equal-animated", stage(moving, 0.0f, 1.0f));
    float worst = worst_relative_difference(a, b);
    INFO("largest relative pixel difference " << worst);
    CHECK(worst <= 1e-4f);
}

TEST_CASE("instance motion: a closed shutter at t renders the pose interpolated at t", "[instance][animation][render]") {
    // Halfway between (rotate -30, translate x 0) and (rotate 30, translate x 1): rotate 0,
    // translate x 0.5.
    std::string moving = R"(<animation name="to_world">
        <transform time="2"><rotate z="1" angle="-30"/><translate x="0" y="0.2"/></transform>
        <transform time="4"><rotate z="1" angle="30"/><translate x="1" y="0.2"/></transform></animation>)";
    std::string halfway = R"(<transform name="to_world"><translate x="0.5" y="0.2"/></transform>)";
    Image a = render_body("motion-fixed-time", stage(moving, 3.0f, 3.0f));
    Image b = render_body("motion-fixed-static", stage(halfway, 3.0f, 3.0f));
    float worst = worst_relative_difference(a, b);
    INFO("largest relative pixel difference " << worst);
    CHECK(worst <= 1e-4f);
    // The ends hold outside the keyframes: a shutter before the first keyframe shows the first pose.
    Image before = render_body("motion-before", stage(moving, 0.5f, 0.5f));
    Image first = render_body(
        "motion-first", stage(R"(<transform name="to_world"><rotate z="1" angle="-30"/><translate y="0.2"/></transform>)", 0.5f, 0.5f));
    CHECK(worst_relative_difference(before, first) <= 1e-4f);
}

TEST_CASE("instance motion: a bar sweeping across the view covers each pixel for its share of the exposure",
          "[instance][animation][render]") {
    // An orthographic camera at the origin looks along +z; column x of 16 sees world x from
    // 1 - 2 (x + 1) / 16 to 1 - 2 x / 16. The black bar at z = 5 blocks the white environment.
    const int Spp = effort_scaled(256, 64);
    Image img = render_body("motion-coverage", sweeping_bar(5.0f) + R"(<emitter type="constant"><rgb name="radiance" value="1"/></emitter>
        <integrator type="path"><integer name="max_depth" value="2"/></integrator>)" +
                                                   exposing_camera("", Spp));
    check_columns(img, Spp, [](int x) { return column_average(15 - x, -1.0, 2.0 / 16.0); });
}

TEST_CASE("instance motion: the bar's shadow is blurred too (shadow rays carry the camera ray's time)", "[instance][animation][render]") {
    // A white floor lit by a directional light travelling along (1, 0, -1): the bar at height 1
    // shadows floor point x when x - 1 lies under it. Irradiance pi sqrt(2) on the beam, cos 45
    // degrees on the floor, albedo 1: a lit floor point has radiance exactly 1. The camera looks
    // down on floor x in [1, 2] (column x sees [1 + x / 16, 1 + (x + 1) / 16]), where the bar
    // itself, within x in [-1, 1], is never in view.
    const int Spp = effort_scaled(256, 64);
    std::string body = sweeping_bar(1.0f) + R"(
        <shape type="rectangle"><transform name="to_world"><scale value="10"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf></shape>
        <emitter type="directional"><vector name="direction" x="1" y="0" z="-1"/><rgb name="irradiance" value="4.442882938158366"/></emitter>
        <integrator type="path"><integer name="max_depth" value="2"/></integrator>)" +
                       exposing_camera(R"(<transform name="to_world"><scale x="0.5" y="0.5"/>
                <lookat origin="1.5, 0, 5" target="1.5, 0, 0" up="0, 1, 0"/></transform>)",
                                       Spp);
    Image img = render_body("motion-shadow", body);
    check_columns(img, Spp, [](int x) { return column_average(x, 0.0, 1.0 / 16.0); });
}

TEST_CASE("instance motion: incommensurate keyframe times stop at their line, a moving area light loads", "[instance][animation][errors]") {
    auto error_of = [](const std::string& body) {
        try {
            load_scene_xml("motion-errors", body);
        } catch (const SceneError& e) {
            return e;
        }
        FAIL("no error");
        return SceneError(SourceLocation{}, "");
    };
    // Times whose intervals share no step within 1025 keyframes (1 and 0.000123).
    SceneError uneven = error_of(R"(<shape type="shapegroup" id="g"><shape type="sphere"/></shape>
<shape type="instance"><ref id="g"/>
<animation name="to_world"><transform time="0"/><transform time="1"/><transform time="1.000123"/></animation></shape>)");
    CHECK_THAT(uneven.message(), Catch::Contains("unevenly spaced"));
    CHECK(uneven.location.line == 4);
    // A moving area light loads (tests/lights/test_area_motion.cpp renders it); a shapegroup
    // written in the scene still refuses an emitter.
    Ref<Scene> light = load_scene_xml("motion-area", R"(<shape type="rectangle"><emitter type="area"/>
<animation name="to_world"><transform time="0"/><transform time="1"><translate x="1"/></transform></animation></shape>)");
    REQUIRE(light->emitters().size() == 1);
    CHECK(light->emitters()[0]->is_animated());
    SceneError grouped = error_of(R"(<shape type="shapegroup" id="g"><shape type="sphere"><emitter type="area"/></shape></shape>)");
    CHECK_THAT(grouped.message(), Catch::Contains("instancing of emitters"));
    SceneError uneven_shape = error_of(R"(<shape type="sphere">
<animation name="to_world"><transform time="0"/><transform time="1"/><transform time="1.000123"/></animation></shape>)");
    CHECK_THAT(uneven_shape.message(), Catch::Contains("unevenly spaced"));
    // An integrator that renders no motion stops at the animation's line.
    Ref<Scene> scene = load_scene_xml("motion-photonmapper", R"(<shape type="shapegroup" id="g"><shape type="sphere"/></shape>
<shape type="instance"><ref id="g"/>
<animation name="to_world"><transform time="0"/><transform time="1"/></animation></shape>
<integrator type="photonmapper"/>)");
    try {
        scene->integrator().render(*scene, RenderOptions());
        FAIL("photonmapper rendered a moving scene");
    } catch (const SceneError& e) {
        CHECK_THAT(e.message(), Catch::Contains("not rendered by the photonmapper integrator"));
        CHECK(e.location.line == 4);
    }
}

TEST_CASE("shape motion: analytic shapes and a mesh with an animated to_world render at the interpolated pose",
          "[instance][animation][render]") {
    // Each shape, with its own parameters, between (rotate -30, translate x 0) at t = 2 and
    // (rotate 30, translate x 1) at t = 4; the shutter closed at t = 3: the pose rotate 0,
    // translate x 0.5, rendered by the same shape with that static to_world (not an instance).
    const std::string moving = R"(<animation name="to_world">
        <transform time="2"><rotate z="1" angle="-30"/><translate x="0" y="0.2"/></transform>
        <transform time="4"><rotate z="1" angle="30"/><translate x="1" y="0.2"/></transform></animation>)";
    const std::string halfway = R"(<transform name="to_world"><translate x="0.5" y="0.2"/></transform>)";
    const std::string material =
        R"(<bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0.7, 0.2, 0.1"/><float name="alpha" value="0.2"/></bsdf>)";
    const std::vector<std::pair<std::string, std::string>> shapes = {
        {"sphere", R"(<point name="center" value="0.2, 0.1, 0"/><float name="radius" value="0.7"/>)"},
        {"disk", R"(<boolean name="flip_normals" value="true"/>)"},
        {"rectangle", ""},
        {"cylinder", R"(<float name="radius" value="0.4"/><point name="p0" value="0, 0, -0.5"/><point name="p1" value="0.3, 0, 0.8"/>)"},
        {"cube", ""}};
    for (const auto& shape : shapes) {
        const std::string& type = shape.first;  // not a structured binding: C++17 lambdas cannot capture one
        const std::string& params = shape.second;
        INFO(type);
        auto scene_with = [&](const std::string& transform) {
            // stage()'s lighting and camera, with this shape in place of the instance.
            std::string body = stage(R"(<transform name="to_world"><translate z="100"/></transform>)", 3.0f, 3.0f);
            return body + "<shape type=\"" + type + "\">" + params + material + transform + "</shape>";
        };
        Image a = render_body("shape-motion-" + type, scene_with(moving));
        Image b = render_body("shape-motion-static-" + type, scene_with(halfway));
        float worst = worst_relative_difference(a, b);
        INFO("largest relative pixel difference " << worst);
        CHECK(worst <= 1e-4f);
    }
}

TEST_CASE("shape motion: a moving sphere renders as the same sphere in a group moved by an instance", "[instance][animation][render]") {
    // The identity the loader relies on, at an open shutter (blurred): bit for bit, since it
    // builds exactly that group and instance.
    const std::string moving = R"(<animation name="to_world">
        <transform time="0"><rotate z="1" angle="-30"/></transform>
        <transform time="1"><rotate z="1" angle="30"/><translate x="1"/></transform></animation>)";
    const std::string sphere = R"(<point name="center" value="0.2, 0.1, 0"/><float name="radius" value="0.7"/>)";
    std::string body = stage(R"(<transform name="to_world"><translate z="100"/></transform>)", 0.0f, 1.0f);
    Image direct = render_body("shape-motion-direct", body + "<shape type=\"sphere\">" + sphere + moving + "</shape>");
    Image grouped =
        render_body("shape-motion-grouped", body + "<shape type=\"shapegroup\" id=\"one\"><shape type=\"sphere\">" + sphere +
                                                "</shape></shape><shape type=\"instance\"><ref id=\"one\"/>" + moving + "</shape>");
    CHECK(worst_relative_difference(direct, grouped) == 0.0f);
}

TEST_CASE("instance motion: keyframes at unequal steps are resampled to equal ones, the same motion", "[instance][animation][render]") {
    // Keyframes at t = 0, 1 and 3 (intervals 1 and 2: Embree gets steps of 1, the one at t = 2
    // interpolated). At t = 2.5, three quarters from the pose at 1 (rotate 10, x 0.2) to the pose
    // at 3 (rotate 50, x 1): rotate 40, x 0.8; at t = 0.5, halfway from rotate -30 to rotate 10.
    const std::string moving = R"(<animation name="to_world">
        <transform time="0"><rotate z="1" angle="-30"/></transform>
        <transform time="1"><rotate z="1" angle="10"/><translate x="0.2"/></transform>
        <transform time="3"><rotate z="1" angle="50"/><translate x="1"/></transform></animation>)";
    for (const auto& [time, pose] : std::vector<std::pair<float, std::string>>{
             {2.5f, R"(<rotate z="1" angle="40"/><translate x="0.8"/>)"}, {0.5f, R"(<rotate z="1" angle="-10"/><translate x="0.1"/>)"}}) {
        INFO("t = " << time);
        Image a = render_body("motion-uneven", stage(moving, time, time));
        Image b = render_body("motion-uneven-static", stage("<transform name=\"to_world\">" + pose + "</transform>", time, time));
        float worst = worst_relative_difference(a, b);
        INFO("largest relative pixel difference " << worst);
        CHECK(worst <= 1e-4f);
    }
}
