// The raster mode's approximations of global illumination against exact answers: ray-cast
// ambient occlusion in the analytic cases, image-based lighting (SH irradiance) against the path
// tracer's direct environment light, and baked lighting against the radiosity render it comes
// from, with its colour bleeding measured against Mitsuba's reference of the Cornell box.

#include "analysis/image_metrics.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/xml.h"
#include "integrators/estimators.h"
#include "integrators/raster/image_lighting.h"
#include "integrators/raster/raster.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace candela;
using namespace candela::test;

namespace {

const std::string Sky = source_path("scenes/validation/textures/sky.exr");
const std::string CboxFile = source_path("scenes/validation/cbox.xml");

// Mean and its standard error of one channel sum (R + G + B) over the pixels where `use` holds;
// the error from the render's variance layers (variance of each pixel mean; pixels independent).
struct MaskedMean {
    double mean = 0.0, std_error = 0.0;
    int pixels = 0;
};
template <typename Use>
MaskedMean masked_mean(const Image& img, Use use) {
    MaskedMean m;
    double var = 0.0;
    int vr = img.channel_index("variance.R");
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            if (!use(x, y)) continue;
            for (int c = 0; c < 3; ++c) {
                m.mean += img.at(x, y, c);
                if (vr >= 0) var += img.at(x, y, vr + c);
            }
            ++m.pixels;
        }
    if (m.pixels == 0) return m;
    m.mean /= m.pixels;
    m.std_error = std::sqrt(var) / m.pixels;
    return m;
}

RenderResult raster_render(const Scene& scene, const std::map<std::string, std::string>& options) {
    RasterSettings s;
    std::string error;
    for (const auto& [name, value] : options) REQUIRE(s.set(name, value, error));
    RasterIntegrator raster(s);
    return raster.render(scene, RenderOptions{});
}

}  // namespace

TEST_CASE("raster AO: analytic cases (open plane 1, sphere not self-occluded, infinite wall 1/2, closed box 0)", "[raster][ao]") {
    // White Lambertian surfaces (kd 1) under a constant environment of radiance 1 and no light:
    // a sample's value is exactly its ambient occlusion.
    const std::string white = R"(<bsdf type="diffuse"><rgb name="reflectance" value="1"/></bsdf>)";
    const std::string sky = R"(<emitter type="constant"><rgb name="radiance" value="1"/></emitter>)";
    const int W = 64, H = 48;
    SECTION("an open plane, and a sphere above it, see the whole sky") {
        Ref<Scene> scene = load_scene_xml(
            "raster-ao-open",
            sky + R"(<shape type="rectangle"><transform name="to_world"><scale value="50"/><rotate x="1" angle="-90"/></transform>)" +
                white + R"(</shape><shape type="sphere"><point name="center" x="0" y="3" z="0"/><float name="radius" value="0.5"/>)" +
                white + "</shape>" + pinhole_camera("0, 3.2, 2.5", "0, 2.5, 0", W, H, 50));
        Image img = raster_render(*scene, {{"ao", "16"}, {"ao_ray_length", "1"}, {"shadows", "none"}}).image;
        Image open = raster_render(*scene, {{"shadows", "none"}}).image;
        // The sphere: its tessellation lies inside the exact sphere, yet no ray may find it from
        // within (the tessellation gap); only directions grazing the tangent plane can.
        MaskedMean sphere = masked_mean(img, [&](int x, int y) { return pixel_view(*scene, x, y).shape == scene->shapes()[1].get(); });
        REQUIRE(sphere.pixels > 200);
        CHECK(sphere.mean / 3.0 > 0.99);
        // The plane far from the sphere (beyond the 1 m reach): AO exactly 1, the image unchanged.
        int exact = 0, plane = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                SurfaceInteraction si;
                if (!scene->intersect(scene->sensor().sample_ray(Vec2(x + 0.5f, y + 0.5f), Vec2(0.5f)), si) ||
                    si.shape != scene->shapes()[0].get())
                    continue;
                if (glm::length(Vec2(si.p.x, si.p.z)) < 1.6f) continue;
                ++plane;
                exact += img.rgb_at(x, y) == open.rgb_at(x, y);
            }
        REQUIRE(plane > 100);
        CHECK(exact == plane);
    }
    SECTION("the floor in front of an infinite wall: exactly half the cosine-weighted directions are open") {
        Ref<Scene> scene = load_scene_xml(
            "raster-ao-wall",
            sky + R"(<shape type="rectangle"><transform name="to_world"><scale value="1000"/><rotate x="1" angle="-90"/></transform>)" +
                white +
                R"(</shape><shape type="rectangle"><transform name="to_world"><scale value="1000"/><translate y="1000" z="-1"/></transform>)" +
                white + "</shape>" + pinhole_camera("0, 1.5, 2", "0, 0, -0.5", W, H, 60));
        const int rays = 8;
        Image img = raster_render(*scene, {{"ao", std::to_string(rays)}, {"ao_ray_length", "1e6"}, {"shadows", "none"}}).image;
        MaskedMean floor = masked_mean(img, [&](int x, int y) { return pixel_view(*scene, x, y).shape == scene->shapes()[0].get(); });
        REQUIRE(floor.pixels > 1000);
        // Each sample's AO is Binomial(rays, 1/2) / rays: the mean over n samples has standard
        // error 0.5 / sqrt(rays n); 4.4 sigma is a two-sided 1e-5 test.
        double mean = floor.mean / 3.0, sigma = 0.5 / std::sqrt(double(rays) * floor.pixels);
        INFO("floor AO " << mean << " +- " << sigma);
        CHECK(std::abs(mean - 0.5) < 4.4 * sigma);
    }
    SECTION("inside a closed box every ray is blocked") {
        Ref<Scene> scene =
            load_scene_xml("raster-ao-box", sky + R"(<shape type="cube"><transform name="to_world"><scale value="2"/></transform>)" +
                                                R"(<bsdf type="twosided">)" + white + "</bsdf></shape>" +
                                                pinhole_camera("0, 0, 1.5", "0, 0, -1", W, H, 70));
        Image img = raster_render(*scene, {{"ao", "4"}, {"ao_ray_length", "100"}, {"shadows", "none"}}).image;
        double max = 0.0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) max = std::max(max, double(max_component(img.rgb_at(x, y))));
        CHECK(max == 0.0);
    }
}

