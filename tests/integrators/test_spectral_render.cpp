// The spectral variant end to end: white furnaces per wavelength (lossless BSDFs under an
// equal-energy or a D65 sky converge to that sky's colour, with error bars from the render
// itself), the RGB variant unchanged, and the plugins that do not render in the variant refused
// at their line.

#include "core/error.h"
#include "core/spectral.h"
#include "core/xml.h"
#include "integrators/estimators.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>

using namespace candela;
using namespace candela::test;

namespace {

std::string furnace_xml(const std::string& emitter, const std::string& bsdf, int spp) {
    return R"(<scene version="3.0.0">
    <integrator type="path"/>
    <sensor type="perspective">
        <float name="fov" value="35"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value=")" +
           std::to_string(spp) + R"("/></sampler>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/><string name="component_format" value="float32"/></film>
    </sensor>
    <emitter type="constant">)" +
           emitter + R"(</emitter>
    <shape type="sphere">)" +
           bsdf + R"(</shape>
</scene>)";
}

RenderResult render_spectral(const std::string& xml) {
    Ref<Scene> scene = load_scene_from_string(xml, scratch_dir("spectral_render").string() + "/scene.xml", {}, Variant::ScalarSpectral);
    RenderOptions options;
    return scene->integrator().render(*scene, options);
}

// A furnace scene with integrator `type` is refused in `variant` at the integrator's line (2),
// with a message that holds each of `parts`.
void check_refused(const std::string& type, Variant variant, const std::vector<std::string>& parts) {
    std::string xml = furnace_xml(R"(<rgb name="radiance" value="1"/>)", R"(<bsdf type="diffuse"/>)", 4);
    const std::string path = R"(<integrator type="path"/>)";
    xml.replace(xml.find(path), path.size(), R"(<integrator type=")" + type + R"("/>)");
    try {
        load_scene_from_string(xml, scratch_dir("spectral_render").string() + "/scene.xml", {}, variant);
        FAIL(type << " loaded in " << variant_name(variant));
    } catch (const SceneError& e) {
        const std::string message = e.what();
        INFO(message);
        CHECK(message.find("scene.xml:2:") != std::string::npos);
        for (const std::string& part : parts) CHECK(message.find(part) != std::string::npos);
    }
}

constexpr int FurnaceTests = 7 * 3;  // z-tests below (per channel), at a 1% family-wise level (Sidak)

void check_colour(const RenderResult& r, const Vec3d& expected, const std::string& what) {
    const double z = two_sided_z(sidak(0.01, FurnaceTests));
    for (int c = 0; c < 3; ++c) {
        MeanAndError m = channel_mean(r.image, c);
        INFO(what << " channel " << c << ": mean " << m.mean << " +- " << m.std_error << " expected " << expected[c]);
        CHECK(std::abs(m.mean - expected[c]) <= z * m.std_error + 1e-5);
        CHECK(m.std_error < 0.01 * std::abs(expected[c]));  // power: a 1% error would show
    }
    CHECK(r.stats.nonfinite == 0);
}

}  // namespace

TEST_CASE("spectral: lossless BSDFs under an equal-energy sky render its colour", "[render][spectral][furnace]") {
    // Every path returns the sky's value 1 at each of its wavelengths; only the wavelengths vary,
    // so the pixels converge to the equal-energy white xyz_to_linear_srgb(1, 1, 1).
    const Vec3d expected = xyz_to_linear_srgb(Vec3d(1.0));
    const std::string sky = R"(<spectrum name="radiance" value="1"/>)";
    for (const char* bsdf :
         {R"(<bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf>)",
          R"(<bsdf type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>)",
          R"(<bsdf type="dielectric"><string name="int_ior" value="glass-SF11"/><float name="ext_ior" value="1"/></bsdf>)",
          R"(<bsdf type="conductor"><string name="material" value="none"/></bsdf>)"}) {
        check_colour(render_spectral(furnace_xml(sky, bsdf, 64)), expected, bsdf);
    }
}

TEST_CASE("spectral: an RGB sky is its colour times D65, white for white", "[render][spectral][furnace]") {
    // rgb (1, 1, 1) emits D65 (unbounded upsampling, core/wavelengths.h), whose colour is sRGB's
    // white; a lossless sphere changes nothing. A coloured sky keeps its colour within the
    // coefficient table's fit.
    for (Vec3 rgb : {Vec3(1.0f), Vec3(0.9f, 0.5f, 0.2f), Vec3(0.1f, 0.3f, 2.0f)}) {
        char sky[128];
        std::snprintf(sky, sizeof sky, R"(<rgb name="radiance" value="%g, %g, %g"/>)", rgb.x, rgb.y, rgb.z);
        RenderResult r = render_spectral(furnace_xml(sky, R"(<bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf>)", 64));
        // The exact expectation is the colour of the upsampled spectrum (within 5e-3 of rgb: the
        // test of core/wavelengths); compare with it through its own estimate's error bars.
        const double z = two_sided_z(sidak(0.01, FurnaceTests));
        for (int c = 0; c < 3; ++c) {
            MeanAndError m = channel_mean(r.image, c);
            INFO("sky " << sky << " channel " << c << ": mean " << m.mean << " +- " << m.std_error);
            CHECK(std::abs(m.mean - rgb[c]) <= z * m.std_error + 5e-3 * max_component(rgb));
        }
    }
}

