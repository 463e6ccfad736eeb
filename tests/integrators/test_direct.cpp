// The direct integrator against two other estimators of the same light: the path tracer at
// max_depth 2 (direct illumination), and its own strategies alone (light sampling only, BSDF
// sampling only), on a box with a glossy sphere, an area light and a dim sky; with a glass
// sphere, a point light and a mask where both sides can see them. Renders are independent (own
// seeds); each comparison is a z-test per 4x4 block and colour channel on the block means with
// the renders' own variance layers, all of them together at a 1% family-wise level (Sidak).

#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

constexpr int Size = 24, Block = 4, Spp = 256;
constexpr int Comparisons = 4;
constexpr int TestsPerComparison = (Size / Block) * (Size / Block) * 3;

// A box open toward the camera and on its right: white floor and back wall, a red left wall; a
// rough metal sphere; a square area light under the ceiling; a dim uniform sky. With `delta`,
// also a glass sphere, a point light and a half-transparent mask in front of the back wall.
std::string box_scene(const std::string& integrator, bool delta) {
    std::string s = integrator + R"(
        <sensor type="perspective"><float name="fov" value="45"/>
            <transform name="to_world"><lookat origin="0, 0, 3.2" target="0, 0, 0" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value=")" +
                    std::to_string(Spp) + R"("/></sampler>
            <film type="hdrfilm"><integer name="width" value=")" +
                    std::to_string(Size) + R"("/><integer name="height" value=")" + std::to_string(Size) +
                    R"("/><rfilter type="box"/><string name="component_format" value="float32"/></film>
        </sensor>
        <emitter type="constant"><rgb name="radiance" value="0.2, 0.25, 0.3"/></emitter>
        <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="-90"/><translate y="-1"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.7"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><translate z="-1"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.6, 0.5"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><rotate y="1" angle="90"/><translate x="-1"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.1, 0.1"/></bsdf></shape>
        <shape type="sphere"><point name="center" value="-0.35, -0.6, -0.2"/><float name="radius" value="0.4"/>
            <bsdf type="roughconductor"><string name="material" value="Au"/><float name="alpha" value="0.2"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="0.3"/><rotate x="1" angle="90"/><translate x="0.2" y="0.98"/></transform>
            <emitter type="area"><rgb name="radiance" value="12, 10, 8"/></emitter></shape>)";
    if (delta)
        s += R"(
        <shape type="sphere"><point name="center" value="0.45, -0.7, 0.2"/><float name="radius" value="0.3"/><bsdf type="dielectric"/></shape>
        <emitter type="point"><point name="position" value="-0.5, 0.6, 0.5"/><rgb name="intensity" value="0.8"/></emitter>
        <shape type="rectangle"><transform name="to_world"><scale x="0.4" y="0.3"/><translate x="0.3" y="0.2" z="-0.6"/></transform>
            <bsdf type="mask"><float name="opacity" value="0.5"/><bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.5, 0.2"/></bsdf></bsdf></shape>)";
    return scene_xml(s);
}

RenderResult render_box(const std::string& integrator, bool delta, uint64_t seed) {
    Ref<Scene> scene = load_scene_from_string(box_scene(integrator, delta), source_path("scenes/direct_test.xml"));
    RenderOptions options;
    options.aovs = {"variance"};
    options.seed = seed;
    return scene->integrator().render(*scene, options);
}

// Every block mean of `a` equals that of `b` within the Sidak-corrected z threshold; returns the
// median relative standard error of the differences over blocks with signal (the test's power).
double check_agree(const Image& a, const Image& b, const std::string& what) {
    const double z = two_sided_z(sidak(0.01, Comparisons * TestsPerComparison));
    std::vector<double> relative;
    for (int by = 0; by < Size; by += Block)
        for (int bx = 0; bx < Size; bx += Block)
            for (int ch = 0; ch < 3; ++ch) {
                MeanAndVariance ma = block_mean(a, ch, bx, by, Block), mb = block_mean(b, ch, bx, by, Block);
                double se = std::sqrt(ma.variance_of_mean + mb.variance_of_mean);
                INFO(what << ": block (" << bx << ", " << by << ") channel "
                          << "RGB"[ch] << ": " << ma.mean << " vs " << mb.mean << " +- " << se);
                CHECK(std::abs(ma.mean - mb.mean) <= z * se);
                if (mb.mean > 0.01) relative.push_back(se / mb.mean);
            }
    std::nth_element(relative.begin(), relative.begin() + long(relative.size() / 2), relative.end());
    return relative[relative.size() / 2];
}

}  // namespace

TEST_CASE("direct: equals path at max_depth 2, with one or several samples per strategy", "[render][direct]") {
    RenderResult path = render_box(R"(<integrator type="path"><integer name="max_depth" value="2"/></integrator>)", true, 1);
    RenderResult direct = render_box(R"(<integrator type="direct"/>)", true, 2);
    RenderResult several = render_box(
        R"(<integrator type="direct"><integer name="emitter_samples" value="3"/><integer name="bsdf_samples" value="2"/></integrator>)",
        true, 3);
    double power = check_agree(direct.image, path.image, "direct vs path");
    CHECK(power < 0.05);  // a bias of 20% in a typical block would show at the threshold
    check_agree(several.image, path.image, "direct (3 emitter, 2 BSDF samples) vs path");
    CHECK(direct.stats.nonfinite == 0);
}

TEST_CASE("direct: light sampling alone and BSDF sampling alone agree where both can see every light", "[render][direct]") {
    RenderResult emitter_only = render_box(
        R"(<integrator type="direct"><integer name="emitter_samples" value="2"/><integer name="bsdf_samples" value="0"/></integrator>)",
        false, 4);
    RenderResult bsdf_only = render_box(
        R"(<integrator type="direct"><integer name="emitter_samples" value="0"/><integer name="bsdf_samples" value="4"/></integrator>)",
        false, 5);
    double power = check_agree(emitter_only.image, bsdf_only.image, "light sampling vs BSDF sampling");
    CHECK(power < 0.1);
}

TEST_CASE("direct: its parameters are checked as Mitsuba checks them", "[render][direct][errors]") {
    auto fails = [](const std::string& body, const std::string& message) {
        try {
            load_scene_from_string(scene_xml(body), source_path("scenes/direct_errors.xml"));
            FAIL_CHECK("expected an error for " << body);
        } catch (const SceneError& e) {
            CHECK_THAT(std::string(e.what()), Catch::Contains(message));
        }
    };
    fails(R"(<integrator type="direct"><integer name="shading_samples" value="2"/><integer name="bsdf_samples" value="1"/></integrator>)",
          "not both");
    fails(R"(<integrator type="direct"><integer name="emitter_samples" value="0"/><integer name="bsdf_samples" value="0"/></integrator>)",
          "at least one");
    fails(R"(<integrator type="direct"><integer name="max_depth" value="2"/></integrator>)", "max_depth");
    fails(R"(<integrator type="direct"><string name="light_sampler" value="bogus"/></integrator>)", "unknown light_sampler");
}