TEST_CASE("raster AO: deterministic, whatever the thread count", "[raster][ao]") {
    Ref<Scene> scene = load_scene(CboxFile, {{"res", "40"}});
    RasterSettings s;
    s.ao = 4;
    RasterIntegrator a(s), b(s);
    RenderOptions one, two;
    one.threads = 1;
    two.threads = 2;
    Image x = a.render(*scene, one).image, y = b.render(*scene, two).image, z = a.render(*scene, two).image;
    bool same = true;
    for (int j = 0; j < x.height(); ++j)
        for (int i = 0; i < x.width(); ++i) same = same && x.rgb_at(i, j) == y.rgb_at(i, j) && x.rgb_at(i, j) == z.rgb_at(i, j);
    CHECK(same);
}

TEST_CASE("raster IBL: SH coefficients of a constant environment, and the SH basis", "[raster][ibl]") {
    // A constant environment L projects onto L_00 = L sqrt(4 pi) alone, and E(n) = pi L exactly.
    Ref<Scene> scene =
        load_scene_xml("raster-ibl-constant", R"(<emitter type="constant"><rgb name="radiance" value="0.5, 1, 2"/></emitter>)" +
                                                  pinhole_camera("0, 0, 1", "0, 0, 0", 8, 8));
    raster::ImageBasedLighting ibl(*scene);
    CHECK(ibl.coefficients()[0].y == Approx(std::sqrt(4.0 * Pi)).epsilon(1e-4));
    for (int i = 1; i < 9; ++i) CHECK(std::abs(ibl.coefficients()[size_t(i)].y) < 1e-3);
    for (Vec3 n : {Vec3(0, 1, 0), glm::normalize(Vec3(1, -2, 0.5f))}) {
        CHECK(ibl.irradiance(n).x == Approx(Pi * 0.5).epsilon(1e-3));
        CHECK(ibl.irradiance(n).z == Approx(Pi * 2.0).epsilon(1e-3));
        // A glossy lookup of a constant environment is the constant, at every roughness.
        // (To 0.5%: the prefiltered maps sum the environment's samples per texel, a few each.)
        for (float alpha : {0.05f, 0.3f, 1.0f}) CHECK(ibl.glossy(n, alpha).y == Approx(1.0f).epsilon(5e-3));
    }
}

