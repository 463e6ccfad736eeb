// volpath and volpathmis in the spectral variant (scalar_spectral), against closed forms:
//   - Beer-Lambert: an orthographic camera looks through a null-bounded slab of thickness 1 whose
//     sigma_t is a measured spectrum at an equal-energy emitter (radiance 1 at every wavelength):
//     the image converges to the colour of exp(-sigma_t(l)), CIE_Y_NORMALIZATION * integral of
//     cmf(l) exp(-sigma_t(l)) dl in linear sRGB.
//   - Furnace: a sphere (null or index-matched dielectric boundary) of a medium of albedo 1 under
//     an equal-energy sky: every path leaves to the sky with the value 1 at each of its
//     wavelengths, so the image is the equal-energy white xyz_to_linear_srgb(1, 1, 1), for an rgb
//     sigma_t (HG), a measured one, and a coloured grid (heterogeneous, rayleigh).
// Image means get their standard errors from the spread of the box-filtered pixels; each test
// case keeps a 1% family-wise level over its z-tests (Sidak).

#include "core/scene.h"
#include "core/spectral.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/support/vol_writer.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

// sigma_t as a measured spectrum (nm:value): linear between the samples, zero beyond
// (tests/media/test_media.cpp checks the medium's values against that closed form).
const char* const MeasuredSigmaT = "400:0.5, 500:2, 600:1, 700:3";

// Renders a scene document in scalar_spectral.
RenderResult render_spectral(const std::string& name, const std::string& xml) {
    auto dir = scratch_dir(name);
    write_text(dir / "scene.xml", xml);
    Ref<Scene> scene = load_scene((dir / "scene.xml").string(), {}, Variant::ScalarSpectral);
    return scene->integrator().render(*scene, RenderOptions());
}

// The image's mean against `expected`, channel by channel: a z-test at `z`, and the power to see
// an error of a few times `power` (relative).
void check_image_mean(const RenderResult& r, const Vec3d& expected, double z, double power) {
    for (int c = 0; c < 3; ++c) {
        MeanAndError m = channel_mean(r.image, c);
        INFO("channel " << c << ": " << m.mean << " +- " << m.std_error << ", expected " << expected[c]);
        CHECK(std::abs(m.mean - expected[c]) < z * m.std_error + 1e-5);
        CHECK(m.std_error < power * expected[c]);
    }
    CHECK(r.stats.nonfinite == 0);
}

}  // namespace

TEST_CASE("spectral volpath: Beer-Lambert rendered through a slab of measured sigma_t", "[volpath][spectral][stats]") {
    // Looking down -z at an equal-energy emitter (radiance 1 at every wavelength) through a slab of
    // thickness d = 1: each wavelength arrives as exp(-sigma_t(l)); the pixel converges to that
    // spectrum's colour, CIE_Y_NORMALIZATION * integral of cmf(l) exp(-sigma_t(l)) dl in sRGB.
    const SampledSpectrum sigma_t = parse_spectrum_pairs(MeasuredSigmaT);
    std::vector<double> lambdas, transmitted;
    for (double l = CieMin; l <= CieMax + 1e-9; l += 0.25) {
        lambdas.push_back(l);
        transmitted.push_back(std::exp(-sigma_t.at(l)));
    }
    const Spectrum expected = spectrum_to_rgb(SampledSpectrum{lambdas, transmitted}, false, false);
    const double z = two_sided_z(sidak(0.01, 3 * 2));
    for (const char* integrator : {"volpath", "volpathmis"}) {
        INFO(integrator);
        const std::string xml = scene_xml(std::string(R"(<integrator type=")") + integrator + R"("/>
        <sensor type="orthographic"><transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>)" +
                                          box_film(16, 256) + R"(</sensor>
        <shape type="rectangle"><transform name="to_world"><scale value="10"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
            <emitter type="area"><spectrum name="radiance" value="1"/></emitter></shape>
        <medium type="homogeneous" id="absorber"><spectrum name="sigma_t" value=")" +
                                          MeasuredSigmaT + R"("/><float name="albedo" value="0"/></medium>
        <shape type="cube"><transform name="to_world"><scale x="10" y="10" z="0.5"/><translate z="2"/></transform>
            <bsdf type="null"/><ref name="interior" id="absorber"/></shape>)");
        check_image_mean(render_spectral("spectral-beer-lambert", xml), Vec3d(expected), z, 0.02);  // an 8% error would be seen
    }
}

