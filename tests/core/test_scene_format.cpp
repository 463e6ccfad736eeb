// Reading the world's Mitsuba scenes: <path> search folders, spectra in every form, the upgrade
// of pre-2.0 scenes, named conductors, and the errors for what Candela does not support.

#include "core/bsdf.h"
#include "core/spectral.h"
#include "core/texture.h"
#include "core/warning.h"
#include "core/xml.h"
#include "materials/ior.h"
#include "tests/probe.h"
#include "tests/scoped_search_folders.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstring>

using namespace candela;
using namespace candela::test;
namespace fs = std::filesystem;

namespace {

const Properties& probe(const std::string& id) {
    REQUIRE(probes().count(id) == 1);
    return probes().at(id);
}

SceneError load_error(const fs::path& file) {
    try {
        load_scene(file.string());
    } catch (const SceneError& e) {
        return e;
    }
    FAIL("expected a SceneError");
    return SceneError(SourceLocation{}, "");
}

SceneError error_of(const std::string& xml) {
    auto dir = scratch_dir("format-errors");
    write_text(dir / "scene.xml", xml);
    return load_error(dir / "scene.xml");
}

// A 4x4 render of `body` (1 sample, box filter) seen by a camera at the origin looking down -z.
Image render_tiny(const std::string& body) {
    auto dir = scratch_dir("format-render");
    write_text(dir / "scene.xml", scene_xml(R"(<sensor type="perspective"><float name="fov" value="10"/>
  <sampler type="independent"><integer name="sample_count" value="1"/></sampler>
  <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/><rfilter type="box"/></film></sensor>
)" + body));
    Ref<Scene> scene = load_scene((dir / "scene.xml").string());
    return scene->integrator().render(*scene, RenderOptions()).image;
}

// Collects the warnings of one scope.
struct WarningCapture {
    std::vector<std::string> lines;
    WarningSink previous;
    WarningCapture() {
        previous = set_warning_sink([this](const std::string& line) { lines.push_back(line); });
    }
    ~WarningCapture() { set_warning_sink(previous); }
};

}  // namespace

TEST_CASE("path: folders named by <path> are searched, the scene's own folder and includes too", "[xml][path]") {
    auto dir = scratch_dir("path");
    fs::create_directories(dir / "scenes" / "include");
    fs::create_directories(dir / "common" / "meshes");
    fs::create_directories(dir / "scenes" / "sub");
    write_text(dir / "common" / "meshes" / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_text(dir / "scenes" / "sub" / "local.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_text(dir / "common" / "grey.spd", "# flat\n400 0.25\n700 0.25\n");
    // The include is found beside the scene; its mesh through the scene's <path>; the include's
    // own mesh beside the include.
    write_text(dir / "scenes" / "include" / "parts.xml",
               scene_xml(R"(<shape type="obj" id="from_path"><string name="filename" value="meshes/tri.obj"/></shape>
<shape type="obj" id="beside_include"><string name="filename" value="../sub/local.obj"/></shape>)"));
    write_text(dir / "scenes" / "main.xml", scene_xml(R"(<path value="../common"/>
<include filename="include/parts.xml"/>
<shape type="obj"><string name="filename" value="sub/local.obj"/></shape>
<bsdf type="test_probe" id="path_spd"><spectrum name="reflectance" filename="grey.spd"/></bsdf>)"));
    Ref<Scene> scene = load_scene((dir / "scenes" / "main.xml").string());
    CHECK(scene->shapes().size() == 3);
    CHECK(probe("path_spd").get_rgb("reflectance").y == Approx(0.25f).epsilon(3e-3));

    // A <path> folder is searched before the scene's own folder (Mitsuba 3 prepends it).
    write_text(dir / "scenes" / "grey.spd", "400 0.75\n700 0.75\n");
    write_text(dir / "scenes" / "order.xml",
               scene_xml(R"(<bsdf type="test_probe" id="order_before"><spectrum name="reflectance" filename="grey.spd"/></bsdf>
<path value="../common"/>
<bsdf type="test_probe" id="order_after"><spectrum name="reflectance" filename="grey.spd"/></bsdf>)"));
    load_scene((dir / "scenes" / "order.xml").string());
    CHECK(probe("order_before").get_rgb("reflectance").y == Approx(0.75f).epsilon(3e-3));
    CHECK(probe("order_after").get_rgb("reflectance").y == Approx(0.25f).epsilon(3e-3));
}

TEST_CASE("path: a missing file names the file and line and where it looked", "[xml][path][errors]") {
    auto dir = scratch_dir("path-errors");
    fs::create_directories(dir / "common");
    write_text(dir / "scene.xml", scene_xml(R"(<path value="common"/>
<shape type="obj">
<string name="filename" value="meshes/gone.obj"/>
</shape>)"));
    SceneError e = load_error(dir / "scene.xml");
    CHECK(e.location.line == 4);
    CHECK_THAT(e.message(), Catch::Contains("file not found: \"meshes/gone.obj\"") && Catch::Contains("looked in: ") &&
                                Catch::Contains((dir / "common").string()) && Catch::Contains(dir.string() + ","));
    write_text(dir / "nopath.xml", scene_xml("<path value=\"nowhere\"/>"));
    SceneError p = load_error(dir / "nopath.xml");
    CHECK(p.location.line == 2);
    CHECK_THAT(p.message(), Catch::Contains("<path>: folder \"nowhere\" not found") && Catch::Contains("looked in"));
    write_text(dir / "nested.xml", scene_xml("<shape type=\"sphere\">\n<path value=\"common\"/>\n</shape>"));
    CHECK_THAT(load_error(dir / "nested.xml").message(), Catch::Contains("<path> may only appear directly inside <scene>"));
    write_text(dir / "spd.xml", scene_xml("<bsdf type=\"diffuse\">\n<spectrum name=\"reflectance\" filename=\"none.spd\"/>\n</bsdf>"));
    SceneError s = load_error(dir / "spd.xml");
    CHECK(s.location.line == 3);
    CHECK_THAT(s.message(), Catch::Contains("file not found: \"none.spd\"") && Catch::Contains("looked in"));
    write_text(dir / "inc.xml", scene_xml("<include filename=\"gone.xml\"/>"));
    CHECK_THAT(load_error(dir / "inc.xml").message(), Catch::Contains("cannot open included file \"gone.xml\" (looked in: "));
}

TEST_CASE("search folders: -a folders are searched after the scene's folder, the working directory and its <path>s", "[xml][path]") {
    // As `mitsuba -a common scene.xml`: mitsuba-data's older docs scenes name meshes/... and
    // textures/... without a <path> and are rendered with the shared folder on the search path.
    auto dir = scratch_dir("search-folders");
    fs::create_directories(dir / "scenes" / "include");
    fs::create_directories(dir / "common" / "meshes");
    fs::create_directories(dir / "other");
    write_text(dir / "common" / "meshes" / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_text(dir / "common" / "grey.spd", "400 0.25\n700 0.25\n");
    write_text(dir / "other" / "grey.spd", "400 0.5\n700 0.5\n");
    write_text(dir / "scenes" / "include" / "parts.xml",
               scene_xml(R"(<shape type="obj"><string name="filename" value="meshes/tri.obj"/></shape>)"));
    write_text(dir / "scenes" / "main.xml", scene_xml(R"(<include filename="include/parts.xml"/>
<bsdf type="test_probe" id="search_spd"><spectrum name="reflectance" filename="grey.spd"/></bsdf>)"));
    fs::path main = dir / "scenes" / "main.xml";
    // Without the folders the mesh is not found; with them, the include's mesh and the scene's
    // spectrum are, from the first search folder that has them.
    CHECK_THAT(load_error(main).message(), Catch::Contains("file not found: \"meshes/tri.obj\""));
    {
        ScopedSearchFolders search({dir / "common", dir / "other"});
        Ref<Scene> scene = load_scene(main.string());
        CHECK(scene->shapes().size() == 1);
        CHECK(probe("search_spd").get_rgb("reflectance").y == Approx(0.25f).epsilon(3e-3));
    }
    {
        ScopedSearchFolders search({dir / "other", dir / "common"});
        load_scene(main.string());
        CHECK(probe("search_spd").get_rgb("reflectance").y == Approx(0.5f).epsilon(3e-3));
        // The scene's own folder comes first, and so does a <path>.
        write_text(dir / "scenes" / "grey.spd", "400 0.75\n700 0.75\n");
        load_scene(main.string());
        CHECK(probe("search_spd").get_rgb("reflectance").y == Approx(0.75f).epsilon(3e-3));
        fs::remove(dir / "scenes" / "grey.spd");
    }
    {
        ScopedSearchFolders search({dir / "common"});
        write_text(dir / "scenes" / "with_path.xml", scene_xml(R"(<path value="../other"/>
<bsdf type="test_probe" id="path_first"><spectrum name="reflectance" filename="grey.spd"/></bsdf>)"));
        load_scene((dir / "scenes" / "with_path.xml").string());
        CHECK(probe("path_first").get_rgb("reflectance").y == Approx(0.5f).epsilon(3e-3));
    }
    // Once cleared, the folders are no longer searched; a folder that does not exist is an error naming it.
    CHECK_THROWS_AS(load_scene(main.string()), SceneError);
    CHECK_THROWS_WITH(FileResolver::set_search_folders({dir / "nowhere"}),
                      Catch::Contains("search folder") && Catch::Contains((dir / "nowhere").string()) && Catch::Contains("not found"));
    CHECK(FileResolver::search_folders().empty());
}

TEST_CASE("plugin names: a name that differs only in case is read with a warning, former names point to their successor", "[xml][errors]") {
    // mitsuba-data's principled_blend_creation scenes say type="Rectangle" and "Sphere", which
    // Mitsuba 3 finds on case-insensitive file systems; the disney_blend_creation ones say "disney".
    WarningCapture warnings;
    Image mixed =
        render_tiny(R"(<shape type="Rectangle"><transform name="to_world"><rotate y="1" angle="180"/><translate z="2"/></transform>
  <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)");
    REQUIRE(warnings.lines.size() == 1);
    CHECK_THAT(warnings.lines[0], Catch::Contains("shape type \"Rectangle\" read as \"rectangle\""));
    Image lower =
        render_tiny(R"(<shape type="rectangle"><transform name="to_world"><rotate y="1" angle="180"/><translate z="2"/></transform>
  <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)");
    CHECK(warnings.lines.size() == 1);
    REQUIRE(mixed.data().size() == lower.data().size());
    CHECK(mixed.data() == lower.data());
    CHECK(lower.at(2, 2, 0) == Approx(1.0f));
    SceneError disney = error_of(scene_xml("<bsdf type=\"disney\"/>"));
    CHECK(disney.location.line == 2);
    CHECK_THAT(disney.message(), Catch::Contains("unknown bsdf type \"disney\"") && Catch::Contains("\"principled\""));
    CHECK_THAT(error_of(scene_xml("<sampler type=\"bush\"/>")).message(),
               Catch::Contains("unknown sampler type \"bush\"") && Catch::Contains("\"orthogonal\""));
    // Case-insensitive only: a misspelt name is still an error with the nearest name.
    CHECK_THAT(error_of(scene_xml("<shape type=\"Rectangel\"/>")).message(), Catch::Contains("nearest supported: \"rectangle\""));
}

TEST_CASE("spectrum: every form of <spectrum> as a reflectance", "[xml][spectral]") {
    auto dir = scratch_dir("spectrum-forms");
    write_text(dir / "flat.spd", "# a flat 0.4\n# wavelength value\n360 0.4\n\n830 0.4 # end\n");
    write_text(dir / "scene.xml", scene_xml(R"(<bsdf type="test_probe" id="forms">
    <spectrum name="one" value="0.4"/>
    <spectrum name="pairs" value="360:0.4, 830:0.4"/>
    <spectrum name="file" filename="flat.spd"/>
    <spectrum name="published" value="400:0.1, 500:0.2, 600:0.4, 700:0.1"/>
    <spectrum type="uniform" name="uniform"><float name="value" value="0.4"/></spectrum>
    <spectrum type="regular" name="regular"><float name="wavelength_min" value="360"/><float name="wavelength_max" value="830"/>
        <string name="values" value="0.4, 0.4, 0.4"/></spectrum>
    <spectrum type="irregular" name="irregular"><string name="wavelengths" value="360, 500, 830"/><string name="values" value="0.4 0.4 0.4"/></spectrum>
    <spectrum type="srgb" name="srgb"><rgb name="color" value="0.1, 0.2, 0.3"/></spectrum>
    <spectrum type="d65" name="d65"><rgb name="color" value="0.5, 0.25, 1"/><float name="scale" value="2"/></spectrum>
</bsdf>)"));
    load_scene((dir / "scene.xml").string());
    const Properties& p = probe("forms");
    CHECK(p.get_rgb("one") == Spectrum(0.4f));
    CHECK(p.get_rgb("uniform") == Spectrum(0.4f));
    for (const char* name : {"pairs", "file", "regular", "irregular"}) {
        INFO(name);
        Spectrum c = p.get_rgb(name);
        CHECK(c.x == Approx(0.4f).epsilon(3e-3));
        CHECK(c.y == Approx(c.x).epsilon(3e-4));
        CHECK(c.z == Approx(c.x).epsilon(3e-4));
    }
    CHECK(p.get_rgb("file") == p.get_rgb("pairs"));                     // the same data read two ways, bit for bit
    CHECK(p.get_rgb("published").x == Approx(0.380475f).margin(2e-6));  // Mitsuba 3's own test value
    CHECK(p.get_rgb("srgb") == Spectrum(0.1f, 0.2f, 0.3f));
    CHECK(p.get_rgb("d65") == Spectrum(1.0f, 0.5f, 2.0f));
}

TEST_CASE("spectrum: emission spectra, D65 white, black bodies, and spectra by reference", "[xml][spectral]") {
    // A uniform emission is the equal-energy white; D65 is sRGB's white; a black body is Planck's
    // law through the CIE curves. The camera sees the constant emitter directly.
    Image one = render_tiny(R"(<emitter type="constant"><spectrum name="radiance" value="1"/></emitter>)");
    CHECK(one.rgb_at(1, 2) == uniform_emission_rgb(1.0));
    Image d65 = render_tiny(
        R"(<emitter type="constant"><spectrum type="d65" name="radiance"><float name="scale" value="3"/></spectrum></emitter>)");
    CHECK(d65.rgb_at(0, 0) == Spectrum(3.0f));
    Image bb = render_tiny(
        R"(<emitter type="constant"><spectrum type="blackbody" name="radiance"><float name="temperature" value="5000"/></spectrum></emitter>)");
    CHECK(bb.rgb_at(3, 3) == blackbody_rgb(5000.0));
    // The same pairs are a reflectance in a BSDF and an emission in an emitter (no D65 weight).
    WarningCapture out_of_gamut;  // this narrow spectrum is clamped (red < 0), with a warning
    auto dir = scratch_dir("spectrum-emission");
    write_text(dir / "scene.xml", scene_xml(R"(<spectrum type="srgb" id="tint"><rgb name="color" value="0.25, 0.5, 1"/></spectrum>
<bsdf type="test_probe" id="as_reflectance"><spectrum name="c" value="500:1, 600:0"/><ref name="tint" id="tint"/></bsdf>
<shape type="sphere"><emitter type="area"><spectrum name="radiance" value="500:1, 600:0"/></emitter></shape>)"));
    Ref<Scene> scene = load_scene((dir / "scene.xml").string());
    SampledSpectrum s{{500.0, 600.0}, {1.0, 0.0}};
    CHECK(probe("as_reflectance").get_rgb("c") == spectrum_to_rgb(s, true, true));
    CHECK(probe("as_reflectance").get_rgb("tint") == Spectrum(0.25f, 0.5f, 1.0f));  // a <ref> to a spectrum is its colour
    CHECK(scene->emitters().size() == 1);
}

TEST_CASE("spectrum: malformed spectra are errors at their line", "[xml][spectral][errors]") {
    struct Case {
        std::string body;
        const char* message;
    };
    const std::vector<Case> cases = {
        {"<spectrum name=\"c\" value=\"0.5\" filename=\"a.spd\"/>", "either value or filename"},
        {"<spectrum name=\"c\" value=\"400:0.5, 300:0.5\"/>", "wavelengths must increase"},
        {"<spectrum name=\"c\" value=\"0.1, 0.2, 0.3\"/>", "one number or wavelength:value pairs"},
        {"<spectrum name=\"c\" value=\"400:x, 500:1\"/>", "is not a number"},
        {"<spectrum type=\"blackbdy\" name=\"c\"/>", "unknown spectrum type \"blackbdy\" (nearest supported: \"blackbody\")"},
        {"<spectrum type=\"blackbody\" name=\"c\"/>", "missing required property \"temperature\""},
        {"<spectrum type=\"srgb\" name=\"c\"><rgb name=\"color\" value=\"2\"/></spectrum>", "outside [0, 1]"},
        {"<spectrum type=\"uniform\" name=\"c\"><float name=\"valu\" value=\"2\"/></spectrum>", "unused property \"valu\""},
        {"<srgb name=\"c\" value=\"#ff0000\"/>", "<srgb> is Mitsuba 0.6 syntax"},
        {"<rgb name=\"c\" value=\"1\" intent=\"reflectance\"/>", "the intent attribute is Mitsuba 0.6 syntax"},
        {"<blackbody name=\"c\" temperature=\"5000\"/>", "<blackbody> is Mitsuba 0.6 syntax"},
    };
    for (const Case& c : cases) {
        INFO(c.body);
        SceneError e = error_of(scene_xml("<bsdf type=\"test_probe\">\n" + c.body + "\n</bsdf>"));
        CHECK_THAT(e.message(), Catch::Contains(c.message));
        CHECK(e.location.line == 3);
    }
    // A reflectance outside the gamut is clamped, with a warning naming the line.
    WarningCapture w;
    auto dir = scratch_dir("spectrum-warning");
    write_text(dir / "scene.xml",
               scene_xml("<bsdf type=\"test_probe\" id=\"bright\">\n<spectrum name=\"c\" value=\"400:3, 700:3\"/>\n</bsdf>"));
    load_scene((dir / "scene.xml").string());
    CHECK(probe("bright").get_rgb("c") == Spectrum(1.0f));
    REQUIRE(w.lines.size() == 1);
    CHECK_THAT(w.lines[0], Catch::Contains("scene.xml:3: warning: spectrum lies outside the sRGB gamut"));
}

TEST_CASE("upgrade: pre-2.0 scenes are read as Mitsuba 3 upgrades them", "[xml][upgrade]") {
    auto dir = scratch_dir("upgrade");
    write_text(dir / "old.xml", R"(<scene version="0.5.0">
    <default name="maxDepth" value="7"/>
    <bsdf type="test_probe" id="old">
        <integer name="maxDepth" value="$maxDepth"/>
        <float name="intIOR" value="1.5"/>
        <boolean name="sampleVisible" value="true"/>
        <transform name="toWorld"><lookAt origin="0, 0, 1" target="0, 0, 0" up="0, 1, 0"/></transform>
        <float name="uoffset" value="0.25"/>
        <float name="vscale" value="4"/>
        <srgb name="hex" value="#ff8000"/>
        <srgb name="numbers" intent="reflectance" value="0.5, 0.5, 1"/>
        <rgb name="plain" intent="illuminant" value="0.2"/>
        <spectrum name="bins" value="0.1, 0.2, 0.3"/>
        <blackbody name="hot" temperature="3000K" scale="2"/>
        <spectrum name="lightLike" intent="illuminant" value="2"/>
    </bsdf>
    <bsdf type="diffuse" id="legacy_diffuse"><rgb name="diffuseReflectance" value="0.3"/></bsdf>
    <shape type="sphere" id="uses_it"><ref id="legacy_diffuse"/></shape>
</scene>)");
    Ref<Scene> scene = load_scene((dir / "old.xml").string());
    const Properties& p = probe("old");
    CHECK(p.get_int("max_depth") == 7);
    CHECK(p.get_float("int_ior") == 1.5f);
    CHECK(p.get_bool("sample_visible", false));
    CHECK(glm::length(p.get_transform("to_world").apply_point(Vec3(0.0f)) - Vec3(0, 0, 1)) < 1e-6f);
    // to_uv = scale(1, 4) * translate(0.25, 0): u -> u + 0.25, v -> 4 v.
    Vec3 uv = p.get_transform("to_uv").apply_point(Vec3(0.5f, 0.5f, 0.0f));
    CHECK(uv.x == Approx(0.75f));
    CHECK(uv.y == Approx(2.0f));
    CHECK(p.get_rgb("hex") == Spectrum(1.0f, srgb_to_linear(128.0f / 255.0f), 0.0f));
    CHECK(p.get_rgb("numbers") == Spectrum(srgb_to_linear(0.5f), srgb_to_linear(0.5f), 1.0f));
    CHECK(p.get_rgb("plain") == Spectrum(0.2f));
    CHECK(p.get_rgb("bins") == Spectrum(0.1f, 0.2f, 0.3f));  // 0.6's RGB builds read three bins as rgb
    CHECK(p.get_rgb("hot") == blackbody_rgb(3000.0) * 2.0f);
    CHECK(p.get_rgb("light_like") == uniform_emission_rgb(2.0));
    SurfaceInteraction si;
    si.wi = Vec3(0, 0, 1);
    CHECK(scene->shapes()[0]->bsdf()->albedo(si) == Spectrum(0.3f));  // diffuse_reflectance became reflectance

    // Version 2 and 3 scenes are read as they are: no renaming.
    write_text(dir / "new.xml", scene_xml("<bsdf type=\"test_probe\" id=\"new\"><float name=\"intIOR\" value=\"1.5\"/></bsdf>"));
    load_scene((dir / "new.xml").string());
    CHECK(probe("new").has("intIOR"));
    // Each file is upgraded by its own version: an old include in a new scene.
    write_text(dir / "old_part.xml",
               "<scene version=\"0.6.0\"><bsdf type=\"test_probe\" id=\"old_part\"><float name=\"extIOR\" value=\"1\"/></bsdf></scene>");
    write_text(dir / "mixed.xml", scene_xml("<include filename=\"old_part.xml\"/>"));
    load_scene((dir / "mixed.xml").string());
    CHECK(probe("old_part").has("ext_ior"));
}

TEST_CASE("upgrade: the 0.6 copies of validation scenes render the 3.0 originals' images", "[xml][upgrade][render]") {
    // scenes/legacy/*.xml are written in Mitsuba 0.5/0.6 syntax (camelCase, lookAt, srgb, intent,
    // diffuseReflectance, uscale/vscale, three-bin spectra, <path>). After the upgrade they are
    // the same scenes, so the renders agree bit for bit.
    for (const char* name : {"cbox", "lights", "textured"}) {
        INFO(name);
        SceneParameters p = {{"res", "24"}, {"spp", "2"}};
        RenderResult legacy = render_file(source_path(std::string("scenes/legacy/") + name + ".xml"), p);
        RenderResult original = render_file(source_path(std::string("scenes/validation/") + name + ".xml"), p);
        REQUIRE(legacy.image.data().size() == original.image.data().size());
        CHECK(std::memcmp(legacy.image.data().data(), original.image.data().data(), legacy.image.data().size() * sizeof(float)) == 0);
    }
}

TEST_CASE("conductors: material names give the measured IOR of Mitsuba 3's table", "[xml][ior]") {
    auto dir = scratch_dir("named-conductors");
    auto au = *named_conductor("Au");
    char eta[96], k[96];
    std::snprintf(eta, sizeof eta, "%.9g, %.9g, %.9g", au.eta.x, au.eta.y, au.eta.z);
    std::snprintf(k, sizeof k, "%.9g, %.9g, %.9g", au.k.x, au.k.y, au.k.z);
    // A gold sphere by name and by explicit eta/k under a white sky: the same image.
    std::string by_name = R"(<emitter type="constant"/><shape type="sphere"><point name="center" x="0" y="0" z="-3"/>
<bsdf type="roughconductor"><string name="material" value="Au"/><float name="alpha" value="0.3"/></bsdf></shape>)";
    std::string by_value = R"(<emitter type="constant"/><shape type="sphere"><point name="center" x="0" y="0" z="-3"/>
<bsdf type="roughconductor"><rgb name="eta" value=")" +
                           std::string(eta) + R"("/><rgb name="k" value=")" + std::string(k) +
                           R"("/><float name="alpha" value="0.3"/></bsdf></shape>)";
    Image a = render_tiny(by_name), b = render_tiny(by_value);
    CHECK(std::memcmp(a.data().data(), b.data().data(), a.data().size() * sizeof(float)) == 0);
    SceneError e = error_of(scene_xml("<bsdf type=\"conductor\">\n<string name=\"material\" value=\"Cuu\"/>\n</bsdf>"));
    CHECK(e.location.line == 3);
    CHECK_THAT(e.message(), Catch::Contains("unknown conductor \"Cuu\" (nearest: \"Cu\")"));
}

TEST_CASE("unsupported: unknown plugins name the nearest supported one, polarisation says what it needs", "[xml][errors]") {
    struct Case {
        std::string body;
        int line;
        const char* message;
    };
    const std::vector<Case> cases = {
        {"<bsdf type=\"roughplastc\"/>", 2, "unknown bsdf type \"roughplastc\" (nearest supported: \"roughplastic\")"},
        {"<shape type=\"spher\"/>", 2, "unknown shape type \"spher\" (nearest supported: \"sphere\")"},
        // Polarisation-only plugins exist; in scalar_rgb they say what they need.
        {"<integrator type=\"stokes\"/>", 2, "stokes renders only in variant scalar_spectral_polarized"},
        {"<bsdf type=\"measured_polarized\"/>", 2, "measured_polarized renders in scalar_rgb only at one wavelength: give `wavelength`"},
        {"<medium type=\"homogenous\" id=\"fog\"/>", 2, "unknown medium type \"homogenous\" (nearest supported: \"homogeneous\")"},
        {"<shape type=\"sphere\">\n<medium type=\"homogeneous\" name=\"inside\"/>\n</shape>", 3,
         "must be named \"interior\" or \"exterior\""},
        {"<phase type=\"hg\"><float name=\"g\" value=\"1\"/></phase>", 2, "strictly between -1 and 1"},
        {"<shape type=\"sphere\">\n<animation name=\"to_world\"/>\n</shape>", 3, "<animation> needs at least one <transform time="},
        {"<shape type=\"sphere\">\n<animation name=\"to_world\">\n<transform time=\"1\"/>\n<transform time=\"1\"/></animation></shape>", 5,
         "keyframe times must increase"},
        {"<shape type=\"sphere\">\n<animation name=\"to_world\">\n<translate x=\"1\"/></animation></shape>", 4,
         "<animation> holds <transform time=\"...\"> keyframes, not <translate>"},
        {"<emitter type=\"directional\">\n<animation name=\"to_world\"><transform time=\"0\"/></animation></emitter>", 3,
         "not supported on directional"},
        {"<resource_path value=\".\"/>", 2, "Mitsuba 3 calls it <path"},
    };
    for (const Case& c : cases) {
        INFO(c.body);
        SceneError e = error_of(scene_xml(c.body));
        CHECK_THAT(e.message(), Catch::Contains(c.message));
        CHECK(e.location.line == c.line);
    }
}

TEST_CASE("references: an object may be declared after the <ref> that uses it", "[xml]") {
    // As in Mitsuba's Cornell box scenes: the luminaire refers to an area emitter declared at the
    // end of the file, and a BSDF refers to a texture declared after it.
    auto dir = scratch_dir("forward-ref");
    write_text(dir / "scene.xml", scene_xml(R"(<bsdf type="diffuse" id="early"><ref name="reflectance" id="late_texture"/></bsdf>
<shape type="sphere"><ref id="early"/><ref id="light"/></shape>
<texture type="checkerboard" id="late_texture"/>
<emitter type="area" id="light"><rgb name="radiance" value="2"/></emitter>)"));
    Ref<Scene> scene = load_scene((dir / "scene.xml").string());
    REQUIRE(scene->shapes().size() == 1);
    CHECK(scene->shapes()[0]->emitter() != nullptr);
    CHECK(scene->emitters().size() == 1);  // the top-level declaration is the shape's emitter, not a second one
    CHECK(scene->shapes()[0]->bsdf()->id == "early");
    // A cycle is an error, and so is an id declared nowhere.
    CHECK_THAT(error_of(scene_xml(R"(<bsdf type="twosided" id="a"><ref id="b"/></bsdf>
<bsdf type="twosided" id="b"><ref id="a"/></bsdf>)"))
                   .message(),
               Catch::Contains("circular reference to id \"a\""));
    CHECK_THAT(error_of(scene_xml("<shape type=\"sphere\"><ref id=\"nowhere\"/></shape>")).message(),
               Catch::Contains("unknown id \"nowhere\""));
    // An area emitter that no shape uses is still an error.
    CHECK_THAT(error_of(scene_xml("<emitter type=\"area\" id=\"lonely\"/>")).message(), Catch::Contains("must be nested inside a shape"));
}

TEST_CASE("alias: <alias id as> gives an object a second id", "[xml]") {
    auto dir = scratch_dir("alias");
    write_text(dir / "scene.xml", scene_xml(R"(<bsdf type="diffuse" id="a"><rgb name="reflectance" value="0.25"/></bsdf>
<alias id="a" as="b"/>
<shape type="sphere"><ref id="b"/></shape>)"));
    Ref<Scene> scene = load_scene((dir / "scene.xml").string());
    CHECK(scene->shapes()[0]->bsdf()->id == "a");
    CHECK_THAT(error_of(scene_xml("<alias id=\"nope\" as=\"b\"/>")).message(), Catch::Contains("<alias> of unknown id \"nope\""));
}
