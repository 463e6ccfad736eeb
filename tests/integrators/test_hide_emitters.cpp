// hide_emitters with Mitsuba 3's semantics (its volpath, and path since 3.6): what the camera sees
// directly, through null surfaces at most, contributes no emission; everything else stays. A
// hidden area light is still a surface: the path goes on from it (it reflects what lights it
// and hides what lies behind it), and it still lights the scene. The environment behind the
// scene renders black, with alpha 0.
// With the same seed, hiding changes no random number, so the two renders differ exactly by the
// hidden emission: Le on pixels that see only the light, the sky on pixels that see only the sky,
// and nothing (bit for bit) on pixels that see only an ordinary surface.

#include "core/scene.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

constexpr float Le = 4.0f, Sky = 0.5f;

// An orthographic view of [-1, 1]^2: a grey area light (a diffuse square, radiance Le) in the
// middle, in front of a backdrop over the left half, the sky elsewhere; a point light on the
// camera's side lights the light's surface too. With `screen`, a null plane in front of it all
// that every camera ray crosses.
std::string scene_with(const std::string& integrator, bool hide, bool screen) {
    std::string hide_xml = std::string(R"(<boolean name="hide_emitters" value=")") + (hide ? "true" : "false") + "\"/>";
    std::string s = "<integrator type=\"" + integrator + "\">" + hide_xml + "</integrator>" + R"(
        <sensor type="orthographic"><transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
            <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/>
                <string name="pixel_format" value="rgba"/><string name="component_format" value="float32"/></film></sensor>
        <emitter type="constant"><rgb name="radiance" value=")" +
                    std::to_string(Sky) + R"("/></emitter>
        <emitter type="point"><point name="position" value="0.3, 0.2, 2"/><rgb name="intensity" value="3"/></emitter>
        <shape type="rectangle"><transform name="to_world"><scale value="0.5"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf>
            <emitter type="area"><rgb name="radiance" value=")" +
                    std::to_string(Le) + R"("/></emitter></shape>
        <shape type="rectangle"><transform name="to_world"><scale x="0.5" y="1"/><translate x="-0.5" z="-1"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>)";
    if (screen)
        s +=
            R"(<shape type="rectangle"><transform name="to_world"><scale value="3"/><translate z="2"/></transform><bsdf type="null"/></shape>)";
    return scene_xml(s);
}

struct Counts {
    int light = 0, sky = 0, surface = 0;
};

Counts check_hiding(const std::string& integrator, bool screen) {
    std::string path = source_path("scenes/hide_emitters_test.xml");
    Ref<Scene> shown_scene = load_scene_from_string(scene_with(integrator, false, screen), path);
    Ref<Scene> hidden_scene = load_scene_from_string(scene_with(integrator, true, screen), path);
    Ref<Scene> unscreened = load_scene_from_string(scene_with(integrator, false, false), path);  // to tell the pixels apart
    RenderOptions options;
    options.seed = 7;
    Image shown = shown_scene->integrator().render(*shown_scene, options).image;
    Image hidden = hidden_scene->integrator().render(*hidden_scene, options).image;
    REQUIRE(shown.channels() == std::vector<std::string>{"R", "G", "B", "A"});
    const Shape* light = nullptr;
    for (const auto& shape : unscreened->shapes())
        if (shape->emitter()) light = shape.get();
    Counts counts;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            PixelView view = pixel_view(*unscreened, x, y);
            if (view.mixed) continue;
            INFO(integrator << (screen ? " behind a null screen" : "") << ": pixel (" << x << ", " << y << ")");
            for (int c = 0; c < 3; ++c) {
                float a = shown.at(x, y, c), b = hidden.at(x, y, c);
                if (view.shape == light) {
                    CHECK(a - b == Approx(Le).epsilon(1e-5));  // only the first segment's emission is gone,
                    CHECK(b > 0.01f);                          // the light's surface still reflects the point light
                } else if (view.nothing()) {
                    CHECK(a == Approx(Sky).epsilon(1e-6));
                    CHECK(b == 0.0f);
                } else {
                    CHECK(a == b);  // an ordinary surface: the same, bit for bit
                }
            }
            // Alpha: path counts a visible sky as valid (Mitsuba's rule); direct only surfaces
            // that scatter. Neither counts the null screen.
            bool sky_valid = integrator == "path";
            CHECK(shown.at(x, y, 3) == (view.nothing() && !sky_valid ? 0.0f : 1.0f));
            CHECK(hidden.at(x, y, 3) == (view.nothing() ? 0.0f : 1.0f));
            (view.shape == light ? counts.light : view.nothing() ? counts.sky : counts.surface)++;
        }
    return counts;
}

}  // namespace

TEST_CASE("hide_emitters: path and direct leave out only the emission seen directly, through null surfaces too",
          "[render][hide_emitters]") {
    for (const char* integrator : {"path", "direct"})
        for (bool screen : {false, true}) {
            Counts c = check_hiding(integrator, screen);
            // The geometry gives every kind of pixel: 8x8 on the light, a quarter of the view
            // on the backdrop, a quarter on the sky (less the mixed ones along edges).
            CHECK(c.light >= 36);
            CHECK(c.sky >= 36);
            CHECK(c.surface >= 36);
        }
}
