// Anti-aliasing and MIP-mapping on a checkerboard plane receding to the horizon: the error
// against a heavily supersampled reference (256 samples per pixel, bilinear texels, box filter)
// falls from nearest to bilinear to trilinear texture filtering, and from 1 to 4 to 16
// supersamples.

#include "analysis/image_metrics.h"
#include "core/image.h"
#include "core/xml.h"
#include "integrators/raster/raster.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

Ref<Scene> checker_plane() {
    auto dir = scratch_dir("raster-aa");
    Image tex = Image::rgb(64, 64);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) tex.set_rgb(x, y, Spectrum(((x / 8) + (y / 8)) % 2 ? 0.9f : 0.05f));
    write_exr(tex, (dir / "checks.exr").string(), true);
    write_text(dir / "plane.xml", scene_xml(R"(
        <sensor type="perspective"><float name="fov" value="60"/>
            <transform name="to_world"><lookat origin="0, 0.6, 2" target="0, 0.35, 0" up="0, 1, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="128"/><integer name="height" value="96"/><rfilter type="box"/></film></sensor>
        <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
        <shape type="rectangle"><transform name="to_world"><scale value="60"/><rotate x="1" angle="-90"/></transform>
            <bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="checks.exr"/>
                <transform name="to_uv"><scale value="240"/></transform></texture></bsdf></shape>)"));
    return load_scene((dir / "plane.xml").string());
}

double rmse_against(const Ref<Scene>& scene, const Image& reference, const std::string& filter, int aa) {
    RasterSettings s;
    std::string error;
    REQUIRE(s.set("texture_filter", filter, error));
    s.aa = aa;
    s.shadows = RasterSettings::Shadows::None;
    RasterIntegrator r(s);
    return compare_images(r.render(*scene, RenderOptions{}).image, reference).rmse;
}

}  // namespace

TEST_CASE("raster: texture filtering and supersampling reduce aliasing", "[raster][aa]") {
    Ref<Scene> scene = checker_plane();
    RasterSettings ref_settings;
    ref_settings.aa = 256;
    ref_settings.texture_filter = TextureFilter::Bilinear;
    ref_settings.shadows = RasterSettings::Shadows::None;
    Image reference = RasterIntegrator(ref_settings).render(*scene, RenderOptions{}).image;

    double nearest = rmse_against(scene, reference, "nearest", 1), bilinear = rmse_against(scene, reference, "bilinear", 1),
           trilinear = rmse_against(scene, reference, "trilinear", 1);
    double aa1 = nearest, aa4 = rmse_against(scene, reference, "nearest", 4), aa16 = rmse_against(scene, reference, "nearest", 16);
    WARN("RMSE against 256x supersampling: nearest " << nearest << ", bilinear " << bilinear << ", trilinear " << trilinear
                                                     << "; nearest with 1, 4, 16 samples: " << aa1 << ", " << aa4 << ", " << aa16);
    CHECK(bilinear < nearest);
    CHECK(trilinear < bilinear);
    CHECK(aa4 < aa1);
    CHECK(aa16 < aa4);
}
