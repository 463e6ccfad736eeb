// bench_samplers: which sampler reaches a given error soonest, on the validation scenes.
//
//   bench_samplers [--dir scenes/validation] [--scenes cbox,glass,...] [--samplers a,b,...]
//                  [--spp 16,64,256] [--threads N]
//
// For every validation scene (NAME.xml with refs/NAME.exr) and every sampler, renders the scene at
// each sample count with that sampler (candela render --sampler) and prints the render time, the
// relMSE against the 2048-spp Mitsuba reference, and relMSE x time: the cost of an error, lower is
// better; its inverse is the efficiency. Samplers that round the count (orthogonal: p^2 for a
// prime p) render the rounded count, which the table shows. Each row is one render: on a shared
// machine compare rows of one run only. It prints figures and asserts nothing.

#include "analysis/image_metrics.h"
#include "analysis/validation.h"
#include "bench/bench_args.h"
#include "core/image.h"
#include "core/integrator.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/xml.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace candela;

namespace {

std::vector<std::string> split(const std::string& text) {
    std::vector<std::string> parts;
    std::stringstream in(text);
    for (std::string part; std::getline(in, part, ',');)
        if (!part.empty()) parts.push_back(part);
    return parts;
}

const char* const usage =
    "usage: bench_samplers [--dir DIR] [--scenes LIST] [--samplers LIST] [--spp LIST] [--threads N]\n"
    "  --dir DIR         the validation scenes, NAME.xml with refs/NAME.exr (default " CANDELA_SOURCE_DIR
    "/scenes/validation)\n"
    "  --scenes LIST     the scenes by name, e.g. cbox,glass (default: all of DIR)\n"
    "  --samplers LIST   sampler plugins (default independent,stratified,multijitter,orthogonal,ldsampler,sobol,zsobol)\n"
    "  --spp LIST        sample counts (default 16,64,256)\n"
    "  --threads N       render threads (default 0: all cores)\n";

int run(int argc, char** argv) {
    std::string dir = std::string(CANDELA_SOURCE_DIR) + "/scenes/validation", scenes,
                samplers = "independent,stratified,multijitter,orthogonal,ldsampler,sobol,zsobol", counts = "16,64,256";
    int threads = 0;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--dir")
            dir = bench::option_value(argc, argv, i);
        else if (a == "--scenes")
            scenes = bench::option_value(argc, argv, i);
        else if (a == "--samplers")
            samplers = bench::option_value(argc, argv, i);
        else if (a == "--spp")
            counts = bench::option_value(argc, argv, i);
        else if (a == "--threads")
            threads = bench::int_option(argc, argv, i, 0);
        else
            bench::reject_argument(a);
    }
    const std::vector<std::string> wanted = split(scenes), sampler_names = split(samplers), spp_texts = split(counts);
    for (const std::string& s : spp_texts) bench::parse_whole("--spp", s.c_str(), 0, INT_MAX);
    std::printf("%-11s  %-12s  %5s  %9s  %12s  %14s\n", "scene", "sampler", "spp", "time (s)", "relMSE", "relMSE x time");
    // Per sampler and requested count: the geometric mean over scenes of relMSE x time relative to
    // the independent sampler's, the summary the default is chosen by.
    std::map<std::string, std::map<int, std::pair<double, int>>> log_ratio;
    for (const ValidationCase& c : find_validation_cases(dir)) {
        if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), c.name) == wanted.end()) continue;
        Ref<Scene> scene = load_scene(c.scene_path);
        Image reference = read_image(c.reference_path);
        for (const std::string& spp_text : spp_texts) {
            const int spp = std::atoi(spp_text.c_str());
            double independent_cost = 0.0;
            for (const std::string& sampler : sampler_names) {
                RenderOptions o;
                o.spp = spp;
                o.sampler = sampler;
                o.threads = threads;
                RenderResult r = scene->integrator().render(*scene, o);
                ImageComparison m = compare_images(r.image, reference);
                double cost = m.relmse * r.stats.seconds;
                std::printf("%-11s  %-12s  %5d  %9.3f  %12.5g  %14.5g\n", c.name.c_str(), sampler.c_str(), r.stats.spp, r.stats.seconds,
                            m.relmse, cost);
                std::fflush(stdout);
                if (sampler == "independent") independent_cost = cost;
                if (independent_cost > 0.0) {
                    auto& entry = log_ratio[sampler][spp];
                    entry.first += std::log(cost / independent_cost);
                    entry.second += 1;
                }
            }
        }
    }
    if (log_ratio.empty()) return 0;
    std::printf("\nrelMSE x time relative to the independent sampler (geometric mean over scenes; below 1 is better)\n%-12s", "sampler");
    for (const std::string& s : spp_texts) std::printf("  %8s spp", s.c_str());
    std::printf("\n");
    for (const std::string& sampler : sampler_names) {
        std::printf("%-12s", sampler.c_str());
        for (const std::string& s : spp_texts) {
            auto& e = log_ratio[sampler][std::atoi(s.c_str())];
            std::printf("  %12.3f", e.second ? std::exp(e.first / e.second) : NAN);
        }
        std::printf("\n");
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
