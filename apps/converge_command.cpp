// candela converge SCENE.xml [--expect VALUE | --reference REF.exr] [--spp 1,4,16,...]
//                  [--plot convergence.svg|png] [--alpha 0.01] [--slope-range -0.55,-0.45]
//
// Renders the scene at each sample count with independent seeds and reports, per count, the
// error against the exact value (from --expect, or the scene's own `expected` parameter) or a
// reference image: RMSE with its standard error, relMSE, and the bias (mean error) with a
// confidence interval. It fits the log-log slope of RMSE against spp (-1/2 for an unbiased Monte
// Carlo estimator; a fit weighted by each count's own uncertainty) and exits with 1 when the
// bias is significant at any count (Sidak-corrected
// two-sided z-test at --alpha, beyond a float32 allowance of 1e-5 relative) or the slope lies
// outside the accepted range by more than z times its standard error. Estimators without variance (errors at float32 rounding level,
// below 1e-4 relative, at every count) are exempt from the slope test.

#include "apps/commands.h"

#include "core/error.h"
#include "analysis/expression.h"
#include "analysis/image_metrics.h"
#include "analysis/plot.h"
#include "core/scene.h"
#include "analysis/statistics.h"

#include <cstdio>
#include <sstream>

namespace candela::app {

namespace {

struct ConvergeArgs {
    std::string scene, reference, plot, spp_list = "1,4,16,64,256,1024", slope_range = "-0.55,-0.45";
    std::vector<std::string> defines;
    double expect = NAN, alpha = 0.01;
    int64_t seed = 0;
    int threads = 0;
};

struct CountResult {
    int spp;
    double rmse, rmse_se, relmse, bias, bias_se, seconds;
};

std::vector<int> parse_counts(const std::string& text) {
    std::vector<int> counts;
    std::stringstream ss(text);
    for (std::string item; std::getline(ss, item, ',');) {
        char* end = nullptr;
        long v = std::strtol(item.c_str(), &end, 10);
        if (item.empty() || *end != '\0' || v <= 0) throw InputError("--spp expects positive integers separated by commas, got \"" + text + "\"");
        counts.push_back(int(v));
    }
    if (counts.size() < 2) throw InputError("--spp needs at least two sample counts to fit a slope");
    for (size_t i = 1; i < counts.size(); ++i)
        if (counts[i] <= counts[i - 1]) throw InputError("--spp must increase");
    return counts;
}

// Error statistics of one render against the target (a constant or a reference image). Pixels
// are the independent units: each pixel's squared and signed errors are averaged over RGB.
CountResult measure(const Image& img, const Image* ref, double value) {
    size_t n = size_t(img.width()) * img.height();
    double s_sum = 0, s_sq = 0, b_sum = 0, b_sq = 0, rel = 0;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            double s = 0, b = 0;
            for (int c = 0; c < 3; ++c) {
                double v = ref ? ref->at(x, y, c) : value, e = img.at(x, y, c) - v;
                s += e * e / 3.0;
                b += e / 3.0;
                rel += e * e / (v * v + 0.01) / 3.0;
            }
            s_sum += s;
            s_sq += s * s;
            b_sum += b;
            b_sq += b * b;
        }
    CountResult r{};
    double mse = s_sum / n;
    double mse_se = std::sqrt(std::max(0.0, (s_sq / n - mse * mse) / double(n - 1)));
    r.rmse = std::sqrt(mse);
    r.rmse_se = r.rmse > 0 ? mse_se / (2.0 * r.rmse) : 0.0;
    r.relmse = rel / n;
    r.bias = b_sum / n;
    r.bias_se = std::sqrt(std::max(0.0, (b_sq / n - r.bias * r.bias) / double(n - 1)));
    return r;
}

}  // namespace

