// specfilm (Mitsuba 3's spectral film): each channel is the integral of one sensor response
// function times the radiance, over 360-830 nm. Checked against closed forms under a sky of known
// spectrum (exact for one box band, whose samples all carry the same value; a z-test otherwise),
// against hdrfilm's XYZ with the CIE matching functions as the bands (Welch's test over seeds),
// for its channel order, and for the errors at their lines.

#include "core/error.h"
#include "core/scene.h"
#include "core/spectral.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <fstream>

using namespace candela;
using namespace candela::test;

namespace {

constexpr int Size = 16;

// A camera that sees only the sky (a constant environment of spectrum `sky`), with the film's
// `bands` in a specfilm; the integrator path unless given.
std::string sky_scene(const std::string& bands, const std::string& sky, int spp,
                      const std::string& integrator = "<integrator type=\"path\"/>") {
    return scene_xml(integrator + R"(
        <sensor type="perspective">
            <sampler type="independent"><integer name="sample_count" value=")" +
                     std::to_string(spp) + R"("/></sampler>
            <film type="specfilm"><integer name="width" value=")" +
                     std::to_string(Size) + R"("/><integer name="height" value=")" + std::to_string(Size) + R"("/>
                <string name="component_format" value="float32"/><rfilter type="box"/>)" +
                     bands + R"(</film></sensor>
        <emitter type="constant"><spectrum name="radiance" value=")" +
                     sky + R"("/></emitter>)");
}

Ref<Scene> load_spectral(const std::string& name, const std::string& xml) {
    const auto dir = scratch_dir(name);
    return load_scene_from_string(xml, (dir / "scene.xml").string(), {}, Variant::ScalarSpectral);
}

Image render_image(const Scene& scene, RenderOptions options = RenderOptions()) { return scene.integrator().render(scene, options).image; }

// Simpson's rule of f over [a, b] with n (even) intervals.
double integrate(const std::function<double(double)>& f, double a, double b, int n = 2000) {
    const double h = (b - a) / n;
    double sum = f(a) + f(b);
    for (int i = 1; i < n; ++i) sum += f(a + i * h) * (i % 2 ? 4.0 : 2.0);
    return sum * h / 3.0;
}

// The error of loading `xml` in the spectral variant (or `variant`): a SceneError at `line`.
std::string load_error(const std::string& xml, int line, Variant variant = Variant::ScalarSpectral) {
    const auto dir = scratch_dir("specfilm-errors");
    try {
        load_scene_from_string(xml, (dir / "scene.xml").string(), {}, variant);
    } catch (const SceneError& e) {
        CHECK(e.location.line == line);
        return e.what();
    }
    FAIL("loaded");
    return "";
}

}  // namespace

TEST_CASE("specfilm: one box band under a flat sky is its width times the radiance in every sample", "[specfilm]") {
    // Wavelengths follow the band itself, so srf(l) / p(l) is the band's integral (100 nm) for
    // every wavelength drawn: no noise at all.
    Ref<Scene> scene = load_spectral("specfilm-box", sky_scene(R"(<spectrum name="only" value="400:1, 500:1"/>)", "360:2, 830:2", 4));
    const Image image = render_image(*scene);
    REQUIRE(image.channels() == std::vector<std::string>{"only"});
    for (float v : image.data()) CHECK(v == Approx(200.0).epsilon(1e-5));
}