TEST_CASE("spectral: scalar_rgb is the default, bit for bit", "[render][spectral]") {
    const std::string xml = furnace_xml(R"(<rgb name="radiance" value="0.7, 0.4, 0.2"/>)",
                                        R"(<bsdf type="roughconductor"><string name="material" value="Au"/></bsdf>)", 4);
    const std::string path = scratch_dir("spectral_default").string() + "/scene.xml";
    Ref<Scene> a = load_scene_from_string(xml, path), b = load_scene_from_string(xml, path, {}, Variant::ScalarRGB);
    RenderOptions options;
    Image ia = a->integrator().render(*a, options).image, ib = b->integrator().render(*b, options).image;
    REQUIRE(ia.width() == ib.width());
    bool same = true;
    for (int y = 0; y < ia.height(); ++y)
        for (int x = 0; x < ia.width(); ++x)
            for (int c = 0; c < 3; ++c) same = same && ia.at(x, y, c) == ib.at(x, y, c);
    CHECK(same);
}

TEST_CASE("spectral: plugins that do not render in the variant stop at their line", "[spectral][errors]") {
    // The raster mode is the one integrator left that draws in RGB only (compare-modes and the
    // viewer show it beside spectral renders; a scene file asks for it by name).
    check_refused("raster", Variant::ScalarSpectral,
                  {"integrator type \"raster\" does not render in variant scalar_spectral", "scalar_rgb"});
}

TEST_CASE("spectral: photonmapper stops at its line in scalar_spectral_polarized", "[spectral][errors][photonmapper]") {
    check_refused("photonmapper", Variant::ScalarSpectralPolarized,
                  {"photonmapper does not render in variant scalar_spectral_polarized", "scalar_spectral and scalar_rgb"});
}

TEST_CASE("spectral: ptracer's and sppm's light paths and path's camera paths estimate the same image", "[render][spectral][ptracer]") {
    // A measured emission spectrum on a coloured floor: each estimator carries its own
    // wavelengths (ptracer per light path; sppm one set per pass, shared by its camera and light
    // paths). Their whole-image means over independent seeds agree.
    auto scene = [](const std::string& integrator) {
        return R"(<scene version="3.0.0">)" + integrator + R"(
    <sensor type="perspective"><float name="fov" value="50"/>
        <transform name="to_world"><lookat origin="0, 2, 3" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="8"/></sampler>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/><string name="component_format" value="float32"/></film></sensor>
    <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.3, 0.1"/></bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="1.5"/></transform>
        <emitter type="area"><spectrum name="radiance" value="400:1, 500:3, 600:2, 700:5"/></emitter></shape>
</scene>)";
    };
    const int seeds = 12;
    // Per channel, the mean over the seeds of the whole-image means (independent renders: the
    // spread of their means is the error).
    auto image_means = [&](const std::string& integrator) {
        Ref<Scene> s =
            load_scene_from_string(scene(integrator), scratch_dir("spectral_ptracer").string() + "/scene.xml", {}, Variant::ScalarSpectral);
        std::array<std::vector<double>, 3> means;
        for (int k = 0; k < seeds; ++k) {
            RenderOptions options;
            options.seed = 1000 + k;
            const Image image = s->integrator().render(*s, options).image;
            for (int c = 0; c < 3; ++c) means[c].push_back(channel_mean(image, c).mean);
        }
        std::array<MeanAndError, 3> out;
        for (int c = 0; c < 3; ++c) out[c] = mean_and_error(means[c]);
        return out;
    };
    const double z = two_sided_z(sidak(0.01, 6));
    const auto path = image_means(R"(<integrator type="path"/>)");
    const double brightest = path[0].mean;  // the red channel (the floor is red): power is judged against it
    for (const char* other : {R"(<integrator type="ptracer"/>)",
                              R"(<integrator type="sppm"><integer name="photon_count" value="2000"/><integer name="max_passes" value="128"/>
                                  <float name="initial_radius" value="0.05"/></integrator>)"}) {
        const auto light = image_means(other);
        for (int c = 0; c < 3; ++c) {
            const double error = std::sqrt(path[c].std_error * path[c].std_error + light[c].std_error * light[c].std_error);
            INFO(other << " channel " << c << ": path " << path[c].mean << " +- " << path[c].std_error << ", light paths " << light[c].mean
                       << " +- " << light[c].std_error);
            CHECK(std::abs(path[c].mean - light[c].mean) <= z * error);
            CHECK(error < 0.02 * brightest);  // power: a disagreement of 2% of the image's level would show
        }
    }
}

