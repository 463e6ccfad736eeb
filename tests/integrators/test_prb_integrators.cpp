// Mitsuba 3's differentiable integrators, rendered forward: prb_projective, direct_projective and
// prbvolpath are path, path at depth 2 and volpath with their defaults (bit for bit); prb_basic
// is its own estimator (BSDF sampling only) of path's image, checked block by block over
// independent seeds (Welch's test, Sidak over blocks and channels), with a power check.

#include "core/error.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

// A grey sphere on a floor under a broad area light and a dim sky: much of the light arrives
// after one or two bounces, and BSDF sampling alone finds the light often enough to converge.
std::string scene_xml(const std::string& integrator, int spp) {
    return R"(<scene version="3.0.0">
    )" + integrator +
           R"(
    <sensor type="perspective"><float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 2, 4" target="0, 0.4, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value=")" +
           std::to_string(spp) + R"("/></sampler>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/><string name="component_format" value="float32"/></film></sensor>
    <shape type="rectangle"><transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.6, 0.5"/></bsdf></shape>
    <shape type="sphere"><point name="center" value="0, 0.6, 0"/><float name="radius" value="0.6"/>
        <bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0.2, 0.5, 0.8"/><float name="alpha" value="0.3"/></bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="1.5"/><rotate x="1" angle="90"/><translate y="3"/></transform>
        <emitter type="area"><rgb name="radiance" value="3, 3, 3"/></emitter></shape>
    <emitter type="constant"><rgb name="radiance" value="0.2, 0.25, 0.3"/></emitter>
</scene>)";
}

Ref<Scene> load(const std::string& integrator, int spp = 4) {
    return load_scene_from_string(scene_xml(integrator, spp), scratch_dir("prb_integrators").string() + "/scene.xml");
}

Image render_image(const Scene& scene) { return scene.integrator().render(scene, RenderOptions()).image; }

// The error of `integrator` loading: its message, at the scene's line 2.
std::string load_error(const std::string& integrator) {
    try {
        load(integrator);
    } catch (const SceneError& e) {
        CHECK(e.location.line == 2);
        return e.what();
    }
    FAIL("loaded " << integrator);
    return "";
}

}  // namespace

TEST_CASE("prb_projective, direct_projective and prbvolpath render path's and volpath's images bit for bit", "[render][prb]") {
    const std::vector<std::pair<std::string, std::string>> pairs = {
        {R"(<integrator type="prb_projective"><integer name="sppc" value="8"/><integer name="sppi" value="64"/>
            <string name="guiding" value="none"/><boolean name="guiding_proj" value="false"/></integrator>)",
         R"(<integrator type="path"/>)"},
        {R"(<integrator type="prb_projective"><integer name="max_depth" value="3"/><integer name="rr_depth" value="2"/></integrator>)",
         R"(<integrator type="path"><integer name="max_depth" value="3"/><integer name="rr_depth" value="2"/></integrator>)"},
        {R"(<integrator type="direct_projective"><integer name="guiding_rounds" value="3"/></integrator>)",
         R"(<integrator type="path"><integer name="max_depth" value="2"/></integrator>)"},
        {R"(<integrator type="direct_projective"><boolean name="hide_emitters" value="true"/></integrator>)",
         R"(<integrator type="path"><integer name="max_depth" value="2"/><boolean name="hide_emitters" value="true"/></integrator>)"},
        {R"(<integrator type="prbvolpath"/>)", R"(<integrator type="volpath"><integer name="max_depth" value="6"/></integrator>)"},
    };
    for (const auto& [differentiable, forward] : pairs) {
        INFO(differentiable << " against " << forward);
        const Image a = render_image(*load(differentiable)), b = render_image(*load(forward));
        CHECK(a.data() == b.data());
    }
    // The defaults differ where Mitsuba's do: prbvolpath stops at 6, volpath does not (paths
    // longer than 6 are rare in this open scene: 64 samples per pixel meet some).
    CHECK(render_image(*load(R"(<integrator type="prbvolpath"/>)", 64)).data() !=
          render_image(*load(R"(<integrator type="volpath"/>)", 64)).data());
}

