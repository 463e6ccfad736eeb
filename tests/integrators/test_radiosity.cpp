// Radiosity: the analytic point-to-polygon form factor; a closed emitting box whose exact
// radiosity is E / (1 - rho); the validation Cornell box against Mitsuba's reference, with the
// error falling as patches shrink; bit-identical images with any thread count; the solution
// file (reuse, and refusal when stale or damaged); the warning for non-diffuse BSDFs; the
// per-vertex irradiance for baked lighting; Ctrl-C.

#include "analysis/image_metrics.h"
#include "core/image.h"
#include "core/warning.h"
#include "core/xml.h"
#include "integrators/form_factor.h"
#include "integrators/radiosity.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstring>

using namespace candela;
using namespace candela::test;

namespace {

// Howell's catalogue (B-3): a differential area parallel to an a x b rectangle at distance c,
// its normal through a corner.
double corner_rectangle_form_factor(double a, double b, double c) {
    double x = a / c, y = b / c;
    return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
            y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
           (2.0 * 3.14159265358979323846);
}

// The validation Cornell box with the radiosity integrator (max_patch_area $area, final_gather
// $gather) instead of the path tracer, plus `extra` integrator properties.
std::string radiosity_cbox(const std::string& extra = "") {
    std::string scene = read_text(source_path("scenes/validation/cbox.xml"));
    std::string path = "<integrator type=\"path\">\n        <integer name=\"max_depth\" value=\"-1\"/>\n    </integrator>";
    REQUIRE(scene.find(path) != std::string::npos);
    scene.replace(
        scene.find(path), path.size(),
        R"(<integrator type="radiosity"><float name="max_patch_area" value="$area"/><boolean name="final_gather" value="$gather"/>)" +
            extra + "</integrator>");
    return scene;
}

RenderResult render_string(const std::string& xml, const std::filesystem::path& file, const SceneParameters& p, int threads = 0,
                           const RadiosityStats** stats = nullptr, Variant variant = Variant::ScalarRGB) {
    write_text(file, xml);
    static Ref<Scene> keep;  // the stats live in the integrator
    keep = load_scene(file.string(), p, variant);
    RenderOptions options;
    options.threads = threads;
    RenderResult r = keep->integrator().render(*keep, options);
    if (stats) *stats = radiosity_stats(keep->integrator());
    return r;
}

// A closed box seen from inside, emitting Le = 1 from every wall, diffuse reflectance 0.5: the
// radiance everywhere is Le / (1 - rho) = 2.
std::string furnace_box(const std::string& display, int spp = 16) {
    return scene_xml(R"(<integrator type="radiosity"><integer name="subdivisions" value="2"/><boolean name="final_gather" value=")" +
                     display +
                     R"("/></integrator>
        <sensor type="perspective"><float name="fov" value="90"/>
            <transform name="to_world"><lookat origin="0.2, 0.1, 0.3" target="1, 0.5, -1" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value=")" +
                     std::to_string(spp) + R"("/></sampler>
            <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/><rfilter type="box"/></film>
        </sensor>
        <shape type="cube"><boolean name="flip_normals" value="true"/>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
            <emitter type="area"><rgb name="radiance" value="1"/></emitter>
        </shape>)");
}

MeanAndError pixel_mean(const Image& img) {
    std::vector<double> v;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) v.push_back(img.at(x, y, 0));
    return mean_and_error(v);
}

double worst_mean_difference(const ImageComparison& c) {
    return std::max(
        {std::abs(c.mean_relative_difference.x), std::abs(c.mean_relative_difference.y), std::abs(c.mean_relative_difference.z)});
}

// Collects the warnings given while alive.
struct CaptureWarnings {
    std::string text;
    WarningSink previous = set_warning_sink([this](const std::string& line) { text += line + "\n"; });
    ~CaptureWarnings() { set_warning_sink(previous); }
};

}  // namespace

