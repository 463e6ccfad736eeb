// candela compare-modes SCENE.xml -o compare.png [--methods LIST] [--spp N]
//                       [--reference REF.exr | --reference-spp N] [--table FILE.md]
//                       [-D k=v]... [--threads N] [--heatmap-range R] [raster options]
//
// Renders one scene by every method of LIST and compares each with a converged path-traced
// reference: its time, the whole-image mean difference, relMSE, MARE and block MARE
// (analysis/image_metrics.h), and the relative difference heatmap. Writes one picture (the
// reference, then per method its image above its heatmap, each with its figures) and prints one
// table (Markdown; --table also writes it to a file).
//
// A method is an integrator by its registered name (raster, radiosity, path, ao, direct, sppm,
// photonmapper, ...: whatever the registry holds), with optional parameters as
// NAME:key=value:key=value (a value reads as an integer, a number, true/false, or else text; an
// rgb parameter takes one grey number). Two shorthands: `raster-gi` is raster with ao=16 (and
// its default image-based lighting), `baked` is raster with lighting=baked. raster-gi occludes
// the ambient light, so it renders as raster does on a scene with neither an environment light
// nor an `ambient` setting: it is not in the default list, and asking for it there gets a
// warning that names the setting (raster-gi:ambient=0.1). The raster options
// of the command line apply to every raster method. `path` without parameters is the scene's
// own path tracer when it has one (its max_depth). --spp sets the samples of the sampling
// methods. The reference is the scene's path tracer (or a default one) at --reference-spp with
// a seed of its own, so that its noise is independent of the `path` method's, or an EXR given
// by --reference.

#include "apps/commands.h"

#include "analysis/compare_modes.h"
#include "core/error.h"
#include "core/file_output.h"
#include "core/scene.h"
#include "core/warning.h"
#include "integrators/raster/raster.h"
#include "integrators/raster/raster_scene.h"

#include <cstdio>

namespace candela::app {

namespace {

struct CompareModesArgs {
    SceneInput input;
    std::string output = "compare.png", methods = DefaultComparedMethods, reference, table;
    int spp = 0, reference_spp = 1024, threads = 0;
    RasterOptionArgs raster;
    double range = 0.5;
};

// The reference the methods are compared with: a converged path-traced render, or a file.
RenderResult reference_of(Scene& scene, const CompareModesArgs& a) {
    if (a.reference.empty()) return reference_render(scene, a.reference_spp, a.threads);
    RenderResult r;
    r.image = read_image(a.reference);
    const Vec2i size = scene.sensor().film().crop_size();
    if (r.image.width() != size.x || r.image.height() != size.y)
        throw InputError(a.reference + ": the reference is " + std::to_string(r.image.width()) + "x" + std::to_string(r.image.height()) +
                         ", the scene renders " + std::to_string(size.x) + "x" + std::to_string(size.y));
    return r;
}

std::string seconds(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f s", s);
    return buf;
}

// raster-gi darkens the ambient light by its occlusion: with none, it is the raster image again.
void warn_if_no_ambient(const std::string& spec, const Ref<Integrator>& integrator, const Scene& scene) {
    auto* r = dynamic_cast<RasterIntegrator*>(integrator.get());
    if (!r || r->settings().ao <= 0 || luminance(r->settings().ambient) > 0.0f || luminance(raster::collect_lights(scene).ambient) > 0.0f)
        return;
    warn(SourceLocation{}, "--methods " + spec +
                               ": the scene has no environment light and no ambient light, so ambient occlusion has nothing to occlude "
                               "and this renders the raster image again; give it an ambient radiance, e.g. " +
                               spec.substr(0, spec.find(':')) + ":ambient=0.1");
}

int compare_modes(CompareModesArgs& a) {
    check_output_path(a.output);
    if (!a.table.empty()) check_output_path(a.table);
    Ref<Scene> scene = a.input.load();
    const std::vector<std::string> specs = split_methods(a.methods);
    std::vector<Ref<Integrator>> integrators;  // all built first: a bad method stops before any render
    for (const std::string& spec : specs) {
        integrators.push_back(method_integrator(spec, *scene, [&](RasterSettings& settings) { a.raster.apply(settings); }));
        warn_if_no_ambient(spec, integrators.back(), *scene);
    }
    RenderResult reference = reference_of(*scene, a);
    std::vector<MethodRun> runs;
    for (size_t k = 0; k < specs.size(); ++k)
        runs.push_back(run_method(specs[k], integrators[k], *scene, a.spp, a.threads, reference.image));
    const std::string table = methods_table(
        runs, a.reference.empty() ? "path tracer, " + std::to_string(a.reference_spp) + " spp, " + seconds(reference.stats.seconds)
                                  : a.reference);
    std::fputs(table.c_str(), stdout);
    const std::vector<std::string> reference_caption = {
        "REFERENCE", a.reference.empty() ? "PATH " + std::to_string(a.reference_spp) + " SPP" : "FROM FILE",
        a.reference.empty() ? seconds(reference.stats.seconds) : ""};
    write_png_display(methods_contact_sheet(runs, reference, reference_caption, float(a.range)), a.output);
    std::printf("wrote %s (the comparison picture)\n", a.output.c_str());
    if (!a.table.empty()) {
        write_file_atomically(a.table, table);
        std::printf("wrote %s (the table)\n", a.table.c_str());
    }
    return ExitOk;
}

}  // namespace

void add_compare_modes_command(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<CompareModesArgs>();
    CLI::App* cmd = app.add_subcommand("compare-modes", "Render a scene by several methods and compare each with a path-traced reference");
    a->input.add_to(cmd);
    cmd->add_option("-o,--output", a->output, "The comparison picture (PNG, default compare.png)");
    cmd->add_option("--methods", a->methods,
                    "Comma-separated methods: integrator names with optional :key=value parameters, raster-gi (raster with AO), baked "
                    "(default " +
                        std::string(DefaultComparedMethods) + ")");
    cmd->add_option("--spp", a->spp, "Samples per pixel of the sampling methods (default: the scene's)")
        ->check(whole_number("--spp", "samples", 1, MaxSampleCount));
    cmd->add_option("--reference", a->reference, "A converged reference EXR instead of rendering one");
    cmd->add_option("--reference-spp", a->reference_spp, "Samples per pixel of the path-traced reference (default 1024)")
        ->check(whole_number("--reference-spp", "samples", 1, MaxSampleCount));
    cmd->add_option("--table", a->table, "Also write the table (Markdown) to this file");
    add_threads_option(cmd, a->threads);
    cmd->add_option("--heatmap-range", a->range, "Relative difference at full colour (default 0.5)")
        ->check(positive_number("--heatmap-range"));
    a->raster.add_to(cmd);
    cmd->callback([a, &run] { run = [a] { return compare_modes(*a); }; });
}

}  // namespace candela::app
