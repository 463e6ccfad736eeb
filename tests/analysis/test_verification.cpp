// Verification as a user feature: the furnace suite through `candela converge` (every analytic
// scene within its error bars, log-log slopes in [-0.55, -0.45]), the validation set through
// `candela validate`, and proof that both can fail, for the right reason.

#include "analysis/image_metrics.h"
#include "analysis/statistics.h"
#include "core/image.h"
#include "core/integrator.h"
#include "core/scene.h"
#include "core/warning.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <vector>

using namespace candela;
using namespace candela::test;

namespace {

int converge(const std::string& scene, const std::string& extra, const std::filesystem::path& log, const std::string& spp = "4,16,64,256") {
    return run_command("'" + candela_binary() + "' converge '" + source_path("scenes/furnace/" + scene) + "' --spp " + spp + " " + extra,
                       log);
}

}  // namespace

TEST_CASE("converge: every analytic furnace scene converges to its stated answer", "[verification][furnace]") {
    auto dir = scratch_dir("converge");
    struct Case {
        const char* scene;
        std::string extra;
        std::string spp = "4,16,64,256";
    };
    const Case cases[] = {
        {"closed_sphere.xml", "-D rho=0.5"},
        {"closed_sphere.xml", "-D rho=0.8"},
        {"closed_sphere.xml", "-D rho=0.95", "16,64,256,1024"},  // deep paths, Russian roulette
        {"closed_sphere_truncated.xml", "-D max_depth=2"},
        {"closed_sphere_truncated.xml", "-D max_depth=3"},
        {"closed_sphere_truncated.xml", "-D max_depth=5"},
        {"white_diffuse.xml", ""},
        {"white_dielectric.xml", ""},
        {"white_conductor.xml", ""},
        {"convex_diffuse.xml", ""},
        {"sky_irradiance.xml", ""},
        {"point_irradiance.xml", ""},
        {"medium_sphere.xml", ""},
        {"medium_sphere.xml", "-D integrator=volpathmis"},
    };
    for (const Case& c : cases) {
        int code = converge(c.scene, c.extra, dir / "log.txt", c.spp);
        std::string log = read_text(dir / "log.txt");
        INFO(c.scene << " " << c.extra << "\n" << log);
        CHECK(code == 0);
        CHECK_THAT(log, Catch::Contains("result           PASS"));
    }
}

TEST_CASE("converge: a wrong expected value fails as a significant bias", "[verification]") {
    auto dir = scratch_dir("converge-wrong");
    // 2% off: closed sphere rho 0.5 is 2, claim 2.04.
    int code = converge("closed_sphere.xml", "--expect 2.04 --plot '" + (dir / "plot.svg").string() + "'", dir / "log.txt");
    std::string log = read_text(dir / "log.txt");
    INFO(log);
    CHECK(code == 1);
    CHECK_THAT(log, Catch::Contains("FAIL: bias") && Catch::Contains("is significant"));
    CHECK_THAT(read_text(dir / "plot.svg"), Catch::StartsWith("<svg") && Catch::Contains("ideal N^-1/2"));
    // A biased answer also bends the log-log slope away from -1/2.
    CHECK_THAT(log, Catch::Contains("FAIL: slope"));
    // Bad input: an expression that is not one.
    CHECK(converge("closed_sphere.xml", "", dir / "bad.txt", "4") == 2);
    CHECK_THAT(read_text(dir / "bad.txt"), Catch::Contains("at least two"));
}

TEST_CASE("validate: the validation scenes agree with Mitsuba 3 and the report shows every image", "[verification][validation]") {
    auto dir = scratch_dir("validate");
    auto report = dir / "report.html";
    int code =
        run_command("'" + candela_binary() + "' validate '" + source_path("scenes/validation") + "' --spp 256 -o '" + report.string() + "'",
                    dir / "log.txt");
    std::string log = read_text(dir / "log.txt");
    INFO(log);
    CHECK(code == 0);
    CHECK_THAT(log, Catch::Contains("8 of 8 scenes pass"));
    std::string html = read_text(report);
    CHECK_THAT(html, Catch::StartsWith("<!DOCTYPE html>"));
    // Four embedded images per scene (render, reference, difference, z map), none linked.
    size_t images = 0;
    for (size_t pos = 0; (pos = html.find("src=\"data:image/png;base64,", pos)) != std::string::npos; ++pos) ++images;
    CHECK(images == 4 * 8);
    CHECK(html.find("src=\"http") == std::string::npos);
}