TEST_CASE("specfilm: each band is the integral of its response times the radiance", "[specfilm]") {
    // A sloped sky E(l) and two bands: a box over 400-500 nm and a ramp over 550-650 nm. Pixels are
    // independent (box filter), so the image mean's error is the pixels' spread over sqrt(256).
    auto sky = [](double l) { return 0.5 + 1.5 * (l - 360.0) / 470.0; };
    auto ramp = [](double l) { return 3.0 * (l - 550.0) / 100.0; };
    const double expected_box = integrate(sky, 400.0, 500.0),
                 expected_ramp = integrate([&](double l) { return ramp(l) * sky(l); }, 550.0, 650.0);
    Ref<Scene> scene = load_spectral(
        "specfilm-two",
        sky_scene(R"(<spectrum name="b_ramp" value="550:0, 650:3"/><spectrum name="a_box" value="400:1, 500:1"/>)", "360:0.5, 830:2", 16));
    const Image image = render_image(*scene);
    REQUIRE(image.channels() == std::vector<std::string>{"a_box", "b_ramp"});  // alphabetical, as Mitsuba's
    const double z_limit = two_sided_z(sidak(0.01, 2));
    const double expected[2] = {expected_box, expected_ramp};
    for (int c = 0; c < 2; ++c) {
        const MeanAndError m = channel_mean(image, c);
        INFO("band " << image.channels()[size_t(c)] << ": " << m.mean << " +- " << m.std_error << ", exact " << expected[c]);
        CHECK(std::abs(m.mean - expected[c]) < z_limit * m.std_error);
        CHECK(m.std_error < 0.01 * expected[c]);  // the test has power: a 3% error would fail it
    }
}

TEST_CASE("specfilm: the CIE matching functions as bands give hdrfilm's XYZ", "[specfilm]") {
    // hdrfilm's xyz is CIE_Y_NORMALIZATION * integral of cmf(l) L(l) dl with wavelengths from the
    // visible density; a specfilm with x-bar, y-bar and z-bar as its bands (named X, Y, Z) gives
    // the integrals themselves with wavelengths from their sum. A diffuse sphere of a saturated
    // colour under a point light and a bluish sky; 4 x 4 blocks of 4 x 4 pixels over 16 seeds.
    const auto dir = scratch_dir("specfilm-cie");
    for (int k = 0; k < 3; ++k) {
        std::ofstream out(dir / (std::string(1, "XYZ"[k]) + ".spd"));
        for (int l = 360; l <= 830; ++l) out << l << " " << cie1931_xyz(l)[k] << "\n";
    }
    auto scene_with = [&](const std::string& film) {
        return scene_xml(R"(<integrator type="path"/>
        <sensor type="perspective"><float name="fov" value="40"/>
            <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="16"/></sampler>)" +
                         film + R"(</sensor>
        <emitter type="point"><point name="position" value="1, 2, 3"/><rgb name="intensity" value="20"/></emitter>
        <emitter type="constant"><rgb name="radiance" value="0.1, 0.2, 0.4"/></emitter>
        <shape type="sphere"><float name="radius" value="0.9"/>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.3, 0.1"/></bsdf></shape>)");
    };
    const std::string size = R"(<integer name="width" value=")" + std::to_string(Size) + R"("/><integer name="height" value=")" +
                             std::to_string(Size) + R"("/><string name="component_format" value="float32"/><rfilter type="box"/>)";
    Ref<Scene> hdr =
        load_scene_from_string(scene_with(R"(<film type="hdrfilm">)" + size + R"(<string name="pixel_format" value="xyz"/></film>)"),
                               (dir / "hdr.xml").string(), {}, Variant::ScalarSpectral);
    Ref<Scene> spec = load_scene_from_string(scene_with(R"(<film type="specfilm">)" + size +
                                                        R"(<spectrum name="Z" filename="Z.spd"/><spectrum name="X" filename="X.spd"/>
                                                           <spectrum name="Y" filename="Y.spd"/></film>)"),
                                             (dir / "spec.xml").string(), {}, Variant::ScalarSpectral);
    const int seeds = 16, block = 4;
    const double level = sidak(0.01, (Size / block) * (Size / block) * 3);
    const SeedBlockMeans hdr_means = seed_block_means(*hdr, seeds, block);
    SeedBlockMeans spec_means = seed_block_means(*spec, seeds, block);
    auto scaled = [](SeedBlockMeans means, double factor) {
        for (auto& b : means)
            for (auto& channel : b)
                for (double& v : channel) v *= factor;
        return means;
    };
    std::string where;
    const double p = smallest_welch_p(hdr_means, scaled(spec_means, CieYNormalization), where);
    INFO("specfilm X, Y, Z times CIE_Y_NORMALIZATION against hdrfilm's xyz: smallest p " << p << " at " << where << " (level " << level
                                                                                         << ")");
    CHECK(p >= level);
    // Power: a 3% error in the scale is found.
    const double p_off = smallest_welch_p(hdr_means, scaled(spec_means, 1.03 * CieYNormalization), where);
    INFO("with the scale 3% off: smallest p " << p_off << " at " << where);
    CHECK(p_off < level);
}

