// candela render SCENE.xml -o OUT.exr [--spp N] [-D k=v]... [-a FOLDER]... [--threads N] [--seed S] [--png]
//                [--quiet] [--aov albedo,normal,depth,variance,samples] [--sampler NAME]
//                [--adaptive-threshold T [--adaptive-min-spp N] [--adaptive-step N]] [--max-memory SIZE]

#include "apps/commands.h"

#include "core/file_resolver.h"
#include "core/integrator.h"
#include "core/memory_budget.h"
#include "core/progress.h"
#include "core/registry.h"
#include "core/warning.h"
#include "apps/render_output.h"
#include "core/xml.h"
#include "integrators/path.h"
#include "integrators/raster/raster.h"

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>

namespace candela::app {

namespace {

std::atomic<bool> g_interrupted{false};

void on_sigint(int) {
    g_interrupted = true;
    std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the program at once
}

struct RenderArgs {
    std::string scene, output, mode, max_memory, sampler;
    AdaptiveSampling adaptive;
    RasterOptionArgs raster;
    int spp = 0, threads = 0;
    int64_t seed = -1;
    std::vector<std::string> defines, aovs, search_path;
    bool png = false, quiet = false;
};

// --mode and the raster options replace or adjust the scene's integrator.
void apply_mode(Scene& scene, const RenderArgs& a) {
    bool options_given = !a.raster.given().empty();
    auto* existing = dynamic_cast<RasterIntegrator*>(&scene.integrator());
    bool raster = a.mode == "raster" || (a.mode.empty() && existing);
    if (!raster) {
        if (options_given) throw InputError("raster options (--shading, --aa, ...) need --mode raster");
        if (a.mode == "path" && scene.integrator().to_string() != "path") scene.set_integrator(std::make_shared<PathIntegrator>(PathSettings{}));
        return;
    }
    RasterSettings settings = existing ? existing->settings() : RasterSettings{};
    a.raster.apply(settings);
    scene.set_integrator(std::make_shared<RasterIntegrator>(settings));
}

}  // namespace

void add_sampler_option(CLI::App* cmd, std::string& sampler) {
    cmd->add_option("--sampler", sampler, "Sampler to use instead of the scene's, with its sample count and seed")
        ->check(CLI::IsMember(plugin_names(ObjectKind::Sampler)));
}

void add_adaptive_options(CLI::App* cmd, AdaptiveSampling& adaptive) {
    auto* threshold = cmd->add_option("--adaptive-threshold", adaptive.threshold,
                                      "Adaptive sampling: stop a pixel once its noise estimate is below this (Cycles' noise threshold, e.g. 0.01; default off)")
                          ->check(CLI::PositiveNumber);
    cmd->add_option("--adaptive-min-spp", adaptive.min_spp, "Adaptive sampling: samples before a pixel's first check (default max(16, spp/16), a power of two)")
        ->check(CLI::PositiveNumber)
        ->needs(threshold);
    cmd->add_option("--adaptive-step", adaptive.step, "Adaptive sampling: samples between checks (default: the minimum)")->check(CLI::PositiveNumber)->needs(threshold);
}

Vec3 parse_triple(const std::string& text, const std::string& option) {
    Vec3 v;
    char extra;
    if (std::sscanf(text.c_str(), " %f , %f , %f %c", &v.x, &v.y, &v.z, &extra) != 3 || !all_finite(v))
        throw InputError(option + " expects three numbers x,y,z, got \"" + text + "\"");
    return v;
}

SceneParameters parse_defines(const std::vector<std::string>& defines) {
    SceneParameters params;
    for (const std::string& d : defines) {
        size_t eq = d.find('=');
        if (eq == std::string::npos || eq == 0) throw InputError("-D expects name=value, got \"" + d + "\"");
        params[d.substr(0, eq)] = d.substr(eq + 1);
    }
    return params;
}

void add_search_path_option(CLI::App* cmd, std::vector<std::string>& folders) {
    cmd->add_option("-a,--search-path", folders,
                    "Also look for the scene's files in this folder, after the scene's own folder and the working directory "
                    "(repeatable; \"a;b\" gives several)");
}

void use_search_folders(const std::vector<std::string>& folders) {
    std::vector<std::filesystem::path> out;
    for (const std::string& list : folders) {
        size_t start = 0;
        while (start <= list.size()) {
            size_t end = list.find(';', start);
            if (end == std::string::npos) end = list.size();
            if (end > start) out.emplace_back(list.substr(start, end - start));
            start = end + 1;
        }
    }
    FileResolver::set_search_folders(out);
}

std::string default_output_for(const std::string& scene_path, const std::string& extension) {
    return std::filesystem::path(scene_path).stem().string() + extension;
}

void add_render_command(CLI::App& app, std::function<int()>& run) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand("render", "Render a Mitsuba 3 scene file to OpenEXR");
    cmd->add_option("scene", args->scene, "Scene file (Mitsuba 3 XML)")->required();
    cmd->add_option("-o,--output", args->output, "Output EXR (default: the scene's name in the current directory)");
    cmd->add_option("--spp", args->spp, "Samples per pixel (default: the scene's sampler)")->check(CLI::PositiveNumber);
    cmd->add_option("-D", args->defines, "Set a scene parameter: -D name=value (repeatable)")->take_all();
    add_search_path_option(cmd, args->search_path);
    cmd->add_option("--threads,-t", args->threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
    cmd->add_option("--seed", args->seed, "Random seed (default: the sampler's)")->check(CLI::NonNegativeNumber);
    cmd->add_flag("--png", args->png, "Also write a tonemapped sRGB PNG beside the EXR");
    cmd->add_flag("--quiet,-q", args->quiet, "No progress bar and no summary line");
    cmd->add_option("--aov", args->aovs, "Extra EXR layers: albedo, normal, depth, variance, samples")->delimiter(',');
    add_sampler_option(cmd, args->sampler);
    add_adaptive_options(cmd, args->adaptive);
    cmd->add_option("--max-memory", args->max_memory,
                    "Stop at once (exit code 2) when the film, meshes or other buffers would need more than SIZE (e.g. 4G, 512M); "
                    "the machine's available memory is always a limit");
    cmd->add_option("--mode", args->mode, "path (Monte Carlo global illumination) or raster (local illumination); default: the scene's integrator")
        ->check(CLI::IsMember({"path", "raster"}));
    args->raster.add_to(cmd);
    cmd->callback([args, &run] {
        run = [args] {
            SceneParameters params = parse_defines(args->defines);
            if (!args->max_memory.empty()) set_memory_limit(parse_memory_size(args->max_memory));
            std::string output = args->output.empty() ? default_output_for(args->scene, ".exr") : args->output;
            std::string png = std::filesystem::path(output).replace_extension(".png").string();
            check_output_path(output);
            if (args->png) check_output_path(png);

            // From here on Ctrl-C stops the render and writes what there is.
            g_interrupted = false;
            auto previous = std::signal(SIGINT, on_sigint);
            use_search_folders(args->search_path);
            Ref<Scene> scene = load_scene(args->scene, params);
            apply_mode(*scene, *args);
            RenderOptions options;
            options.spp = args->spp;
            if (args->seed >= 0) options.seed = uint64_t(args->seed);
            options.threads = args->threads;
            options.progress = !args->quiet && stderr_is_terminal();
            options.interrupt = &g_interrupted;
            options.aovs = args->aovs;
            options.sampler = args->sampler;
            options.adaptive = args->adaptive;

            RenderResult result = scene->integrator().render(*scene, options);
            std::signal(SIGINT, previous);

            if (args->spp > 0 && result.stats.spp != args->spp && !result.stats.single_frame)
                warn(SourceLocation{}, "--spp " + std::to_string(args->spp) + " rounded up to " + std::to_string(result.stats.spp) + " by the " +
                                           result.stats.sampler + " sampler");
            annotate_render(result, *scene, args->scene);
            write_exr(result.image, output, scene->sensor().film().float32());
            if (args->png) write_png_display(scene->integrator().preview(result.image), png);
            if (!args->quiet) std::cerr << render_summary(result.stats, output) << "\n";
            if (result.stats.nonfinite > 0)
                std::cerr << "warning: " << result.stats.nonfinite << " samples were NaN or infinite and were dropped\n";
            if (result.stats.partial) {
                std::cerr << "interrupted: wrote the partial image to " << output << "\n";
                return ExitInterrupted;
            }
            return ExitOk;
        };
    });
}

}  // namespace candela::app