TEST_CASE("validate: the HTML report escapes every scene and file name", "[verification][validation][errors]") {
    // A scene file whose name is markup: in the report it must show as text, never as a tag, an
    // attribute or an entity. The reference differs (other seed, fewer samples), so the scene
    // fails and its reason is printed too.
    auto dir = scratch_dir("validate-escape");
    const std::string name = "<img src=x onerror=\"alert('&amp;')\">";
    std::filesystem::create_directories(dir / "refs");
    write_text(
        dir / (name + ".xml"),
        scene_xml(
            "<integrator type=\"path\"/>\n<sensor type=\"perspective\"><transform name=\"to_world\"><lookat origin=\"0,0,4\" target=\"0,0,0\" up=\"0,1,0\"/></transform>\n"
            "<film type=\"hdrfilm\"><integer name=\"width\" value=\"16\"/><integer name=\"height\" value=\"16\"/></film></sensor>\n"
            "<emitter type=\"constant\"/>\n<shape type=\"sphere\"><bsdf type=\"diffuse\"/></shape>"));
    Image dark = Image::rgb(16, 16);
    write_exr(dark, (dir / "refs" / (name + ".exr")).string(), true);
    auto report = dir / "report.html";
    int code =
        run_command("'" + candela_binary() + "' validate '" + dir.string() + "' --spp 2 -o '" + report.string() + "'", dir / "log.txt");
    INFO(read_text(dir / "log.txt"));
    CHECK(code == 1);  // the black reference disagrees
    std::string html = read_text(report);
    CHECK(html.find("<img src=x") == std::string::npos);
    CHECK(html.find("onerror=\"") == std::string::npos);
    CHECK(html.find("'&amp;'") == std::string::npos);  // the name's entity text is escaped too
    CHECK_THAT(html, Catch::Contains("&lt;img src=x onerror=&quot;alert(&#39;&amp;amp;&#39;)&quot;&gt;"));
    // Every tag in the report is one the report itself writes.
    for (size_t pos = 0; (pos = html.find('<', pos)) != std::string::npos; ++pos) {
        size_t end = html.find_first_of(" >", pos);
        std::string tag = html.substr(pos + 1, end - pos - 1);
        if (!tag.empty() && tag[0] == '/') tag.erase(0, 1);
        INFO(tag);
        CHECK((tag == "!DOCTYPE" || tag == "html" || tag == "head" || tag == "meta" || tag == "title" || tag == "style" || tag == "body" ||
               tag == "h1" || tag == "h2" || tag == "p" || tag == "table" || tag == "tr" || tag == "th" || tag == "td" || tag == "a" ||
               tag == "section" || tag == "span" || tag == "figure" || tag == "figcaption" || tag == "img"));
    }
    // Exactly the four images the report embeds, each an alt text and a data URL, no other attribute.
    size_t images = 0;
    for (size_t pos = 0; (pos = html.find("<img ", pos)) != std::string::npos; ++pos) {
        ++images;
        CHECK(html.compare(pos, 10, "<img alt=\"") == 0);
        const std::string data_url = "\" src=\"data:image/png;base64,";
        CHECK(html.compare(html.find('"', pos + 10), data_url.size(), data_url) == 0);
    }
    CHECK(images == 4);
}

TEST_CASE("validate: a reference scaled by 1.02 or mirrored left-right is a failure with its reason", "[verification]") {
    auto dir = scratch_dir("validate-broken");
    std::filesystem::create_directories(dir / "refs");
    std::filesystem::copy_file(source_path("scenes/validation/cbox.xml"), dir / "cbox.xml");
    std::filesystem::copy_file(source_path("scenes/validation/cbox.xml"), dir / "cbox_mirrored.xml");
    Image ref = read_image(source_path("scenes/validation/refs/cbox.exr"));
    Image scaled = ref, mirrored = ref;
    for (float& v : scaled.data()) v *= 1.02f;
    for (int y = 0; y < ref.height(); ++y)
        for (int x = 0; x < ref.width(); ++x) mirrored.set_rgb(x, y, ref.rgb_at(ref.width() - 1 - x, y));
    write_exr(scaled, (dir / "refs" / "cbox.exr").string(), true);
    write_exr(mirrored, (dir / "refs" / "cbox_mirrored.exr").string(), true);
    int code = run_command(
        "'" + candela_binary() + "' validate '" + dir.string() + "' --spp 64 -o '" + (dir / "report.html").string() + "'", dir / "log.txt");
    std::string log = read_text(dir / "log.txt");
    INFO(log);
    CHECK(code == 1);
    CHECK_THAT(log, Catch::Contains("0 of 2 scenes pass"));
    // Scaled: every channel mean is 2% off. Mirrored: the means are unchanged (a mirror keeps
    // every pixel), but the red and green walls swap, which the block metric sees.
    CHECK_THAT(log, Catch::Matches("(.|\n)*cbox +FAIL.*channel R mean differs by -1\\.9.%(.|\n)*"));
    CHECK_THAT(log, Catch::Matches("(.|\n)*cbox_mirrored +FAIL.*block luminance differs(.|\n)*"));
    CHECK_THAT(read_text(dir / "report.html"), Catch::Contains("class=\"fail\">FAIL"));
}

