// bench_media: throughput of volumetric path tracing.
//
//   bench_media [--threads N] [--spp N]
//
// Renders (1) a scene standing in homogeneous fog and (2) a mostly empty heterogeneous volume (a
// dense blob filling a few percent of a 64^3 grid) with volpath and volpathmis, and reports
// camera samples per second. The heterogeneous scene is rendered twice: with the majorant grid
// (majorant_resolution_factor 8, the default) and with one global majorant (0), and the ratio
// of their rates is the gain of the grid. It also times shadow-ray transmittance (ratio tracking)
// alone through the volume with both majorants. It prints figures and asserts nothing.

#include "bench/bench_args.h"
#include "core/medium.h"
#include "core/scene.h"
#include "core/xml.h"
#include "tests/support/vol_writer.h"

#include <unistd.h>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

using namespace candela;

namespace {

std::string scene_text(const std::string& integrator, const std::string& media, int spp) {
    return R"(<scene version="3.0.0"><integrator type=")" + integrator + R"("/>)" + media + R"(
        <sensor type="perspective"><float name="fov" value="45"/>SENSOR_MEDIUM
            <transform name="to_world"><lookat origin="0, 1.5, 4" target="0, 0.5, 0" up="0, 1, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="64"/><rfilter type="box"/></film>
            <sampler type="independent"><integer name="sample_count" value=")" +
           std::to_string(spp) + R"("/></sampler></sensor>
        <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
            <bsdf type="diffuse"/></shape>
        <shape type="sphere"><point name="center" value="0.6, 0.5, 0"/><float name="radius" value="0.4"/></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="2.5"/></transform>
            <emitter type="area"><rgb name="radiance" value="10"/></emitter></shape></scene>)";
}

struct Rate {
    double samples_per_second = 0.0, seconds = 0.0;
};

Rate render(const std::filesystem::path& dir, const std::string& xml, int threads) {
    std::ofstream(dir / "scene.xml") << xml;
    Ref<Scene> scene = load_scene((dir / "scene.xml").string());
    RenderOptions options;
    options.threads = threads;
    RenderResult r = scene->integrator().render(*scene, options);
    return Rate{double(r.stats.samples) / r.stats.seconds, r.stats.seconds};
}

std::string replace(std::string s, const std::string& what, const std::string& with) {
    size_t at = s.find(what);
    if (at != std::string::npos) s.replace(at, what.size(), with);
    return s;
}

const char* const usage =
    "usage: bench_media [--threads N] [--spp N]\n"
    "  --threads N   render threads (default 0: all cores)\n"
    "  --spp N       samples per pixel of each 64 x 64 render (default 16)\n";

int run(int argc, char** argv) {
    int threads = 0, spp = 16;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--threads")
            threads = bench::int_option(argc, argv, i, 0);
        else if (a == "--spp")
            spp = bench::int_option(argc, argv, i, 1);
        else
            bench::reject_argument(a);
    }
    auto dir = std::filesystem::temp_directory_path() / ("bench_media_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);

    // A 64^3 grid, empty but for a ball of radius 8 voxels (about 1% of the volume) of density 40.
    const int n = 64;
    std::vector<float> density(size_t(n) * n * n, 0.0f);
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                float dx = x - 40.5f, dy = y - 20.5f, dz = z - 32.5f;
                if (dx * dx + dy * dy + dz * dz < 64.0f) density[(size_t(z) * n + y) * n + x] = 40.0f;
            }
    write_vol(dir / "blob.vol", glm::ivec3(n), 1, density);

    const std::string fog =
        R"(<medium type="homogeneous" id="fog"><float name="sigma_t" value="0.3"/><float name="albedo" value="0.8"/></medium>)";
    auto smoke = [](int factor) {
        return R"(<medium type="heterogeneous" id="smoke"><float name="albedo" value="0.9"/>
            <integer name="majorant_resolution_factor" value=")" +
               std::to_string(factor) + R"("/>
            <volume type="gridvolume" name="sigma_t"><string name="filename" value="blob.vol"/>
                <transform name="to_world"><scale value="2"/><translate x="-1" y="0.01" z="-1"/></transform></volume></medium>
            <shape type="cube"><transform name="to_world"><translate x="0" y="1.01" z="0"/></transform>
                <bsdf type="null"/><ref name="interior" id="smoke"/></shape>)";
    };
    std::printf("bench_media: 64 x 64 pixels, %d spp, %s threads\n", spp, threads ? std::to_string(threads).c_str() : "all");
    for (const char* integrator : {"volpath", "volpathmis"}) {
        Rate homogeneous = render(dir, replace(scene_text(integrator, fog, spp), "SENSOR_MEDIUM", "<ref id=\"fog\"/>"), threads);
        Rate grid = render(dir, replace(scene_text(integrator, smoke(8), spp), "SENSOR_MEDIUM", ""), threads);
        Rate global = render(dir, replace(scene_text(integrator, smoke(0), spp), "SENSOR_MEDIUM", ""), threads);
        std::printf("%-10s homogeneous fog:          %10.0f samples/s\n", integrator, homogeneous.samples_per_second);
        std::printf("%-10s heterogeneous, grid:      %10.0f samples/s\n", integrator, grid.samples_per_second);
        std::printf("%-10s heterogeneous, global:    %10.0f samples/s   (majorant grid gain %.2fx)\n", integrator,
                    global.samples_per_second, grid.samples_per_second / global.samples_per_second);
    }

    // Ratio tracking alone, through the volume along random rays.
    for (int factor : {8, 0}) {
        std::ofstream(dir / "scene.xml") << "<scene version=\"3.0.0\">" + smoke(factor) + "</scene>";
        Ref<Scene> scene = load_scene((dir / "scene.xml").string());
        const Medium& medium = *scene->shapes()[0]->interior();
        PCG32 rng(1, 2);
        const int rays = 200000;
        double sum = 0.0;
        auto start = std::chrono::steady_clock::now();
        for (int i = 0; i < rays; ++i) {
            Vec3 o(-2.0f, 0.2f + 1.6f * rng.next_float(), -0.8f + 1.6f * rng.next_float());
            Vec3 target(2.0f, 0.2f + 1.6f * rng.next_float(), -0.8f + 1.6f * rng.next_float());
            Ray ray(o, glm::normalize(target - o));
            sum += ratio_tracking_transmittance(medium, ray, glm::length(target - o), rng).x;
        }
        double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("ratio tracking, %s: %10.0f shadow rays/s (mean transmittance %.4f)\n", factor ? "majorant grid" : "global majorant",
                    rays / seconds, sum / rays);
    }
    std::filesystem::remove_all(dir);
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
