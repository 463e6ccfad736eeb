// bench_adaptive: does adaptive sampling reach the same error with fewer samples?
//
//   bench_adaptive [--scene scenes/validation/cbox.xml] [--reference scenes/validation/refs/cbox.exr]
//                  [--spp 256] [--uniform 16,32,64,128,256] [--thresholds 0.1,0.05,0.02,0.01]
//                  [--min-spp N] [--step N] [--sampler NAME] [--threads N]
//
// Renders the scene (default: the validation Cornell box, 256 x 256, with its own sampler unless
// --sampler names another) uniformly at each count of --uniform, then adaptively at each
// threshold with at most --spp samples per pixel, and prints per render the mean samples per
// pixel, the relMSE against the reference (Mitsuba 3, 2048 spp) and the render time. For an
// adaptive render it also prints the uniform sample count that reaches the same relMSE (log-log
// interpolation between the uniform renders; outside them, extrapolation at relMSE ~ 1/N) and
// the ratio of its mean samples to that count: below 1 means the same error at fewer samples.
// Times are single runs on a possibly shared machine: compare them within one run only. It
// prints figures and asserts nothing.

#include "analysis/image_metrics.h"
#include "bench/bench_args.h"
#include "core/image.h"
#include "core/integrator.h"
#include "core/scene.h"
#include "core/xml.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace candela;

namespace {

struct Row {
    double spp = 0, relmse = 0, seconds = 0;
    double best_allocation = NAN;  // see optimal_allocation_ratio
};

// What the best allocation of samples to pixels could gain, from a uniform render's per-pixel
// variance AOV: relMSE is sum_i v_i / n_i (v_i: pixel i's per-sample variance over
// (reference^2 + 0.01), summed over channels, as compare_images weighs it), and for a fixed total
// of samples it is least at n_i ~ sqrt(v_i) (a Lagrange multiplier). That allocation reaches
// the uniform relMSE with (mean_i sqrt(v_i))^2 / mean_i v_i of the samples.
double optimal_allocation_ratio(const Image& image, const Image& reference, double spp) {
    const int variance = image.channel_index("variance.R");
    if (variance < 0) return NAN;
    double sum_v = 0, sum_sqrt_v = 0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) {
            double v = 0;
            for (int c = 0; c < 3; ++c) {
                const double r = reference.at(x, y, c);
                v += image.at(x, y, variance + c) * spp / (r * r + 0.01);
            }
            sum_v += v;
            sum_sqrt_v += std::sqrt(v);
        }
    const double pixels = double(image.width()) * image.height();
    return sum_v > 0 ? (sum_sqrt_v / pixels) * (sum_sqrt_v / pixels) / (sum_v / pixels) : NAN;
}

Row render(const Scene& scene, const Image& reference, RenderOptions o) {
    RenderResult r = scene.integrator().render(scene, o);
    const double pixels = double(r.image.width()) * r.image.height();
    Row row{double(r.stats.samples) / pixels, compare_images(r.image, reference).relmse, r.stats.seconds};
    row.best_allocation = optimal_allocation_ratio(r.image, reference, row.spp);
    return row;
}

// The uniform sample count whose relMSE would be `relmse`: piecewise linear in log relMSE over
// log spp between the uniform renders (sorted by spp), and relMSE ~ 1/N beyond them.
double equivalent_uniform_spp(const std::vector<Row>& uniform, double relmse) {
    if (uniform.empty() || !(relmse > 0)) return NAN;
    if (relmse >= uniform.front().relmse) return uniform.front().spp * uniform.front().relmse / relmse;
    for (size_t i = 1; i < uniform.size(); ++i) {
        const Row &a = uniform[i - 1], &b = uniform[i];
        if (relmse >= b.relmse) {
            const double t = std::log(relmse / a.relmse) / std::log(b.relmse / a.relmse);
            return std::exp(std::log(a.spp) + t * std::log(b.spp / a.spp));
        }
    }
    return uniform.back().spp * uniform.back().relmse / relmse;
}