TEST_CASE("validate: reads the shared set's layout DIR/scenes/NAME.xml with DIR/refs/NAME.exr", "[verification][validation]") {
    auto dir = scratch_dir("validate-scenes-layout");
    std::filesystem::create_directories(dir / "scenes");
    std::filesystem::create_directories(dir / "refs");
    std::filesystem::copy_file(source_path("scenes/validation/cbox.xml"), dir / "scenes" / "cbox.xml");
    std::filesystem::copy_file(source_path("scenes/validation/refs/cbox.exr"), dir / "refs" / "cbox.exr");
    const std::string command =
        "'" + candela_binary() + "' validate '" + dir.string() + "' --spp 64 -o '" + (dir / "report.html").string() + "'";
    int code = run_command(command, dir / "log.txt");
    std::string log = read_text(dir / "log.txt");
    INFO(log);
    CHECK(code == 0);
    CHECK_THAT(log, Catch::Contains("cbox") && Catch::Contains("1 of 1 scenes pass"));
    // The same name in both places is ambiguous: bad input, before anything renders.
    std::filesystem::copy_file(source_path("scenes/validation/cbox.xml"), dir / "cbox.xml");
    CHECK(run_command(command, dir / "both.txt") == 2);
    CHECK_THAT(read_text(dir / "both.txt"), Catch::Contains("cbox.xml is both in the directory and in scenes/"));
}

// The stratified and low-discrepancy samplers on a smooth furnace: a convex diffuse sphere under
// a constant sky, where a path's light sample sees a half-space (a smooth boundary) and its BSDF
// sample a smooth MIS weight. Every sampler must be unbiased (the converge command's Sidak-
// corrected z-tests) and never slower than -1/2; each stratified or low-discrepancy one must be
// significantly faster than -1/2 (its slope plus 2.58 standard errors below -0.5), as theory says
// for a 2D integrand with a smooth discontinuity (-3/4) or none (down to -3/2). A deep-path
// furnace (closed sphere, Russian roulette) checks the bias with every sampler too.
TEST_CASE("converge: every sampler is unbiased, and the low-discrepancy ones converge faster than -1/2 on a smooth furnace",
          "[verification][furnace][sampler]") {
    auto dir = scratch_dir("converge-samplers");
    // 14 runs (7 samplers x 2 scenes) each test their bias at every count: each run gets its share
    // (Sidak) of a 1% family-wise significance, so that this test case as a whole, not each run,
    // fails an unbiased sampler 1% of the time.
    const std::string alpha = " --alpha " + std::to_string(sidak(0.01, 14));
    for (const char* sampler : {"independent", "stratified", "multijitter", "orthogonal", "ldsampler", "sobol", "zsobol"}) {
        const bool low_discrepancy = std::string(sampler) != "independent";
        int code = converge("convex_diffuse.xml", std::string("--threads 2 --sampler ") + sampler + alpha, dir / "log.txt");
        std::string log = read_text(dir / "log.txt");
        INFO(sampler << "\n" << log);
        CHECK(code == 0);
        CHECK_THAT(log, Catch::Contains("result           PASS"));
        if (low_discrepancy) CHECK_THAT(log, Catch::Contains("faster than 1/2  yes"));
        code = converge("closed_sphere.xml", std::string("-D rho=0.5 --threads 2 --sampler ") + sampler + alpha, dir / "log2.txt");
        std::string log2 = read_text(dir / "log2.txt");
        INFO(log2);
        CHECK(code == 0);
        CHECK_THAT(log2, Catch::Contains("result           PASS"));
    }
}

