// The raster mode's fog: the medium around the camera attenuates what each sample sees by
// exp(-sigma_t d) (d its distance from the eye) and adds albedo * ambient * (1 - exp(-sigma_t d)).
// A camera in fog looks at an emitting plane at distance 2: the central pixels (whose rays are
// within a degree of the axis, so d = 2 within 2e-4) show L exp(-2 sigma_t) + fog, and the
// background beyond the plane's edge shows the fog colour alone. Deterministic.

#include "core/scene.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

TEST_CASE("raster: the medium around the camera is exponential fog", "[raster][media]") {
    auto dir = scratch_dir("raster-fog");
    write_text(dir / "scene.xml", scene_xml(R"(<integrator type="raster"/>
        <medium type="homogeneous" id="fog"><rgb name="sigma_t" value="0.2, 0.5, 1"/><float name="albedo" value="0.5"/></medium>
        <emitter type="constant"><rgb name="radiance" value="0.4"/></emitter>
        <sensor type="perspective"><float name="fov" value="40"/><ref id="fog"/>
            <transform name="to_world"><lookat origin="0, 0, 2" target="0, 0, 0" up="0, 1, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="64"/><rfilter type="box"/></film></sensor>
        <shape type="rectangle"><transform name="to_world"><scale value="0.3"/></transform>
            <emitter type="area"><rgb name="radiance" value="3, 2, 1"/></emitter></shape>)"));
    Ref<Scene> scene = load_scene((dir / "scene.xml").string());
    RenderResult r = scene->integrator().render(*scene, RenderOptions());
    const Vec3 L(3.0f, 2.0f, 1.0f), sigma(0.2f, 0.5f, 1.0f);
    for (int ch = 0; ch < 3; ++ch) {
        // The emitter itself adds L; its black diffuse surface reflects none of the ambient light.
        double T = std::exp(-2.0 * sigma[ch]), fog = 0.5 * 0.4;
        for (int y = 31; y <= 32; ++y)
            for (int x = 31; x <= 32; ++x) CHECK(r.image.at(x, y, ch) == Approx(L[ch] * T + fog * (1.0 - T)).epsilon(1e-3));
        // A corner sees past the plane: the fog colour alone.
        CHECK(r.image.at(0, 0, ch) == Approx(fog).epsilon(1e-4));
    }
}
