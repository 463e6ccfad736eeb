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
// its default image-based lighting), `baked` is raster with lighting=baked. The raster options
// of the command line apply to every raster method. `path` without parameters is the scene's
// own path tracer when it has one (its max_depth). --spp sets the samples of the sampling
// methods. The reference is the scene's path tracer (or a default one) at --reference-spp with
// a seed of its own, so that its noise is independent of the `path` method's, or an EXR given
// by --reference.

#include "apps/commands.h"

#include "analysis/image_metrics.h"
#include "core/error.h"
#include "core/file_output.h"
#include "core/image_draw.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "integrators/path.h"
#include "integrators/raster/raster.h"

#include <cstdio>
#include <map>
#include <sstream>

namespace candela::app {

namespace {

struct CompareModesArgs {
    std::string scene, output = "compare.png", methods = "raster,raster-gi,baked,radiosity,path", reference, table;
    std::vector<std::string> defines, search_path;
    int spp = 0, reference_spp = 1024, threads = 0;
    RasterOptionArgs raster;
    double range = 0.5;
};

struct MethodRun {
    std::string label;
    RenderResult result;
    double bake_seconds = 0.0;
    ImageComparison c;
};

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> out;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, separator)) out.push_back(item);
    return out;
}

// One parameter from its text: integer, number, boolean, or else text.
void set_parameter(Properties& props, const std::string& name, const std::string& value) {
    char* end = nullptr;
    long long i = std::strtoll(value.c_str(), &end, 10);
    if (!value.empty() && !*end) return props.set_int(name, i);
    double d = std::strtod(value.c_str(), &end);
    if (!value.empty() && !*end) return props.set_float(name, d);
    if (value == "true" || value == "false") return props.set_bool(name, value == "true");
    props.set_string(name, value);
}

// The integrator's properties from a method's text (shorthands expanded); InputError when a
// parameter is not key=value.
Properties method_properties(const std::string& spec) {
    std::vector<std::string> parts = split(spec, ':');
    if (parts.empty() || parts[0].empty()) throw InputError("--methods: empty method in \"" + spec + "\"");
    const std::string name = parts[0];
    // The shorthands' own parameter, unless the method gives it.
    auto given = [&](const std::string& key) {
        for (size_t k = 1; k < parts.size(); ++k)
            if (parts[k].rfind(key + "=", 0) == 0) return true;
        return false;
    };
    if (name == "raster-gi" && !given("ao")) parts.push_back("ao=16");
    if (name == "baked" && !given("lighting")) parts.push_back("lighting=baked");
    Properties props(name == "raster-gi" || name == "baked" ? "raster" : name, SourceLocation{"--methods " + spec, 0});
    for (size_t k = 1; k < parts.size(); ++k) {
        size_t eq = parts[k].find('=');
        if (eq == std::string::npos || eq == 0) throw InputError("--methods: \"" + parts[k] + "\" in \"" + spec + "\" is not key=value");
        set_parameter(props, parts[k].substr(0, eq), parts[k].substr(eq + 1));
    }
    return props;
}

// The integrator of one method, built through the registry (unknown names and parameters are
// errors naming the method).
Ref<Integrator> method_integrator(const std::string& spec, const Scene& scene, const RasterOptionArgs& raster) {
    Properties props = method_properties(spec);
    if (spec == "path" && scene.integrator().to_string() == "path") return nullptr;  // the scene's own
    Ref<Integrator> integrator = create_plugin_as<Integrator>(ObjectKind::Integrator, props);
    if (auto* r = dynamic_cast<RasterIntegrator*>(integrator.get())) raster.apply(r->settings());
    return integrator;
}