TEST_CASE("specfilm: its bands come first, then the integrator's channels and the AOV layers", "[specfilm]") {
    Ref<Scene> scene = load_spectral(
        "specfilm-channels",
        sky_scene(
            R"(<spectrum name="vis" value="1"/><spectrum name="nir" value="700:1, 830:1"/>)", "360:1, 830:1", 2,
            R"(<integrator type="aov"><string name="aovs" value="dd.y:depth"/><integrator type="path" name="radiance"/></integrator>)"));
    RenderOptions options;
    options.aovs = {"albedo", "samples"};
    const Image image = render_image(*scene, options);
    CHECK(image.channels() == std::vector<std::string>{"nir", "vis", "radiance.R", "radiance.G", "radiance.B", "radiance.A", "dd.y.T",
                                                       "albedo.R", "albedo.G", "albedo.B", "samples.N"});
    // "vis" is flat over 360-830 nm: 470 nm times the flat sky, in every sample's expectation (the
    // nested integrator's channels are RGB, as Mitsuba's aov integrator converts them).
    CHECK(channel_mean(image, 1).mean == Approx(470.0).epsilon(0.05));
}

TEST_CASE("specfilm: errors at their lines", "[specfilm][errors]") {
    auto film = [](const std::string& bands, const std::string& sensor_extra = "") {
        return std::string("<scene version=\"3.0.0\">\n<sensor type=\"perspective\">") + sensor_extra + "\n<film type=\"specfilm\">\n" +
               bands + "\n</film></sensor></scene>";
    };
    CHECK_THAT(load_error(film(R"(<spectrum name="a" value="400:1, 500:1"/>)"), 3, Variant::ScalarRGB),
               Catch::Contains("spectral variants only"));
    CHECK_THAT(load_error(film(""), 3), Catch::Contains("at least one sensor response"));
    CHECK_THAT(load_error(film(R"(<spectrum name="a" value="400:1, 500:-1"/>)"), 4), Catch::Contains("must not be negative"));
    CHECK_THAT(load_error(film(R"(<spectrum type="uniform"><float name="value" value="1"/></spectrum>)"), 4),
               Catch::Contains("needs a name"));
    CHECK_THAT(load_error(film(R"(<spectrum name="a" value="900:1, 1000:1"/>)"), 3), Catch::Contains("360-830"));
    CHECK_THAT(load_error(film(R"(<spectrum name="a,b" value="400:1, 500:1"/>)"), 4), Catch::Contains("no commas or spaces"));
    CHECK_THAT(load_error(film(R"(<spectrum name="a" value="400:1, 500:1"/>)", R"(<spectrum name="srf" value="400:1, 500:1"/>)"), 2),
               Catch::Contains("specfilm"));
    // The integrators that develop their own image stop at the film when they render.
    for (const char* integrator : {"ptracer", "sppm"}) {
        INFO(integrator);
        Ref<Scene> scene = load_spectral("specfilm-ptracer", sky_scene(R"(<spectrum name="a" value="400:1, 500:1"/>)", "360:1, 830:1", 1,
                                                                       std::string("<integrator type=\"") + integrator + "\"/>"));
        try {
            render_image(*scene);
            FAIL("rendered");
        } catch (const SceneError& e) {
            CHECK(e.location.line == scene->sensor().film().location().line);
            CHECK_THAT(e.what(), Catch::Contains("specfilm"));
        }
    }
    // The colour-noise measures have no colour to measure.
    Ref<Scene> scene = load_spectral("specfilm-variance", sky_scene(R"(<spectrum name="a" value="400:1, 500:1"/>)", "360:1, 830:1", 1));
    RenderOptions options;
    options.aovs = {"variance"};
    CHECK_THROWS_AS(render_image(*scene, options), InputError);
}
