// candela estimate irradiance SCENE.xml --at x,y,z --normal x,y,z [-n N] [--seed S] [-D k=v]...
// candela estimate radiance SCENE.xml --origin x,y,z --direction x,y,z [-n N] [--seed S] [-D k=v]...
// Prints the RGB estimate, its standard error, a 95% confidence interval and the luminance.
// -n (--sample-count) is the number of samples; --samples N, its older name, still works with a
// warning, as `render --samples` means a range of sample indices.

#include "apps/commands.h"

#include "core/error.h"
#include "core/scene.h"
#include "core/warning.h"
#include "integrators/estimators.h"

#include <cstdio>

namespace candela::app {

namespace {

struct EstimateArgs {
    SceneInput input;
    std::string at, normal, origin, direction, light_sampler = DefaultLightSampler;
    int64_t samples = 65536, seed = 0;
    int max_depth = -1, threads = 0;
};

void print_estimate(const char* quantity, const char* unit, const Estimate& e) {
    std::printf("%s (%llu samples)\n", quantity, (unsigned long long)e.samples);
    std::printf("  RGB              %.6g %.6g %.6g %s\n", e.mean.x, e.mean.y, e.mean.z, unit);
    std::printf("  standard error   %.3g %.3g %.3g\n", e.std_error.x, e.std_error.y, e.std_error.z);
    Spectrum lo = e.ci95_low(), hi = e.ci95_high();
    std::printf("  95%% interval     R [%.6g, %.6g]  G [%.6g, %.6g]  B [%.6g, %.6g]\n", lo.x, hi.x, lo.y, hi.y, lo.z, hi.z);
    std::printf("  luminance        %.6g +- %.3g %s (95%%: [%.6g, %.6g])\n", e.luminance, e.luminance_std_error, unit,
                e.luminance - Estimate::Z95 * e.luminance_std_error, e.luminance + Estimate::Z95 * e.luminance_std_error);
    if (e.nonfinite) std::printf("  warning          %llu non-finite samples dropped\n", (unsigned long long)e.nonfinite);
}

void add_common(CLI::App* cmd, EstimateArgs& a) {
    a.input.add_to(cmd);
    const CLI::Validator count = whole_number("-n", "samples", 1, LLONG_MAX);
    cmd->add_option("-n,--sample-count", a.samples, "Number of samples (default 65536)")->check(count);
    // The older name: `render --samples` is a range of sample indices, so this one goes.
    cmd->add_option("--samples", a.samples, "Old name of -n (deprecated)")->check(count)->group("")->each([](const std::string& text) {
        warn(SourceLocation{}, "--samples " + text +
                                   ": estimate's --samples is now -n (or --sample-count); the old name goes away "
                                   "in the next release (render --samples means a range of sample indices)");
    });
    add_seed_option(cmd, a.seed, "default 0");
    cmd->add_option("--max-depth", a.max_depth, "Longest path in segments, -1 unbounded (default -1)")
        ->check(whole_number("--max-depth", "segments", -1, INT_MAX));
    cmd->add_option("--light-sampler", a.light_sampler,
                    "How next-event estimation picks a light (default " + std::string(DefaultLightSampler) + ")")
        ->check(one_of("--light-sampler", light_sampler_names()));
    add_threads_option(cmd, a.threads);
}

// The command-line spelling of a parameter name: light_sampler -> light-sampler.
std::string dashed(std::string name) {
    std::replace(name.begin(), name.end(), '_', '-');
    return name;
}

EstimatorOptions options_from(const EstimateArgs& a) {
    EstimatorOptions o;
    o.samples = uint64_t(a.samples);
    o.seed = uint64_t(a.seed);
    o.path.max_depth = a.max_depth;
    o.path.light_sampler = a.light_sampler;
    o.threads = a.threads;
    // Checked before the scene loads, with the option's name.
    if (auto problem = check_path_settings(o.path)) throw InputError("--" + dashed(problem->parameter) + ": " + problem->message);
    return o;
}

}  // namespace

void add_estimate_command(CLI::App& app, std::function<int()>& run) {
    CLI::App* cmd = app.add_subcommand("estimate", "Measure irradiance at a point or radiance along a ray, with error bars");
    cmd->require_subcommand(1);

    auto irr = std::make_shared<EstimateArgs>();
    CLI::App* irradiance = cmd->add_subcommand("irradiance", "Irradiance (W/m^2) arriving at a point on a surface with the given normal");
    add_common(irradiance, *irr);
    irradiance->add_option("--at", irr->at, "The point x,y,z")->required();
    irradiance->add_option("--normal", irr->normal, "The surface normal x,y,z")->required();
    irradiance->callback([irr, &run] {
        run = [irr] {
            Vec3 p = parse_triple(irr->at, "--at"), n = parse_triple(irr->normal, "--normal");
            if (squared_length(n) == 0.0f) throw InputError("--normal must not be zero");
            EstimatorOptions o = options_from(*irr);
            Ref<Scene> scene = irr->input.load();
            Estimate e = estimate_irradiance(*scene, p, n, o);
            n = glm::normalize(n);
            std::printf("irradiance at (%g, %g, %g), normal (%g, %g, %g)\n", p.x, p.y, p.z, n.x, n.y, n.z);
            print_estimate("estimate", "W/m^2", e);
            return ExitOk;
        };
    });

    auto rad = std::make_shared<EstimateArgs>();
    CLI::App* radiance = cmd->add_subcommand("radiance", "Radiance (W/m^2/sr) arriving at a point from a direction");
    add_common(radiance, *rad);
    radiance->add_option("--origin", rad->origin, "Where the ray starts, x,y,z")->required();
    radiance->add_option("--direction", rad->direction, "The direction looked in, x,y,z")->required();
    radiance->callback([rad, &run] {
        run = [rad] {
            Vec3 o = parse_triple(rad->origin, "--origin"), d = parse_triple(rad->direction, "--direction");
            if (squared_length(d) == 0.0f) throw InputError("--direction must not be zero");
            EstimatorOptions opt = options_from(*rad);
            Ref<Scene> scene = rad->input.load();
            Estimate e = estimate_radiance(*scene, o, d, opt);
            d = glm::normalize(d);
            std::printf("radiance along (%g, %g, %g) + t (%g, %g, %g)\n", o.x, o.y, o.z, d.x, d.y, d.z);
            print_estimate("estimate", "W/m^2/sr", e);
            return ExitOk;
        };
    });
}

}  // namespace candela::app
