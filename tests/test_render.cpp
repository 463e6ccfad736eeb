// Rendering end to end: the analytic furnace (with error bars from the render itself), scale
// robustness of ray offsets, bit-identical results for any thread count, crop windows, and the
// Cornell box against Mitsuba 3's reference.

#include "core/image_metrics.h"
#include "core/ray.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstring>

using namespace candela;
using namespace candela::test;

namespace {

RenderResult render(const std::string& scene_path, const SceneParameters& params, int threads = 0, std::vector<std::string> aovs = {}) {
    Ref<Scene> scene = load_scene(scene_path, params);
    RenderOptions options;
    options.threads = threads;
    options.aovs = std::move(aovs);
    return scene->integrator().render(*scene, options);
}

// Every pixel of a furnace has the same expectation and (box filter) independent samples: the
// pixel values are i.i.d., so their mean has a standard error computed from their spread.
MeanAndError pixel_mean(const Image& img, int channel) {
    std::vector<double> v;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) v.push_back(img.at(x, y, channel));
    return mean_and_error(v);
}

constexpr int FurnaceTests = 10;  // the z-tests below share a 1% family-wise level (Sidak)

void check_furnace(double rho, int max_depth, double expected, const SceneParameters& extra = {}) {
    SceneParameters p = {{"rho", std::to_string(rho)}, {"max_depth", std::to_string(max_depth)}, {"Le", "1"}};
    for (auto& [k, v] : extra) p[k] = v;
    RenderResult r = render(source_path("scenes/furnace/closed_sphere.xml"), p);
    MeanAndError m = pixel_mean(r.image, 0);
    double z = two_sided_z(sidak(0.01, FurnaceTests));
    INFO("rho " << rho << " max_depth " << max_depth << ": mean " << m.mean << " +- " << m.std_error << " expected " << expected
                << " (z threshold " << z << ")");
    // Beyond the noise, two systematic effects of float32 arithmetic: ray offsets move path
    // vertices by up to OffsetSafety * sqrt(3) * gamma_7 of their magnitude at each end of a
    // segment, and accumulation rounds at about 1e-6. They matter only where the estimator has
    // (next to) no variance, as at max_depth 1 and 2 here.
    const double systematic = 2.0 * OffsetSafety * std::sqrt(3.0) * gamma_bound(7) + 1e-6;
    CHECK(std::abs(m.mean - expected) <= z * m.std_error + systematic * expected);
    CHECK(m.std_error < 0.01 * expected);  // the test has power: errors of 1% and more would show
    CHECK(r.stats.nonfinite == 0);
}

}  // namespace

TEST_CASE("furnace: a closed emitting diffuse sphere renders Le / (1 - rho)", "[render][furnace]") {
    check_furnace(0.5, -1, 2.0);
    check_furnace(0.9, -1, 10.0, {{"spp", "256"}});
}

TEST_CASE("furnace: max_depth truncates the path sum (Mitsuba semantics)", "[render][furnace]") {
    check_furnace(0.5, 3, 1.0 + 0.5 + 0.25);  // emitters seen directly, one and two bounces
    check_furnace(0.8, 1, 1.0);               // only emitters seen directly
    check_furnace(0.8, 2, 1.8);               // direct illumination
}

TEST_CASE("furnace: ray offsets hold when the scene is scaled by 1000 or by 1/1000", "[render][furnace]") {
    check_furnace(0.5, -1, 2.0, {{"radius", "1000"}});
    check_furnace(0.5, -1, 2.0, {{"radius", "0.001"}, {"near_clip", "1e-5"}});
}

TEST_CASE("furnace: lossless BSDFs under a uniform environment render exactly 1", "[render][furnace]") {
    for (const char* name : {"white_diffuse", "white_dielectric", "white_conductor"}) {
        RenderResult r = render(source_path(std::string("scenes/furnace/") + name + ".xml"), {});
        MeanAndError m = pixel_mean(r.image, 1);
        double z = two_sided_z(sidak(0.01, FurnaceTests));
        INFO(name << ": mean " << m.mean << " +- " << m.std_error);
        const double systematic = 2.0 * OffsetSafety * std::sqrt(3.0) * gamma_bound(7) + 1e-6;
        CHECK(std::abs(m.mean - 1.0) <= z * m.std_error + systematic);
        CHECK(m.std_error < 0.01);
        CHECK(r.stats.nonfinite == 0);
    }
}