TEST_CASE("form factor: point to polygon equals Howell's rectangle formula and sums to 1 over a closed box", "[radiosity]") {
    for (auto [a, b, c] : {std::array<double, 3>{1, 1, 1}, {0.3, 2.5, 0.7}, {40, 0.1, 2}}) {
        Vec3d rect[4] = {{0, 0, c}, {a, 0, c}, {a, b, c}, {0, b, c}};
        INFO(a << " x " << b << " at " << c);
        CHECK(point_polygon_form_factor(Vec3d(0), Vec3d(0, 0, 1), rect, 4) == Approx(corner_rectangle_form_factor(a, b, c)).epsilon(1e-9));
    }
    // Every direction of the hemisphere meets the box exactly once: the form factors to its 12
    // triangles (several cut by the tangent plane) sum to 1, from inside or from a wall.
    const Vec3d corners[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
    const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
    auto sum_over_box = [&](const Vec3d& x, const Vec3d& n) {
        double sum = 0.0;
        for (const auto& f : faces)
            for (int t = 0; t < 2; ++t) {
                Vec3d tri[3] = {corners[f[0]], corners[f[1 + t]], corners[f[2 + t]]};
                sum += point_polygon_form_factor(x, n, tri, 3);
            }
        return sum;
    };
    CHECK(sum_over_box(Vec3d(0.3, -0.2, 0.5), glm::normalize(Vec3d(1, 2, -0.5))) == Approx(1.0).epsilon(1e-9));
    CHECK(sum_over_box(Vec3d(0.3, -0.2, -1.0), Vec3d(0, 0, 1)) == Approx(1.0).epsilon(1e-9));
    CHECK(sum_over_box(Vec3d(0.999, 0.999, -1.0), Vec3d(0, 0, 1)) == Approx(1.0).epsilon(1e-9));  // in a corner
    // Behind the receiver: nothing.
    Vec3d below[3] = {{0, 0, -1}, {1, 0, -1}, {0, 1, -1}};
    CHECK(point_polygon_form_factor(Vec3d(0), Vec3d(0, 0, 1), below, 3) == 0.0);
}

TEST_CASE("radiosity: a closed emitting box reaches E / (1 - rho), smoothly and through the final gather", "[radiosity][furnace]") {
    auto dir = scratch_dir("radiosity-furnace");
    const RadiosityStats* stats = nullptr;
    // Smooth display: no sampling noise at all (every visibility ray inside a convex box
    // arrives), so only the unshot power is missing: at most `tolerance` (1e-3) of it.
    RenderResult smooth = render_string(furnace_box("false"), dir / "smooth.xml", {}, 0, &stats);
    REQUIRE(stats);
    CHECK(stats->converged);
    CHECK(stats->patches == 48);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            INFO("pixel " << x << ", " << y);
            REQUIRE(smooth.image.at(x, y, 0) == Approx(2.0).epsilon(3e-3));
        }
    // Final gather: emission, light sampling of the box itself and one gathered bounce; the
    // light sampling is noisy (heavy-tailed next to the box's edges, where 1 / r^2 is large),
    // so the image mean is tested against its standard error.
    RenderResult gather = render_string(furnace_box("true", 1024), dir / "gather.xml", {});
    MeanAndError m = pixel_mean(gather.image);
    double z = two_sided_z(sidak(0.01, 1));
    INFO("gather: " << m.mean << " +- " << m.std_error);
    CHECK(std::abs(m.mean - 2.0) <= z * m.std_error + 2.0 * 1e-3);
    CHECK(m.std_error < 0.01);  // power: an error of 1.5% would show
}

TEST_CASE("radiosity: in scalar_spectral the emitting box is 2 x white in every channel", "[radiosity][furnace][spectral]") {
    // The solve is RGB (every patch 2); emission and light sampling are at the sample's
    // wavelengths (white radiance is D65) and the gathered radiosity is upsampled there: every
    // channel's mean is 2 within its error bars, the coefficient table's fit (5e-3 of the value)
    // and the unshot power (1e-3).
    auto dir = scratch_dir("radiosity-furnace-spectral");
    for (const char* display : {"false", "true"}) {
        RenderResult r = render_string(furnace_box(display, 256), dir / "box.xml", {}, 0, nullptr, Variant::ScalarSpectral);
        const double z = two_sided_z(sidak(0.01, 6));
        for (int c = 0; c < 3; ++c) {
            MeanAndError m = channel_mean(r.image, c);
            INFO("final_gather " << display << ", channel " << c << ": " << m.mean << " +- " << m.std_error);
            CHECK(std::abs(m.mean - 2.0) <= z * m.std_error + 2.0 * (5e-3 + 1e-3));
            CHECK(m.std_error > 0.0);   // the wavelengths did vary
            CHECK(m.std_error < 0.02);  // power: an error of 5% would show
        }
    }
}

