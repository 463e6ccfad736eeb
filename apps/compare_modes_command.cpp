// candela compare-modes SCENE.xml -o compare.png [--spp N] [-D k=v]... [raster options]
//
// Renders the scene twice, with local illumination (the rasterizer) and with global illumination
// (the path tracer), and writes one picture: local, global, and the relative difference as a
// heatmap with a legend. Prints the time of each render and the error metrics of local against
// global.

#include "apps/commands.h"

#include "core/error.h"
#include "core/image_draw.h"
#include "analysis/image_metrics.h"
#include "core/scene.h"
#include "integrators/path.h"
#include "integrators/raster/raster.h"

#include <cstdio>
#include <map>

namespace candela::app {

namespace {
struct CompareModesArgs {
    std::string scene, output = "compare.png";
    std::vector<std::string> defines;
    int spp = 0, threads = 0;
    RasterOptionArgs raster;
    double range = 0.5;
};
}  // namespace

void add_compare_modes_command(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<CompareModesArgs>();
    CLI::App* cmd = app.add_subcommand("compare-modes", "Render local (raster) and global (path traced) illumination side by side");
    cmd->add_option("scene", a->scene, "Scene file (Mitsuba 3 XML)")->required();
    cmd->add_option("-o,--output", a->output, "The comparison picture (PNG, default compare.png)");
    cmd->add_option("--spp", a->spp, "Samples per pixel of the path tracer (default: the scene's)")->check(CLI::PositiveNumber);
    cmd->add_option("-D", a->defines, "Set a scene parameter: -D name=value (repeatable)")->take_all();
    cmd->add_option("--threads,-t", a->threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
    cmd->add_option("--heatmap-range", a->range, "Relative difference at full colour (default 0.5)")->check(CLI::PositiveNumber);
    a->raster.add_to(cmd);
    cmd->callback([a, &run] {
        run = [a] {
            check_output_path(a->output);
            Ref<Scene> scene = load_scene(a->scene, parse_defines(a->defines));
            RasterSettings settings;
            if (auto* r = dynamic_cast<RasterIntegrator*>(&scene->integrator())) settings = r->settings();
            a->raster.apply(settings);
            RenderOptions options;
            options.threads = a->threads;
            RasterIntegrator raster(settings);
            RenderResult local = raster.render(*scene, options);
            // The scene's own path tracer when it has one, else a default one.
            Ref<Integrator> path = scene->integrator().to_string() == "path" ? nullptr : std::make_shared<PathIntegrator>(PathSettings{});
            Integrator& global_integrator = path ? *path : scene->integrator();
            options.spp = a->spp;
            RenderResult global = global_integrator.render(*scene, options);

            ImageComparison c = compare_images(local.image, global.image);
            std::printf("local illumination (raster)   %8.3f s\n", local.stats.seconds);
            std::printf("global illumination (path)    %8.3f s  (%d spp)\n", global.stats.seconds, global.stats.spp);
            std::printf("time ratio global / local     %8.1f\n", global.stats.seconds / std::max(local.stats.seconds, 1e-9));
            std::printf("mean (local)    %.6g %.6g %.6g\n", c.mean_test.x, c.mean_test.y, c.mean_test.z);
            std::printf("mean (global)   %.6g %.6g %.6g\n", c.mean_reference.x, c.mean_reference.y, c.mean_reference.z);
            std::printf("mean rel. diff  %+.2f%% %+.2f%% %+.2f%%\n", 100 * c.mean_relative_difference.x, 100 * c.mean_relative_difference.y,
                        100 * c.mean_relative_difference.z);
            std::printf("RMSE %.6g  relMSE %.6g  MARE %.6g  block MARE %.2f%%\n", c.rmse, c.relmse, c.mare, 100 * c.block_mare);

            // One picture: local | global | difference (with its legend), each under a title.
            Image l = tonemap_srgb(local.image), g = tonemap_srgb(global.image);
            Image heat = relative_difference_heatmap(local.image, global.image, float(a->range));
            const int pad = 8, title = draw::GlyphHeight * 2 + 2 * pad;
            int w = l.width() + g.width() + heat.width() + 4 * pad, h = std::max(l.height(), heat.height()) + title + pad;
            Image sheet = Image::rgb(w, h);
            draw::fill_rect(sheet, 0, 0, w, h, Spectrum(1.0f));
            int x = pad;
            for (auto [img, label] : {std::pair<const Image*, const char*>{&l, "LOCAL (RASTER)"}, {&g, "GLOBAL (PATH)"}, {&heat, "(LOCAL - GLOBAL) / GLOBAL"}}) {
                draw::text(sheet, x, pad, label, Spectrum(0.0f), 2);
                draw::blit(sheet, *img, x, title);
                x += img->width() + pad;
            }
            write_png_display(sheet, a->output);
            std::printf("wrote %s\n", a->output.c_str());
            return ExitOk;
        };
    });
}

}  // namespace candela::app
