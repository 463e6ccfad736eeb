// bench_raster: frame times of the rasterized local-illumination mode.
//
//   bench_raster [--res N] [--frames N] [--threads N] [--quick]
//
// Reports frames per second at 1024 x 1024 (by default) for the Cornell box and for a mesh of
// about a million triangles; the time against the number of lights (1, 10, 100) for each
// shading mode; and shadow maps against shadow volumes. Geometry is tessellated once per scene;
// everything else (shadow maps, shadow volumes, shading) is redone every frame. It prints
// figures and asserts nothing.
// --quick (under a minute on two cores): 256 x 256, 20 frames, only the Cornell box with each
// kind of shadow, and the light counts 1 and 10 on a sphere of about 100 000 triangles.
// Both end with the approximations of global illumination: ambient occlusion, image-based
// lighting and baked lighting, each with its one-off cost (the first frame) and frame time.

#include "bench/bench_args.h"
#include "core/rng.h"
#include "core/xml.h"
#include "integrators/raster/raster.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

using namespace candela;

namespace {

int g_res = 1024, g_frames = 5, g_threads = 0;
bool g_quick = false;

double seconds_per_frame(const Ref<Scene>& scene, RasterSettings s) {
    RasterIntegrator raster(s);
    RenderOptions o;
    o.threads = g_threads;
    raster.render(*scene, o);  // tessellate and warm up
    auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < g_frames; ++i) raster.render(*scene, o);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / g_frames;
}

std::string film() {
    return "<film type=\"hdrfilm\"><integer name=\"width\" value=\"" + std::to_string(g_res) + "\"/><integer name=\"height\" value=\"" +
           std::to_string(g_res) + "\"/></film>";
}

Ref<Scene> load_text(const std::string& name, const std::string& xml) {
    auto path = std::filesystem::temp_directory_path() / ("candela-bench-raster-" + name + ".xml");
    std::ofstream(path) << xml;
    return load_scene(path.string());
}

// A sphere of about a million triangles (tessellation 1000 gives 1000 x 500 quads) on a floor,
// with `lights` point lights.
Ref<Scene> big_mesh_scene(int lights) {
    std::string s =
        "<scene version=\"3.0.0\"><sensor type=\"perspective\"><float name=\"fov\" value=\"45\"/><transform name=\"to_world\"><lookat origin=\"0, 2, 5\" "
        "target=\"0, 0.8, 0\" up=\"0, 1, 0\"/></transform>" +
        film() +
        "</sensor><shape type=\"sphere\"><point name=\"center\" x=\"0\" y=\"1\" z=\"0\"/><bsdf type=\"roughplastic\"/></shape>"
        "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"4\"/><rotate x=\"1\" angle=\"-90\"/></transform></shape>";
    PCG32 rng(7, 1);
    for (int i = 0; i < lights; ++i)
        s += "<emitter type=\"point\"><point name=\"position\" x=\"" + std::to_string(6 * rng.next_float() - 3) + "\" y=\"" +
             std::to_string(2.5f + rng.next_float()) + "\" z=\"" + std::to_string(6 * rng.next_float() - 3) +
             "\"/><rgb name=\"intensity\" value=\"" + std::to_string(10.0 / lights) + "\"/></emitter>";
    return load_text("mesh" + std::to_string(lights), s + "</scene>");
}

// The approximations of global illumination: the one-off cost (image-based lighting built, or
// lighting baked) and the frame time after it, on the Cornell box and the environment-map
// validation scene.
void global_illumination_table() {
    Ref<Scene> cbox = load_scene(std::string(CANDELA_SOURCE_DIR) + "/scenes/validation/cbox.xml", {{"res", std::to_string(g_res)}});
    Ref<Scene> env = load_scene(std::string(CANDELA_SOURCE_DIR) + "/scenes/validation/envmap.xml", {{"res", std::to_string(g_res)}});
    std::printf("\napproximations of global illumination (phong, shadow maps), ms\n");
    std::printf("%-40s %12s %10s\n", "scene / configuration", "first frame", "ms/frame");
    auto row = [](const char* what, const Ref<Scene>& scene, const std::map<std::string, std::string>& options) {
        RasterSettings s;
        std::string error;
        for (const auto& [name, value] : options) s.set(name, value, error);
        RasterIntegrator raster(s);
        RenderOptions o;
        o.threads = g_threads;
        auto t0 = std::chrono::steady_clock::now();
        raster.render(*scene, o);
        double first = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("%-40s %12.1f %10.1f\n", what, 1000 * first, 1000 * seconds_per_frame(scene, s));
    };
    row("envmap, average ambient", env, {{"environment_lighting", "average"}});
    row("envmap, image-based lighting", env, {});
    row("envmap, image-based lighting, ao 4", env, {{"ao", "4"}});
    row("envmap, image-based lighting, ao 16", env, {{"ao", "16"}});
    row("cbox, local", cbox, {});
    row("cbox, baked by radiosity", cbox, {{"lighting", "baked"}});
    row("cbox, baked by path (256 paths/patch)", cbox, {{"lighting", "baked"}, {"bake", "path"}});
}

}  // namespace