// Adaptive sampling stops pixels early without biasing them: on the convex furnace (every pixel
// has the same answer, so a stopping rule that favoured low or high estimates would show as a
// significant mean error) the bias tests pass at every count while the sample-count map shows
// that pixels stopped. The slope is not judged: at a fixed threshold the error stops falling by
// design.
TEST_CASE("adaptive sampling: no bias, deterministic across thread counts, and a sample-count AOV", "[verification][adaptive]") {
    auto dir = scratch_dir("converge-adaptive");
    int code = converge("convex_diffuse.xml", "--threads 2 --adaptive-threshold 0.05 --adaptive-min-spp 8 --slope-range -2,0",
                        dir / "log.txt", "16,64,256");
    std::string log = read_text(dir / "log.txt");
    INFO(log);
    CHECK(code == 0);
    CHECK_THAT(log, Catch::Contains("result           PASS"));

    Ref<Scene> scene = load_scene(source_path("scenes/validation/cbox.xml"), {{"res", "32"}});
    auto render = [&](int threads) {
        RenderOptions o;
        o.spp = 64;
        o.threads = threads;
        o.aovs = {"samples"};
        o.adaptive.threshold = 0.05f;
        o.adaptive.min_spp = 8;
        return scene->integrator().render(*scene, o);
    };
    RenderResult one = render(1), three = render(3);
    REQUIRE(one.image.data().size() == three.image.data().size());
    CHECK(std::memcmp(one.image.data().data(), three.image.data().data(), one.image.data().size() * sizeof(float)) == 0);
    int channel = one.image.channel_index("samples.N");
    REQUIRE(channel >= 0);
    float fewest = 1e9f, most = 0.0f;
    for (int y = 0; y < one.image.height(); ++y)
        for (int x = 0; x < one.image.width(); ++x) {
            float n = one.image.at(x, y, channel);
            fewest = std::min(fewest, n), most = std::max(most, n);
            CHECK(n >= 8.0f);
            CHECK(n <= 64.0f);
        }
    CHECK(fewest < 64.0f);  // some pixels stopped early
    CHECK(most == 64.0f);   // and some did not
}

namespace {

// `image` averaged over factor x factor blocks: with a box filter, the render of the same view
// at 1/factor of the resolution has this as its expectation (a pixel integrates its area).
Image box_downsample(const Image& image, int factor) {
    Image small = Image::rgb(image.width() / factor, image.height() / factor);
    for (int y = 0; y < small.height(); ++y)
        for (int x = 0; x < small.width(); ++x) {
            Spectrum sum(0.0f);
            for (int j = 0; j < factor; ++j)
                for (int i = 0; i < factor; ++i) sum += image.rgb_at(x * factor + i, y * factor + j);
            small.set_rgb(x, y, sum / float(factor * factor));
        }
    return small;
}

// One-sided paired t statistic of a - b over the seeds (positive: a is larger).
double paired_t(const std::vector<double>& a, const std::vector<double>& b) {
    std::vector<double> d(a.size());
    for (size_t i = 0; i < a.size(); ++i) d[i] = a[i] - b[i];
    const MeanAndError m = mean_and_error(d);
    return m.std_error > 0.0 ? m.mean / m.std_error : (m.mean > 0.0 ? INFINITY : m.mean < 0.0 ? -INFINITY : 0.0);
}

}  // namespace

