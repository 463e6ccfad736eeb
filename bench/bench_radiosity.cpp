// bench_radiosity: the radiosity integrator's error against the Mitsuba reference of the
// validation Cornell box as patches shrink, with its cost.
//
//   bench_radiosity [--areas 0.32,0.16,...] [--spp N] [--smooth-spp N] [--threads N] [--tolerance T]
//
// For each max_patch_area it renders scenes/validation/cbox.xml (256 x 256) with the radiosity
// integrator, once displayed smoothly and once through the final gather (which reads the first
// render's solution file instead of solving again), and prints the patch count, shots, the
// unshot fraction left, the solve time, each render's total time, the worst channel's
// whole-image mean difference and the 16x16 block MARE (the criteria of
// scenes/validation/README.md). It prints figures and asserts nothing.

#include "analysis/image_metrics.h"
#include "bench/bench_args.h"
#include "core/xml.h"
#include "integrators/radiosity.h"

#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

using namespace candela;

namespace {

std::string read_file(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

const char* const usage =
    "usage: bench_radiosity [--areas LIST] [--spp N] [--smooth-spp N] [--threads N] [--tolerance T]\n"
    "  --areas LIST     max_patch_area of each row (default 0.32,0.16,0.08,0.04,0.02,0.01)\n"
    "  --spp N          samples per pixel of the final gather render (default 64)\n"
    "  --smooth-spp N   samples per pixel of the smooth display render (default 4)\n"
    "  --threads N      render threads (default 0: all cores)\n"
    "  --tolerance T    the radiosity integrator's tolerance (default 0.001)\n";

int run(int argc, char** argv) {
    std::vector<float> areas = {0.32f, 0.16f, 0.08f, 0.04f, 0.02f, 0.01f};
    int spp = 64, smooth_spp = 4, threads = 0;
    std::string tolerance = "0.001";
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--areas")
            areas = bench::number_list(a, bench::option_value(argc, argv, i));
        else if (a == "--spp")
            spp = bench::int_option(argc, argv, i, 1);
        else if (a == "--smooth-spp")
            smooth_spp = bench::int_option(argc, argv, i, 1);
        else if (a == "--threads")
            threads = bench::int_option(argc, argv, i, 0);
        else if (a == "--tolerance")
            tolerance = bench::option_value(argc, argv, i);
        else
            bench::reject_argument(a);
    }
    const std::string dir = std::string(CANDELA_SOURCE_DIR) + "/scenes/validation/";
    std::string scene = read_file(dir + "cbox.xml");
    const std::string path = "<integrator type=\"path\">\n        <integer name=\"max_depth\" value=\"-1\"/>\n    </integrator>";
    size_t at = scene.find(path);
    if (at == std::string::npos) {
        std::fprintf(stderr, "cbox.xml no longer has the expected integrator\n");
        return 1;
    }
    scene.replace(
        at, path.size(),
        "<integrator type=\"radiosity\"><float name=\"max_patch_area\" value=\"$area\"/><boolean name=\"final_gather\" value=\"$gather\"/>"
        "<float name=\"tolerance\" value=\"" +
            tolerance + "\"/><string name=\"solution\" value=\"$solution\"/></integrator>");
    const std::string solution =
        (std::filesystem::temp_directory_path() / ("bench_radiosity_" + std::to_string(::getpid()) + ".bin")).string();
    Image reference = read_image(dir + "refs/cbox.exr");

    std::printf("radiosity on the validation Cornell box (256 x 256), against Mitsuba 3 at 2048 spp; tolerance %s\n", tolerance.c_str());
    std::printf("%-8s %-7s %8s %7s %9s %8s %9s %10s %10s\n", "area", "display", "patches", "shots", "unshot", "solve s", "total s",
                "mean diff", "block MARE");
    for (float area : areas) {
        double solve_seconds = 0.0;
        std::filesystem::remove(solution);
        for (bool gather : {false, true}) {
            SceneParameters p = {{"area", std::to_string(area)}, {"gather", gather ? "true" : "false"}, {"solution", solution}};
            Ref<Scene> s = load_scene_from_string(scene, dir + "cbox_radiosity.xml", p);
            RenderOptions options;
            options.spp = gather ? spp : smooth_spp;
            options.threads = threads;
            RenderResult r = s->integrator().render(*s, options);
            const RadiosityStats& st = *radiosity_stats(s->integrator());
            if (!gather) solve_seconds = st.seconds;
            ImageComparison c = compare_images(r.image, reference);
            float worst_mean = 0.0f;
            for (int k = 0; k < 3; ++k) worst_mean = std::max(worst_mean, std::abs(c.mean_relative_difference[k]));
            std::printf("%-8.4g %-7s %8zu %7d %8.2g%% %8.2f %9.2f %9.2f%% %9.2f%%\n", double(area), gather ? "gather" : "smooth",
                        st.patches, st.shots, 100.0 * st.unshot_fraction, solve_seconds, r.stats.seconds, 100.0 * worst_mean,
                        100.0 * c.block_mare);
            std::fflush(stdout);
        }
    }
    std::filesystem::remove(solution);
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