TEST_CASE("radiosity: per-vertex irradiance for baked lighting", "[radiosity]") {
    auto dir = scratch_dir("radiosity-bake");
    write_text(dir / "box.xml", furnace_box("false"));
    Ref<Scene> scene = load_scene((dir / "box.xml").string());
    RadiositySettings settings;
    settings.subdivisions = 2;
    RadiosityStats stats;
    std::vector<RadiosityMesh> meshes = bake_radiosity(*scene, settings, RenderOptions(), &stats);
    REQUIRE(meshes.size() == 1);
    const RadiosityMesh& m = meshes[0];
    CHECK(m.shape == scene->shapes()[0].get());
    CHECK(m.patches.triangles.size() == 48);
    REQUIRE(m.irradiance.size() == m.patches.positions.size());
    REQUIRE(m.radiosity.size() == m.patches.positions.size());
    CHECK(m.irradiance_back.empty());  // one-sided
    // Irradiance = the radiosity of the surroundings = pi Le / (1 - rho); leaving: the same.
    for (size_t v = 0; v < m.irradiance.size(); ++v) {
        REQUIRE(m.irradiance[v].x == Approx(2.0 * Pi).epsilon(3e-3));
        REQUIRE(m.radiosity[v].x == Approx(2.0 * Pi).epsilon(3e-3));
    }
    // A two-sided BSDF has patches lit on both sides.
    write_text(dir / "panel.xml", scene_xml(R"(<shape type="rectangle"><bsdf type="twosided"><bsdf type="diffuse"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="180"/><translate z="3"/></transform><emitter type="area"/></shape>)"));
    Ref<Scene> panel = load_scene((dir / "panel.xml").string());
    std::vector<RadiosityMesh> two = bake_radiosity(*panel, settings, RenderOptions());
    REQUIRE(two.size() == 2);
    CHECK(two[0].irradiance_back.size() == two[0].irradiance.size());
    CHECK(two[0].irradiance[0].x > 0.0f);        // the front faces the light
    CHECK(two[0].irradiance_back[0].x == 0.0f);  // the back sees nothing
}

TEST_CASE("radiosity: the Cornell box agrees with Mitsuba through the final gather", "[radiosity][validation]") {
    // The finest setting the suite affords: 0.04 m^2 patches (920), 32 samples per pixel.
    // bench_radiosity prints the whole curve down to 0.01 m^2.
    auto dir = scratch_dir("radiosity-cbox");
    RenderResult r = render_string(radiosity_cbox(), dir / "cbox.xml", {{"area", "0.04"}, {"gather", "true"}, {"spp", "32"}});
    ImageComparison c = compare_images(r.image, read_image(source_path("scenes/validation/refs/cbox.exr")));
    INFO("mean difference " << worst_mean_difference(c) << ", block MARE " << c.block_mare);
    CHECK(worst_mean_difference(c) < 0.02);
    CHECK(c.block_mare < 0.04);
}

TEST_CASE("radiosity: in scalar_spectral the Cornell box agrees with the spectral path tracer", "[radiosity][validation][spectral]") {
    // Mitsuba's reference is RGB, and spectral rendering of RGB inputs differs from it by itself
    // (the path tracer's blue is 3.4% below it at 256 spp): compare with the path tracer in the
    // same variant: per channel, the mean of the pixels' differences (paired, so the image's own
    // contrast cancels) is within its error bars (Sidak over 3 channels) and the 2% the RGB
    // validation allows radiosity.
    auto dir = scratch_dir("radiosity-cbox-spectral");
    const SceneParameters common = {{"res", "128"}};
    SceneParameters radiosity = common, path = common;
    radiosity.insert({{"area", "0.04"}, {"gather", "true"}, {"spp", "32"}});
    path.insert({"spp", "64"});
    RenderResult r = render_string(radiosity_cbox(), dir / "radiosity.xml", radiosity, 0, nullptr, Variant::ScalarSpectral);
    RenderResult p =
        render_string(read_text(source_path("scenes/validation/cbox.xml")), dir / "path.xml", path, 0, nullptr, Variant::ScalarSpectral);
    const double z = two_sided_z(sidak(0.01, 3));
    for (int c = 0; c < 3; ++c) {
        const MeanAndError d = mean_difference(r.image, p.image, c);
        const double path_mean = channel_mean(p.image, c).mean;
        INFO("channel " << c << ": radiosity - path " << d.mean << " +- " << d.std_error << " (path " << path_mean << ")");
        CHECK(std::abs(d.mean) <= z * d.std_error + 0.02 * path_mean);
        CHECK(d.std_error < 0.01 * path_mean);  // power: a difference of 5% would show
    }
}

