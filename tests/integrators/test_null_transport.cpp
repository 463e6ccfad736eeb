// Light transport through surfaces that let light pass (null, mask, polarizer): shadow rays keep
// their null_transmission, the path tracer crosses them without a bounce, and MIS stays right.
//   - Under a point light (direct lighting only, no noise in the lighting) a blocker multiplies
//     each pixel sample exactly by its transmission, sample by sample.
//   - With an area light, a glossy floor and full path tracing (both NEE and BSDF sampling carry
//     the light through the mask), a black mask of opacity a scales the image by 1 - a.
//   - A null shape, or a mask of opacity 0, renders as no shape at all; a mask of opacity 1 as its
//     nested BSDF.
// The statistical comparisons are z-tests on image means and block means with the renders' own
// variance AOVs; together they keep a 1% family-wise level (Sidak).

#include "core/scene.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstring>

using namespace candela;
using namespace candela::test;

namespace {

RenderResult render_string(const std::string& xml, const std::string& name, std::vector<std::string> aovs = {}) {
    Ref<Scene> scene = load_scene_from_string(xml, source_path("scenes/validation/" + name + ".xml"));
    RenderOptions options;
    options.aovs = std::move(aovs);
    return scene->integrator().render(*scene, options);
}

// A diffuse floor (z = 0) seen from below the plane z = 1, lit from above; `blockers` are placed
// between (the camera cannot see them). `lighting` is the emitter and integrator.
std::string floor_scene(const std::string& lighting, const std::string& floor_bsdf, const std::string& blockers, int spp) {
    return scene_xml(lighting + R"(
        <sensor type="perspective"><float name="fov" value="30"/>
            <transform name="to_world"><lookat origin="0, -2, 0.8" target="0, 0.3, 0" up="0, 0, 1"/></transform>
            <sampler type="independent"><integer name="sample_count" value=")" +
                     std::to_string(spp) + R"("/></sampler>
            <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/><rfilter type="box"/>
                <string name="component_format" value="float32"/></film>
        </sensor>
        <shape type="rectangle"><transform name="to_world"><scale value="20"/></transform>)" +
                     floor_bsdf + R"(</shape>)" + blockers);
}

// A rectangle at height z over x in [x0, x1], y in [-2, 2], with the given BSDF.
std::string blocker(const std::string& bsdf, float z, float x0 = -2.0f, float x1 = 0.3f) {
    return "<shape type=\"rectangle\"><transform name=\"to_world\"><scale x=\"" + std::to_string(0.5f * (x1 - x0)) +
           "\" y=\"2\"/><translate x=\"" + std::to_string(0.5f * (x0 + x1)) + "\" z=\"" + std::to_string(z) + "\"/></transform>" + bsdf +
           "</shape>";
}
// A plane at z = 1 that every path between the floor and a light above crosses.
std::string ceiling(const std::string& bsdf) {
    return "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"30\"/><translate z=\"1\"/></transform>" + bsdf +
           "</shape>";
}

const std::string PointLight = R"(<integrator type="path"><integer name="max_depth" value="2"/></integrator>
    <emitter type="point"><point name="position" value="0.3, 0.5, 2"/><rgb name="intensity" value="10"/></emitter>)";
const std::string Diffuse = R"(<bsdf type="diffuse"/>)";

struct RatioCounts {
    int at_one = 0, at_k = 0, between = 0, outside = 0;
};
// Classifies each pixel's ratio to the unblocked render: 1 (lit), k (in the blocker's shadow),
// between (a pixel the shadow's edge crosses), or outside [k, 1] (wrong).
RatioCounts ratios(const Image& blocked, const Image& open, float k) {
    RatioCounts c;
    for (int y = 0; y < open.height(); ++y)
        for (int x = 0; x < open.width(); ++x)
            for (int ch = 0; ch < 3; ++ch) {
                float a = blocked.at(x, y, ch), b = open.at(x, y, ch);
                REQUIRE(b > 0.0f);
                float r = a / b;
                if (std::abs(r - 1.0f) < 1e-5f)
                    ++c.at_one;
                else if (std::abs(r - k) < 1e-5f)
                    ++c.at_k;
                else if (r > std::min(k, 1.0f) - 1e-5f && r < std::max(k, 1.0f) + 1e-5f)
                    ++c.between;
                else
                    ++c.outside;
            }
    return c;
}

