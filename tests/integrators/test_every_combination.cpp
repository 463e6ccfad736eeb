// Every integrator with every sampler, as a user can combine them (the scene's <integrator> and
// `--sampler`), with and without the film's sample_border, at sample counts that are not what
// the samplers round to: each render finishes, takes the samples it says, and is finite.
//
// Before issue 28, sppm with a stratified sampler of 9 samples looped forever in its camera
// pass (its sampler was asked for sample 9 of 9), and sobol or zsobol with sample_border read
// past their tables for the ring pixels left of and above the film (ASan: heap-buffer-overflow).

#include "core/integrator.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "core/variant.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <regex>

using namespace candela;
using namespace candela::test;

namespace {

const std::vector<std::string> AllSamplers = {"independent", "stratified", "multijitter", "orthogonal", "ldsampler", "sobol", "zsobol"};

// The integrators as a scene writes them, each kept small enough to render 16 x 16 pixels quickly.
struct IntegratorCase {
    std::string name, xml;
};
const std::vector<IntegratorCase>& integrator_cases() {
    static const std::vector<IntegratorCase> cases = {
        {"path", R"(<integrator type="path"/>)"},
        {"prb", R"(<integrator type="prb"/>)"},
        {"prb_basic", R"(<integrator type="prb_basic"/>)"},
        {"prb_projective", R"(<integrator type="prb_projective"><integer name="sppi" value="4"/></integrator>)"},
        {"direct_projective", R"(<integrator type="direct_projective"><string name="guiding" value="grid"/></integrator>)"},
        {"prbvolpath", R"(<integrator type="prbvolpath"/>)"},
        {"volpath", R"(<integrator type="volpath"/>)"},
        {"volpathmis", R"(<integrator type="volpathmis"/>)"},
        {"direct", R"(<integrator type="direct"/>)"},
        {"ao", R"(<integrator type="ao"/>)"},
        {"depth", R"(<integrator type="depth"/>)"},
        {"irradiance", R"(<integrator type="irradiance"><integer name="max_depth" value="3"/></integrator>)"},
        {"moment", R"(<integrator type="moment"><integrator type="path" name="p"/></integrator>)"},
        {"aov", R"(<integrator type="aov"><string name="aovs" value="dd.y:depth,nn:sh_normal"/><integrator type="path"/></integrator>)"},
        {"ptracer", R"(<integrator type="ptracer"/>)"},
        {"sppm", R"(<integrator type="sppm"><integer name="photon_count" value="2000"/></integrator>)"},
        {"photonmapper",
         R"(<integrator type="photonmapper"><integer name="global_photons" value="2000"/><integer name="caustic_photons" value="0"/>
            <integer name="glossy_samples" value="2"/><integer name="direct_samples" value="2"/></integrator>)"},
        {"radiosity", R"(<integrator type="radiosity"><integer name="subdivisions" value="2"/></integrator>)"},
        {"raster", R"(<integrator type="raster"/>)"},
    };
    return cases;
}

// The validation Cornell box at 16 x 16 with `integrator`, a gaussian filter (it reaches a pixel
// beyond its own) and `border` as its sample_border, written into `dir`.
std::string combination_scene(const std::filesystem::path& dir, const std::string& integrator, bool border) {
    std::string xml = read_text(source_path("scenes/validation/cbox.xml"));
    xml = std::regex_replace(xml, std::regex(R"(<integrator type="path">[\s\S]*?</integrator>)"), integrator);
    xml = std::regex_replace(
        xml, std::regex(R"(<rfilter type="box"/>)"),
        std::string(R"(<rfilter type="gaussian"/><boolean name="sample_border" value=")") + (border ? "true" : "false") + R"("/>)");
    REQUIRE(xml.find(integrator) != std::string::npos);
    REQUIRE(xml.find("sample_border") != std::string::npos);
    const std::filesystem::path path = dir / (std::string("scene") + (border ? "_border" : "") + ".xml");
    write_text(path, xml);
    return path.string();
}

// Whether `integrator` stops in `variant` when its scene loads: raster renders RGB only, and
// neither the photon mappers nor Mitsuba's differentiable integrators render polarization.
bool refuses_variant(const std::string& integrator, Variant variant) {
    if (variant == Variant::ScalarRGB) return false;
    if (integrator == "raster") return true;
    const std::vector<std::string> unpolarized = {"sppm",           "photonmapper",      "prb",       "prb_basic",
                                                  "prb_projective", "direct_projective", "prbvolpath"};
    return variant == Variant::ScalarSpectralPolarized &&
           std::find(unpolarized.begin(), unpolarized.end(), integrator) != unpolarized.end();
}

// The scene at `path` in `variant` (with `params`), or null when it stops as it loads, which it
// must then be expected to (`refused`), at `line` ("scene.xml:N:"), naming the variant.
Ref<Scene> load_unless_refused(const std::string& path, Variant variant, bool refused, const std::string& line,
                               const SceneParameters& params = {}) {
    try {
        Ref<Scene> scene = load_scene(path, params, variant);
        CHECK_FALSE(refused);
        return scene;
    } catch (const SceneError& e) {
        INFO(e.what());
        CHECK(refused);
        CHECK(std::string(e.what()).find(line) != std::string::npos);
        CHECK(std::string(e.what()).find(variant_name(variant)) != std::string::npos);
        return nullptr;
    }
}

// A render that ran to its end: every pixel finite, no sample dropped as non-finite, not cut
// short; with `lit`, not black either.
void check_complete(const RenderResult& r, bool lit = false) {
    CHECK(all_finite_pixels(r.image));
    CHECK(r.stats.nonfinite == 0);
    CHECK_FALSE(r.stats.partial);
    if (!lit) return;
    double sum = 0.0;
    for (float v : r.image.data()) sum += v;
    CHECK(sum > 0.0);
}

// Two threads and 5 samples with `sampler`: 5 is a square for none of the samplers and a power of
// two for neither.
RenderOptions five_samples_with(const std::string& sampler) {
    RenderOptions options;
    options.sampler = sampler;
    options.threads = 2;
    options.spp = 5;
    return options;
}

}  // namespace

TEST_CASE("every integrator renders with every sampler, with and without sample_border, finitely and to the end", "[integrator][sampler]") {
    const auto dir = scratch_dir("every-combination");
    for (bool border : {false, true})
        for (const IntegratorCase& integrator : integrator_cases()) {
            const std::string scene_path = combination_scene(dir, integrator.xml, border);
            Ref<Scene> scene = load_scene(scene_path, {{"res", "16"}, {"spp", "5"}});
            for (const std::string& sampler : AllSamplers) {
                INFO(integrator.name << " with " << sampler << (border ? ", sample_border" : ""));
                const RenderResult r = scene->integrator().render(*scene, five_samples_with(sampler));
                CHECK(r.image.width() == 16);
                CHECK(r.image.height() == 16);
                check_complete(r);
            }
        }
}

TEST_CASE("every integrator renders with every sampler in the spectral variants, or stops at its line", "[integrator][sampler][spectral]") {
    // In the spectral and polarized variants paths draw their wavelengths from the sampler too
    // (after the camera's numbers), so every sampler meets a different sequence of dimensions.
    // What does not render in a variant stops at the integrator's line, naming it.
    const auto dir = scratch_dir("every-combination-spectral");
    for (Variant variant : {Variant::ScalarSpectral, Variant::ScalarSpectralPolarized})
        for (const IntegratorCase& integrator : integrator_cases()) {
            INFO(integrator.name << " in " << variant_name(variant));
            const std::string scene_path = combination_scene(dir, integrator.xml, false);
            Ref<Scene> scene = load_unless_refused(scene_path, variant, refuses_variant(integrator.name, variant),
                                                   "scene.xml:5:", {{"res", "16"}, {"spp", "5"}});
            if (!scene) continue;
            for (const std::string& sampler : AllSamplers) {
                INFO("with " << sampler);
                const RenderResult r = scene->integrator().render(*scene, five_samples_with(sampler));
                check_complete(r);
            }
        }
}

TEST_CASE("every integrator renders through every measuring sensor and a batch, with every sampler, or refuses it",
          "[integrator][sampler][sensor]") {
    // The validation Cornell box's camera replaced by each instrument (with a gaussian filter,
    // which the instruments warn about and must still render with) or by a batch of two cameras.
    // The particle tracer cannot reach a delta sensor or a batch, and the raster mode draws only
    // through a pinhole: those stop with a message naming the sensor's kind.
    const std::string film = R"(<film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/></film>)";
    const std::vector<std::pair<std::string, std::string>> sensors = {
        {"radiancemeter", R"(<sensor type="radiancemeter"><point name="origin" value="0, 0, 3.9"/>
            <vector name="direction" value="0.1, -0.2, -1"/>)" +
                              film + "</sensor>"},
        {"irradiancemeter", R"(<shape type="rectangle"><transform name="to_world"><scale value="0.2"/><rotate x="1" angle="-90"/>
            <translate y="-0.99" z="0.5"/></transform><sensor type="irradiancemeter">)" +
                                film + "</sensor></shape>"},
        {"distant", R"(<sensor type="distant"><vector name="direction" value="0, -0.3, -1"/>)" + film + "</sensor>"},
        {"batch", R"(<sensor type="batch"><sensor type="perspective"><float name="fov" value="40"/>
            <transform name="to_world"><lookat origin="0, 0, 3.9" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
            <sensor type="thinlens"><float name="fov" value="30"/><float name="aperture_radius" value="0.05"/>
            <transform name="to_world"><lookat origin="0.3, 0.2, 3" target="0, -0.3, 0" up="0, 1, 0"/></transform></sensor>
            <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="8"/></film></sensor>)"},
    };
    const auto dir = scratch_dir("every-combination-sensors");
    for (const auto& [kind, sensor_xml] : sensors)
        for (const IntegratorCase& integrator : integrator_cases()) {
            INFO(integrator.name << " through " << kind);
            std::string xml = read_text(source_path("scenes/validation/cbox.xml"));
            xml = std::regex_replace(xml, std::regex(R"(<integrator type="path">[\s\S]*?</integrator>)"), integrator.xml);
            xml = std::regex_replace(xml, std::regex(R"(<sensor type="perspective">[\s\S]*?</sensor>)"), sensor_xml);
            write_text(dir / "scene.xml", xml);
            Ref<Scene> scene = load_scene((dir / "scene.xml").string());
            const bool refused = integrator.name == "raster" || (integrator.name == "ptracer" && kind != "irradiancemeter");
            const Vec2i size = kind == "batch" ? Vec2i(16, 8) : Vec2i(1, 1);
            for (const std::string& sampler : AllSamplers) {
                INFO("with " << sampler);
                RenderResult r;
                try {
                    r = scene->integrator().render(*scene, five_samples_with(sampler));
                } catch (const InputError& e) {
                    INFO(e.what());
                    CHECK(refused);
                    continue;
                }
                CHECK_FALSE(refused);
                CHECK(r.image.width() == size.x);
                CHECK(r.image.height() == size.y);
                check_complete(r);
            }
        }
}

