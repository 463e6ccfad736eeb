// The example scenes of scenes/examples load and render (small and noisy here): finite images
// with light in them, and the rasterizer draws those whose camera is a pinhole, lighting them
// with the same delta lights (projector and textured spot through sample_direction), and the
// fog around the camera as exponential fog.

#include "core/registry.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {
double image_mean(const Image& img, bool& finite) {
    double sum = 0.0;
    finite = true;
    for (float v : img.data()) {
        finite = finite && std::isfinite(v);
        sum += v;
    }
    return sum / double(img.data().size());
}
}  // namespace

TEST_CASE("example scenes: sensors, lights and media render", "[scenes][camera][lights][media]") {
    const SceneParameters small = {{"res", "24"}, {"spp", "4"}};
    for (const char* name : {"orthographic", "thinlens", "projector", "spot_texture", "directionalarea", "fog", "smoke"}) {
        INFO(name);
        Ref<Scene> scene = load_scene(source_path(std::string("scenes/examples/") + name + ".xml"), small);
        RenderOptions options;
        bool finite = false;
        double mean = image_mean(scene->integrator().render(*scene, options).image, finite);
        CHECK(finite);
        CHECK(mean > 0.0);
        if (!scene->sensor().pinhole()) continue;
        scene->set_integrator(create_plugin_as<Integrator>(ObjectKind::Integrator, Properties("raster", SourceLocation{})));
        double raster_mean = image_mean(scene->integrator().render(*scene, options).image, finite);
        CHECK(finite);
        CHECK(raster_mean > 0.0);
    }
}
