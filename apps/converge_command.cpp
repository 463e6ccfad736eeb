// candela converge SCENE.xml [--expect VALUE | --reference REF.exr] [--spp 1,4,16,...]
//                  [--plot convergence.svg|png] [--alpha 0.01] [--slope-range LO,HI]
//                  [--sampler NAME] [--adaptive-threshold T ...]
//
// Renders the scene at each sample count with independent seeds and reports, per count, the
// error against the exact value (from --expect, or the scene's own `expected` parameter) or a
// reference image: RMSE with its standard error, relMSE, and the bias (mean error) with a
// Sidak-corrected confidence interval; then the fitted log-log slope of RMSE against spp. Exits
// with 1 when the bias is significant at any count or the slope lies outside its range: -1/2
// (accepted [-0.55, -0.45]) for the independent sampler; for the stratified and low-discrepancy
// samplers never slower than -1/2 and, as scrambled nets converge at best as N^-3/2 on smooth
// integrands (Owen 1997), accepted [-1.5, -0.45]. It also says whether the slope is
// significantly faster than -1/2. (The criteria are in analysis/convergence.h, which does the
// work; this file is the command line.)

#include "apps/commands.h"

#include "analysis/convergence.h"
#include "analysis/expression.h"
#include "core/error.h"
#include "core/scene.h"
#include "core/text.h"

#include <climits>
#include <cstdio>
#include <sstream>

