// candela render SCENE.xml -o OUT.exr [--spp N] [-D k=v]... [--threads N] [--seed S] [--png]
//                [--quiet] [--aov albedo,normal,depth,variance] [--samples START:END] [--crop x,y,w,h]
// With --samples or --crop it renders one part of a split render (farm/part_file.h), which
// `candela merge` adds up with the others.

#include "apps/commands.h"

#include "core/integrator.h"
#include "core/progress.h"
#include "apps/render_output.h"
#include "core/xml.h"
#include "integrators/path.h"
#include "integrators/raster/raster.h"
#include "farm/part_file.h"
#include "farm/shell.h"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <unistd.h>

namespace candela::app {

namespace {

std::atomic<bool> g_interrupted{false};

void on_sigint(int) {
    g_interrupted = true;
    std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the program at once
}

struct RenderArgs {
    std::string scene, output, mode;
    RasterOptionArgs raster;
    int spp = 0, threads = 0;
    int64_t seed = -1;
    std::vector<std::string> defines, aovs;
    std::string samples, crop;  // a part of a split render
    bool png = false, quiet = false;

    bool part() const { return !samples.empty() || !crop.empty(); }
};

double seconds_since_epoch() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

// The command that renders this scene again, as every part of the split render records it: the
// options that change the image, with spp and seed spelled out.
std::string repeat_command(const RenderArgs& a, const RenderStats& stats) {
    std::vector<std::string> words = {program_path(), "render", std::filesystem::absolute(a.scene).string(), "--spp", std::to_string(stats.spp),
                                      "--seed", std::to_string(stats.seed)};
    for (const std::string& d : a.defines) words.insert(words.end(), {"-D", d});
    if (!a.aovs.empty()) {
        std::string list;
        for (const std::string& v : a.aovs) list += (list.empty() ? "" : ",") + v;
        words.insert(words.end(), {"--aov", list});
    }
    if (!a.mode.empty()) words.insert(words.end(), {"--mode", a.mode});
    return shell_join(words);
}

// The part options, checked against the integrator.
void set_part_options(const RenderArgs& a, const Scene& scene, RenderOptions& options) {
    if (!scene.integrator().renders_parts())
        throw InputError("the " + scene.integrator().to_string() + " integrator cannot render a part (--samples, --crop): its samples " +
                         "are not independent of each other; render the whole image");
    if (!a.samples.empty()) options.samples = parse_sample_range(a.samples);
    if (!a.crop.empty()) options.region = parse_rect(a.crop);
}

void write_render_part(const RenderArgs& a, const Scene& scene, const RenderResult& result, double started, const std::string& output) {
    PartHeader h;
    h.identity = render_identity(scene, a.scene, result.stats, result.sums.layout(), repeat_command(a, result.stats));
    const Vec2i image = h.identity.image;
    h.rect = a.crop.empty() ? ImageRect{Vec2i(0), image} : parse_rect(a.crop);
    const SampleRange samples = a.samples.empty() ? SampleRange{0, result.stats.spp} : parse_sample_range(a.samples);
    h.coverage = {CoverageBox{h.rect, samples}};
    h.render_seconds = result.stats.seconds;
    h.started = started;
    h.finished = seconds_since_epoch();
    char host[256] = {0};
    if (::gethostname(host, sizeof host - 1) == 0) h.host = host;
    h.samples = result.stats.samples;
    h.rays = result.stats.rays;
    h.nonfinite = result.stats.nonfinite;
    write_part(output, result.sums, h);
}

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

std::string program_path() {
    std::error_code ec;
    std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? std::string("candela") : self.string();
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
    cmd->add_option("--threads,-t", args->threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
    cmd->add_option("--seed", args->seed, "Random seed (default: the sampler's)")->check(CLI::NonNegativeNumber);
    cmd->add_flag("--png", args->png, "Also write a tonemapped sRGB PNG beside the EXR");
    cmd->add_flag("--quiet,-q", args->quiet, "No progress bar and no summary line");
    cmd->add_option("--aov", args->aovs, "Extra EXR layers: albedo, normal, depth, variance")->delimiter(',');
    cmd->add_option("--samples", args->samples, "Render only sample indices START:END of every pixel, as one part for `candela merge`");
    cmd->add_option("--crop", args->crop, "Render only the image region x,y,width,height (pixels), as one part for `candela merge`");
    cmd->add_option("--mode", args->mode, "path (Monte Carlo global illumination) or raster (local illumination); default: the scene's integrator")
        ->check(CLI::IsMember({"path", "raster"}));
    args->raster.add_to(cmd);
    cmd->callback([args, &run] {
        run = [args] {
            SceneParameters params = parse_defines(args->defines);
            std::string output = args->output.empty() ? default_output_for(args->scene, ".exr") : args->output;
            std::string png = std::filesystem::path(output).replace_extension(".png").string();
            check_output_path(output);
            if (args->png) check_output_path(png);
            if (args->part() && args->png) throw InputError("--png needs the whole image: a part (--samples, --crop) holds sums; merge the parts first");

            // From here on Ctrl-C stops the render and writes what there is.
            g_interrupted = false;
            auto previous = std::signal(SIGINT, on_sigint);
            Ref<Scene> scene = load_scene(args->scene, params);
            apply_mode(*scene, *args);
            RenderOptions options;
            options.spp = args->spp;
            if (args->seed >= 0) options.seed = uint64_t(args->seed);
            options.threads = args->threads;
            options.progress = !args->quiet && stderr_is_terminal();
            options.interrupt = &g_interrupted;
            options.aovs = args->aovs;
            if (args->part()) set_part_options(*args, *scene, options);

            const double started = seconds_since_epoch();
            RenderResult result = scene->integrator().render(*scene, options);
            std::signal(SIGINT, previous);
            if (args->part()) {
                if (result.stats.partial) {
                    std::cerr << "interrupted: nothing written (a part holds its whole sample range or nothing)\n";
                    return ExitInterrupted;
                }
                write_render_part(*args, *scene, result, started, output);
                if (!args->quiet) std::cerr << render_summary(result.stats, output) << " (part)\n";
                if (result.stats.nonfinite > 0)
                    std::cerr << "warning: " << result.stats.nonfinite << " samples were NaN or infinite and were dropped\n";
                return ExitOk;
            }

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