// The statistical tests of this file (green channel): the image mean of the scaled comparison, and
// the image mean and 16 block means of each of three "equals" comparisons.
constexpr int StatisticalTests = 1 + 3 * 17;

// z-tests that `a` equals k * `b` in expectation: every 8x8 block and the whole image (green).
void check_scaled_equal(const Image& a, const Image& b, double k, const std::string& what) {
    const double z = two_sided_z(sidak(0.01, StatisticalTests));
    auto test = [&](int x0, int y0, int size) {
        MeanAndVariance ma = block_mean(a, 1, x0, y0, size), mb = block_mean(b, 1, x0, y0, size);
        double diff = ma.mean - k * mb.mean, se = std::sqrt(ma.variance_of_mean + k * k * mb.variance_of_mean);
        INFO(what << ": block (" << x0 << ", " << y0 << ") size " << size << ": " << ma.mean << " vs " << k * mb.mean << " +- " << se);
        CHECK(std::abs(diff) <= z * se);
        return se / std::max(mb.mean * k, 1e-6);
    };
    double relative_se = test(0, 0, a.width());
    CHECK(relative_se < 0.01);  // power: a 3% bias in the image mean would show
    if (k == 1.0)
        for (int by = 0; by < a.height(); by += 8)
            for (int bx = 0; bx < a.width(); bx += 8) test(bx, by, 8);
}

}  // namespace

TEST_CASE("null transport: shadow rays keep each blocker's transmission, sample by sample", "[render][null]") {
    RenderResult open = render_string(floor_scene(PointLight, Diffuse, "", 4), "null_open");
    struct Case {
        std::string name, blockers;
        float k;
    };
    std::vector<Case> cases = {
        {"mask 0.3", blocker(R"(<bsdf type="mask"><float name="opacity" value="0.3"/><bsdf type="diffuse"/></bsdf>)", 1.0f), 0.7f},
        {"null", blocker(R"(<bsdf type="null"/>)", 1.0f), 1.0f},
        {"polarizer", blocker(R"(<bsdf type="polarizer"/>)", 1.0f), 0.5f},
        {"circular", blocker(R"(<bsdf type="circular"/>)", 1.0f), 0.5f},
        {"two polarizers (RGB: no crossing effect)",
         blocker(R"(<bsdf type="polarizer"/>)", 1.0f) + blocker(R"(<bsdf type="polarizer"><float name="theta" value="90"/></bsdf>)", 1.3f),
         0.25f},
        {"two masks",
         blocker(R"(<bsdf type="mask"><float name="opacity" value="0.2"/><bsdf type="diffuse"/></bsdf>)", 1.0f) +
             blocker(R"(<bsdf type="mask"><float name="opacity" value="0.5"/><bsdf type="conductor"/></bsdf>)", 1.4f),
         0.8f * 0.5f},
        {"blend of null and diffuse",
         blocker(R"(<bsdf type="blendbsdf"><float name="weight" value="0.4"/><bsdf type="null"/><bsdf type="diffuse"/></bsdf>)", 1.0f),
         0.6f},
        {"opaque diffuse", blocker(Diffuse, 1.0f), 0.0f},
    };
    for (const Case& c : cases) {
        RenderResult blocked = render_string(floor_scene(PointLight, Diffuse, c.blockers, 4), "null_blocked");
        RatioCounts r = ratios(blocked.image, open.image, c.k);
        INFO(c.name << ": " << r.at_one << " lit, " << r.at_k << " shadowed, " << r.between << " on the edge, " << r.outside << " wrong");
        CHECK(r.outside == 0);
        if (c.k == 1.0f) {
            CHECK(r.at_one == 3 * 32 * 32);
            continue;
        }
        CHECK(r.at_k > 3 * 32 * 32 / 5);     // the blocker shadows most of the view, ...
        CHECK(r.at_one > 3 * 32 * 32 / 20);  // ... not all of it
        CHECK(r.between < 3 * 32 * 3);       // only a column or so of pixels straddles the edge
    }
    // The floor seen through a null plane or a clear mask just in front of the camera: with
    // max_depth 2 (direct light only) the crossing must not count as a bounce, or the floor's
    // light would be cut off. The crossing moves ray origins by rounding, so 1e-5 (at_one).
    for (const char* bsdf :
         {R"(<bsdf type="null"/>)", R"(<bsdf type="mask"><float name="opacity" value="0"/><bsdf type="diffuse"/></bsdf>)"}) {
        std::string screen = std::string(R"(<shape type="rectangle"><transform name="to_world"><scale value="2"/>
            <lookat origin="0, -1.53, 0.64" target="0, 0.3, 0" up="0, 0, 1"/></transform>)") +
                             bsdf + "</shape>";
        RenderResult through = render_string(floor_scene(PointLight, Diffuse, screen, 4), "null_screen");
        RatioCounts r = ratios(through.image, open.image, 1.0f);
        INFO(bsdf << ": " << r.at_one << " equal, " << r.outside << " different");
        CHECK(r.at_one == 3 * 32 * 32);
    }
    // Nothing but null surfaces between: the very same image.
    RenderResult null_only = render_string(floor_scene(PointLight, Diffuse, cases[1].blockers, 4), "null_blocked");
    CHECK(std::memcmp(null_only.image.data().data(), open.image.data().data(), open.image.data().size() * sizeof(float)) == 0);
}