TEST_CASE("raster IBL: a diffuse sphere under an environment map agrees with the path tracer at max_depth 2", "[raster][ibl][physics]") {
    // The sphere alone under the sky: at max_depth 2 the path tracer computes its direct
    // environment light exactly (in expectation), the quantity SH irradiance approximates.
    const int W = 96, H = 96;
    Ref<Scene> scene = load_scene_xml(
        "raster-ibl-sphere",
        R"(<emitter type="envmap"><string name="filename" value=")" + Sky +
            R"("/><transform name="to_world"><rotate y="1" angle="60"/></transform><float name="scale" value="0.8"/></emitter>
            <shape type="sphere"><float name="radius" value="0.5"/><bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf></shape>
            <integrator type="path"><integer name="max_depth" value="2"/></integrator>)" +
            pinhole_camera("0, 0.4, 1.8", "0, 0, 0", W, H, 40));
    RenderOptions path_options;
    path_options.spp = 64;
    path_options.aovs = {"variance"};
    RenderResult path = scene->integrator().render(*scene, path_options);
    RenderResult ibl = raster_render(*scene, {{"aa", "4"}, {"tessellation", "256"}});
    auto on_sphere = [&](int x, int y) { return pixel_view(*scene, x, y).shape != nullptr && !pixel_view(*scene, x, y).mixed; };
    MaskedMean p = masked_mean(path.image, on_sphere), r = masked_mean(ibl.image, on_sphere);
    REQUIRE(p.pixels > 2000);
    double relative = (r.mean - p.mean) / p.mean, noise = p.std_error / p.mean;
    INFO("sphere mean: raster (SH irradiance) " << r.mean / 3 << ", path " << p.mean / 3 << " +- " << p.std_error / 3 << " (relative noise "
                                                << 100 * noise << "%); difference " << 100 * relative << "%");
    // The path tracer's side must be precise enough for the 3% criterion to mean something.
    REQUIRE(noise < 0.003);
    CHECK(std::abs(relative) < 0.03);
    // The average-radiance ambient misses the sky's direction: it is further off.
    RenderResult average = raster_render(*scene, {{"aa", "4"}, {"tessellation", "256"}, {"environment_lighting", "average"}});
    MaskedMean a = masked_mean(average.image, on_sphere);
    WARN("sphere mean with the average ambient: " << 100 * (a.mean - p.mean) / p.mean << "% from the path tracer; SH irradiance "
                                                  << 100 * relative << "%");
}

TEST_CASE("raster baked lighting: the Cornell box agrees with its radiosity render and shows colour bleeding", "[raster][baked]") {
    const SceneParameters params = {{"res", "128"}, {"spp", "16"}};
    Ref<Scene> scene = load_scene(CboxFile, params);
    const std::string area = "0.08";
    RenderResult baked = raster_render(*scene, {{"lighting", "baked"}, {"bake_patch_area", area}, {"aa", "16"}});
    // The radiosity render of the same solution, displayed smoothly (vertex-interpolated).
    Properties props("radiosity", SourceLocation{"<test>", 0});
    props.set_float("max_patch_area", std::stod(area));
    props.set_bool("final_gather", false);
    Ref<Integrator> radiosity = create_plugin_as<Integrator>(ObjectKind::Integrator, props);
    RenderOptions options;
    options.spp = 16;
    RenderResult smooth = radiosity->render(*scene, options);
    ImageComparison c = compare_images(baked.image, smooth.image);
    INFO("baked raster against the radiosity render: means "
         << 100 * c.mean_relative_difference.x << "% " << 100 * c.mean_relative_difference.y << "% " << 100 * c.mean_relative_difference.z
         << "%, block MARE " << 100 * c.block_mare << "%");
    for (int k = 0; k < 3; ++k) CHECK(std::abs(c.mean_relative_difference[k]) < 0.01);
    CHECK(c.block_mare < 0.02);

    // Colour bleeding: the floor's red-to-green ratio near the red wall over the same near the
    // green wall. The local model (one light colour, white floor) gives exactly 1; the bake
    // must show the tint as Mitsuba's path-traced reference does.
    auto bleeding = [&](const Image& img) {
        double near_red[3] = {0, 0, 0}, near_green[3] = {0, 0, 0};
        for (int y = 0; y < img.height(); ++y)
            for (int x = 0; x < img.width(); ++x) {
                SurfaceInteraction si;
                Ray ray = scene->sensor().sample_ray(Vec2(x + 0.5f, y + 0.5f), Vec2(0.5f));
                if (!scene->intersect(ray, si) || std::abs(si.p.y + 1.0f) > 1e-3f || si.p.z < 0.4f) continue;
                // Strips along the walls, clear of the pixels that also see the wall.
                double* side = si.p.x < -0.8f && si.p.x > -0.95f ? near_red : si.p.x > 0.8f && si.p.x < 0.95f ? near_green : nullptr;
                if (!side) continue;
                for (int k = 0; k < 3; ++k) side[k] += img.at(x, y, k);
            }
        return (near_red[0] / near_red[1]) / (near_green[0] / near_green[1]);
    };
    RenderResult local = raster_render(*scene, {{"aa", "16"}});
    Ref<Scene> full = load_scene(CboxFile, {{"res", "256"}});
    Image reference = read_image(source_path("scenes/validation/refs/cbox.exr"));
    double b_baked = bleeding(baked.image), b_local = bleeding(local.image);
    scene = full;  // the reference's resolution
    double b_reference = bleeding(reference);
    INFO("floor red/green near the red wall over near the green wall: local " << b_local << ", baked " << b_baked << ", Mitsuba reference "
                                                                              << b_reference);
    CHECK(b_local == Approx(1.0).epsilon(1e-3));
    CHECK(b_reference > 1.2);
    CHECK(std::abs(b_baked / b_reference - 1.0) < 0.1);
}

