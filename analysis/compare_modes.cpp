#include "analysis/compare_modes.h"

#include "core/error.h"
#include "core/image_draw.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "integrators/path.h"
#include "integrators/raster/raster.h"

#include <cstdio>
#include <sstream>

namespace candela {

namespace {

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

std::string format(const char* pattern, double value) {
    char buf[64];
    std::snprintf(buf, sizeof buf, pattern, value);
    return buf;
}

// Text lines under a picture, at (x, y); returns the y below them.
int caption(Image& sheet, int x, int y, const std::vector<std::string>& lines) {
    for (const std::string& line : lines) {
        draw::text(sheet, x, y, line, Spectrum(0.0f), 1);
        y += draw::GlyphHeight + 4;
    }
    return y;
}

}  // namespace

std::vector<std::string> split_methods(const std::string& list) {
    std::vector<std::string> specs = split(list, ',');
    if (specs.empty()) throw InputError("--methods: no method given");
    return specs;
}

Ref<Integrator> method_integrator(const std::string& spec, const Scene& scene, const std::function<void(RasterSettings&)>& adjust_raster) {
    Properties props = method_properties(spec);
    if (spec == "path" && scene.integrator().to_string() == "path") return nullptr;  // the scene's own
    // Methods are refused in a variant they do not render in, as in a scene file; the raster
    // modes draw the local model in RGB in every variant.
    if (props.plugin_type() != "raster") props.set_variant(scene.variant());
    Ref<Integrator> integrator = create_plugin_as<Integrator>(ObjectKind::Integrator, props);
    if (auto* r = dynamic_cast<RasterIntegrator*>(integrator.get()); r && adjust_raster) adjust_raster(r->settings());
    return integrator;
}

RenderResult reference_render(Scene& scene, int spp, int threads) {
    Ref<Integrator> own = scene.integrator().to_string() == "path" ? nullptr : std::make_shared<PathIntegrator>(PathSettings{});
    RenderOptions options;
    options.threads = threads;
    options.spp = spp;
    options.seed = 0x7265666572656e63ULL;  // "referenc": not the seed any method uses
    RenderResult r = (own ? *own : scene.integrator()).render(scene, options);
    r.image = linear_rgb(r.image);
    return r;
}

MethodRun run_method(const std::string& spec, const Ref<Integrator>& integrator, Scene& scene, int spp, int threads,
                     const Image& reference) {
    RenderOptions options;
    options.threads = threads;
    options.spp = spp;
    MethodRun run;
    run.label = spec;
    run.result = (integrator ? *integrator : scene.integrator()).render(scene, options);
    run.result.image = linear_rgb(run.result.image);
    if (auto* r = dynamic_cast<RasterIntegrator*>(integrator.get())) run.bake_seconds = r->bake_seconds();
    run.comparison = compare_images(run.result.image, reference);
    return run;
}

double mean_luminance_difference(const ImageComparison& c) {
    double reference = luminance(c.mean_reference);
    return reference > 0.0 ? (luminance(c.mean_test) - reference) / reference : 0.0;
}

std::string methods_table(const std::vector<MethodRun>& runs, const std::string& reference_label) {
    std::string t =
        "| method | time (s) | of which baking (s) | mean luminance vs reference | relMSE | MARE | block MARE |\n|---|---|---|---|---|---|---|\n";
    for (const MethodRun& r : runs)
        t += "| " + r.label + " | " + format("%.3f", r.result.stats.seconds) + " | " +
             (r.bake_seconds > 0.0 ? format("%.3f", r.bake_seconds) : "") + " | " +
             format("%+.2f%%", 100.0 * mean_luminance_difference(r.comparison)) + " | " + format("%.4g", r.comparison.relmse) + " | " +
             format("%.2f%%", 100.0 * r.comparison.mare) + " | " + format("%.2f%%", 100.0 * r.comparison.block_mare) + " |\n";
    return t + "\nReference: " + reference_label + ".\n";
}

Image methods_contact_sheet(const std::vector<MethodRun>& runs, const RenderResult& reference,
                            const std::vector<std::string>& reference_caption, float heatmap_range) {
    const int pad = 8, line = draw::GlyphHeight + 4;
    std::vector<Image> images{tonemap_srgb(reference.image)}, heatmaps{Image()};
    std::vector<std::vector<std::string>> top{reference_caption}, bottom{{}};
    for (const MethodRun& r : runs) {
        images.push_back(tonemap_srgb(r.result.image));
        heatmaps.push_back(relative_difference_heatmap(r.result.image, reference.image, heatmap_range));
        top.push_back(
            {r.label, format("%.3f S", r.result.stats.seconds), r.bake_seconds > 0.0 ? format("(BAKE %.3f S)", r.bake_seconds) : ""});
        bottom.push_back({"RELMSE " + format("%.4g", r.comparison.relmse),
                          "BLOCK MARE " + format("%.1f%%", 100.0 * r.comparison.block_mare),
                          "MEAN " + format("%+.1f%%", 100.0 * mean_luminance_difference(r.comparison))});
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

}  // namespace candela