TEST_CASE("null transport: a black mask of opacity a scales light from an area light by 1 - a, with NEE and BSDF sampling combined by MIS",
          "[render][null]") {
    // A glossy floor under a large area light: both strategies find the light through the mask.
    const std::string area = R"(<integrator type="path"/>
        <shape type="rectangle"><transform name="to_world"><scale value="1.5"/><rotate x="1" angle="180"/><translate z="2"/></transform>
            <emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>)";
    const std::string floor =
        R"(<bsdf type="roughplastic"><float name="alpha" value="0.15"/><rgb name="diffuse_reflectance" value="0.3"/></bsdf>)";
    const std::string mask = ceiling(
        R"(<bsdf type="mask"><float name="opacity" value="0.6"/><bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf></bsdf>)");
    RenderResult open = render_string(floor_scene(area, floor, "", 64), "null_area_open", {"variance"});
    RenderResult masked = render_string(floor_scene(area, floor, mask, 64), "null_area_masked", {"variance"});
    check_scaled_equal(masked.image, open.image, 0.4, "mask 0.6 under an area light");
    // A null plane in the same place changes nothing.
    RenderResult nulled = render_string(floor_scene(area, floor, ceiling(R"(<bsdf type="null"/>)"), 64), "null_area_null", {"variance"});
    check_scaled_equal(nulled.image, open.image, 1.0, "null plane under an area light");
}

