// photonmapper in scalar_spectral: its maps are built once and serve every camera sample's
// wavelengths through photons binned over wavelength (integrators/photons.h). Checked against
// path's camera paths on a Cornell box lit by a measured spectrum, with a copper ball (whole-image
// means over independent seeds: z-tests, the photon-mapping bias allowed as the Cornell-box test
// of test_light_paths.cpp allows it); against its own photons in scalar_rgb on a grey box lit by a
// peaked spectrum, where the only difference in expectation is the bins' blur, computed here (a
// photon read at the wrong wavelength changes the colour of the photon maps' light); and the same
// image with 1 and 2 threads.

#include "core/spectral.h"
#include "core/xml.h"
#include "integrators/photons.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <functional>

using namespace candela;
using namespace candela::test;

namespace {

// A 16 x 16 Cornell box (scenes/validation/cbox.xml's walls) with a ball on the floor and an area
// light of radiance `emitter`.
std::string box_xml(const std::string& integrator, const std::string& emitter, const std::string& ball, const std::string& white,
                    const std::string& red, const std::string& green, int spp) {
    return R"(<scene version="3.0.0">)" + integrator + R"(
    <sensor type="perspective"><float name="fov" value="39.3077"/>
        <transform name="to_world"><lookat origin="0, 0, 3.9" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value=")" +
           std::to_string(spp) + R"("/></sampler>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/><string name="component_format" value="float32"/></film></sensor>
    <bsdf type="diffuse" id="white"><rgb name="reflectance" value=")" +
           white + R"("/></bsdf>
    <bsdf type="diffuse" id="red"><rgb name="reflectance" value=")" +
           red + R"("/></bsdf>
    <bsdf type="diffuse" id="green"><rgb name="reflectance" value=")" +
           green + R"("/></bsdf>
    <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="-90"/><translate y="-1"/></transform><ref id="white"/></shape>
    <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="90"/><translate y="1"/></transform><ref id="white"/></shape>
    <shape type="rectangle"><transform name="to_world"><translate z="-1"/></transform><ref id="white"/></shape>
    <shape type="rectangle"><transform name="to_world"><rotate y="1" angle="90"/><translate x="-1"/></transform><ref id="red"/></shape>
    <shape type="rectangle"><transform name="to_world"><rotate y="1" angle="-90"/><translate x="1"/></transform><ref id="green"/></shape>
    <shape type="sphere"><point name="center" x="0.3" y="-0.6" z="0.1"/><float name="radius" value="0.4"/>)" +
           ball + R"(</shape>
    <shape type="rectangle"><transform name="to_world"><scale value="0.25"/><rotate x="1" angle="90"/><translate y="0.99"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
        <emitter type="area">)" +
           emitter + R"(</emitter></shape>
</scene>)";
}

std::string photonmapper(int global, int caustic, int direct_samples, int glossy_samples) {
    return R"(<integrator type="photonmapper"><integer name="global_photons" value=")" + std::to_string(global) +
           R"("/><integer name="caustic_photons" value=")" + std::to_string(caustic) + R"("/><integer name="direct_samples" value=")" +
           std::to_string(direct_samples) + R"("/><integer name="glossy_samples" value=")" + std::to_string(glossy_samples) +
           R"("/><integer name="granularity" value="1000"/></integrator>)";
}

// Per channel, the whole-image mean over renders with `seeds` seeds, and its standard error from
// the spread of their means (independent renders: each builds its own photon maps).
std::array<MeanAndError, 3> image_means(const std::string& xml, Variant variant, int seeds) {
    Ref<Scene> scene = load_scene_from_string(xml, scratch_dir("spectral_photonmapper").string() + "/scene.xml", {}, variant);
    std::array<std::vector<double>, 3> means;
    for (int k = 0; k < seeds; ++k) {
        RenderOptions options;
        options.seed = uint64_t(2000 + k);
        RenderResult r = scene->integrator().render(*scene, options);
        CHECK(r.stats.nonfinite == 0);
        for (int c = 0; c < 3; ++c) means[c].push_back(channel_mean(r.image, c).mean);
    }
    return {mean_and_error(means[0]), mean_and_error(means[1]), mean_and_error(means[2])};
}

// The linear sRGB colour of an emission spectrum, CIE_Y_NORMALIZATION * integral of cmf s, by
// the midpoint rule at 0.01 nm.
Vec3d colour_of(const std::function<double(double)>& s) {
    const int n = 47000;
    const double step = (CieMax - CieMin) / n;
    Vec3d xyz(0.0);
    for (int i = 0; i < n; ++i) {
        const double l = CieMin + (i + 0.5) * step;
        xyz += cie1931_xyz(l) * (s(l) * step);
    }
    return xyz_to_linear_srgb(xyz * CieYNormalization);
}

}  // namespace