void add_converge_command(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<ConvergeArgs>();
    CLI::App* cmd = app.add_subcommand("converge", "Convergence test against an exact value or a reference image");
    cmd->add_option("scene", a->scene, "Scene file (Mitsuba 3 XML)")->required();
    auto* expect = cmd->add_option("--expect", a->expect, "Exact value every pixel should converge to (default: the scene's `expected` parameter)");
    cmd->add_option("--reference", a->reference, "Reference image to converge to instead")->excludes(expect);
    cmd->add_option("--spp", a->spp_list, "Sample counts, comma separated (default 1,4,16,64,256,1024)");
    cmd->add_option("--plot", a->plot, "Write a log-log convergence plot (.svg or .png)");
    cmd->add_option("--alpha", a->alpha, "Family-wise significance of the bias tests (default 0.01)")->check(CLI::Range(1e-9, 0.5));
    cmd->add_option("--slope-range", a->slope_range, "Accepted log-log slope range (default -0.55,-0.45)");
    cmd->add_option("--seed", a->seed, "Base seed; count i renders with seed + i (default 0)")->check(CLI::NonNegativeNumber);
    cmd->add_option("-D", a->defines, "Set a scene parameter: -D name=value (repeatable)")->take_all();
    cmd->add_option("--threads,-t", a->threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
    cmd->callback([a, &run] {
        run = [a] {
            std::vector<int> counts = parse_counts(a->spp_list);
            double slope_lo, slope_hi;
            char extra;
            if (std::sscanf(a->slope_range.c_str(), " %lf , %lf %c", &slope_lo, &slope_hi, &extra) != 2 || !(slope_lo < slope_hi))
                throw InputError("--slope-range expects two increasing numbers lo,hi");
            if (!a->plot.empty()) check_output_path(a->plot);
            Ref<Scene> scene = load_scene(a->scene, parse_defines(a->defines));
            Image reference;
            double value = a->expect;
            std::string target;
            if (!a->reference.empty()) {
                reference = read_image(a->reference);
                Vec2i size = scene->sensor().film().crop_size();
                if (reference.width() != size.x || reference.height() != size.y || reference.channel_count() < 3)
                    throw InputError(a->reference + ": reference is not an RGB image of the film's size");
                target = "reference " + a->reference;
            } else {
                if (std::isnan(value)) {
                    auto it = scene->parameters.find("expected");
                    if (it == scene->parameters.end())
                        throw InputError(a->scene + ": no --expect or --reference given, and the scene states no `expected` parameter");
                    value = evaluate_expression(it->second);
                    target = "exact value " + it->second + " = " + std::to_string(value);
                } else {
                    target = "exact value " + std::to_string(value);
                }
            }
            const Image* ref = a->reference.empty() ? nullptr : &reference;
            double scale = ref ? std::max(1e-12, double(std::abs(luminance(compare_images(reference, reference).mean_reference)))) : std::abs(value);
            // A reference with its own variance layers: subtract its noise from the MSE.
            double ref_noise = 0.0;
            if (ref && reference.channel_index("variance.R") >= 0) {
                Image v = reference.select_channels({"variance.R", "variance.G", "variance.B"});
                for (float x : v.data()) ref_noise += x;
                ref_noise /= double(v.data().size());
            }

            std::printf("%s converging to %s\n\n", a->scene.c_str(), target.c_str());
            std::printf("%8s  %12s  %10s  %12s  %13s  %27s  %8s\n", "spp", "RMSE", "+- SE", "relMSE", "bias", "bias CI (Sidak)", "time");
            const double z = two_sided_z(sidak(a->alpha, int(counts.size())));
            const double float_allowance = 1e-5 * scale;
            std::vector<CountResult> results;
            std::vector<std::string> failures;
            for (size_t i = 0; i < counts.size(); ++i) {
                RenderOptions o;
                o.spp = counts[i];
                o.seed = uint64_t(a->seed) + i;
                o.threads = a->threads;
                RenderResult r = scene->integrator().render(*scene, o);
                CountResult c = measure(r.image, ref, value);
                c.spp = counts[i];
                c.seconds = r.stats.seconds;
                results.push_back(c);
                std::printf("%8d  %12.6g  %10.3g  %12.6g  %+13.6g  [%+12.6g, %+12.6g]  %7.2fs\n", c.spp, c.rmse, c.rmse_se, c.relmse, c.bias,
                            c.bias - z * c.bias_se, c.bias + z * c.bias_se, c.seconds);
                if (std::abs(c.bias) > z * c.bias_se + float_allowance) {
                    char buf[256];
                    std::snprintf(buf, sizeof buf, "bias %+.6g at %d spp is significant (%.1f standard errors; threshold %.2f)", c.bias, c.spp,
                                  c.bias_se > 0 ? std::abs(c.bias) / c.bias_se : INFINITY, z);
                    failures.push_back(buf);
                }
            }
            // Least-squares slope of log RMSE against log spp (with the reference's noise taken out).
            // Below 1e-4 relative the error is float32 rounding (accumulating thousands of samples),
            // not Monte Carlo noise, and has no reason to fall as N^-1/2.
            const double rounding_floor = 1e-4 * scale;
            bool exact_everywhere = true;
            // Weighted least squares of ln RMSE against ln spp: each point weighted by the inverse
            // variance of its ln RMSE, (RMSE / SE)^2 by the delta method (the reference's own
            // noise, when known, taken out of the MSE first).
            std::vector<double> lx, ly, w;
            for (const auto& c : results) {
                if (c.rmse > rounding_floor) exact_everywhere = false;
                double mse = c.rmse * c.rmse - ref_noise;
                if (mse <= 0.0 || c.rmse_se <= 0.0) continue;
                double mse_se = 2.0 * c.rmse * c.rmse_se;
                lx.push_back(std::log(double(c.spp)));
                ly.push_back(0.5 * std::log(mse));
                double sigma = 0.5 * mse_se / mse;
                w.push_back(1.0 / (sigma * sigma));
            }
            std::printf("\n");
            if (exact_everywhere) {
                std::printf("slope            not applicable: the error is at float32 rounding level (below %.3g) at every sample count; "
                            "the estimator has no Monte Carlo variance here\n", rounding_floor);
            } else if (lx.size() < 2) {
                failures.push_back("too few sample counts with a measurable error to fit a slope");
            } else {
                double sw = 0, mx = 0, my = 0;
                for (size_t i = 0; i < lx.size(); ++i) sw += w[i], mx += w[i] * lx[i], my += w[i] * ly[i];
                mx /= sw;
                my /= sw;
                double sxx = 0, sxy = 0;
                for (size_t i = 0; i < lx.size(); ++i) sxx += w[i] * (lx[i] - mx) * (lx[i] - mx), sxy += w[i] * (lx[i] - mx) * (ly[i] - my);
                double slope = sxy / sxx, slope_se = std::sqrt(1.0 / sxx);
                // The slope must be shown to lie outside the accepted range before it fails: by
                // more than the z-threshold times its standard error.
                double z_slope = two_sided_z(a->alpha);
                std::printf("slope            %.4f +- %.4f (weighted fit of log RMSE vs log spp; expected -0.5, accepted [%g, %g] within %.2f standard errors)\n",
                            slope, slope_se, slope_lo, slope_hi, z_slope);
                if (slope < slope_lo - z_slope * slope_se || slope > slope_hi + z_slope * slope_se) {
                    char buf[256];
                    std::snprintf(buf, sizeof buf, "slope %.4f +- %.4f lies outside [%g, %g]", slope, slope_se, slope_lo, slope_hi);
                    failures.push_back(buf);
                }
            }
            if (ref_noise > 0) std::printf("reference noise  %.6g subtracted from the MSE before fitting\n", ref_noise);

            if (!a->plot.empty()) {
                LogLogPlot plot;
                plot.title = "Convergence";
                plot.x_label = "samples per pixel";
                plot.y_label = "RMSE";
                PlotSeries measured{"measured RMSE", {}, {}, Spectrum(0.1f, 0.3f, 0.8f)}, ideal{"ideal N^-1/2", {}, {}, Spectrum(0.8f, 0.2f, 0.1f), true, false};
                for (const auto& c : results) {
                    measured.x.push_back(c.spp);
                    measured.y.push_back(c.rmse);
                    ideal.x.push_back(c.spp);
                    ideal.y.push_back(results.front().rmse * std::sqrt(double(results.front().spp) / c.spp));
                }
                plot.series = {measured, ideal};
                plot.write(a->plot);
                std::printf("plot             %s\n", a->plot.c_str());
            }
            if (failures.empty()) {
                std::printf("result           PASS\n");
                return ExitOk;
            }
            for (const auto& f : failures) std::printf("result           FAIL: %s\n", f.c_str());
            return ExitCheckFailed;
        };
    });
}

}  // namespace candela::app