TEST_CASE("radiosity: the smooth display's error falls as patches shrink", "[radiosity][validation]") {
    auto dir = scratch_dir("radiosity-curve");
    Image reference = read_image(source_path("scenes/validation/refs/cbox.exr"));
    std::vector<double> errors;
    for (const char* area : {"0.32", "0.08", "0.04"}) {
        RenderResult r = render_string(radiosity_cbox(), dir / "cbox.xml", {{"area", area}, {"gather", "false"}, {"spp", "2"}});
        errors.push_back(compare_images(r.image, reference).block_mare);
    }
    INFO("block MARE at 0.32, 0.08, 0.04 m^2: " << errors[0] << ", " << errors[1] << ", " << errors[2]);
    CHECK(errors[1] < 0.8 * errors[0]);
    CHECK(errors[2] < 0.8 * errors[1]);
}

TEST_CASE("radiosity: bit-identical images with 1 and 2 threads", "[radiosity][determinism]") {
    auto dir = scratch_dir("radiosity-determinism");
    for (const char* gather : {"false", "true"}) {
        SceneParameters p = {{"area", "0.16"}, {"gather", gather}, {"res", "40"}, {"spp", "3"}};
        RenderResult one = render_string(radiosity_cbox(), dir / "cbox.xml", p, 1);
        RenderResult two = render_string(radiosity_cbox(), dir / "cbox.xml", p, 2);
        REQUIRE(one.image.data().size() == two.image.data().size());
        INFO("final_gather " << gather);
        CHECK(std::memcmp(one.image.data().data(), two.image.data().data(), one.image.data().size() * sizeof(float)) == 0);
    }
}

TEST_CASE("radiosity: a solution file is reused, and refused when stale or damaged", "[radiosity]") {
    auto dir = scratch_dir("radiosity-solution");
    std::string scene = radiosity_cbox(R"(<string name="solution" value="cbox.radiosity"/>)");
    SceneParameters p = {{"area", "0.16"}, {"gather", "false"}, {"res", "32"}, {"spp", "2"}};
    const RadiosityStats* stats = nullptr;
    RenderResult first = render_string(scene, dir / "cbox.xml", p, 0, &stats);
    CHECK_FALSE(stats->loaded);
    REQUIRE(std::filesystem::exists(dir / "cbox.radiosity"));
    int shots = stats->shots;
    RenderResult again = render_string(scene, dir / "cbox.xml", p, 0, &stats);
    CHECK(stats->loaded);
    CHECK(stats->shots == shots);
    CHECK(std::memcmp(first.image.data().data(), again.image.data().data(), first.image.data().size() * sizeof(float)) == 0);

    // Other geometry (the short box moved): the file is refused, solved again and replaced.
    std::string moved = scene;
    std::string at = R"(<translate x="0.33" y="-0.7" z="0.3"/>)";
    REQUIRE(moved.find(at) != std::string::npos);
    moved.replace(moved.find(at), at.size(), R"(<translate x="0.2" y="-0.7" z="0.3"/>)");
    {
        CaptureWarnings err;
        render_string(moved, dir / "cbox.xml", p, 0, &stats);
        CHECK_THAT(err.text, Catch::Contains("refused") && Catch::Contains("other geometry"));
    }
    CHECK_FALSE(stats->loaded);
    render_string(moved, dir / "cbox.xml", p, 0, &stats);
    CHECK(stats->loaded);
    // Other settings count as stale too.
    {
        CaptureWarnings err;
        render_string(moved, dir / "cbox.xml", {{"area", "0.2"}, {"gather", "false"}, {"res", "32"}, {"spp", "2"}}, 0, &stats);
        CHECK_FALSE(stats->loaded);
    }

    // A damaged (truncated) file is refused.
    std::string bytes = read_text(dir / "cbox.radiosity");
    write_text(dir / "cbox.radiosity", bytes.substr(0, bytes.size() - 5));
    CaptureWarnings err;
    render_string(moved, dir / "cbox.xml", {{"area", "0.2"}, {"gather", "false"}, {"res", "32"}, {"spp", "2"}}, 0, &stats);
    CHECK_FALSE(stats->loaded);
    CHECK_THAT(err.text, Catch::Contains("damaged"));
}