TEST_CASE("sppm takes its camera samples from the sampler the render names, one sample index per pass, whatever the passes",
          "[integrator][sampler][sppm]") {
    // The issue's scene: a stratified sampler of 9 samples and 40 passes (which today is 40
    // indices of a 49-sample stratified sampler); also passes beyond a power of two for sobol.
    const auto dir = scratch_dir("sppm-passes");
    const std::string scene_path = combination_scene(
        dir, R"(<integrator type="sppm"><integer name="photon_count" value="1000"/><integer name="max_passes" value="40"/></integrator>)",
        false);
    std::string xml = read_text(scene_path);
    xml = std::regex_replace(xml, std::regex(R"(<sampler type="independent">)"), R"(<sampler type="stratified">)");
    write_text(scene_path, xml);
    Ref<Scene> scene = load_scene(scene_path, {{"res", "16"}, {"spp", "9"}});  // before issue 28: hangs at 16 x 16
    for (const std::string& sampler : {std::string(), std::string("sobol"), std::string("orthogonal")}) {
        INFO("sampler " << (sampler.empty() ? "of the scene" : sampler));
        RenderOptions options;
        options.sampler = sampler;
        const RenderResult r = scene->integrator().render(*scene, options);
        CHECK(all_finite_pixels(r.image));
        CHECK(r.stats.sampler == (sampler.empty() ? "stratified" : sampler));
        CHECK_FALSE(r.stats.partial);
    }
}