// The converged reference: the scene's path tracer (or a default one) with its own seed.
RenderResult reference_render(Scene& scene, const CompareModesArgs& a) {
    if (!a.reference.empty()) {
        RenderResult r;
        r.image = read_image(a.reference);
        const Vec2i size = scene.sensor().film().crop_size();
        if (r.image.width() != size.x || r.image.height() != size.y)
            throw InputError(a.reference + ": the reference is " + std::to_string(r.image.width()) + "x" +
                             std::to_string(r.image.height()) + ", the scene renders " + std::to_string(size.x) + "x" +
                             std::to_string(size.y));
        return r;
    }
    Ref<Integrator> own = scene.integrator().to_string() == "path" ? nullptr : std::make_shared<PathIntegrator>(PathSettings{});
    RenderOptions options;
    options.threads = a.threads;
    options.spp = a.reference_spp;
    options.seed = 0x7265666572656e63ULL;  // "referenc": not the seed any method uses
    RenderResult r = (own ? *own : scene.integrator()).render(scene, options);
    r.image = linear_rgb(r.image);
    return r;
}

MethodRun run_method(const std::string& spec, const Ref<Integrator>& integrator, Scene& scene, const CompareModesArgs& a,
                     const Image& reference) {
    RenderOptions options;
    options.threads = a.threads;
    options.spp = a.spp;
    MethodRun run;
    run.label = spec;
    run.result = (integrator ? *integrator : scene.integrator()).render(scene, options);
    run.result.image = linear_rgb(run.result.image);
    if (auto* r = dynamic_cast<RasterIntegrator*>(integrator.get())) run.bake_seconds = r->bake_seconds();
    run.c = compare_images(run.result.image, reference);
    return run;
}

std::string format(const char* pattern, double value) {
    char buf[64];
    std::snprintf(buf, sizeof buf, pattern, value);
    return buf;
}

double mean_luminance_difference(const ImageComparison& c) {
    double reference = luminance(c.mean_reference);
    return reference > 0.0 ? (luminance(c.mean_test) - reference) / reference : 0.0;
}

std::string results_table(const std::vector<MethodRun>& runs, const RenderResult& reference, const CompareModesArgs& a) {
    std::string t =
        "| method | time (s) | of which baking (s) | mean luminance vs reference | relMSE | MARE | block MARE |\n|---|---|---|---|---|---|---|\n";
    for (const MethodRun& r : runs)
        t += "| " + r.label + " | " + format("%.3f", r.result.stats.seconds) + " | " +
             (r.bake_seconds > 0.0 ? format("%.3f", r.bake_seconds) : "") + " | " +
             format("%+.2f%%", 100.0 * mean_luminance_difference(r.c)) + " | " + format("%.4g", r.c.relmse) + " | " +
             format("%.2f%%", 100.0 * r.c.mare) + " | " + format("%.2f%%", 100.0 * r.c.block_mare) + " |\n";
    t += a.reference.empty()
             ? "\nReference: path tracer, " + std::to_string(a.reference_spp) + " spp, " + format("%.1f s", reference.stats.seconds) + ".\n"
             : "\nReference: " + a.reference + ".\n";
    return t;
}

// Text lines under a picture, at (x, y); returns the y below them.
int caption(Image& sheet, int x, int y, const std::vector<std::string>& lines) {
    for (const std::string& line : lines) {
        draw::text(sheet, x, y, line, Spectrum(0.0f), 1);
        y += draw::GlyphHeight + 4;
    }
    return y;
}

