// Light paths under motion blur. ptracer: each light path takes one shutter time, and its
// emitter, its rays and its connections to the sensor their poses then. sppm: each pass takes
// one, for its camera rays and photons. Their images must be the one path's camera paths give:
// block by block, over independent seeds (Welch's test, Sidak over the blocks and channels). One
// that ignored the motion (its shutter closed) must fail the same test, so the test has the
// power to see what it checks.

#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

constexpr int Block = 4, Blocks = 16 / Block, Seeds = 16;

// `integrator`: a plugin name, or the integrator's whole element.
Ref<Scene> with_integrator(const std::string& xml, const std::string& integrator, const SceneParameters& params) {
    std::string text = xml;
    const std::string slot = "<integrator/>";
    text.replace(text.find(slot), slot.size(), integrator[0] == '<' ? integrator : R"(<integrator type=")" + integrator + R"("/>)");
    return load_scene_from_string(text, scratch_dir("light_path_motion").string() + "/scene.xml", params);
}

SeedBlockMeans block_means(const std::string& xml, const std::string& integrator, const SceneParameters& params) {
    return seed_block_means(*with_integrator(xml, integrator, params), Seeds, Block);
}

// Renders `xml` (with "<integrator/>" where the integrator goes, and a sensor whose shutter
// closes at $close) by `reference` and by `light_paths` with the shutter open over [0, 1], and by
// `light_paths` with it closed at 0: the first two agree, the last differs from the reference.
void check_follows_motion(const std::string& xml, const std::string& light_paths, const std::string& reference = "path") {
    const double level = sidak(0.01, Blocks * Blocks * 3);
    const SeedBlockMeans path = block_means(xml, reference, {{"close", "1"}});
    const SeedBlockMeans moving = block_means(xml, light_paths, {{"close", "1"}});
    std::string where;
    const double p = smallest_welch_p(path, moving, where);
    INFO(light_paths << " against " << reference << " over the shutter: smallest p " << p << " at " << where << " (per-test level " << level
                     << ")");
    CHECK(p >= level);
    const SeedBlockMeans still = block_means(xml, light_paths, {{"close", "0"}});
    const double p_still = smallest_welch_p(path, still, where);
    INFO(reference << " over the shutter against " << light_paths << " at its opening: smallest p " << p_still << " at " << where);
    CHECK(p_still < level);
}

std::string sensor_xml(const std::string& to_world) {
    return R"(<sensor type="perspective"><float name="fov" value="45"/>)" + to_world + R"(
        <float name="shutter_open" value="0"/><float name="shutter_close" value="$close"/>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/><string name="component_format" value="float32"/></film></sensor>)";
}

// A moving camera, box, area, point and spot light.
std::string moving_scene_xml() {
    return R"(<scene version="3.0.0"><default name="close" value="1"/><integrator/>)" + sensor_xml(R"(
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
}

}  // namespace

TEST_CASE("ptracer motion: a moving camera, box, area, point and spot light render as path renders them", "[render][ptracer][animation]") {
    check_follows_motion(moving_scene_xml(), "ptracer");
}

TEST_CASE("sppm motion: each pass at one shutter time renders the moving scene as path does", "[render][sppm][animation]") {
    // Direct light (max_depth 2): the visible points' next-event estimation, unbiased, block by block.
    check_follows_motion(
        moving_scene_xml(),
        R"(<integrator type="sppm"><integer name="max_depth" value="2"/><integer name="photon_count" value="1000"/></integrator>)",
        R"(<integrator type="path"><integer name="max_depth" value="2"/></integrator>)");
    // All depths: the photons of each pass meet the scene in its pose (sppm's radius blurs the
    // indirect light, so the whole image's mean, per channel, is what must agree).
    const std::string sppm =
        R"(<integrator type="sppm"><integer name="photon_count" value="4000"/><float name="initial_radius" value="0.05"/></integrator>)";
    const SeedBlockMeans path = seed_block_means(*with_integrator(moving_scene_xml(), "path", {}), Seeds, 16);
    const SeedBlockMeans photons = seed_block_means(*with_integrator(moving_scene_xml(), sppm, {}), Seeds, 16);
    std::string where;
    const double p = smallest_welch_p(path, photons, where);
    INFO("sppm against path, whole image: smallest p " << p << " at " << where);
    CHECK(p >= sidak(0.01, 3));
}

TEST_CASE("ptracer and sppm motion: light paths under timed_sunsky see the sun of their own time", "[render][ptracer][sppm][sunsky]") {
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
    check_follows_motion(xml, "ptracer");
    check_follows_motion(
        xml, R"(<integrator type="sppm"><integer name="max_depth" value="2"/><integer name="photon_count" value="1000"/></integrator>)",
        R"(<integrator type="path"><integer name="max_depth" value="2"/></integrator>)");
}