TEST_CASE("spectral: photonmapper agrees with path on a Cornell box lit by a measured spectrum", "[render][spectral][photonmapper]") {
    // A measured emission spectrum, coloured walls and a copper ball (its measured eta and k; a
    // delta lobe, so the caustic map is filled). path and photonmapper, both in scalar_spectral,
    // estimate the same image but for photon mapping's bias, which the Cornell-box test
    // (test_light_paths.cpp) bounds at 2% of the whole-image mean; here it is allowed as much.
    const std::string emitter = R"(<spectrum name="radiance" value="400:4, 500:12, 600:8, 700:20"/>)";
    const std::string ball = R"(<bsdf type="conductor"><string name="material" value="Cu"/></bsdf>)";
    auto scene = [&](const std::string& integrator, int spp) {
        return box_xml(integrator, emitter, ball, "0.725, 0.71, 0.68", "0.63, 0.065, 0.05", "0.14, 0.45, 0.091", spp);
    };
    const int seeds = 8;
    const auto path = image_means(scene(R"(<integrator type="path"/>)", 256), Variant::ScalarSpectral, seeds);
    const auto photons = image_means(scene(photonmapper(20000, 20000, 2, 4), 64), Variant::ScalarSpectral, seeds);
    const double z = two_sided_z(sidak(0.01, 3)), bias = 0.02;
    for (int c = 0; c < 3; ++c) {
        const double error = std::hypot(path[c].std_error, photons[c].std_error);
        INFO("channel " << c << ": path " << path[c].mean << " +- " << path[c].std_error << ", photonmapper " << photons[c].mean << " +- "
                        << photons[c].std_error << " (z " << (photons[c].mean - path[c].mean) / error << ")");
        CHECK(std::abs(photons[c].mean - path[c].mean) <= z * error + bias * path[c].mean);
        CHECK(error < 0.015 * path[c].mean);  // power: a disagreement of 6% of the channel's level would show
    }
}

TEST_CASE("spectral: photonmapper's binned photons carry the colour of its RGB photons", "[render][spectral][photonmapper]") {
    // A grey box with a glass ball, lit by a peaked spectrum (a 20 nm line on a flat base, within
    // sRGB's gamut, so that scalar_rgb's emitter is its exact colour). Every surface's spectrum is
    // flat, so every photon's flux is the emitted spectrum S times a factor that does not depend on
    // the wavelength: in expectation the spectral render's photon-map light has the colour of S
    // averaged over each bin, scalar_rgb's that of S. Without next-event estimation (direct_samples
    // 0) and with the emitter hidden, the image is the photon maps' light (caustics and final
    // gathering), so a pixel's expectation in channel c differs between the variants by at most
    // its RGB expectation times |blurred_c / S_c - 1|; the rest is noise (z-tests over seeds).
    const std::string spectrum = "360:3, 535:3, 545:30, 555:3, 830:3";
    const std::string emitter = R"(<spectrum name="radiance" value=")" + spectrum + R"("/>)";
    const std::string ball = R"(<bsdf type="dielectric"><float name="int_ior" value="1.5"/></bsdf>)";
    std::string integrator = photonmapper(20000, 20000, 0, 8);
    integrator.insert(integrator.find("</integrator>"), R"(<boolean name="hide_emitters" value="true"/>)");
    const std::string xml = box_xml(integrator, emitter, ball, "0.7", "0.7", "0.7", 32);
    const int seeds = 8;
    const auto spectral = image_means(xml, Variant::ScalarSpectral, seeds);
    const auto rgb = image_means(xml, Variant::ScalarRGB, seeds);

    const SampledSpectrum s = parse_spectrum_pairs(spectrum);
    std::array<double, SpectralBins> bin_mean{};
    const int steps = 4000;
    for (int b = 0; b < SpectralBins; ++b) {
        for (int i = 0; i < steps; ++i) bin_mean[b] += s.at(CieMin + (b + (i + 0.5) / steps) * SpectralBinWidth) / steps;
    }
    const Vec3d exact = colour_of([&](double l) { return s.at(l); });
    const Vec3d blurred = colour_of([&](double l) { return bin_mean[spectral_bin(float(l))]; });
    const double z = two_sided_z(sidak(0.01, 3));
    for (int c = 0; c < 3; ++c) {
        const double error = std::hypot(spectral[c].std_error, rgb[c].std_error), blur = std::abs(blurred[c] / exact[c] - 1.0);
        INFO("channel " << c << ": spectral " << spectral[c].mean << " +- " << spectral[c].std_error << ", rgb " << rgb[c].mean << " +- "
                        << rgb[c].std_error << " (z " << (spectral[c].mean - rgb[c].mean) / error << "), bins' blur " << blur);
        CHECK(std::abs(spectral[c].mean - rgb[c].mean) <= z * error + blur * rgb[c].mean);
        // Power: a colour error of 5% would show (reading the bins one bin off, 14.7 nm, moves the
        // red channel by 40%).
        CHECK(z * error + blur * rgb[c].mean < 0.05 * rgb[c].mean);
    }
}

TEST_CASE("light paths: photonmapper in scalar_spectral gives the same image with 1 and 2 threads", "[render][spectral][photonmapper]") {
    const std::string xml = box_xml(photonmapper(5000, 5000, 2, 4), R"(<spectrum name="radiance" value="400:4, 500:12, 600:8, 700:20"/>)",
                                    R"(<bsdf type="conductor"><string name="material" value="Cu"/></bsdf>)", "0.725, 0.71, 0.68",
                                    "0.63, 0.065, 0.05", "0.14, 0.45, 0.091", 2);
    Ref<Scene> scene =
        load_scene_from_string(xml, scratch_dir("spectral_photonmapper").string() + "/scene.xml", {}, Variant::ScalarSpectral);
    RenderOptions one, two;
    one.threads = 1;
    two.threads = 2;
    Image a = scene->integrator().render(*scene, one).image, b = scene->integrator().render(*scene, two).image;
    CHECK(a.data() == b.data());
    double sum = 0.0;
    for (float v : a.data()) sum += v;
    CHECK(sum > 0.0);
}