// The picture: the reference, then per method its image above its difference heatmap.
Image contact_sheet(const std::vector<MethodRun>& runs, const RenderResult& reference, const CompareModesArgs& a) {
    const int pad = 8, line = draw::GlyphHeight + 4;
    std::vector<Image> images{tonemap_srgb(reference.image)}, heatmaps{Image()};
    std::vector<std::vector<std::string>> top{{"REFERENCE",
                                               a.reference.empty() ? "PATH " + std::to_string(a.reference_spp) + " SPP" : "FROM FILE",
                                               a.reference.empty() ? format("%.2f S", reference.stats.seconds) : ""}},
        bottom{{}};
    for (const MethodRun& r : runs) {
        images.push_back(tonemap_srgb(r.result.image));
        heatmaps.push_back(relative_difference_heatmap(r.result.image, reference.image, float(a.range)));
        top.push_back(
            {r.label, format("%.3f S", r.result.stats.seconds), r.bake_seconds > 0.0 ? format("(BAKE %.3f S)", r.bake_seconds) : ""});
        bottom.push_back({"RELMSE " + format("%.4g", r.c.relmse), "BLOCK MARE " + format("%.1f%%", 100.0 * r.c.block_mare),
                          "MEAN " + format("%+.1f%%", 100.0 * mean_luminance_difference(r.c))});
    }
    std::vector<int> widths;
    int width = pad, heat_height = 0;
    for (size_t k = 0; k < images.size(); ++k) {
        int w = std::max(images[k].width(), heatmaps[k].width());
        for (const auto& s : top[k]) w = std::max(w, draw::text_width(s));
        widths.push_back(w);
        width += w + pad;
        heat_height = std::max(heat_height, heatmaps[k].height());
    }
    const int image_top = pad + 3 * line, heat_top = image_top + images[0].height() + pad;
    Image sheet = Image::rgb(width, heat_top + heat_height + 3 * line + pad);
    draw::fill_rect(sheet, 0, 0, sheet.width(), sheet.height(), Spectrum(1.0f));
    int x = pad;
    for (size_t k = 0; k < images.size(); ++k) {
        caption(sheet, x, pad, top[k]);
        draw::blit(sheet, images[k], x, image_top);
        if (heatmaps[k].width() > 0) draw::blit(sheet, heatmaps[k], x, heat_top);
        caption(sheet, x, heat_top + heat_height + 4, bottom[k]);
        x += widths[k] + pad;
    }
    return sheet;
}

int compare_modes(const CompareModesArgs& a) {
    check_output_path(a.output);
    if (!a.table.empty()) check_output_path(a.table);
    use_search_folders(a.search_path);
    Ref<Scene> scene = load_scene(a.scene, parse_defines(a.defines));
    std::vector<std::string> specs = split(a.methods, ',');
    if (specs.empty()) throw InputError("--methods: no method given");
    std::vector<Ref<Integrator>> integrators;  // all built first: a bad method stops before any render
    for (const std::string& spec : specs) integrators.push_back(method_integrator(spec, *scene, a.raster));
    RenderResult reference = reference_render(*scene, a);
    std::vector<MethodRun> runs;
    for (size_t k = 0; k < specs.size(); ++k) runs.push_back(run_method(specs[k], integrators[k], *scene, a, reference.image));
    std::string table = results_table(runs, reference, a);
    std::fputs(table.c_str(), stdout);
    write_png_display(contact_sheet(runs, reference, a), a.output);
    if (!a.table.empty()) write_file_atomically(a.table, table);
    std::printf("wrote %s\n", a.output.c_str());
    return ExitOk;
}

}  // namespace

void add_compare_modes_command(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<CompareModesArgs>();
    CLI::App* cmd = app.add_subcommand("compare-modes", "Render a scene by several methods and compare each with a path-traced reference");
    cmd->add_option("scene", a->scene, "Scene file (Mitsuba 3 XML)")->required();
    cmd->add_option("-o,--output", a->output, "The comparison picture (PNG, default compare.png)");
    cmd->add_option("--methods", a->methods,
                    "Comma-separated methods: integrator names with optional :key=value parameters, raster-gi (raster with AO), baked "
                    "(default raster,raster-gi,baked,radiosity,path)");
    cmd->add_option("--spp", a->spp, "Samples per pixel of the sampling methods (default: the scene's)")->check(CLI::PositiveNumber);
    cmd->add_option("--reference", a->reference, "A converged reference EXR instead of rendering one");
    cmd->add_option("--reference-spp", a->reference_spp, "Samples per pixel of the path-traced reference (default 1024)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--table", a->table, "Also write the table (Markdown) to this file");
    cmd->add_option("-D", a->defines, "Set a scene parameter: -D name=value (repeatable)")->take_all();
    add_search_path_option(cmd, a->search_path);
    cmd->add_option("--threads,-t", a->threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
    cmd->add_option("--heatmap-range", a->range, "Relative difference at full colour (default 0.5)")->check(CLI::PositiveNumber);
    a->raster.add_to(cmd);
    cmd->callback([a, &run] { run = [a] { return compare_modes(*a); }; });
}

}  // namespace candela::app
