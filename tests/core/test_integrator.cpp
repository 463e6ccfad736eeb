// The pixel loop: bit-identical results for any thread count, crop windows, and AOVs with the
// variance of the pixel mean.

#include "core/pixel_sums.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>

using namespace candela;
using namespace candela::test;

TEST_CASE("determinism: one command gives a bit-identical image with 1 or 2 threads", "[render][determinism]") {
    auto dir = scratch_dir("determinism");
    // A gaussian filter (samples splat across tile borders) and a size that is not a multiple of
    // the tile size: the hardest case for order-independent accumulation.
    std::string scene = read_text(source_path("scenes/validation/cbox.xml"));
    std::string box = "<rfilter type=\"box\"/>";
    scene.replace(scene.find(box), box.size(), "<rfilter type=\"gaussian\"/>");
    write_text(dir / "cbox_gauss.xml", scene);
    SceneParameters p = {{"res", "70"}, {"spp", "6"}};
    RenderResult one = render_file((dir / "cbox_gauss.xml").string(), p, 1, {"variance", "albedo"});
    RenderResult two = render_file((dir / "cbox_gauss.xml").string(), p, 2, {"variance", "albedo"});
    RenderResult again = render_file((dir / "cbox_gauss.xml").string(), p, 2, {"variance", "albedo"});
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

TEST_CASE("passes: the widest pass sets how often checkpoints come, not the image", "[render][determinism]") {
    // The viewer's progressive render: one call in passes of one sample per pixel, a checkpoint
    // after each (all but the last), each holding the sample indices [0, k) of every pixel.
    Ref<Scene> s = load_scene(source_path("scenes/validation/cbox.xml"), {{"res", "40"}, {"spp", "8"}});
    RenderResult whole = s->integrator().render(*s, RenderOptions());
    RenderOptions narrow;
    narrow.widest_pass = 1;
    narrow.checkpoint_seconds = 1e-9;
    std::vector<int> seen;
    narrow.checkpoint = [&](const PixelSums&, const std::vector<CoverageBox>& coverage) {
        REQUIRE(coverage.size() == 1);
        CHECK(coverage[0].samples.begin == 0);
        seen.push_back(coverage[0].samples.end);
    };
    RenderResult passes = s->integrator().render(*s, narrow);
    CHECK(seen == std::vector<int>{1, 2, 3, 4, 5, 6, 7});
    REQUIRE(passes.image.data().size() == whole.image.data().size());
    CHECK(std::memcmp(passes.image.data().data(), whole.image.data().data(), whole.image.data().size() * sizeof(float)) == 0);
}

TEST_CASE("film: a crop window renders exactly the same pixels as the full film", "[render][film]") {
    auto dir = scratch_dir("crop");
    std::string scene = read_text(source_path("scenes/validation/cbox.xml"));
    std::string anchor = "<rfilter type=\"box\"/>";
    scene.replace(scene.find(anchor), anchor.size(),
                  anchor +
                      "<integer name=\"crop_offset_x\" value=\"10\"/><integer name=\"crop_offset_y\" value=\"20\"/>"
                      "<integer name=\"crop_width\" value=\"30\"/><integer name=\"crop_height\" value=\"17\"/>");
    write_text(dir / "crop.xml", scene);
    SceneParameters p = {{"res", "64"}, {"spp", "4"}};
    RenderResult full = render_file(source_path("scenes/validation/cbox.xml"), p);
    RenderResult crop = render_file((dir / "crop.xml").string(), p);
    REQUIRE(crop.image.width() == 30);
    REQUIRE(crop.image.height() == 17);
    for (int y = 0; y < 17; ++y)
        for (int x = 0; x < 30; ++x) REQUIRE(crop.image.rgb_at(x, y) == full.image.rgb_at(x + 10, y + 20));
}

TEST_CASE("render: AOVs and the variance of the pixel mean", "[render][aov]") {
    RenderResult r = render_file(source_path("scenes/furnace/closed_sphere.xml"), {{"rho", "0.5"}, {"res", "8"}}, 0,
                                 {"albedo", "normal", "depth", "variance"});
    const Image& img = r.image;
    REQUIRE(img.channel_index("albedo.R") == 3);
    REQUIRE(img.channel_index("variance.B") == img.channel_count() - 1);
    int depth = img.channel_index("depth.Z"), nz = img.channel_index("normal.Z"), var = img.channel_index("variance.R");
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            CHECK(img.at(x, y, 3) == Approx(0.5f));      // albedo of the sphere
            CHECK(img.at(x, y, depth) == Approx(1.0f));  // distance to the unit sphere
            CHECK(img.at(x, y, nz) < 0.0f);              // inward normals face the camera
            CHECK(img.at(x, y, var) > 0.0f);
        }
}

TEST_CASE("develop: finite sums whose mean lies beyond float range give the largest float, never infinity", "[render][film]") {
    // A weight sum near zero (negative filter lobes cancelling, or a damaged part file: fuzz_part
    // found one) makes the mean of finite sums larger than any float.
    for (PixelFormat format : {PixelFormat::RGB, PixelFormat::RGBA, PixelFormat::XYZ, PixelFormat::Luminance}) {
        PixelSums sums(ImageRect{Vec2i(0), Vec2i(2, 1)}, SampleLayout(format, {}), AovLayout({"albedo", "variance"}));
        double* huge = sums.filtered_at(0, 0);
        for (int c = 0; c + 1 < sums.stride(); ++c) huge[c] = c == 1 ? -1e30 : 1e30;
        huge[sums.stride() - 1] = 1e-30;  // the weight sum
        PixelStats& stats = sums.stats_at(0, 0);
        stats.n = 2;
        for (int k = 0; k < 3; ++k) {
            stats.albedo[k] = 1e300;
            stats.sum[k] = 3e38;
            stats.sum_sq[k] = 1e300;
        }
        double* plain = sums.filtered_at(1, 0);
        for (int c = 0; c + 1 < sums.stride(); ++c) plain[c] = 0.5;
        plain[sums.stride() - 1] = 1.0;
        const Image image = sums.develop();
        for (float v : image.data()) REQUIRE(std::isfinite(v));
        const float largest = std::numeric_limits<float>::max();
        if (format == PixelFormat::RGB || format == PixelFormat::RGBA) {
            CHECK(image.at(0, 0, 0) == largest);
            CHECK(image.at(0, 0, 1) == -largest);
            CHECK(image.at(1, 0, 0) == 0.5f);  // an ordinary pixel is as before
        }
        CHECK(image.at(0, 0, image.channel_index("albedo.R")) == largest);
        CHECK(image.at(0, 0, image.channel_index("variance.G")) == largest);
    }
}