// The claim for adaptive sampling, tested as stated: on the Cornell box (32 x 32, its
// independent sampler) adaptive sampling at threshold 0.035 with at most 128 spp takes fewer
// samples in total than uniform sampling at 64 spp, while its relMSE against the reference (the
// 2048-spp Mitsuba render averaged over 8 x 8 blocks: 131072 samples per pixel, whose own error
// is negligible here) is not significantly larger; and it converges to the same image: per
// channel, the image mean of the adaptive render does not differ significantly from the uniform
// render's, and agrees with the reference by the validation criterion (each channel's mean
// within 1%, averaged over the seeds). Each seed renders both (the adaptive render's first
// samples of a pixel are the uniform render's, so pairing per seed removes most of the common
// noise); the paired differences over the seeds are judged by Student's t (K - 1 degrees of
// freedom; relMSE over 1024 pixels is near normal across seeds), 4 tests (relMSE one-sided, 3
// channel means two-sided) at a family-wise 1% (Sidak). A rule that stops the noisy pixels
// instead of the quiet ones fails it (planted: 0.29 of the samples at 4x the relMSE, p 2e-5), and
// so does one that also stops a pixel whose estimate came out 10% below its left neighbour's
// (planted: channel means t -5.9 to -7.5 against the uniform render's, 2.9% below the reference).
// Deterministic: fixed seeds, and the renders do not depend on the thread count.
TEST_CASE("adaptive sampling: the uniform render's error at fewer samples on the Cornell box, converging to the same image",
          "[verification][adaptive]") {
    Ref<Scene> scene = load_scene(source_path("scenes/validation/cbox.xml"), {{"res", "32"}});
    const Image reference = box_downsample(read_image(source_path("scenes/validation/refs/cbox.exr")), 8);
    const int seeds = effort_scaled(8, 4);
    const double alpha = sidak(0.01, 4);
    std::vector<double> relmse_uniform, relmse_adaptive, mean_difference[3], reference_difference[3];
    uint64_t samples_uniform = 0, samples_adaptive = 0;
    for (int k = 0; k < seeds; ++k) {
        RenderOptions o;
        o.seed = uint64_t(1000 + k);
        o.threads = 2;
        o.spp = 64;
        RenderResult uniform = scene->integrator().render(*scene, o);
        o.spp = 128;
        o.adaptive.threshold = 0.035f;
        RenderResult adaptive = scene->integrator().render(*scene, o);
        samples_uniform += uniform.stats.samples;
        samples_adaptive += adaptive.stats.samples;
        const ImageComparison u = compare_images(uniform.image, reference), a = compare_images(adaptive.image, reference);
        relmse_uniform.push_back(u.relmse);
        relmse_adaptive.push_back(a.relmse);
        for (int c = 0; c < 3; ++c) {
            mean_difference[c].push_back(double(a.mean_test[c]) - double(u.mean_test[c]));
            reference_difference[c].push_back(a.mean_relative_difference[c]);
        }
    }
    const double dof = seeds - 1;
    const double t_relmse = paired_t(relmse_adaptive, relmse_uniform);
    const double p_relmse = t_relmse > 0.0 ? student_t_two_sided_p(t_relmse, dof) / 2.0 : 1.0;
    INFO("samples: adaptive " << samples_adaptive << ", uniform " << samples_uniform << " (" << double(samples_adaptive) / samples_uniform
                              << ")");
    INFO("relMSE: adaptive " << mean_and_error(relmse_adaptive).mean << ", uniform " << mean_and_error(relmse_uniform).mean << ", t "
                             << t_relmse << ", one-sided p " << p_relmse << ", per-test alpha " << alpha);
    CHECK(samples_adaptive < samples_uniform);
    CHECK(p_relmse >= alpha);
    for (int c = 0; c < 3; ++c) {
        const std::vector<double> zero(mean_difference[c].size(), 0.0);
        const double t = paired_t(mean_difference[c], zero);
        INFO("channel " << c << ": mean difference " << mean_and_error(mean_difference[c]).mean << ", t " << t);
        CHECK(student_t_two_sided_p(t, dof) >= alpha);
        // And against Mitsuba's reference by the validation criterion (scenes/validation/README.md).
        const double relative = mean_and_error(reference_difference[c]).mean;
        INFO("channel " << c << ": mean relative difference to the reference " << relative);
        CHECK(std::abs(relative) <= 0.01);
    }
}

// Adaptive sampling with a sampler whose strata cover a pixel only with all its samples says so
// (bench_adaptive: with `stratified` it needed more samples than uniform for the same error);
// with the independent and Sobol samplers it does not.
TEST_CASE("adaptive sampling warns with samplers stratified only as a whole", "[verification][adaptive]") {
    Ref<Scene> scene = load_scene(source_path("scenes/validation/cbox.xml"), {{"res", "8"}});
    for (const char* sampler : {"stratified", "multijitter", "orthogonal", "ldsampler", "independent", "sobol"}) {
        INFO(sampler);
        std::vector<std::string> warnings;
        WarningSink previous = set_warning_sink([&](const std::string& w) { warnings.push_back(w); });
        RenderOptions o;
        o.spp = 16;
        o.sampler = sampler;
        o.adaptive.threshold = 0.05f;
        o.adaptive.min_spp = 4;
        scene->integrator().render(*scene, o);
        set_warning_sink(previous);
        bool warned = false;
        for (const std::string& w : warnings) warned |= w.find("lose the stratification") != std::string::npos;
        const bool whole = std::string(sampler) != "independent" && std::string(sampler) != "sobol";
        CHECK(warned == whole);
    }
}