TEST_CASE(
    "null transport: in the Cornell box a null sphere and a clear mask in front of the camera render as nothing, an opaque mask as its BSDF",
    "[render][null]") {
    std::string box = read_text(source_path("scenes/validation/cbox.xml"));
    auto with = [&](const std::string& shapes) {
        std::string s = box;
        s.insert(s.rfind("</scene>"), shapes);
        return s;
    };
    SceneParameters small = {{"res", "32"}, {"spp", "256"}};
    auto render = [&](const std::string& xml, const std::string& name) {
        Ref<Scene> scene = load_scene_from_string(xml, source_path("scenes/validation/" + name + ".xml"), small);
        RenderOptions options;
        options.aovs = {"variance"};
        return scene->integrator().render(*scene, options);
    };
    RenderResult plain = render(box, "cbox_plain");
    // A null sphere around the tall box's top and the light's neighbourhood, and a null plane
    // filling the view just in front of the camera (every camera ray crosses it).
    const std::string null_sphere =
        R"(<shape type="sphere"><point name="center" value="0, 0.4, 0"/><float name="radius" value="0.5"/><bsdf type="null"/></shape>)";
    const std::string null_plane =
        R"(<shape type="rectangle"><transform name="to_world"><translate z="3"/></transform><bsdf type="null"/></shape>)";
    check_scaled_equal(render(with(null_sphere + null_plane), "cbox_null").image, plain.image, 1.0, "null shapes");
    const std::string clear_mask = R"(<shape type="sphere"><point name="center" value="0.2, -0.2, 0.3"/><float name="radius" value="0.45"/>
        <bsdf type="mask"><float name="opacity" value="0"/><bsdf type="diffuse"/></bsdf></shape>)";
    check_scaled_equal(render(with(clear_mask), "cbox_clear_mask").image, plain.image, 1.0, "mask of opacity 0");

    // Opacity 1: the same BSDF, the same random numbers, the same image, bit for bit.
    std::string opaque = box;
    std::string anchor = "<shape type=\"cube\" id=\"short_box\">";
    size_t at = opaque.find(anchor);
    REQUIRE(at != std::string::npos);
    size_t ref = opaque.find("<ref id=\"white\"/>", at);
    opaque.replace(ref, std::strlen("<ref id=\"white\"/>"),
                   R"(<bsdf type="mask"><float name="opacity" value="1"/><ref id="white"/></bsdf>)");
    RenderResult masked = render(opaque, "cbox_opaque_mask");
    CHECK(std::memcmp(masked.image.data().data(), plain.image.data().data(), plain.image.data().size() * sizeof(float)) == 0);
}

TEST_CASE("null transport: a ray crosses at most MaxNullCrossings null surfaces in every integrator, then is blocked", "[render][null]") {
    // An area light seen by the camera through a stack of `layers` null rectangles (planes
    // z = 0.001 i between the camera at z = 2 and the light at z = -1). Up to MaxNullCrossings
    // crossings the camera sees the light's radiance exactly (null surfaces transmit 1); beyond,
    // the ray is taken as blocked, as shadow rays always were, so the pixel is black. Before issue
    // 28 path, volpath and direct crossed any number of them (a degenerate stack could loop).
    auto scene_text = [](int layers, const std::string& integrator) {
        std::string xml = integrator + pinhole_camera("0, 0, 2", "0, 0, 0", 4, 4, 10) + R"(
            <shape type="rectangle"><transform name="to_world"><scale value="5"/><translate z="-1"/></transform>
                <emitter type="area"><rgb name="radiance" value="3"/></emitter></shape>)";
        for (int i = 0; i < layers; ++i)
            xml += "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"5\"/><translate z=\"" +
                   std::to_string(0.001 * i) + "\"/></transform><bsdf type=\"null\"/></shape>";
        return scene_xml(xml);
    };
    for (const std::string& integrator : {std::string("path"), std::string("volpath"), std::string("direct")})
        for (int layers : {MaxNullCrossings, MaxNullCrossings + 1}) {
            INFO(integrator << " through " << layers << " null surfaces");
            Ref<Scene> scene =
                load_scene_from_string(scene_text(layers, "<integrator type=\"" + integrator + "\"/>"), source_path("scenes/x.xml"));
            RenderOptions options;
            options.spp = 1;
            const RenderResult r = scene->integrator().render(*scene, options);
            const float expected = layers <= MaxNullCrossings ? 3.0f : 0.0f;
            for (int y = 0; y < 4; ++y)
                for (int x = 0; x < 4; ++x)
                    for (int c = 0; c < 3; ++c) CHECK(r.image.at(x, y, c) == Approx(expected).margin(1e-6));
        }
}