TEST_CASE("every integrator renders an outdoor scene under sun and sky in every variant, or stops at its line",
          "[integrator][sampler][sunsky]") {
    // The sunsky emitter's extremes in one view: a sun some 10^5 times brighter than the sky,
    // seen directly, through a glass pane and off a rough metal cube, over a lit ground (no
    // closed glass: radiosity would shoot light around inside it for minutes). Each
    // integrator in each variant with two samplers renders finitely and to the end, or refuses
    // at its line as in the Cornell box.
    // timed_sunsky over the sensor's shutter: each sample sees the sky of another day and hour.
    const auto dir = scratch_dir("every-combination-sunsky");
    const std::vector<std::pair<std::string, std::string>> skies = {
        {R"(<emitter type="sunsky"><float name="hour" value="17"/>)", ""},
        {R"(<emitter type="timed_sunsky"><float name="window_start_time" value="9"/><float name="window_end_time" value="16"/>)",
         R"(<float name="shutter_close" value="1"/>)"}};
    for (const auto& [sky, shutter] : skies)
        for (Variant variant : {Variant::ScalarRGB, Variant::ScalarSpectral, Variant::ScalarSpectralPolarized})
            for (const IntegratorCase& integrator : integrator_cases()) {
                INFO(integrator.name << " in " << variant_name(variant) << " under " << sky);
                write_text(dir / "scene.xml", R"(<scene version="3.0.0">
  )" + integrator.xml + R"(
  )" + sky + R"(<transform name="to_world"><rotate x="1" angle="-90"/></transform></emitter>
  <shape type="rectangle"><transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/></transform></shape>
  <shape type="rectangle"><transform name="to_world"><rotate y="1" angle="30"/><translate y="1"/></transform><bsdf type="dielectric"/></shape>
  <shape type="cube"><transform name="to_world"><translate x="2.5" y="1"/></transform>
    <bsdf type="roughconductor"><float name="alpha" value="0.1"/></bsdf></shape>
  <sensor type="perspective"><float name="fov" value="100"/>)" +
                                                  shutter + R"(
    <transform name="to_world"><lookat origin="0, 1.5, 5" target="0, 1.2, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>
</scene>)");
                Ref<Scene> scene =
                    load_unless_refused((dir / "scene.xml").string(), variant, refuses_variant(integrator.name, variant), "scene.xml:2:");
                if (!scene) continue;
                for (const std::string& sampler : std::vector<std::string>{"independent", "zsobol"}) {
                    INFO("with " << sampler);
                    const RenderResult r = scene->integrator().render(*scene, five_samples_with(sampler));
                    check_complete(r, true);
                }
            }
}

