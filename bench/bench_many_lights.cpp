// bench_many_lights: how the number of lights affects rendering, per light-selection strategy.
//
//   bench_many_lights [--res N] [--spp N] [--reference-spp N] [--threads N]
//
// For 1, 10, 100 and 1000 lights (a mix of point, spot and small area lights scattered over a
// floor with a few boxes), it renders a reference with the light tree at a high sample count,
// then renders with each strategy (uniform, power, tree) at the same, lower sample count and
// prints the time, the relative MSE against the reference, and time x relMSE (lower is better:
// the cost of reaching a given error). It prints figures and asserts nothing.

#include "analysis/image_metrics.h"
#include "bench/bench_args.h"
#include "core/rng.h"
#include "core/xml.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

using namespace candela;

namespace {

std::string scene_with_lights(int count, int res, const std::string& strategy) {
    PCG32 rng(1234, 7);
    std::string s = "<scene version=\"3.0.0\">\n<default name=\"spp\" value=\"16\"/>\n";
    s += "<integrator type=\"path\"><integer name=\"max_depth\" value=\"4\"/><string name=\"light_sampler\" value=\"" + strategy +
         "\"/></integrator>\n";
    s +=
        "<sensor type=\"perspective\"><float name=\"fov\" value=\"55\"/><transform name=\"to_world\"><lookat origin=\"0, 9, 11\" target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform>"
        "<sampler type=\"independent\"><integer name=\"sample_count\" value=\"$spp\"/></sampler><film type=\"hdrfilm\"><integer name=\"width\" value=\"" +
        std::to_string(res) + "\"/><integer name=\"height\" value=\"" + std::to_string(res) +
        "\"/><rfilter type=\"box\"/></film></sensor>\n";
    s += "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"12\"/><rotate x=\"1\" angle=\"-90\"/></transform>"
         "<bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"0.6\"/></bsdf></shape>\n";
    for (int i = 0; i < 6; ++i) {
        float x = -6 + 12 * rng.next_float(), z = -6 + 12 * rng.next_float(), h = 0.3f + rng.next_float();
        s += "<shape type=\"cube\"><transform name=\"to_world\"><scale x=\"0.7\" y=\"" + std::to_string(h) +
             "\" z=\"0.7\"/><translate x=\"" + std::to_string(x) + "\" y=\"" + std::to_string(h) + "\" z=\"" + std::to_string(z) +
             "\"/></transform></shape>\n";
    }
    // Total emitted power stays about the same whatever the count, so images are comparable.
    float scale = 40.0f / float(count);
    for (int i = 0; i < count; ++i) {
        float x = -6 + 12 * rng.next_float(), y = 0.4f + 3 * rng.next_float(), z = -6 + 12 * rng.next_float();
        float power = scale * (0.2f + 1.8f * rng.next_float());
        std::string pos = std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z);
        if (i % 3 == 0) {
            s += "<emitter type=\"point\"><point name=\"position\" value=\"" + pos + "\"/><rgb name=\"intensity\" value=\"" +
                 std::to_string(power) + "\"/></emitter>\n";
        } else if (i % 3 == 1) {
            s += "<emitter type=\"spot\"><transform name=\"to_world\"><lookat origin=\"" + pos + "\" target=\"" + std::to_string(x) +
                 ", 0, " + std::to_string(z) +
                 "\"/></transform><float name=\"cutoff_angle\" value=\"35\"/><rgb name=\"intensity\" value=\"" + std::to_string(3 * power) +
                 "\"/></emitter>\n";
        } else {
            s +=
                "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"0.15\"/><rotate x=\"1\" angle=\"90\"/><translate value=\"" +
                pos + "\"/></transform><emitter type=\"area\"><rgb name=\"radiance\" value=\"" + std::to_string(power * 15) +
                "\"/></emitter></shape>\n";
        }
    }
    return s + "</scene>\n";
}

const char* const usage =
    "usage: bench_many_lights [--res N] [--spp N] [--reference-spp N] [--threads N]\n"
    "  --res N             width and height of the images (default 128)\n"
    "  --spp N             samples per pixel of each strategy's render (default 16)\n"
    "  --reference-spp N   samples per pixel of the light tree's reference (default 1024)\n"
    "  --threads N         render threads (default 0: all cores)\n";

int run(int argc, char** argv) {
    int res = 128, spp = 16, ref_spp = 1024, threads = 0;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--res")
            res = bench::int_option(argc, argv, i, 1);
        else if (a == "--spp")
            spp = bench::int_option(argc, argv, i, 1);
        else if (a == "--reference-spp")
            ref_spp = bench::int_option(argc, argv, i, 1);
        else if (a == "--threads")
            threads = bench::int_option(argc, argv, i, 0);
        else
            bench::reject_argument(a);
    }
    std::filesystem::path dir = std::filesystem::temp_directory_path() / "candela-bench-many-lights";
    std::filesystem::create_directories(dir);
    std::printf("%d x %d pixels, %d spp per strategy, references at %d spp with the light tree\n\n", res, res, spp, ref_spp);
    std::printf("%7s  %-8s  %9s  %11s  %12s  %14s\n", "lights", "strategy", "time (s)", "Msamples/s", "relMSE", "time x relMSE");
    for (int count : {1, 10, 100, 1000}) {
        auto render = [&](const std::string& strategy, int n) {
            std::string path = (dir / ("lights" + std::to_string(count) + "_" + strategy + ".xml")).string();
            std::ofstream(path) << scene_with_lights(count, res, strategy);
            Ref<Scene> scene = load_scene(path);
            RenderOptions o;
            o.spp = n;
            o.threads = threads;
            return scene->integrator().render(*scene, o);
        };
        RenderResult reference = render("tree", ref_spp);
        for (const char* strategy : {"uniform", "power", "tree"}) {
            RenderResult r = render(strategy, spp);
            ImageComparison c = compare_images(r.image, reference.image);
            std::printf("%7d  %-8s  %9.3f  %11.3f  %12.5f  %14.6f\n", count, strategy, r.stats.seconds,
                        double(r.stats.samples) / r.stats.seconds * 1e-6, c.relmse, c.relmse * r.stats.seconds);
        }
        std::printf("\n");
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
