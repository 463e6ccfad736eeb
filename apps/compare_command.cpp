// candela compare A.exr B.exr [--heatmap OUT.png] [--heatmap-range R] [--tolerance T]
//                 [--block-tolerance B] [--pixel-tolerance P] [--allow-ldr]
// Compares a test image A against a reference B. With --tolerance the exit code says whether
// they agree: 0 yes, 1 no (channel means within T, 16x16 block luminance within B, default 2T).
// With --pixel-tolerance every pixel of every layer must agree within relative difference P
// (e.g. 1e-5: a merged farm render against the single-machine one). Radiance metrics need
// radiance: an 8- or 16-bit image (a --png preview, a JPEG) holds tonemapped, sRGB-encoded display
// values, so compare refuses one (exit 2) unless --allow-ldr says to compare the values as they are.

#include "apps/commands.h"

#include "analysis/image_metrics.h"
#include "core/error.h"

#include <cstdio>

namespace candela::app {

namespace {
struct CompareArgs {
    std::string a, b, heatmap;
    double tolerance = -1.0, block_tolerance = -1.0, pixel_tolerance = -1.0, range = 0.1;
    bool allow_ldr = false;
};

// An image of 8- or 16-bit integers holds display values (tonemapped, sRGB-encoded), not radiance.
void check_radiance(const Image& image, const std::string& path, const std::string& role, bool allow_ldr) {
    if (image.integer_bits == 0 || allow_ldr) return;
    throw InputError(path + ": the " + role + " is a " + std::to_string(image.integer_bits) +
                     "-bit image: tonemapped, sRGB-encoded display values (a --png preview, a JPEG), not radiance, so the "
                     "errors would mean nothing; compare against the EXR, or give --allow-ldr to compare the values as they are");
}

int check_pixels(const Image& a, const Image& b, double tolerance) {
    PixelDifference d = max_pixel_relative_difference(a, b);
    std::printf("max pixel rel. diff  %.3g", d.max_relative);
    if (d.x >= 0) std::printf(" at (%d, %d)%s%s", d.x, d.y, d.layer.empty() ? "" : " in ", d.layer.c_str());
    bool agree = d.max_relative <= tolerance;
    std::printf("\nagree                %s\n", agree ? "yes" : "no");
    return agree ? ExitOk : ExitCheckFailed;
}

}  // namespace

void add_compare_command(CLI::App& app, std::function<int()>& run) {
    auto args = std::make_shared<CompareArgs>();
    CLI::App* cmd = app.add_subcommand("compare", "Compare an image against a reference: RMSE, relMSE, relative errors");
    cmd->add_option("test", args->a, "Image to check (EXR or any OpenImageIO format)")->required();
    cmd->add_option("reference", args->b, "Reference image")->required();
    cmd->add_option("--heatmap", args->heatmap, "Write a relative-difference heatmap (PNG) with a legend");
    cmd->add_option("--heatmap-range", args->range, "Relative difference at full colour (default 0.1 = 10%)")
        ->check(positive_number("--heatmap-range"));
    cmd->add_option("--tolerance", args->tolerance,
                    "Agreement check: channel means within this relative tolerance, a fraction (e.g. 0.01 = 1%; default: no check)")
        ->check(non_negative_number("--tolerance"));
    cmd->add_option("--block-tolerance", args->block_tolerance, "Block luminance tolerance, a fraction (default: twice --tolerance)")
        ->check(non_negative_number("--block-tolerance"));
    cmd->add_option("--pixel-tolerance", args->pixel_tolerance,
                    "Pixel check: every pixel of every layer within this relative difference (e.g. 1e-5; default: no check)")
        ->check(non_negative_number("--pixel-tolerance"));
    cmd->add_flag("--allow-ldr", args->allow_ldr,
                  "Compare 8- or 16-bit images (display values, e.g. a --png preview) as they are instead of refusing them");
    cmd->callback([args, &run] {
        run = [args] {
            if (!args->heatmap.empty()) check_output_path(args->heatmap);
            Image a = read_image(args->a), b = read_image(args->b);
            check_radiance(a, args->a, "test image", args->allow_ldr);
            check_radiance(b, args->b, "reference", args->allow_ldr);
            if (args->pixel_tolerance >= 0.0) return check_pixels(a, b, args->pixel_tolerance);
            ImageComparison c = compare_images(a, b);
            std::printf("size            %d x %d\n", c.width, c.height);
            std::printf("mean (test)     %.6g %.6g %.6g\n", c.mean_test.x, c.mean_test.y, c.mean_test.z);
            std::printf("mean (ref)      %.6g %.6g %.6g\n", c.mean_reference.x, c.mean_reference.y, c.mean_reference.z);
            std::printf("mean rel. diff  %+.3f%% %+.3f%% %+.3f%%\n", 100 * c.mean_relative_difference.x, 100 * c.mean_relative_difference.y,
                        100 * c.mean_relative_difference.z);
            std::printf("RMSE            %.6g\n", c.rmse);
            std::printf("relMSE          %.6g\n", c.relmse);
            std::printf("MARE            %.3f%% (mean absolute relative error)\n", 100 * c.mare);
            std::printf("block MARE      %.3f%% (%d of %d 16x16 blocks)\n", 100 * c.block_mare, c.blocks_used, c.blocks_total);
            if (!args->heatmap.empty()) {
                write_png_display(relative_difference_heatmap(a, b, float(args->range)), args->heatmap);
                std::printf("heatmap         wrote %s (relative difference, full colour at %g%%)\n", args->heatmap.c_str(),
                            100 * args->range);
            }
            if (args->tolerance < 0.0) return ExitOk;
            AgreementThresholds t;
            t.mean = args->tolerance;
            t.block = args->block_tolerance >= 0.0 ? args->block_tolerance : 2.0 * args->tolerance;
            std::string reason;
            if (images_agree(c, t, &reason)) {
                std::printf("agree           yes\n");
                return ExitOk;
            }
            std::printf("agree           no: %s\n", reason.c_str());
            return ExitCheckFailed;
        };
    });
}

}  // namespace candela::app
