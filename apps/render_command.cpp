// candela render SCENE.xml -o OUT.exr [--spp N] [-D k=v]... [-a FOLDER]... [--threads N] [--seed S] [--png]
//                [--quiet] [--aov albedo,normal,depth,variance,samples] [--sampler NAME]
//                [--adaptive-threshold T [--adaptive-min-spp N] [--adaptive-step N]] [--max-memory SIZE]
//                [--samples START:END] [--crop x,y,w,h] [--resume PARTIAL.exr] [--checkpoint MINUTES]
//                [--no-wavefront]
// With --samples or --crop it renders one part of a split render (farm/part_file.h), which
// `candela merge` adds up with the others. Ctrl-C or SIGTERM stops a render and writes what it has
// as a part marked partial; --resume continues it, --checkpoint writes one every MINUTES. Renders
// that cannot be split (adaptive sampling, integrators that are not pixel loops) write their image
// as it is when stopped, marked partial.

#include "apps/commands.h"

#include "apps/render_output.h"
#include "core/file_resolver.h"
#include "core/film.h"
#include "core/integrator.h"
#include "core/memory_budget.h"
#include "core/progress.h"
#include "core/registry.h"
#include "core/stop.h"
#include "core/warning.h"
#include "core/xml.h"
#include "farm/coverage.h"
#include "farm/part_file.h"
#include "farm/plan.h"
#include "farm/resumable_render.h"
#include "farm/shell.h"
#include "integrators/path.h"
#include "integrators/raster/raster.h"

#include <unistd.h>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>

namespace candela::app {

namespace {

struct RenderArgs {
    SceneInput input;
    std::string output, mode, max_memory, sampler;
    AdaptiveSampling adaptive;
    RasterOptionArgs raster;
    int spp = 0, threads = 0;
    int64_t seed = -1;
    std::vector<std::string> aovs;
    std::string samples, crop;  // a part of a split render
    std::string resume;         // a part to continue
    double checkpoint_minutes = 0.0;
    bool png = false, quiet = false, no_wavefront = false;