TEST_CASE("every integrator renders a moving scene in every variant, or stops at the animation's line",
          "[integrator][sampler][animation]") {
    // A moving camera, box and area light over the shutter [0, 1]. The camera-path integrators,
    // ptracer and sppm take each sample's, light path's or pass's time; photonmapper and radiosity
    // cache light at one instant and stop at the line of the first moving shape's animation;
    // raster draws the shutter's opening. Variant refusals stop at load, at the integrator's
    // line (2).
    const auto dir = scratch_dir("every-combination-motion");
    const std::vector<std::string> without_motion = {"photonmapper", "radiosity"};
    for (Variant variant : {Variant::ScalarRGB, Variant::ScalarSpectral, Variant::ScalarSpectralPolarized})
        for (const IntegratorCase& integrator : integrator_cases()) {
            INFO(integrator.name << " in " << variant_name(variant));
            const std::string xml = R"(<scene version="3.0.0">
  )" + integrator.xml + R"(
  <sensor type="perspective"><float name="fov" value="50"/><float name="shutter_close" value="1"/>
    <animation name="to_world">
      <transform time="0"><lookat origin="0, 2, 5" target="0, 0.5, 0" up="0, 1, 0"/></transform>
      <transform time="1"><lookat origin="0.5, 2, 5" target="0.5, 0.5, 0" up="0, 1, 0"/></transform></animation>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>
  <shape type="rectangle"><transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/></transform></shape>
  <shape type="cube"><bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf>
    <animation name="to_world">
      <transform time="0"><scale value="0.4"/><translate x="-1" y="0.4"/></transform>
      <transform time="1"><scale value="0.4"/><translate x="1" y="0.4"/></transform></animation></shape>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="8"/></emitter>
    <animation name="to_world">
      <transform time="0"><scale value="0.5"/><rotate x="1" angle="90"/><translate x="-0.5" y="2.5"/></transform>
      <transform time="1"><scale value="0.5"/><rotate x="1" angle="90"/><translate x="0.5" y="2.5"/></transform></animation></shape>
  <emitter type="constant"><rgb name="radiance" value="0.1"/></emitter>
</scene>)";
            write_text(dir / "scene.xml", xml);
            const size_t cube_animation = xml.find("<animation", xml.find(R"(<shape type="cube">)"));
            const std::string cube_line =
                "scene.xml:" + std::to_string(1 + std::count(xml.begin(), xml.begin() + cube_animation, '\n')) + ":";
            const bool refused_at_render = std::find(without_motion.begin(), without_motion.end(), integrator.name) != without_motion.end();
            Ref<Scene> scene =
                load_unless_refused((dir / "scene.xml").string(), variant, refuses_variant(integrator.name, variant), "scene.xml:2:");
            if (!scene) continue;
            for (const std::string& sampler : std::vector<std::string>{"independent", "ldsampler"}) {
                INFO("with " << sampler);
                RenderResult r;
                try {
                    r = scene->integrator().render(*scene, five_samples_with(sampler));
                } catch (const SceneError& e) {
                    INFO(e.what());
                    CHECK(refused_at_render);
                    CHECK(std::string(e.what()).find(cube_line) != std::string::npos);
                    CHECK(std::string(e.what()).find("motion blur") != std::string::npos);
                    continue;
                }
                CHECK_FALSE(refused_at_render);
                check_complete(r, true);
            }
        }
}