namespace candela::app {

namespace {

struct ConvergeArgs {
    SceneInput input;
    std::string reference, plot, spp_list = "1,4,16,64,256,1024", slope_range, sampler;
    AdaptiveSampling adaptive;
    double expect = NAN, alpha = 0.01;
    int64_t seed = 0;
    int threads = 0;
};

std::vector<int> parse_counts(const std::string& text) {
    std::vector<int> counts;
    std::stringstream ss(text);
    for (std::string item; std::getline(ss, item, ',');) {
        long long v = 0;
        if (!parse_integer(item, v) || v <= 0 || v > INT_MAX)
            throw InputError("--spp expects positive integers separated by commas, got \"" + text + "\"");
        counts.push_back(int(v));
    }
    if (counts.size() < 2) throw InputError("--spp needs at least two sample counts to fit a slope");
    for (size_t i = 1; i < counts.size(); ++i)
        if (counts[i] <= counts[i - 1]) throw InputError("--spp must increase");
    return counts;
}

// The slope range: --slope-range, else -1/2 for the independent sampler and [-1.5, -0.45] for
// every other one (`sampler` is the one that renders).
ConvergenceCriteria parse_criteria(const ConvergeArgs& a, const std::string& sampler) {
    ConvergenceCriteria c;
    c.alpha = a.alpha;
    std::string range = !a.slope_range.empty() ? a.slope_range : sampler == "independent" ? "-0.55,-0.45" : "-1.5,-0.45";
    char extra;
    if (std::sscanf(range.c_str(), " %lf , %lf %c", &c.slope_low, &c.slope_high, &extra) != 2 || !(c.slope_low < c.slope_high))
        throw InputError("--slope-range expects two increasing numbers lo,hi");
    return c;
}

// The answer to converge to: --reference, --expect, or the scene's own `expected` parameter.
// `reference` holds the reference image the target points to; `description` says what it is.
ConvergenceTarget target_from(const ConvergeArgs& a, const Scene& scene, Image& reference, std::string& description) {
    if (!a.reference.empty()) {
        reference = read_image(a.reference);
        Vec2i size = scene.sensor().film().crop_size();
        if (reference.width() != size.x || reference.height() != size.y || reference.channel_count() < 3)
            throw InputError(a.reference + ": reference is not an RGB image of the film's size");
        description = "reference " + a.reference;
        return reference_target(reference);
    }
    if (!std::isnan(a.expect)) {
        description = "exact value " + std::to_string(a.expect);
        return constant_target(a.expect);
    }
    auto it = scene.parameters.find("expected");
    if (it == scene.parameters.end())
        throw InputError(a.input.scene + ": no --expect or --reference given, and the scene states no `expected` parameter");
    double value = evaluate_expression(it->second);
    description = "exact value " + it->second + " = " + std::to_string(value);
    return constant_target(value);
}

void print_slope(const SlopeFit& s, const ConvergenceCriteria& c, double slope_z) {
    if (s.status == SlopeFit::Status::NoVariance)
        std::printf(
            "slope            not applicable: the error is at float32 rounding level (below %.3g) at every sample count; "
            "the estimator has no Monte Carlo variance here\n",
            s.rounding_floor);
    else if (s.status == SlopeFit::Status::Fitted) {
        std::printf("slope            %.4f +- %.4f (weighted fit of log RMSE vs log spp; accepted [%g, %g] within %.2f standard errors)\n",
                    s.slope, s.slope_se, c.slope_low, c.slope_high, slope_z);
        bool faster = s.slope + slope_z * s.slope_se < -0.5;
        std::printf("faster than 1/2  %s\n", faster ? "yes: the slope lies below -0.5 by more than its standard errors allow"
                                                    : "no: the slope is -0.5 or slower within its standard errors");
    }
}

int converge(ConvergeArgs& a) {
    std::vector<int> counts = parse_counts(a.spp_list);
    if (!a.plot.empty()) check_output_path(a.plot);
    Ref<Scene> scene = a.input.load();
    ConvergenceCriteria criteria = parse_criteria(a, a.sampler.empty() ? scene->sensor().sampler().to_string() : a.sampler);
    Image reference;
    std::string description;
    ConvergenceTarget target = target_from(a, *scene, reference, description);

    std::printf("%s converging to %s\n\n", a.input.scene.c_str(), description.c_str());
    std::printf("%8s  %12s  %10s  %12s  %13s  %27s  %8s\n", "spp", "RMSE", "+- SE", "relMSE", "bias", "bias CI (Sidak)", "time");
    auto print_count = [](const CountError& c, double z) {
        std::printf("%8d  %12.6g  %10.3g  %12.6g  %+13.6g  [%+12.6g, %+12.6g]  %7.2fs\n", c.spp, c.rmse, c.rmse_se, c.relmse, c.bias,
                    c.bias - z * c.bias_se, c.bias + z * c.bias_se, c.seconds);
    };
    RenderOptions options;
    options.seed = uint64_t(a.seed);
    options.threads = a.threads;
    options.sampler = a.sampler;
    options.adaptive = a.adaptive;
    ConvergenceStudy study = study_convergence(*scene, target, counts, options, criteria, print_count);
    std::printf("\n");
    print_slope(study.slope, criteria, study.slope_z);
    if (target.reference_noise > 0) std::printf("reference noise  %.6g subtracted from the MSE before fitting\n", target.reference_noise);
    if (!a.plot.empty()) {
        write_convergence_plot(study.counts, a.plot);
        std::printf("plot             %s\n", a.plot.c_str());
    }
    if (study.failures.empty()) {
        std::printf("result           PASS\n");
        return ExitOk;
    }
    for (const auto& f : study.failures) std::printf("result           FAIL: %s\n", f.c_str());
    return ExitCheckFailed;
}

}  // namespace

void add_converge_command(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<ConvergeArgs>();
    CLI::App* cmd = app.add_subcommand("converge", "Convergence test against an exact value or a reference image");
    a->input.add_to(cmd);
    auto* expect =
        cmd->add_option("--expect", a->expect, "Exact value every pixel should converge to (default: the scene's `expected` parameter)");
    cmd->add_option("--reference", a->reference, "Reference image to converge to instead")->excludes(expect);
    cmd->add_option("--spp", a->spp_list, "Sample counts, comma separated (default 1,4,16,64,256,1024)");
    cmd->add_option("--plot", a->plot, "Write a log-log convergence plot (.svg or .png)");
    cmd->add_option("--alpha", a->alpha, "Family-wise significance of the bias tests, in (0, 0.5] (default 0.01)")
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                char* end = nullptr;
                const double v = std::strtod(text.c_str(), &end);
                if (text.empty() || *end != '\0' || !(v > 0.0 && v <= 0.5))
                    return "--alpha must be a significance level greater than 0 and at most 0.5 (got " + text + ")";
                return "";
            },
            ""));
    cmd->add_option("--slope-range", a->slope_range,
                    "Accepted log-log slope range (default -0.55,-0.45 for the independent sampler, -1.5,-0.45 for the others)");
    add_sampler_option(cmd, a->sampler);
    add_adaptive_options(cmd, a->adaptive);
    add_seed_option(cmd, a->seed, "default 0; count i renders with seed + i");
    add_threads_option(cmd, a->threads);
    cmd->callback([a, &run] { run = [a] { return converge(*a); }; });
}

}  // namespace candela::app
