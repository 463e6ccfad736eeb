// The example scenes of scenes/shapes load and render (small and fast here): every shape kind
// of this folder, instancing in both modes, and finite pixels everywhere.

#include "core/registry.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {
void check_image(const Image& img) {
    double sum = 0.0;
    int nonfinite = 0;
    for (float v : img.data()) {
        nonfinite += !std::isfinite(v);
        sum += v;
    }
    CHECK(nonfinite == 0);
    CHECK(sum > 0.0);
}
}  // namespace

TEST_CASE("scenes/shapes: the example scenes render", "[shapes][scenes]") {
    for (const char* name : {"scenes/shapes/shapes.xml", "scenes/shapes/forest.xml"}) {
        INFO(name);
        check_image(render_file(source_path(name), {{"spp", "2"}, {"res", "32"}}).image);
    }
    Ref<Scene> forest = load_scene(source_path("scenes/shapes/forest.xml"), {{"res", "32"}});
    CHECK(forest->shapes().size() == 26);  // the ground and 25 instances; the group itself is not drawn
    Properties raster("raster", SourceLocation{});
    forest->set_integrator(create_plugin_as<Integrator>(ObjectKind::Integrator, raster));
    check_image(forest->integrator().render(*forest, RenderOptions{}).image);
}