TEST_CASE("raster baked lighting: the path tracer's bake agrees with radiosity's", "[raster][baked]") {
    // Both estimate the irradiance at the same patches (radiosity at each patch's centre with
    // visibility-sampled form factors, the path tracer with every bounce): the whole-image means
    // agree to within radiosity's own error on the Cornell box (0.3% at these patches, see
    // README) plus the bake's noise (256 paths per patch, ~400 patches: well under 1%).
    Ref<Scene> scene = load_scene(CboxFile, {{"res", "64"}});
    RenderResult by_radiosity = raster_render(*scene, {{"lighting", "baked"}, {"bake_patch_area", "0.08"}});
    RenderResult by_path =
        raster_render(*scene, {{"lighting", "baked"}, {"bake", "path"}, {"bake_patch_area", "0.08"}, {"bake_samples", "256"}});
    ImageComparison c = compare_images(by_path.image, by_radiosity.image);
    INFO("path bake against radiosity bake: means " << 100 * c.mean_relative_difference.x << "% " << 100 * c.mean_relative_difference.y
                                                    << "% " << 100 * c.mean_relative_difference.z << "%, block MARE " << 100 * c.block_mare
                                                    << "%");
    for (int k = 0; k < 3; ++k) CHECK(std::abs(c.mean_relative_difference[k]) < 0.02);
}

TEST_CASE("raster GI options: parsed from the one table, bad values refused", "[raster]") {
    RasterSettings s;
    std::string error;
    CHECK(s.set("ao", "8", error));
    CHECK(s.ao == 8);
    CHECK(s.set("lighting", "baked", error));
    CHECK(s.lighting == RasterSettings::Lighting::Baked);
    CHECK(s.set("bake", "path", error));
    CHECK(s.set("ao_ray_length", "2.5", error));
    CHECK(s.ao_ray_length == 2.5f);
    CHECK(s.set("environment_lighting", "average", error));
    CHECK_FALSE(s.set("ao", "-1", error));
    CHECK_FALSE(s.set("ao_ray_length", "0", error));
    CHECK_THAT(error, Catch::Contains("ao_ray_length must be a number > 0"));
    CHECK_FALSE(s.set("lighting", "global", error));
    CHECK_THAT(error, Catch::Contains("lighting must be one of local baked"));
}

TEST_CASE("raster IBL: the widest prefiltered level is the irradiance over pi, as the path tracer estimates it", "[raster][ibl]") {
    // At roughness 1 the Phong exponent is 1: the normalised lobe max(w.r, 0) / pi averages the
    // environment into E(r) / pi, the irradiance of a surface facing r. The path tracer's
    // irradiance estimator measures E(r) independently (with its standard error); SH irradiance
    // approximates the same quantity.
    Ref<Scene> scene = load_scene_xml("raster-ibl-glossy", R"(<emitter type="envmap"><string name="filename" value=")" + Sky +
                                                               R"("/><float name="scale" value="0.8"/></emitter>)" +
                                                               pinhole_camera("0, 0, 1", "0, 0, 0", 8, 8));
    raster::ImageBasedLighting ibl(*scene);
    EstimatorOptions eo;
    eo.samples = 1 << 18;
    double worst_glossy = 0.0, worst_sh = 0.0;
    for (Vec3 n :
         {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1), glm::normalize(Vec3(1, 1, 1))}) {
        Estimate e = estimate_irradiance(*scene, Vec3(0.0f), n, eo);
        double exact = luminance(e.mean), glossy = Pi * luminance(ibl.glossy(n, 1.0f)), sh = luminance(ibl.irradiance(n));
        INFO("normal " << n.x << " " << n.y << " " << n.z << ": estimate " << exact << " +- " << e.luminance_std_error
                       << ", pi x glossy(1) " << glossy << ", SH " << sh);
        REQUIRE(e.luminance_std_error < 0.002 * exact);
        worst_glossy = std::max(worst_glossy, std::abs(glossy / exact - 1.0));
        worst_sh = std::max(worst_sh, std::abs(sh / exact - 1.0));
    }
    // Nine SH terms cannot follow the sky's sharp horizon: pointwise they are off by up to ~0.1
    // W/m^2 (28% where the irradiance is smallest); reported, not checked (the sphere test above
    // checks what SH irradiance is for: the mean).
    WARN("largest relative difference from the path-traced irradiance: prefiltered (roughness 1) " << 100 * worst_glossy << "%, SH "
                                                                                                   << 100 * worst_sh << "%");
    // The lat-long levels' texels (5.6 degrees) and interpolation, against 0.12% noise.
    CHECK(worst_glossy < 0.03);
}
