// The Mitsuba XML loader: every property tag, parameters, references, includes, transforms and
// every error path, with the line numbers the errors must name.

#include "core/bsdf.h"
#include "core/file_resolver.h"
#include "core/xml.h"
#include "tests/probe.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

Ref<Scene> load(const std::string& xml, const SceneParameters& defines = {}, const std::string& name = "scene.xml") {
    auto dir = scratch_dir("xml");
    write_text(dir / name, xml);
    return load_scene((dir / name).string(), defines);
}

// Loads and returns the SceneError it must raise.
SceneError load_error(const std::string& xml, const SceneParameters& defines = {}) {
    try {
        load(xml, defines);
    } catch (const SceneError& e) {
        return e;
    }
    FAIL("expected a SceneError");
    return SceneError(SourceLocation{}, "");
}

const Properties& probe(const std::string& id) {
    REQUIRE(probes().count(id) == 1);
    return probes().at(id);
}

}  // namespace

TEST_CASE("xml: every property tag is parsed with its type", "[xml]") {
    load(scene_xml(R"(
<bsdf type="test_probe" id="tags">
    <integer name="i" value="-42"/>
    <float name="f" value="2.5e-1"/>
    <boolean name="b" value="TRUE"/>
    <string name="s" value="hello world"/>
    <point name="p" x="1" y="2" z="3"/>
    <point name="p2" value="4, 5, 6"/>
    <vector name="v" x="0.5"/>
    <rgb name="c" value="0.1 0.2, 0.3"/>
    <rgb name="gray" value="0.7"/>
    <spectrum name="sp" value="0.25"/>
    <transform name="t"><translate x="1"/></transform>
</bsdf>)"));
    const Properties& p = probe("tags");
    CHECK(p.get_int("i") == -42);
    CHECK(p.get_float("f") == Approx(0.25f));
    CHECK(p.get_bool("b", false));
    CHECK(p.get_string("s") == "hello world");
    CHECK(p.get_point("p") == Vec3(1, 2, 3));
    CHECK(p.get_point("p2") == Vec3(4, 5, 6));
    CHECK(p.get_vector("v") == Vec3(0.5f, 0, 0));
    CHECK(p.get_rgb("c") == Spectrum(0.1f, 0.2f, 0.3f));
    CHECK(p.get_rgb("gray") == Spectrum(0.7f));
    CHECK(p.get_rgb("sp") == Spectrum(0.25f));
    CHECK(p.get_transform("t").apply_point(Vec3(0.0f)) == Vec3(1, 0, 0));
    // An integer is accepted where a float is asked for, and a float where an rgb is.
    CHECK(p.get_float("i") == -42.0f);
    CHECK(p.get_rgb("f") == Spectrum(0.25f));
}

TEST_CASE("xml: <default>, $name substitution in any attribute, and -D overrides", "[xml]") {
    std::string xml = scene_xml(R"(
<default name="albedo" value="0.3"/>
<default name="kind" value="test_probe"/>
<default name="prop" value="x"/>
<bsdf type="$kind" id="params">
    <float name="$prop" value="$albedo"/>
    <string name="joined" value="a$albedo-b"/>
</bsdf>)");
    load(xml);
    CHECK(probe("params").get_float("x") == Approx(0.3f));
    CHECK(probe("params").get_string("joined") == "a0.3-b");
    load(xml, {{"albedo", "0.9"}, {"prop", "y"}});
    CHECK(probe("params").get_float("y") == Approx(0.9f));
    CHECK(probe("params").get_string("joined") == "a0.9-b");
}

TEST_CASE("xml: transforms compose in document order", "[xml][transform]") {
    load(scene_xml(R"(
<bsdf type="test_probe" id="tf">
    <transform name="ts"><translate x="1"/><scale value="2"/></transform>
    <transform name="st"><scale value="2"/><translate x="1"/></transform>
    <transform name="rot"><rotate z="1" angle="90"/></transform>
    <transform name="rot_value"><rotate value="0, 0, 1" angle="90"/></transform>
    <transform name="scale_xyz"><scale x="2" y="3"/></transform>
    <transform name="m16"><matrix value="1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1"/></transform>
    <transform name="m9"><matrix value="0 -1 0  1 0 0  0 0 1"/></transform>
    <transform name="chain"><rotate z="1" angle="90"/><translate x="1"/><scale x="3"/></transform>
</bsdf>)"));
    const Properties& p = probe("tf");
    auto apply = [&](const char* name, Vec3 v) { return p.get_transform(name).apply_point(v); };
    auto near = [](Vec3 a, Vec3 b) { return glm::length(a - b) < 1e-5f; };
    CHECK(near(apply("ts", Vec3(0.0f)), Vec3(2, 0, 0)));      // translate, then scale
    CHECK(near(apply("st", Vec3(0.0f)), Vec3(1, 0, 0)));      // scale, then translate
    CHECK(near(apply("rot", Vec3(1, 0, 0)), Vec3(0, 1, 0)));  // counter-clockwise about +z
    CHECK(near(apply("rot_value", Vec3(1, 0, 0)), Vec3(0, 1, 0)));
    CHECK(near(apply("scale_xyz", Vec3(1, 1, 1)), Vec3(2, 3, 1)));
    CHECK(near(apply("m16", Vec3(1, 1, 1)), Vec3(6, 7, 8)));  // row-major: translation in the last column
    CHECK(near(apply("m9", Vec3(1, 0, 0)), Vec3(0, 1, 0)));
    CHECK(near(apply("chain", Vec3(1, 0, 0)), Vec3(3, 1, 0)));  // (1,0,0) -> (0,1,0) -> (1,1,0) -> (3,1,0)
    // The stored inverse really is the inverse.
    Transform c = p.get_transform("chain");
    CHECK(near(c.inverse().apply_point(c.apply_point(Vec3(0.3f, -2, 5))), Vec3(0.3f, -2, 5)));
}

TEST_CASE("xml: lookat builds [left, up, dir, origin] and finds an up when none is given", "[xml][transform]") {
    load(scene_xml(R"(
<bsdf type="test_probe" id="look">
    <transform name="with_up"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <transform name="no_up"><lookat origin="1, 3, 1" target="0.5, 0, 0"/></transform>
</bsdf>)"));
    const Properties& p = probe("look");
    Mat4 m = p.get_transform("with_up").matrix();
    CHECK(glm::length(Vec3(m[2]) - Vec3(0, 0, -1)) < 1e-6f);  // dir
    CHECK(glm::length(Vec3(m[1]) - Vec3(0, 1, 0)) < 1e-6f);   // up
    CHECK(glm::length(Vec3(m[0]) - Vec3(-1, 0, 0)) < 1e-6f);  // left = up x dir
    CHECK(glm::length(Vec3(m[3]) - Vec3(0, 0, 5)) < 1e-6f);   // origin
    Mat4 n = p.get_transform("no_up").matrix();
    Vec3 dir = glm::normalize(Vec3(-0.5f, -3, -1));
    CHECK(glm::length(Vec3(n[2]) - dir) < 1e-5f);
    CHECK(std::abs(glm::dot(Vec3(n[0]), dir)) < 1e-5f);
    CHECK(std::abs(glm::dot(Vec3(n[1]), dir)) < 1e-5f);
    // Mitsuba's fallback up is the first vector of coordinate_system(dir).
    Vec3 s, t;
    coordinate_system(dir, s, t);
    Vec3 expected_left = glm::normalize(glm::cross(s, dir));
    CHECK(glm::length(Vec3(n[0]) - expected_left) < 1e-5f);
}

TEST_CASE("xml: ids, <ref> with and without name, and <include>", "[xml]") {
    auto dir = scratch_dir("xml-include");
    write_text(dir / "materials.xml", scene_xml(R"(<bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.8"/></bsdf>
<bsdf type="test_probe" id="included"><float name="depth" value="1"/></bsdf>)"));
    std::filesystem::create_directories(dir / "sub");
    write_text(dir / "sub" / "more.xml", scene_xml(R"(<bsdf type="test_probe" id="nested_include"/>)"));
    write_text(dir / "main.xml", scene_xml(R"(
<include filename="materials.xml"/>
<include filename="sub/more.xml"/>
<texture type="checkerboard" id="checks"/>
<shape type="rectangle"><ref id="white"/></shape>
<shape type="sphere"><bsdf type="diffuse"><ref name="reflectance" id="checks"/></bsdf></shape>)"));
    Ref<Scene> scene = load_scene((dir / "main.xml").string());
    REQUIRE(scene->shapes().size() == 2);
    CHECK(scene->shapes()[0]->bsdf()->id == "white");
    CHECK(probe("included").get_float("depth") == 1.0f);
    CHECK(probes().count("nested_include") == 1);
}

TEST_CASE("xml: a shape without a bsdf gets Mitsuba's default", "[xml]") {
    Ref<Scene> scene = load(scene_xml(R"(<shape type="sphere"/>
<shape type="sphere"><emitter type="area"/></shape>)"));
    SurfaceInteraction si;
    si.wi = Vec3(0, 0, 1);
    CHECK(scene->shapes()[0]->bsdf()->albedo(si) == Spectrum(0.5f));
    CHECK(scene->shapes()[1]->bsdf()->albedo(si) == Spectrum(0.0f));  // emitters default to black
}

TEST_CASE("xml: errors name the file and line", "[xml][errors]") {
    struct Case {
        const char* what;
        std::string xml;
        int line;
        const char* message;
    };
    const std::vector<Case> cases = {
        {"malformed XML", "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n</scene>\n", 3, "malformed XML"},
        {"unknown plugin type", scene_xml("<shape type=\"teapot\"/>"), 2, "unknown shape type \"teapot\""},
        {"unused property", scene_xml("<bsdf type=\"diffuse\">\n<rgb name=\"reflectence\" value=\"0.5\"/>\n</bsdf>"), 3,
         "unused property \"reflectence\""},
        {"missing mesh", scene_xml("<shape type=\"obj\">\n<string name=\"filename\" value=\"nothere.obj\"/>\n</shape>"), 3,
         "file not found: \"nothere.obj\""},
        {"NaN in a matrix",
         scene_xml(
             "<shape type=\"sphere\"><transform name=\"to_world\">\n<matrix value=\"1 0 0 0 0 nan 0 0 0 0 1 0 0 0 0 1\"/>\n</transform></shape>"),
         3, "not a finite number"},
        {"singular transform",
         scene_xml("<shape type=\"rectangle\"><transform name=\"to_world\">\n<scale value=\"0\"/>\n</transform></shape>"), 3, "singular"},
        {"undefined parameter", scene_xml("<shape type=\"sphere\">\n<float name=\"radius\" value=\"$r\"/>\n</shape>"), 3,
         "undefined parameter $r"},
        {"unknown id", scene_xml("<shape type=\"sphere\">\n<ref id=\"nope\"/>\n</shape>"), 3, "unknown id \"nope\""},
        {"duplicate id", scene_xml("<bsdf type=\"diffuse\" id=\"a\"/>\n<bsdf type=\"diffuse\" id=\"a\"/>"), 3, "duplicate id"},
        {"bad number", scene_xml("<shape type=\"sphere\">\n<float name=\"radius\" value=\"1.0x\"/>\n</shape>"), 3, "is not a number"},
        // Finite as a double, infinite as the float it becomes (found by fuzz_scene: a raster
        // render of a point light of intensity 1e75 held infinite pixels).
        {"beyond float", scene_xml("<emitter type=\"point\">\n<rgb name=\"intensity\" value=\"1e75\"/>\n</emitter>"), 3,
         "beyond the range of a 32-bit float"},
        {"spectrum beyond float",
         scene_xml("<emitter type=\"point\">\n<spectrum name=\"intensity\" value=\"400:1, 500:1e40\"/>\n</emitter>"), 3,
         "beyond the range of a 32-bit float"},
        {"bad integer", scene_xml("<integrator type=\"path\">\n<integer name=\"max_depth\" value=\"2.5\"/>\n</integrator>"), 3,
         "is not an integer"},
        {"bad boolean", scene_xml("<integrator type=\"path\">\n<boolean name=\"hide_emitters\" value=\"yes\"/>\n</integrator>"), 3,
         "is not a boolean"},
        {"wrong type", scene_xml("<shape type=\"sphere\">\n<string name=\"radius\" value=\"1\"/>\n</shape>"), 3,
         "has type string, expected float"},
        {"unknown element", scene_xml("<shape type=\"sphere\">\n<color name=\"c\" value=\"1\"/>\n</shape>"), 3, "unknown element <color>"},
        {"unexpected attribute", scene_xml("<shape type=\"sphere\" colour=\"red\"/>"), 2, "unexpected attribute \"colour\""},
        {"rotate without angle", scene_xml("<shape type=\"sphere\"><transform name=\"to_world\">\n<rotate x=\"1\"/>\n</transform></shape>"),
         3, "needs the attribute \"angle\""},
        {"property twice",
         scene_xml("<shape type=\"sphere\">\n<float name=\"radius\" value=\"1\"/>\n<float name=\"radius\" value=\"2\"/>\n</shape>"), 4,
         "already specified"},
        {"no version", "<scene>\n<shape type=\"sphere\"/>\n</scene>\n", 1, "needs the attribute \"version\""},
        {"not a scene", "<shape type=\"sphere\"/>\n", 1, "root element must be <scene>"},
        {"nested object nobody reads", scene_xml("<shape type=\"sphere\">\n<sampler type=\"independent\"/>\n</shape>"), 3,
         "unexpected nested sampler"},
        {"missing include", scene_xml("<include filename=\"gone.xml\"/>"), 2, "cannot open included file"},
        {"area emitter outside a shape", scene_xml("<emitter type=\"area\"/>"), 0, "must be nested inside a shape"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        SceneError e = load_error(c.xml);
        CHECK_THAT(std::string(e.what()), Catch::Contains(c.message));
        CHECK_THAT(e.location.file, Catch::EndsWith("scene.xml"));
        if (c.line > 0) CHECK(e.location.line == c.line);
        // The printed form is "file:line: message".
        if (c.line > 0) CHECK_THAT(std::string(e.what()), Catch::Contains("scene.xml:" + std::to_string(c.line) + ": "));
    }
}

TEST_CASE("xml: an include cycle is reported, not followed forever", "[xml][errors]") {
    auto dir = scratch_dir("xml-cycle");
    write_text(dir / "a.xml", scene_xml("<include filename=\"b.xml\"/>"));
    write_text(dir / "b.xml", scene_xml("<include filename=\"a.xml\"/>"));
    CHECK_THROWS_WITH(load_scene((dir / "a.xml").string()), Catch::Contains("nest too deeply"));
}

TEST_CASE("xml: a confined file resolver finds nothing outside its folders, through .., absolute names or links", "[xml][errors]") {
    namespace fs = std::filesystem;
    auto dir = scratch_dir("xml-confined");
    fs::create_directories(dir / "inside" / "sub");
    fs::create_directories(dir / "outside");
    write_text(dir / "outside" / "secret.xml", scene_xml("<bsdf type=\"diffuse\" id=\"secret\"/>"));
    write_text(dir / "inside" / "sub" / "part.xml", scene_xml("<bsdf type=\"diffuse\" id=\"part\"/>"));
    fs::create_symlink(dir / "outside" / "secret.xml", dir / "inside" / "link.xml");
    const std::string secret = (dir / "outside" / "secret.xml").string();
    auto load = [&](const std::string& include) {
        write_text(dir / "inside" / "scene.xml", scene_xml("<include filename=\"" + include + "\"/>"));
        return load_scene((dir / "inside" / "scene.xml").string());
    };
    // Unconfined, every one of them loads.
    for (const std::string& name : std::vector<std::string>{"sub/part.xml", "../outside/secret.xml", secret, "link.xml"})
        CHECK_NOTHROW(load(name));
    FileResolver::confine_to({dir / "inside"});
    CHECK_NOTHROW(load("sub/part.xml"));
    for (const std::string& name : std::vector<std::string>{"../outside/secret.xml", secret, "link.xml", "sub/../../outside/secret.xml"}) {
        INFO(name);
        CHECK_THROWS_WITH(load(name), Catch::Contains("scene.xml:2") && Catch::Contains("cannot open included file"));
    }
    // Mesh and texture names go through the same resolver.
    write_text(dir / "inside" / "scene.xml", scene_xml("<shape type=\"obj\">\n<string name=\"filename\" value=\"" +
                                                       (dir / "outside" / "m.obj").string() + "\"/>\n</shape>"));
    write_text(dir / "outside" / "m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK_THROWS_WITH(load_scene((dir / "inside" / "scene.xml").string()), Catch::Contains("file not found"));
    FileResolver::confine_to({});
    CHECK_NOTHROW(load_scene((dir / "inside" / "scene.xml").string()));
}

TEST_CASE("xml: a merge shape's shapes are the scene's own, nested merges too, and it holds shapes only", "[xml][merge]") {
    // Mitsuba 3.8's merge joins meshes and changes no pixel: the scene with merges renders the
    // image of the same shapes written at the top level, bit for bit.
    const std::string camera =
        R"(<sensor type="perspective"><transform name="to_world"><lookat origin="0, 1, 6" target="0, 0, 0" up="0, 1, 0"/>
        </transform><sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/></film></sensor>
        <emitter type="constant"/>)";
    const std::string a = R"(<shape type="cube"><transform name="to_world"><translate x="-1.5"/></transform></shape>)";
    const std::string b = R"(<shape type="sphere"><bsdf type="roughconductor"/></shape>)";
    const std::string c = R"(<shape type="rectangle" id="floor"><transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/>
        <translate y="-1"/></transform></shape>)";
    Ref<Scene> flat = load(scene_xml(camera + a + b + c));
    Ref<Scene> merged =
        load(scene_xml(camera + "<shape type=\"merge\" id=\"all\">" + a + "<shape type=\"merge\">" + b + "</shape>" + c + "</shape>"));
    REQUIRE(merged->shapes().size() == flat->shapes().size());
    RenderOptions options;
    options.threads = 2;
    const Image one = flat->integrator().render(*flat, options).image, two = merged->integrator().render(*merged, options).image;
    CHECK(one.data() == two.data());

    SceneError e = load_error(scene_xml("<shape type=\"merge\">\n<bsdf type=\"diffuse\"/></shape>"));
    CHECK_THAT(e.message(), Catch::Contains("holds shapes only, not <bsdf>"));
    CHECK(e.location.line == 3);
    e = load_error(scene_xml("<shape type=\"instance\">\n<shape type=\"merge\"/></shape>"));
    CHECK_THAT(e.message(), Catch::Contains("directly inside <scene>"));
    CHECK(e.location.line == 3);
}