TEST_CASE("spectral volpath: furnace, a sphere of albedo-1 medium under an equal-energy sky", "[volpath][spectral][stats][furnace]") {
    // The medium scatters all it stops and its boundary passes everything, so every path leaves
    // to the sky with the value 1 at each of its wavelengths: the image is the equal-energy white.
    auto dir = scratch_dir("spectral-medium-furnace");
    PCG32 rng(3, 17);
    const glm::ivec3 res(8, 8, 8);
    std::vector<float> density;
    for (int i = 0; i < res.x * res.y * res.z; ++i) {
        const float v = rng.next_float() < 0.3f ? 0.0f : 6.0f * rng.next_float();
        density.insert(density.end(), {v, 0.3f * v, 0.1f * v});
    }
    write_vol(dir / "smoke.vol", res, 3, density);
    const std::string boxed = R"(<transform name="to_world"><translate value="-0.5, -0.5, -0.5"/></transform>)";
    struct Case {
        std::string name, medium, boundary;
    };
    const std::string null_boundary = R"(<bsdf type="null"/>)";
    const Case cases[] = {
        {"homogeneous, rgb sigma_t, hg", R"(<medium type="homogeneous" id="m"><rgb name="sigma_t" value="0.5, 1.5, 3"/>
            <rgb name="albedo" value="1"/><phase type="hg"><float name="g" value="0.3"/></phase></medium>)",
         null_boundary},
        {"homogeneous, measured sigma_t, index-matched dielectric",
         std::string(R"(<medium type="homogeneous" id="m"><spectrum name="sigma_t" value=")") + MeasuredSigmaT +
             R"("/><float name="albedo" value="1"/></medium>)",
         R"(<bsdf type="dielectric"><float name="int_ior" value="1"/><float name="ext_ior" value="1"/></bsdf>)"},
        {"heterogeneous, rgb grid, rayleigh",
         R"(<medium type="heterogeneous" id="m"><float name="albedo" value="1"/>
            <volume type="gridvolume" name="sigma_t"><string name="filename" value="smoke.vol"/>)" +
             boxed + R"(</volume><phase type="rayleigh"/></medium>)",
         null_boundary},
    };
    const Vec3d expected = xyz_to_linear_srgb(Vec3d(1.0));
    const double z = two_sided_z(sidak(0.01, 3 * 2 * 3));
    for (const Case& c : cases) {
        for (const char* integrator : {"volpath", "volpathmis"}) {
            INFO(c.name << ", " << integrator);
            write_text(dir / "scene.xml",
                       scene_xml(std::string(R"(<integrator type=")") + integrator + R"("/>)" +
                                 R"(<sensor type="perspective"><float name="fov" value="40"/>
                <transform name="to_world"><lookat origin="0, 0, 3" target="0, 0, 0" up="0, 1, 0"/></transform>)" +
                                 box_film(24, 256) + R"(</sensor>
                <emitter type="constant"><spectrum name="radiance" value="1"/></emitter>)" +
                                 c.medium + R"(<shape type="sphere">)" + c.boundary + R"(<ref name="interior" id="m"/></shape>)"));
            Ref<Scene> scene = load_scene((dir / "scene.xml").string(), {}, Variant::ScalarSpectral);
            check_image_mean(scene->integrator().render(*scene, RenderOptions()), expected, z, 0.01);  // a 4% error would be seen
        }
    }
}