const char* const usage =
    "usage: bench_adaptive [--scene SCENE.xml] [--reference REF.exr] [--spp N] [--uniform LIST] [--thresholds LIST]\n"
    "                      [--min-spp N] [--step N] [--sampler NAME] [--threads N]\n"
    "  --scene SCENE.xml    the scene (default " CANDELA_SOURCE_DIR
    "/scenes/validation/cbox.xml)\n"
    "  --reference REF.exr  its reference image (default " CANDELA_SOURCE_DIR
    "/scenes/validation/refs/cbox.exr)\n"
    "  --spp N              most samples per pixel of an adaptive render (default 256; 0: the scene's sample_count)\n"
    "  --uniform LIST       sample counts of the uniform renders (default 16,32,64,128,256)\n"
    "  --thresholds LIST    thresholds of the adaptive renders (default 0.1,0.05,0.02,0.01)\n"
    "  --min-spp N          adaptive sampling's min_spp (default 0: the renderer's default)\n"
    "  --step N             adaptive sampling's step (default 0: the renderer's default)\n"
    "  --sampler NAME       the sampler plugin (default: the scene's own)\n"
    "  --threads N          render threads (default 0: all cores)\n";

int run(int argc, char** argv) {
    std::string scene_path = std::string(CANDELA_SOURCE_DIR) + "/scenes/validation/cbox.xml";
    std::string reference_path = std::string(CANDELA_SOURCE_DIR) + "/scenes/validation/refs/cbox.exr";
    std::string sampler;
    std::vector<float> uniform_counts = {16, 32, 64, 128, 256}, thresholds = {0.1f, 0.05f, 0.02f, 0.01f};
    int spp = 256, threads = 0, min_spp = 0, step = 0;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--scene")
            scene_path = bench::option_value(argc, argv, i);
        else if (a == "--reference")
            reference_path = bench::option_value(argc, argv, i);
        else if (a == "--spp")
            spp = bench::int_option(argc, argv, i, 0);
        else if (a == "--uniform")
            uniform_counts = bench::number_list(a, bench::option_value(argc, argv, i));
        else if (a == "--thresholds")
            thresholds = bench::number_list(a, bench::option_value(argc, argv, i));
        else if (a == "--min-spp")
            min_spp = bench::int_option(argc, argv, i, 0);
        else if (a == "--step")
            step = bench::int_option(argc, argv, i, 0);
        else if (a == "--sampler")
            sampler = bench::option_value(argc, argv, i);
        else if (a == "--threads")
            threads = bench::int_option(argc, argv, i, 0);
        else
            bench::reject_argument(a);
    }
    Ref<Scene> scene = load_scene(scene_path);
    const Image reference = read_image(reference_path);
    RenderOptions base;
    base.sampler = sampler;
    base.threads = threads;
    std::printf("%s, sampler %s, reference %s\n", scene_path.c_str(), sampler.empty() ? "(the scene's)" : sampler.c_str(),
                reference_path.c_str());
    std::printf("%-9s  %9s  %9s  %12s  %9s  %13s  %13s\n", "mode", "threshold", "mean spp", "relMSE", "time (s)", "uniform spp*",
                "samples ratio");

    std::vector<Row> uniform;
    for (double n : uniform_counts) {
        RenderOptions o = base;
        o.spp = int(n);
        o.aovs = {"variance"};
        uniform.push_back(render(*scene, reference, o));
        const Row& r = uniform.back();
        std::printf("%-9s  %9s  %9.2f  %12.5g  %9.3f\n", "uniform", "-", r.spp, r.relmse, r.seconds);
        std::fflush(stdout);
    }
    for (double t : thresholds) {
        RenderOptions o = base;
        o.spp = spp;
        o.adaptive.threshold = float(t);
        o.adaptive.min_spp = min_spp;
        o.adaptive.step = step;
        const Row r = render(*scene, reference, o);
        const double equivalent = equivalent_uniform_spp(uniform, r.relmse);
        std::printf("%-9s  %9.4g  %9.2f  %12.5g  %9.3f  %13.1f  %13.3f\n", "adaptive", t, r.spp, r.relmse, r.seconds, equivalent,
                    r.spp / equivalent);
        std::fflush(stdout);
    }
    if (!uniform.empty())
        std::printf(
            "\nthe best allocation of samples to pixels (n_i ~ sqrt(v_i), from the %.0f-spp render's variance) would reach uniform's "
            "relMSE with %.3f of the samples\n",
            uniform.back().spp, uniform.back().best_allocation);
    std::printf(
        "\n* the uniform sample count with the same relMSE; samples ratio = mean spp / that count (below 1: fewer samples "
        "for the same error)\n");
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