TEST_CASE("determinism: one command gives a bit-identical image with 1 or 2 threads", "[render][determinism]") {
    auto dir = scratch_dir("determinism");
    // A gaussian filter (samples splat across tile borders) and a size that is not a multiple of
    // the tile size: the hardest case for order-independent accumulation.
    std::string scene = read_text(source_path("scenes/validation/cbox.xml"));
    std::string box = "<rfilter type=\"box\"/>";
    scene.replace(scene.find(box), box.size(), "<rfilter type=\"gaussian\"/>");
    write_text(dir / "cbox_gauss.xml", scene);
    SceneParameters p = {{"res", "70"}, {"spp", "6"}};
    RenderResult one = render((dir / "cbox_gauss.xml").string(), p, 1, {"variance", "albedo"});
    RenderResult two = render((dir / "cbox_gauss.xml").string(), p, 2, {"variance", "albedo"});
    RenderResult again = render((dir / "cbox_gauss.xml").string(), p, 2, {"variance", "albedo"});
    REQUIRE(one.image.data().size() == two.image.data().size());
    CHECK(std::memcmp(one.image.data().data(), two.image.data().data(), one.image.data().size() * sizeof(float)) == 0);
    CHECK(std::memcmp(two.image.data().data(), again.image.data().data(), two.image.data().size() * sizeof(float)) == 0);
    // A different seed gives a different image.
    Ref<Scene> s = load_scene((dir / "cbox_gauss.xml").string(), p);
    RenderOptions o;
    o.seed = 99;
    RenderResult other = s->integrator().render(*s, o);
    CHECK(std::memcmp(one.image.data().data(), other.image.data().data(), 3 * sizeof(float) * 70 * 70) != 0);
}

TEST_CASE("film: a crop window renders exactly the same pixels as the full film", "[render][film]") {
    auto dir = scratch_dir("crop");
    std::string scene = read_text(source_path("scenes/validation/cbox.xml"));
    std::string anchor = "<rfilter type=\"box\"/>";
    scene.replace(scene.find(anchor), anchor.size(),
                  anchor + "<integer name=\"crop_offset_x\" value=\"10\"/><integer name=\"crop_offset_y\" value=\"20\"/>"
                           "<integer name=\"crop_width\" value=\"30\"/><integer name=\"crop_height\" value=\"17\"/>");
    write_text(dir / "crop.xml", scene);
    SceneParameters p = {{"res", "64"}, {"spp", "4"}};
    RenderResult full = render(source_path("scenes/validation/cbox.xml"), p);
    RenderResult crop = render((dir / "crop.xml").string(), p);
    REQUIRE(crop.image.width() == 30);
    REQUIRE(crop.image.height() == 17);
    for (int y = 0; y < 17; ++y)
        for (int x = 0; x < 30; ++x) REQUIRE(crop.image.rgb_at(x, y) == full.image.rgb_at(x + 10, y + 20));
}

TEST_CASE("render: AOVs and the variance of the pixel mean", "[render][aov]") {
    RenderResult r = render(source_path("scenes/furnace/closed_sphere.xml"), {{"rho", "0.5"}, {"res", "8"}}, 0,
                            {"albedo", "normal", "depth", "variance"});
    const Image& img = r.image;
    REQUIRE(img.channel_index("albedo.R") == 3);
    REQUIRE(img.channel_index("variance.B") == img.channel_count() - 1);
    int depth = img.channel_index("depth.Z"), nz = img.channel_index("normal.Z"), var = img.channel_index("variance.R");
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            CHECK(img.at(x, y, 3) == Approx(0.5f));         // albedo of the sphere
            CHECK(img.at(x, y, depth) == Approx(1.0f));     // distance to the unit sphere
            CHECK(img.at(x, y, nz) < 0.0f);                 // inward normals face the camera
            CHECK(img.at(x, y, var) > 0.0f);
        }
}
