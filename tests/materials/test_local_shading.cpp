// The local-model view (local_shading) of the composite and principled BSDFs: the mappings each
// file documents, checked in the limits where they are plain, and a raster render of every new
// BSDF that must stay finite.

#include "core/local_model.h"
#include "core/texture.h"
#include "core/xml.h"
#include "tests/bsdf_harness.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {
Spectrum kd(const LocalShading& s) { return s.diffuse ? s.diffuse->eval(Vec2(0.3f, 0.6f)) : Spectrum(0.0f); }
bool near(const Spectrum& a, const Spectrum& b) { return max_abs_component(a - b) < 1e-5f; }
}  // namespace

TEST_CASE("local model: null, mask, blendbsdf and polarizer", "[bsdf][raster]") {
    LocalShading null = make_bsdf(R"(<bsdf type="null"/>)").bsdf->local_shading();
    CHECK(!null.diffuse);
    CHECK(null.transmission == Spectrum(1.0f));
    CHECK(null.eta == 1.0f);

    LocalShading mask = make_bsdf(R"(<bsdf type="mask"><float name="opacity" value="0.3"/>
                                        <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.4, 0.2"/></bsdf></bsdf>)")
                            .bsdf->local_shading();
    CHECK(near(kd(mask), 0.3f * Spectrum(0.8f, 0.4f, 0.2f)));
    CHECK(near(mask.transmission, Spectrum(0.7f)));

    LocalShading blend = make_bsdf(R"(<bsdf type="blendbsdf"><float name="weight" value="0.25"/>
                                         <bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf>
                                         <bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf></bsdf>)")
                             .bsdf->local_shading();
    CHECK(near(kd(blend), Spectrum(0.6f)));
    CHECK(near(blend.specular, Spectrum(0.25f)));  // the mirror's F0 = 1, a quarter of it
    CHECK(blend.shininess == Approx(2.0f / 0.04f - 2.0f));

    LocalShading polarizer = make_bsdf(R"(<bsdf type="polarizer"/>)").bsdf->local_shading();
    CHECK(near(polarizer.transmission, Spectrum(0.5f)));
}

TEST_CASE("local model: principled and principledthin", "[bsdf][raster][principled]") {
    LocalShading plastic =
        make_bsdf(R"(<bsdf type="principled"><rgb name="base_color" value="0.2, 0.5, 0.7"/><float name="roughness" value="0.5"/>
                                           <float name="eta" value="1.5"/></bsdf>)")
            .bsdf->local_shading();
    CHECK(near(kd(plastic), Spectrum(0.2f, 0.5f, 0.7f)));
    CHECK(near(plastic.specular, Spectrum(0.04f)));
    CHECK(plastic.transmission == Spectrum(0.0f));

    LocalShading metal =
        make_bsdf(R"(<bsdf type="principled"><rgb name="base_color" value="0.9, 0.6, 0.2"/><float name="metallic" value="1"/></bsdf>)")
            .bsdf->local_shading();
    CHECK(near(kd(metal), Spectrum(0.0f)));
    CHECK(near(metal.mirror, Spectrum(0.9f, 0.6f, 0.2f)));

    LocalShading glass = make_bsdf(R"(<bsdf type="principled"><float name="spec_trans" value="1"/><rgb name="base_color" value="1"/>
                                         <float name="eta" value="1.5"/></bsdf>)")
                             .bsdf->local_shading();
    CHECK(near(glass.transmission, Spectrum(0.96f)));
    CHECK(glass.eta == 1.5f);
    CHECK(glass.two_sided);

    LocalShading sheet =
        make_bsdf(R"(<bsdf type="principledthin"><rgb name="base_color" value="0.5"/><float name="diff_trans" value="1"/></bsdf>)")
            .bsdf->local_shading();
    CHECK(near(kd(sheet), Spectrum(0.25f)));
    CHECK(near(sheet.transmission, Spectrum(0.25f)));
    CHECK(sheet.two_sided);
}

TEST_CASE("local model: a raster render of every new BSDF stays finite", "[bsdf][raster]") {
    std::string shapes;
    const char* bsdfs[] = {
        R"(<bsdf type="principled"><float name="clearcoat" value="0.5"/><float name="spec_trans" value="0.3"/></bsdf>)",
        R"(<bsdf type="principledthin"><float name="spec_trans" value="0.5"/></bsdf>)",
        R"(<bsdf type="blendbsdf"><bsdf type="diffuse"/><bsdf type="conductor"/></bsdf>)",
        R"(<bsdf type="mask"><texture type="checkerboard" name="opacity"/><bsdf type="diffuse"/></bsdf>)",
        R"(<bsdf type="null"/>)",
        R"(<bsdf type="hair"/>)",
        R"(<bsdf type="pplastic"/>)",
        R"(<bsdf type="polarizer"/>)",
    };
    float x = -1.75f;
    for (const char* b : bsdfs) {
        shapes += "<shape type=\"sphere\"><point name=\"center\" value=\"" + std::to_string(x) +
                  ", 0, 0\"/><float name=\"radius\" value=\"0.2\"/>" + b + "</shape>";
        x += 0.5f;
    }
    std::string xml = scene_xml(R"(<integrator type="raster"/>
        <sensor type="perspective"><float name="fov" value="60"/>
            <transform name="to_world"><lookat origin="0, -4, 1" target="0, 0, 0" up="0, 0, 1"/></transform>
            <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="32"/><rfilter type="box"/></film></sensor>
        <emitter type="point"><point name="position" value="0, -2, 3"/><rgb name="intensity" value="5"/></emitter>
        <emitter type="constant"><rgb name="radiance" value="0.2"/></emitter>
        <shape type="rectangle"><transform name="to_world"><scale value="5"/><translate z="-0.2"/></transform></shape>)" +
                                shapes);
    Ref<Scene> scene = load_scene_from_string(xml, source_path("scenes/validation/local_all.xml"));
    RenderResult r = scene->integrator().render(*scene, RenderOptions());
    for (float v : r.image.data()) REQUIRE(std::isfinite(v));
}
