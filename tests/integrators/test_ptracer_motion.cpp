// ptracer under motion blur: each light path takes one shutter time, and its emitter, its rays
// and its connections to the sensor their poses then. Its image must be the one path's camera
// paths give: block by block, over independent seeds (Welch's test, Sidak over the blocks and
// channels). A ptracer that ignored the motion (its shutter closed) must fail the same test, so
// the test has the power to see what it checks.

#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <array>

using namespace candela;
using namespace candela::test;

namespace {

constexpr int Side = 16, Block = 4, Blocks = Side / Block, Seeds = 16;

// Per block (row-major) and channel, the block means of renders with seeds 1000, 1001, ...
using BlockMeans = std::vector<std::array<std::vector<double>, 3>>;

BlockMeans block_means(const std::string& xml, const std::string& integrator, const SceneParameters& params) {
    std::string text = xml;
    const std::string slot = "<integrator/>";
    text.replace(text.find(slot), slot.size(), R"(<integrator type=")" + integrator + R"("/>)");
    Ref<Scene> scene = load_scene_from_string(text, scratch_dir("ptracer_motion").string() + "/scene.xml", params);
    BlockMeans means(Blocks * Blocks);
    for (int k = 0; k < Seeds; ++k) {
        RenderOptions options;
        options.seed = 1000 + k;
        const Image image = scene->integrator().render(*scene, options).image;
        REQUIRE(image.width() == Side);
        for (int b = 0; b < Blocks * Blocks; ++b)
            for (int c = 0; c < 3; ++c)
                means[b][c].push_back(channel_mean(image, c, (b % Blocks) * Block, (b / Blocks) * Block, Block, Block).mean);
    }
    return means;
}

// The smallest Welch p-value of the blocks' and channels' comparisons, and where it was.
double smallest_p(const BlockMeans& a, const BlockMeans& b, std::string& where) {
    double smallest = 1.0;
    for (int block = 0; block < Blocks * Blocks; ++block)
        for (int c = 0; c < 3; ++c) {
            const WelchResult w = welch_test(a[block][c], b[block][c]);
            if (w.p_value < smallest) {
                smallest = w.p_value;
                where = "block " + std::to_string(block) + " channel " + std::to_string(c) + ": t = " + std::to_string(w.t) + ", means " +
                        std::to_string(mean_and_error(a[block][c]).mean) + " and " + std::to_string(mean_and_error(b[block][c]).mean);
            }
        }
    return smallest;
}

// Renders `xml` (with "<integrator/>" where the integrator goes, and a sensor whose shutter
// closes at $close) by path and by ptracer with the shutter open over [0, 1], and by ptracer
// with it closed at 0: the first two agree, the last differs from path.
void check_ptracer_follows_motion(const std::string& xml) {
    const double level = sidak(0.01, Blocks * Blocks * 3);
    const BlockMeans path = block_means(xml, "path", {{"close", "1"}});
    const BlockMeans ptracer = block_means(xml, "ptracer", {{"close", "1"}});
    std::string where;
    const double p = smallest_p(path, ptracer, where);
    INFO("path against ptracer over the shutter: smallest p " << p << " at " << where << " (per-test level " << level << ")");
    CHECK(p >= level);
    const BlockMeans still = block_means(xml, "ptracer", {{"close", "0"}});
    const double p_still = smallest_p(path, still, where);
    INFO("path over the shutter against ptracer at its opening: smallest p " << p_still << " at " << where);
    CHECK(p_still < level);
}

std::string sensor_xml(const std::string& to_world) {
    return R"(<sensor type="perspective"><float name="fov" value="45"/>)" + to_world + R"(
        <float name="shutter_open" value="0"/><float name="shutter_close" value="$close"/>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/><string name="component_format" value="float32"/></film></sensor>)";
}

}  // namespace

TEST_CASE("ptracer motion: a moving camera, box, area, point and spot light render as path renders them", "[render][ptracer][animation]") {
    const std::string xml = R"(<scene version="3.0.0"><default name="close" value="1"/><integrator/>)" + sensor_xml(R"(
        <animation name="to_world">
            <transform time="0"><lookat origin="0, 3, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
            <transform time="1"><lookat origin="1, 3, 5" target="1, 0, 0" up="0, 1, 0"/></transform></animation>)") +
                            R"(
    <shape type="rectangle"><transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.7, 0.7"/></bsdf></shape>
    <shape type="cube">
        <animation name="to_world">
            <transform time="0"><scale value="0.5"/><translate x="-1" y="0.5"/></transform>
            <transform time="1"><scale value="0.5"/><translate x="1" y="0.5"/></transform></animation>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.2, 0.1"/></bsdf></shape>
    <shape type="rectangle">
        <animation name="to_world">
            <transform time="0"><scale value="0.5"/><rotate x="1" angle="90"/><translate x="-1" y="2.5"/></transform>
            <transform time="1"><scale value="0.5"/><rotate x="1" angle="90"/><translate x="1" y="2.5"/></transform></animation>
        <emitter type="area"><rgb name="radiance" value="6, 6, 6"/></emitter></shape>
    <emitter type="point"><rgb name="intensity" value="4, 2, 1"/>
        <animation name="to_world">
            <transform time="0"><translate x="2" y="2" z="-1"/></transform>
            <transform time="1"><translate x="2" y="2" z="2"/></transform></animation></emitter>
    <emitter type="spot"><rgb name="intensity" value="1, 3, 8"/><float name="cutoff_angle" value="25"/>
        <animation name="to_world">
            <transform time="0"><lookat origin="-2, 3, 0" target="-1, 0, 0" up="0, 1, 0"/></transform>
            <transform time="1"><lookat origin="-2, 3, 2" target="0, 0, 1" up="0, 1, 0"/></transform></animation></emitter>
</scene>)";
    check_ptracer_follows_motion(xml);
}

TEST_CASE("ptracer motion: light paths under timed_sunsky see the sun of their own time", "[render][ptracer][sunsky]") {
    // The shutter's [0, 1] spans the day window 6:00 to 18:00 of one day: the sun crosses the sky
    // while the floor and the box stand still.
    const std::string xml =
        R"(<scene version="3.0.0"><default name="close" value="1"/><integrator/>)" +
        sensor_xml(R"(<transform name="to_world"><lookat origin="0, 3, 5" target="0, 0, 0" up="0, 1, 0"/></transform>)") + R"(
    <shape type="rectangle"><transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.7, 0.7"/></bsdf></shape>
    <shape type="cube"><transform name="to_world"><scale value="0.5"/><translate y="0.5"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.2, 0.1"/></bsdf></shape>
    <emitter type="timed_sunsky">
        <integer name="start_year" value="2025"/><integer name="start_month" value="6"/><integer name="start_day" value="21"/>
        <integer name="end_year" value="2025"/><integer name="end_month" value="6"/><integer name="end_day" value="21"/>
        <float name="window_start_time" value="6"/><float name="window_end_time" value="18"/>
        <transform name="to_world"><rotate x="1" angle="-90"/></transform></emitter>
</scene>)";
    check_ptracer_follows_motion(xml);
}