TEST_CASE("spectral: the aov integrator's albedo layer is the RGB albedo in both variants", "[render][spectral][aov]") {
    // Film positions come from the same sampler dimensions in both variants (the wavelengths
    // have their own), so first-hit layers agree bit for bit; the radiance channels differ.
    const std::string xml = furnace_xml(R"(<rgb name="radiance" value="1"/>)", R"(
        <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.4, 0.1"/></bsdf>)",
                                        4);
    std::string with_aov = xml;
    with_aov.replace(
        with_aov.find(R"(<integrator type="path"/>)"), 25,
        R"(<integrator type="aov"><string name="aovs" value="a:albedo, d:depth"/><integrator type="path" name="p"/></integrator>)");
    const std::string path = scratch_dir("spectral_aov").string() + "/scene.xml";
    RenderOptions options;
    Ref<Scene> rgb = load_scene_from_string(with_aov, path), spectral = load_scene_from_string(with_aov, path, {}, Variant::ScalarSpectral);
    Image a = rgb->integrator().render(*rgb, options).image, b = spectral->integrator().render(*spectral, options).image;
    REQUIRE(a.channel_count() == b.channel_count());
    const int first_aov = a.channel_count() - 4;  // a.R a.G a.B d.T
    bool same = true;
    double radiance_difference = 0.0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            for (int c = first_aov; c < a.channel_count(); ++c) same = same && a.at(x, y, c) == b.at(x, y, c);
            radiance_difference += std::abs(a.at(x, y, 0) - b.at(x, y, 0));
        }
    CHECK(same);
    CHECK(radiance_difference > 0.0);  // the radiance itself was rendered spectrally
}

TEST_CASE("spectral: the irradiance estimate under a uniform sky is pi L per channel", "[spectral][estimate]") {
    // A white sky of radiance L (its spectrum L times D65, whose colour is white within the
    // coefficient table's fit) over an open plane: E = pi L, with the estimate's own error bars
    // (each sample carries its wavelengths, so colour noise is in them).
    Ref<Scene> scene = load_scene(source_path("scenes/furnace/sky_irradiance.xml"), {}, Variant::ScalarSpectral);
    EstimatorOptions options;
    options.samples = uint64_t(1) << 16;
    Estimate e = estimate_irradiance(*scene, Vec3(0.0f), Vec3(0, 1, 0), options);
    const double expected = Pi * 0.7, z = two_sided_z(sidak(0.01, 3));
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": " << e.mean[c] << " +- " << e.std_error[c] << " expected " << expected);
        // The sky's colour is white within 2e-3 (tests/core/test_wavelengths.cpp).
        CHECK(std::abs(e.mean[c] - expected) <= z * e.std_error[c] + 2e-3 * expected);
        CHECK(e.std_error[c] < 0.01 * expected);
    }
    CHECK(e.nonfinite == 0);
}

TEST_CASE("spectral: a sensor response (srf) weights the wavelengths it lets through", "[render][spectral][srf]") {
    // A triangular response 500-580 nm under an equal-energy sky on a lossless sphere: every pixel
    // is the colour of the response itself, CIE_Y_NORMALIZATION * integral of srf cmf.
    std::string xml =
        furnace_xml(R"(<spectrum name="radiance" value="1"/>)", R"(<bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf>)", 64);
    const std::string fov = R"(<float name="fov" value="35"/>)";
    xml.replace(xml.find(fov), fov.size(), fov + R"(<spectrum name="srf" value="500:0, 540:1, 580:0"/>)");
    auto srf = [](double l) { return std::max(0.0, 1.0 - std::abs(l - 540.0) / 40.0); };
    Vec3d xyz(0.0);
    const int n = 16000;
    for (int i = 0; i < n; ++i) {
        const double l = 500.0 + (i + 0.5) * 80.0 / n;
        xyz += cie1931_xyz(l) * (srf(l) * 80.0 / n);
    }
    check_colour(render_spectral(xml), xyz_to_linear_srgb(xyz * CieYNormalization), "srf 500-580 nm");
    // The RGB variant refuses it at its line, as Mitsuba's RGB variants do.
    try {
        load_scene_from_string(xml, scratch_dir("spectral_srf").string() + "/scene.xml");
        FAIL("srf accepted in scalar_rgb");
    } catch (const SceneError& e) {
        CHECK_THAT(std::string(e.what()), Catch::Contains("needs a spectral variant"));
    }
}
