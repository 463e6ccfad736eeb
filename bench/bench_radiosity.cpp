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
#include "core/xml.h"
#include "integrators/radiosity.h"

#include <unistd.h>
#include <cstdio>
#include <cstring>
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

std::vector<float> parse_list(const char* text) {
    std::vector<float> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(std::stof(item));
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<float> areas = {0.32f, 0.16f, 0.08f, 0.04f, 0.02f, 0.01f};
    int spp = 64, smooth_spp = 4, threads = 0;
    std::string tolerance = "0.001";
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--areas"))
            areas = parse_list(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--spp"))
            spp = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--smooth-spp"))
            smooth_spp = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--threads"))
            threads = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--tolerance"))
            tolerance = argv[i + 1];
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