    bool part() const { return !samples.empty() || !crop.empty(); }
};

// The command that renders this scene again, as every part of the split render records it: the
// options that change the image, with spp and seed spelled out.
std::string repeat_command(const RenderArgs& a, const RenderStats& stats) {
    FarmRequest r;
    r.candela = program_path();
    r.scene = std::filesystem::absolute(a.input.scene).string();
    r.spp = stats.spp;
    r.seed = stats.seed;
    r.defines = a.input.defines;
    r.search_path = absolute_search_folders(a.input.search_path);
    r.aovs = a.aovs;
    r.sampler = a.sampler;
    r.mode = a.mode;
    r.variant = a.input.variant;
    return shell_join(render_words(r));
}

// What the render renders: --crop's pixels (default all) times --samples (default [0, spp)).
CoverageBox render_target(const RenderArgs& a, const Scene& scene, int spp) {
    CoverageBox t{ImageRect{Vec2i(0), scene.sensor().film().crop_size()}, SampleRange{0, spp}};
    if (!a.crop.empty()) t.rect = parse_rect(a.crop);
    if (!a.samples.empty()) t.samples = parse_sample_range(a.samples);
    return t;
}

// --resume without --spp or --seed takes them from the part, so that the same command line
// with --resume added continues the render.
void take_resumed_settings(const RenderArgs& a, RenderOptions& options) {
    if (a.resume.empty()) return;
    const PartHeader h = read_part_header(a.resume);
    if (a.spp <= 0) options.spp = h.identity.spp;
    if (a.seed < 0) options.seed = h.identity.seed;
}

// The command that continues a render interrupted after writing `output`.
std::string resume_command(const RenderArgs& a, const std::string& repeat, const std::string& output) {
    std::string cmd = repeat;
    if (!a.samples.empty()) cmd += " --samples " + a.samples;
    if (!a.crop.empty()) cmd += " --crop " + a.crop;
    return cmd + " --resume " + shell_quote(output) + " -o " + shell_quote(output);
}

// Why this render cannot be split, resumed or checkpointed (the integrator's reason, or adaptive
// sampling's).
std::string parts_refusal(const Scene& scene, const RenderOptions& options) {
    const std::string what = "cannot render a part (--samples, --crop), resume or checkpoint: ";
    if (std::string reason = scene.integrator().parts_refusal(); !reason.empty())
        return "the " + scene.integrator().to_string() + " integrator " + what + reason;
    return "adaptive sampling (--adaptive-threshold) " + what + "whether a pixel takes a sample depends on its earlier samples and " +
           "on its neighbours', which a part does not have; render the whole image";
}

// The lines every render prints after writing: --spp rounded by the sampler, the summary (with
// `samples` in place of "N spp" for a part), the dropped non-finite samples.
void report_render(const RenderArgs& a, const RenderStats& stats, const std::string& output, const std::string& samples,
                   const std::string& png) {
    if (a.spp > 0 && stats.spp != a.spp && !stats.single_frame)
        warn(SourceLocation{},
             "--spp " + std::to_string(a.spp) + " rounded up to " + std::to_string(stats.spp) + " by the " + stats.sampler + " sampler");
    if (!a.quiet) std::cerr << render_summary(stats, output, samples) << "\n";
    if (!a.quiet && a.png) std::cerr << "wrote " << png << ": the tonemapped sRGB preview (8 bits; not for measuring)\n";
    if (stats.nonfinite > 0) std::cerr << "warning: " << stats.nonfinite << " samples were NaN, infinite or beyond 1e30 and were dropped\n";
}

// "part: samples 0:8 of 16" (and ", pixels x,y,w,h" for a crop): what a part holds.
std::string part_description(const CoverageBox& target, const Scene& scene, int spp) {
    std::string text = "part: samples " + format_sample_range(target.samples) + " of " + std::to_string(spp);
    if (target.rect.size != scene.sensor().film().crop_size()) text += ", pixels " + format_rect(target.rect);
    return text;
}

// --samples past the render's sample count: when the count is the scene's sampler's (no --spp),
// say so and name the --spp that makes the range fit.
void check_sample_range(const RenderArgs& a, const CoverageBox& target, const RenderStats& planned) {
    if (a.samples.empty() || target.samples.end <= planned.spp) return;
    const std::string range = format_sample_range(target.samples);
    if (a.spp > 0)
        throw InputError("--samples " + range + " reaches past --spp " + std::to_string(planned.spp) +
                         ": a part's sample range lies within [0, spp), the samples of the whole render");
    throw InputError("--samples " + range + " reaches past the render's " + std::to_string(planned.spp) +
                     " samples per pixel, the sample_count of the scene's " + planned.sampler +
                     " sampler; give the whole render's count: --spp " + std::to_string(target.samples.end) + " --samples " + range);
}

// A Monte Carlo render through the sums (farm/resumable_render.h): the image when it is whole and
// not a part, else a part (a farm part, or an interrupted render to continue).
int render_with_sums(const RenderArgs& a, const Scene& scene, RenderOptions options, const std::string& output, const std::string& png) {
    take_resumed_settings(a, options);
    const RenderStats planned = planned_render(scene, options);
    ResumableRequest request;
    request.scene_path = a.input.scene;
    request.command = repeat_command(a, planned);
    request.target = render_target(a, scene, planned.spp);
    request.resume = a.resume;
    request.checkpoint_seconds = a.checkpoint_minutes * 60.0;
    request.output = output;
    check_sample_range(a, request.target, planned);
    ResumableResult r = render_resumable(scene, options, request);
    const bool whole = !r.header.partial && !a.part();
    if (whole) {
        RenderResult result;
        result.image = r.sums.develop();
        result.stats = r.stats;
        annotate_render(result, scene, a.input.scene);
        write_exr(result.image, output, scene.sensor().film().float32());
        if (a.png) write_png_display(scene.integrator().preview(result.image), png);
    } else {
        write_part(output, r.sums, r.header);
    }
    report_render(a, r.stats, output, a.part() ? part_description(request.target, scene, r.stats.spp) : "", png);
    if (r.header.partial) {
        std::cerr << (r.interrupted ? "interrupted: " : "") << "wrote the partial render (a part holding "
                  << format_coverage(r.header.coverage) << ") to " << output << "; continue it with:\n  "
                  << resume_command(a, request.command, output) << "\n";
        return r.interrupted ? stop_exit_code() : ExitOk;
    }
    return ExitOk;
}

// A render that keeps no sums (the rasterizer, particle tracers, adaptive sampling): the image as
// it comes.
int render_frame(const RenderArgs& a, const Scene& scene, const RenderOptions& options, const std::string& output, const std::string& png) {
    RenderResult result = scene.integrator().render(scene, options);
    annotate_render(result, scene, a.input.scene);
    write_exr(result.image, output, scene.sensor().film().float32());
    if (a.png) write_png_display(scene.integrator().preview(result.image), png);
    report_render(a, result.stats, output, "", png);
    if (result.stats.partial) {
        std::cerr << "interrupted: wrote the partial image to " << output << "\n";
        return stop_exit_code();
    }
    return ExitOk;
}

// --mode and the raster options replace or adjust the scene's integrator.
void apply_mode(Scene& scene, const RenderArgs& a) {
    bool options_given = !a.raster.given().empty();
    auto* existing = dynamic_cast<RasterIntegrator*>(&scene.integrator());
    bool raster = a.mode == "raster" || (a.mode.empty() && existing);
    if (!raster) {
        if (options_given) throw InputError("raster options (--shading, --aa, ...) need --mode raster");
        if (a.mode == "path" && scene.integrator().to_string() != "path")
            scene.set_integrator(std::make_shared<PathIntegrator>(PathSettings{}));
        return;
    }
    if (a.spp > 0)
        warn(SourceLocation{}, "--spp " + std::to_string(a.spp) +
                                   " does not apply to the raster mode, which takes no Monte Carlo samples; its anti-aliasing "
                                   "samples are --aa N (supersampling per pixel)");
    if (!a.sampler.empty()) warn(SourceLocation{}, "--sampler " + a.sampler + " does not apply to the raster mode (its samples are --aa)");
    if (scene.spectral())
        warn(SourceLocation{},
             std::string("--variant ") + variant_name(scene.variant()) + ": the raster mode draws its local model in RGB in every variant");
    RasterSettings settings = existing ? existing->settings() : RasterSettings{};
    a.raster.apply(settings);
    scene.set_integrator(std::make_shared<RasterIntegrator>(settings));
}

}  // namespace

void add_sampler_option(CLI::App* cmd, std::string& sampler) {
    std::string names;
    for (const std::string& n : plugin_names(ObjectKind::Sampler)) names += (names.empty() ? "" : ", ") + n;
    cmd->add_option("--sampler", sampler,
                    "Sampler to use instead of the scene's, with its sample count and seed (default: the scene's; " + names + ")")
        ->check(one_of("--sampler", plugin_names(ObjectKind::Sampler)));
}

void add_adaptive_options(CLI::App* cmd, AdaptiveSampling& adaptive) {
    auto* threshold =
        cmd->add_option(
               "--adaptive-threshold", adaptive.threshold,
               "Adaptive sampling: stop a pixel with n samples once its noise estimate (Cycles', pooled over 3x3 pixels) is below this "
               "times sqrt(n / min-spp) (e.g. 0.01; default off; use the independent sampler)")
            ->check(positive_number("--adaptive-threshold"));
    cmd->add_option("--adaptive-min-spp", adaptive.min_spp,
                    "Adaptive sampling: samples before a pixel's first check (default max(16, spp/16), a power of two)")
        ->check(whole_number("--adaptive-min-spp", "samples", 1, MaxSampleCount))
        ->needs(threshold);
    cmd->add_option("--adaptive-step", adaptive.step, "Adaptive sampling: samples between checks (default: the minimum)")
        ->check(whole_number("--adaptive-step", "samples", 1, MaxSampleCount))
        ->needs(threshold);
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

namespace {

// The folders of -a options: each option one folder or several joined by ';'.
std::vector<std::filesystem::path> split_search_folders(const std::vector<std::string>& folders) {
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
    return out;
}

}  // namespace

void use_search_folders(const std::vector<std::string>& folders) { FileResolver::set_search_folders(split_search_folders(folders)); }

std::vector<std::string> absolute_search_folders(const std::vector<std::string>& folders) {
    std::vector<std::string> out;
    for (const std::filesystem::path& f : split_search_folders(folders))
        out.push_back(std::filesystem::absolute(f).lexically_normal().string());
    return out;
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
    args->input.add_to(cmd);
    cmd->add_option("-o,--output", args->output, "Output EXR (default: the scene's name in the current directory)");
    cmd->add_option("--spp", args->spp, "Samples per pixel (default: the scene's sampler's sample_count)")
        ->check(whole_number("--spp", "samples", 1, MaxSampleCount));
    add_threads_option(cmd, args->threads);
    add_seed_option(cmd, args->seed, "default: the scene's sampler's");
    cmd->add_flag("--png", args->png, "Also write a tonemapped sRGB PNG beside the EXR (a preview: 8 bits, not for measuring)");
    cmd->add_flag("--quiet,-q", args->quiet, "No progress bar and no summary line");
    cmd->add_option("--aov", args->aovs, "Extra EXR layers, comma separated: albedo, normal, depth, variance, samples (default none)")
        ->delimiter(',');
    add_sampler_option(cmd, args->sampler);
    add_adaptive_options(cmd, args->adaptive);
    cmd->add_option("--max-memory", args->max_memory,
                    "Stop at once (exit code 2) when the film, meshes or other buffers would need more than SIZE (e.g. 4G, 512M); "
                    "the machine's available memory is always a limit (default: that limit only)");
    cmd->add_option("--samples", args->samples,
                    "Render only sample indices START:END (within [0, spp)) of every pixel, as one part for `candela merge` "
                    "(default: all)");
    cmd->add_option("--crop", args->crop,
                    "Render only the image region x,y,width,height (pixels), as one part for `candela merge` (default: the whole image)");
    cmd->add_option("--resume", args->resume, "Continue the render that wrote this partial EXR (after Ctrl-C, SIGTERM or a checkpoint)");
    cmd->add_option("--checkpoint", args->checkpoint_minutes,
                    "Write a resumable partial render to the output every MINUTES, atomically (default: none)")
        ->check(positive_number("--checkpoint"));
    cmd->add_option("--mode", args->mode,
                    "path (Monte Carlo global illumination) or raster (local illumination); default: the scene's integrator")
        ->check(one_of("--mode", {"path", "raster"}));
    cmd->add_flag("--no-wavefront", args->no_wavefront,
                  "Trace camera paths one at a time even where the path tracer would trace them as a wavefront, in ray batches "
                  "(the image is the same bit for bit; for comparison and benchmarks)");
    args->raster.add_to(cmd);
    cmd->callback([args, &run] {
        run = [args] {
            args->input.resolve();
            if (!args->max_memory.empty()) set_memory_limit(parse_memory_size(args->max_memory));
            std::string output = args->output.empty() ? default_output_for(args->input.scene, ".exr") : args->output;
            std::string png = std::filesystem::path(output).replace_extension(".png").string();
            check_output_path(output);
            check_exr_output(output);
            if (args->png) check_output_path(png);
            if (args->part() && args->png)
                throw InputError("--png needs the whole image: a part (--samples, --crop) holds sums; merge the parts first");

            // Ctrl-C or SIGTERM (what Slurm and systemd send before they kill) stops the render,
            // which writes what it has: main() chose StopMode::Graceful for it (core/stop.h).
            Ref<Scene> scene = args->input.load();
            apply_mode(*scene, *args);
            if (args->png) require_colour_film(scene->sensor().film(), "--png previews the image's colour");
            RenderOptions options;
            options.spp = args->spp;
            if (args->seed >= 0) options.seed = uint64_t(args->seed);
            options.threads = args->threads;
            options.progress = !args->quiet && stderr_is_terminal();
            options.interrupt = &stop_flag();
            options.aovs = args->aovs;
            options.sampler = args->sampler;
            options.adaptive = args->adaptive;
            options.wavefront = !args->no_wavefront;
            const bool sums = scene->integrator().renders_parts() && !options.adaptive.enabled();
            if (!sums && (args->part() || !args->resume.empty() || args->checkpoint_minutes > 0.0))
                throw InputError(parts_refusal(*scene, options));
            return sums ? render_with_sums(*args, *scene, options, output, png) : render_frame(*args, *scene, options, output, png);
        };
    });
}

}  // namespace candela::app
