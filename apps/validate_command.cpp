// candela validate DIR [--spp N] [--sampler NAME] [-o report.html] [--reference-spp 2048]
//
// Renders every scene NAME.xml in DIR (or in DIR/scenes, the layout of the shared validation set)
// that has a reference DIR/refs/NAME.exr, compares them by the validation criteria (channel
// means within 1%, 16x16 block luminance within 2%), runs a per-pixel z-test with the render's
// own variance, and writes one self-contained HTML report: a summary table, then per scene
// Candela's image, the reference and a relative-difference heatmap with a legend, and the
// metrics. The exit code is 0 when every scene passes, 1 otherwise. The work is done by
// analysis/validation.h; this file is the command line.

#include "apps/commands.h"

#include "analysis/validation.h"
#include "core/file_output.h"
#include "core/variant.h"

#include <cstdio>

namespace candela::app {

namespace {

struct ValidateArgs {
    std::string dir, report = "validation-report.html";
    ValidationSettings settings;
    int64_t seed = -1;
    std::string variant = "scalar_rgb";
    bool quiet = false;
};

void print_scene(const SceneValidation& r) {
    if (!r.compared) {
        std::printf("%-12s FAIL  not compared: %s\n", r.name.c_str(), r.reason.c_str());
        return;
    }
    std::printf(
        "%-12s %s  channel means %+.3f%% %+.3f%% %+.3f%%, block MARE %.3f%%; per-pixel z-test: %lld of %lld pixel channels beyond "
        "|z| = %.2f (largest |z| %.1f); %.1f s%s%s\n",
        r.name.c_str(), r.pass ? "pass" : "FAIL", 100 * r.metrics.mean_relative_difference.x, 100 * r.metrics.mean_relative_difference.y,
        100 * r.metrics.mean_relative_difference.z, 100 * r.metrics.block_mare, r.z.rejected, r.z.tested, r.z.threshold, r.z.max_abs_z,
        r.seconds, r.pass ? "" : ": ", r.reason.c_str());
}

int validate(ValidateArgs& a) {
    check_output_path(a.report);
    if (a.seed >= 0) a.settings.seed = a.seed;
    a.settings.variant = *parse_variant(a.variant);
    std::vector<ValidationCase> cases = find_validation_cases(a.dir);
    std::vector<SceneValidation> reports;
    for (const ValidationCase& c : cases) {
        reports.push_back(validate_scene(c, a.settings));
        if (!a.quiet) print_scene(reports.back());
    }
    write_file_atomically(a.report, validation_report_html(reports, a.settings));
    int passed = 0;
    for (const auto& r : reports) passed += r.pass;
    std::printf("%d of %zu scenes pass; wrote the report %s\n", passed, reports.size(), a.report.c_str());
    return passed == int(reports.size()) ? ExitOk : ExitCheckFailed;
}

}  // namespace

void add_validate_command(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<ValidateArgs>();
    ValidationSettings& s = a->settings;
    CLI::App* cmd = app.add_subcommand("validate", "Render every scene with a reference in DIR and report agreement as HTML");
    cmd->add_option("dir", a->dir, "Directory with NAME.xml (or scenes/NAME.xml) scenes and refs/NAME.exr references")->required();
    cmd->add_option("-o,--output", a->report, "HTML report to write (default validation-report.html)");
    cmd->add_option("--spp", s.spp, "Samples per pixel (default: each scene's own)")
        ->check(whole_number("--spp", "samples", 1, MaxSampleCount));
    add_sampler_option(cmd, s.sampler);
    cmd->add_option("--reference-spp", s.reference_spp, "Samples per pixel of the references, for their variance (default 2048)")
        ->check(whole_number("--reference-spp", "samples", 1, MaxSampleCount));
    cmd->add_option("--mean-tolerance", s.thresholds.mean, "Channel mean tolerance, a fraction (default 0.01 = 1%)")
        ->check(positive_number("--mean-tolerance"));
    cmd->add_option("--block-tolerance", s.thresholds.block, "Block luminance tolerance, a fraction (default 0.02 = 2%)")
        ->check(positive_number("--block-tolerance"));
    add_seed_option(cmd, a->seed, "default: each scene's sampler's");
    add_threads_option(cmd, s.threads);
    add_variant_option(cmd, a->variant);
    cmd->add_flag("--quiet,-q", a->quiet, "Only the summary line");
    cmd->callback([a, &run] { run = [a] { return validate(*a); }; });
}

}  // namespace candela::app