TEST_CASE("radiosity: non-diffuse BSDFs are named as approximated, bad parameters fail", "[radiosity]") {
    auto dir = scratch_dir("radiosity-bsdfs");
    std::string scene = radiosity_cbox();
    std::string white = R"(<bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.725, 0.71, 0.68"/></bsdf>)";
    REQUIRE(scene.find(white) != std::string::npos);
    scene.replace(scene.find(white), white.size(), R"(<bsdf type="plastic" id="white"/>)");
    const RadiosityStats* stats = nullptr;
    {
        CaptureWarnings err;
        render_string(scene, dir / "cbox.xml", {{"area", "0.32"}, {"gather", "true"}, {"res", "16"}, {"spp", "1"}}, 0, &stats);
        CHECK_THAT(err.text, Catch::Contains("cbox.xml:") &&
                                 Catch::Contains("warning: radiosity treats non-diffuse BSDFs by their diffuse albedo: plastic"));
    }
    CHECK(stats->approximated_bsdfs == std::vector<std::string>{"plastic"});
    {
        CaptureWarnings err;
        render_string(radiosity_cbox(), dir / "cbox.xml", {{"area", "0.32"}, {"gather", "true"}, {"res", "16"}, {"spp", "1"}});
        CHECK(err.text.find("warning") == std::string::npos);
    }
    for (const char* bad : {R"(<float name="max_patch_area" value="-1"/>)", R"(<integer name="subdivisions" value="0"/>)",
                            R"(<float name="tolerance" value="2"/>)", R"(<integer name="visibility_rays" value="0"/>)",
                            R"(<float name="max_patch_area" value="1"/><integer name="subdivisions" value="2"/>)"}) {
        write_text(dir / "bad.xml", scene_xml(std::string(R"(<integrator type="radiosity">)") + bad + "</integrator>"));
        INFO(bad);
        CHECK_THROWS_WITH(load_scene((dir / "bad.xml").string()), Catch::Contains("bad.xml:"));
    }
}

TEST_CASE("radiosity and ao: Ctrl-C writes the image so far, marked partial", "[radiosity][ao][cli][interrupt]") {
    auto dir = scratch_dir("radiosity-interrupt");
    // Radiosity interrupted during a solve far too long to finish (about 50,000 patches), and
    // ao during the pixel loop.
    std::string ao = read_text(source_path("scenes/validation/cbox.xml"));
    std::string path = "<integrator type=\"path\">\n        <integer name=\"max_depth\" value=\"-1\"/>\n    </integrator>";
    ao.replace(ao.find(path), path.size(), R"(<integrator type="ao"><integer name="shading_samples" value="64"/></integrator>)");
    write_text(dir / "radiosity.xml", radiosity_cbox());
    write_text(dir / "ao.xml", ao);
    for (const char* name : {"radiosity", "ao"}) {
        auto out = dir / (std::string(name) + ".exr");
        std::string cmd = interrupt_after_start("'" + candela_binary() + "' render '" + (dir / (std::string(name) + ".xml")).string() +
                                                "' -o '" + out.string() + "' -D area=0.0005 -D gather=true --spp 100000");
        int code = run_command(cmd, dir / "log.txt");
        INFO(name << ": " << read_text(dir / "log.txt"));
        CHECK(code == 130);
        REQUIRE(std::filesystem::exists(out));
        Image img = read_image(out.string());
        CHECK(img.metadata["candela.partial"] == "true");
        CHECK_THAT(read_text(dir / "log.txt"), Catch::Contains("interrupted"));
    }
}