// The quick mode: the Cornell box with no shadows, shadow maps and shadow volumes, then the
// shading modes against 1 and 10 lights on a sphere of about 100 000 triangles.
void quick(const Ref<Scene>& cbox) {
    std::printf("%d x %d pixels, %d frames each, 1 sample per pixel, phong unless noted\n\n", g_res, g_res, g_frames);
    std::printf("%-34s %10s %10s %10s\n", "cbox, ms/frame", "none", "maps", "volumes");
    double t[3];
    int k = 0;
    for (auto shadows : {RasterSettings::Shadows::None, RasterSettings::Shadows::Map, RasterSettings::Shadows::Volume}) {
        RasterSettings r;
        r.shadows = shadows;
        t[k++] = seconds_per_frame(cbox, r);
    }
    std::printf("%-34s %10.2f %10.2f %10.2f\n", "", 1000 * t[0], 1000 * t[1], 1000 * t[2]);
    std::printf("\ntime against the number of point lights (100k-triangle sphere, no shadows), ms/frame\n");
    std::printf("%-10s %10s %10s %10s\n", "lights", "flat", "gouraud", "phong");
    for (int lights : {1, 10}) {
        Ref<Scene> s = big_mesh_scene(lights);
        k = 0;
        for (auto shading : {RasterSettings::Shading::Flat, RasterSettings::Shading::Gouraud, RasterSettings::Shading::Phong}) {
            RasterSettings r;
            r.tessellation = 316;
            r.shadows = RasterSettings::Shadows::None;
            r.shading = shading;
            t[k++] = seconds_per_frame(s, r);
        }
        std::printf("%-10d %10.2f %10.2f %10.2f\n", lights, 1000 * t[0], 1000 * t[1], 1000 * t[2]);
    }
}

const char* const usage =
    "usage: bench_raster [--res N] [--frames N] [--threads N] [--quick]\n"
    "  --res N       width and height of the frames (default 1024; 256 with --quick)\n"
    "  --frames N    timed frames of each configuration (default 5; 20 with --quick)\n"
    "  --threads N   render threads (default 0: all cores)\n"
    "  --quick       the Cornell box with each kind of shadow and 1 and 10 lights on a 100k-triangle sphere\n";

int run(int argc, char** argv) {
    bool res_given = false, frames_given = false;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--quick")
            g_quick = true;
        else if (a == "--res")
            g_res = bench::int_option(argc, argv, i, 1), res_given = true;
        else if (a == "--frames")
            g_frames = bench::int_option(argc, argv, i, 1), frames_given = true;
        else if (a == "--threads")
            g_threads = bench::int_option(argc, argv, i, 0);
        else
            bench::reject_argument(a);
    }
    if (g_quick) {
        if (!res_given) g_res = 256;
        if (!frames_given) g_frames = 20;
        quick(load_scene(std::string(CANDELA_SOURCE_DIR) + "/scenes/cbox.xml", {{"res", std::to_string(g_res)}}));
        global_illumination_table();
        return 0;
    }
    Ref<Scene> cbox = load_scene(std::string(CANDELA_SOURCE_DIR) + "/scenes/cbox.xml", {{"res", std::to_string(g_res)}});
    Ref<Scene> mesh = big_mesh_scene(1);
    RasterSettings base;
    base.tessellation = 1000;

    std::printf("%d x %d pixels, %d frames each, 1 sample per pixel unless noted\n\n", g_res, g_res, g_frames);
    std::printf("%-34s %10s %8s\n", "scene / configuration", "ms/frame", "fps");
    auto row = [](const std::string& what, double s) { std::printf("%-34s %10.1f %8.2f\n", what.c_str(), 1000 * s, 1.0 / s); };
    row("cbox, phong, shadow maps", seconds_per_frame(cbox, base));
    row("1M-triangle sphere, phong, maps", seconds_per_frame(mesh, base));
    RasterSettings none = base;
    none.shadows = RasterSettings::Shadows::None;
    row("1M-triangle sphere, phong, none", seconds_per_frame(mesh, none));

    std::printf("\ntime against the number of point lights (1M-triangle sphere, no shadows), ms/frame\n");
    std::printf("%-10s %10s %10s %10s\n", "lights", "flat", "gouraud", "phong");
    for (int lights : {1, 10, 100}) {
        Ref<Scene> s = big_mesh_scene(lights);
        double t[3];
        int k = 0;
        for (auto shading : {RasterSettings::Shading::Flat, RasterSettings::Shading::Gouraud, RasterSettings::Shading::Phong}) {
            RasterSettings r = none;
            r.shading = shading;
            t[k++] = seconds_per_frame(s, r);
        }
        std::printf("%-10d %10.1f %10.1f %10.1f\n", lights, 1000 * t[0], 1000 * t[1], 1000 * t[2]);
    }

    std::printf("\nshadow maps against shadow volumes, ms/frame (phong)\n");
    std::printf("%-34s %10s %10s %10s\n", "scene", "none", "maps", "volumes");
    for (auto [name, scene] : {std::pair<const char*, Ref<Scene>>{"cbox", cbox},
                               {"1M-triangle sphere, 1 light", mesh},
                               {"1M-triangle sphere, 10 lights", big_mesh_scene(10)}}) {
        double t[3];
        int k = 0;
        for (auto shadows : {RasterSettings::Shadows::None, RasterSettings::Shadows::Map, RasterSettings::Shadows::Volume}) {
            RasterSettings r = base;
            r.shadows = shadows;
            t[k++] = seconds_per_frame(scene, r);
        }
        std::printf("%-34s %10.1f %10.1f %10.1f\n", name, 1000 * t[0], 1000 * t[1], 1000 * t[2]);
    }
    global_illumination_table();
    return 0;
}

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