TEST_CASE("prb_basic: BSDF sampling alone estimates path's image", "[render][prb]") {
    const int seeds = 16, block = 4;
    const double level = sidak(0.01, (16 / block) * (16 / block) * 3);
    auto means = [&](const std::string& integrator) { return seed_block_means(*load(integrator, 64), seeds, block); };
    const SeedBlockMeans path = means(R"(<integrator type="path"><integer name="max_depth" value="6"/></integrator>)");
    std::string where;
    const double p = smallest_welch_p(path, means(R"(<integrator type="prb_basic"/>)"), where);
    INFO("prb_basic against path, both to depth 6: smallest p " << p << " at " << where << " (per-test level " << level << ")");
    CHECK(p >= level);
    // Power: light that arrives after two bounces and more is missing at depth 2, and the test sees it.
    const double p_short =
        smallest_welch_p(path, means(R"(<integrator type="prb_basic"><integer name="max_depth" value="2"/></integrator>)"), where);
    INFO("prb_basic at depth 2 against path at 6: smallest p " << p_short << " at " << where);
    CHECK(p_short < level);
}

TEST_CASE("prb_basic: at depth 1 it sees what path sees directly, bit for bit, and hide_emitters hides it", "[render][prb]") {
    const Image basic = render_image(*load(R"(<integrator type="prb_basic"><integer name="max_depth" value="1"/></integrator>)"));
    const Image path = render_image(*load(R"(<integrator type="path"><integer name="max_depth" value="1"/></integrator>)"));
    CHECK(basic.data() == path.data());
    double lit = 0.0;
    for (float v : basic.data()) lit += v;
    CHECK(lit > 0.0);
    const Image hidden = render_image(*load(
        R"(<integrator type="prb_basic"><integer name="max_depth" value="1"/><boolean name="hide_emitters" value="true"/></integrator>)"));
    for (int y = 0; y < hidden.height(); ++y)
        for (int x = 0; x < hidden.width(); ++x)
            for (int c = 0; c < 3; ++c) CHECK(hidden.at(x, y, c) == 0.0f);
    // Unbounded: roulette ends the paths (a closed scene would otherwise never finish); finite.
    const Image unbounded = render_image(*load(R"(<integrator type="prb_basic"><integer name="max_depth" value="-1"/></integrator>)"));
    CHECK(all_finite_pixels(unbounded));
}

TEST_CASE("prb_basic: its alpha is whether the camera ray meets a surface (prb_basic.py's validity)", "[render][prb]") {
    // The view's top rows see the sky past the floor. prb_basic.py returns "depth != 0" as its
    // validity, so alpha is 0 there; path counts a visible environment as valid (alpha 1), and
    // the depth integrator's alpha is the camera ray's hit, from the same camera rays.
    auto rgba = [](const std::string& integrator) {
        std::string xml = scene_xml(integrator, 4);
        const std::string filter = R"(<rfilter type="box"/>)";
        xml.replace(xml.find(filter), filter.size(), R"(<string name="pixel_format" value="rgba"/>)" + filter);
        return render_image(*load_scene_from_string(xml, scratch_dir("prb_integrators").string() + "/scene.xml"));
    };
    const Image basic = rgba(R"(<integrator type="prb_basic"/>)");
    const Image path = rgba(R"(<integrator type="path"/>)");
    const Image depth = rgba(R"(<integrator type="depth"/>)");
    REQUIRE(basic.channel_count() == 4);
    int missed = 0, hit = 0;
    for (int y = 0; y < basic.height(); ++y)
        for (int x = 0; x < basic.width(); ++x) {
            CHECK(basic.at(x, y, 3) == depth.at(x, y, 3));
            CHECK(path.at(x, y, 3) == 1.0f);
            missed += basic.at(x, y, 3) == 0.0f;
            hit += basic.at(x, y, 3) == 1.0f;
        }
    CHECK(missed > 0);
    CHECK(hit > 0);
}

TEST_CASE("prb_projective and direct_projective: their gradient settings are checked at their lines", "[render][prb][errors]") {
    CHECK_THAT(load_error(R"(<integrator type="prb_projective"><string name="guiding" value="kdtree"/></integrator>)"),
               Catch::Contains("guiding must be none, grid or octree"));
    CHECK_THAT(load_error(R"(<integrator type="direct_projective"><integer name="sppp" value="-1"/></integrator>)"),
               Catch::Contains("sppp must be 0"));
    CHECK_THAT(load_error(R"(<integrator type="prb_projective"><integer name="guiding_rounds" value="0"/></integrator>)"),
               Catch::Contains("guiding_rounds must be 1 or more"));
    CHECK_THAT(load_error(R"(<integrator type="prb_basic"><integer name="max_depth" value="-2"/></integrator>)"),
               Catch::Contains("max_depth"));
    CHECK_THAT(load_error(R"(<integrator type="prb_projective"><float name="sppd" value="1"/></integrator>)"), Catch::Contains("sppd"));
}
