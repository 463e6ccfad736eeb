#pragma once
// Convergence of a Monte Carlo render to a known answer (what `candela converge` reports): the
// scene is rendered at growing sample counts with independent seeds; each render's error against
// an exact value or a reference image is measured (RMSE with its standard error, relMSE, and the
// bias with a Sidak-corrected confidence interval); the log-log slope of RMSE against spp is fitted
// (-1/2 for an unbiased estimator) and the convergence plot drawn.

#include "core/image.h"
#include "core/integrator.h"

#include <functional>
#include <string>
#include <vector>

namespace candela {

class Scene;

// What every pixel should converge to: a constant or a reference image.
struct ConvergenceTarget {
    const Image* reference = nullptr;  // when null, every pixel and channel converges to `value`
    double value = 0.0;
    double scale = 0.0;            // magnitude of the answer, for float32 allowances
    double reference_noise = 0.0;  // mean variance of the reference's pixels (its variance layers), else 0
};
ConvergenceTarget constant_target(double value);
// The reference must stay alive while the target is used.
ConvergenceTarget reference_target(const Image& reference);

// The error of one render. Pixels are the independent units: each pixel's squared and signed
// errors are averaged over RGB, and their spread across pixels gives the standard errors.
struct CountError {
    int spp = 0;
    double rmse = 0, rmse_se = 0, relmse = 0, bias = 0, bias_se = 0, seconds = 0;
};
CountError measure_error(const Image& render, const ConvergenceTarget& target);

// Weighted least-squares slope of ln RMSE against ln spp, each point weighted by the inverse
// variance of its ln RMSE ((RMSE / SE)^2 by the delta method), with the reference's own noise
// taken out of the MSE first. Below 1e-4 relative the error is float32 rounding, not Monte Carlo
// noise, and has no reason to fall as N^-1/2: when every count is there, no slope applies.
struct SlopeFit {
    enum class Status { Fitted, NoVariance, TooFewPoints } status = Status::TooFewPoints;
    double slope = 0.0, slope_se = 0.0;
    double rounding_floor = 0.0;  // RMSE below which an error counts as rounding
};
SlopeFit fit_convergence_slope(const std::vector<CountError>& counts, const ConvergenceTarget& target);

struct ConvergenceCriteria {
    double alpha = 0.01;  // family-wise significance of the bias tests
    double slope_low = -0.55, slope_high = -0.45;
};

struct ConvergenceStudy {
    std::vector<CountError> counts;
    SlopeFit slope;
    double bias_z = 0.0;                // |bias| / SE beyond which a bias is significant (Sidak over the counts)
    double slope_z = 0.0;               // standard errors by which the slope must leave the accepted range
    std::vector<std::string> failures;  // empty when the render converges as it should
};

// Renders `scene` with its own integrator at each of `spp_counts` with the options `base` (count
// i with seed base.seed + i, or 0 + i) and judges the result: a bias is significant beyond bias_z
// standard errors plus a float32 allowance of 1e-5 relative; the slope fails when it lies
// outside the accepted range by more than slope_z of its standard errors. Each count's spp is
// the one rendered (samplers may round a count up). `on_count` sees each count as soon as it is
// measured.
ConvergenceStudy study_convergence(const Scene& scene, const ConvergenceTarget& target, const std::vector<int>& spp_counts,
                                   const RenderOptions& base, const ConvergenceCriteria& criteria,
                                   const std::function<void(const CountError&, double bias_z)>& on_count = nullptr);

// The log-log plot of measured RMSE against spp beside the ideal N^-1/2 line through the first
// count; ".svg" writes SVG, anything else a PNG.
void write_convergence_plot(const std::vector<CountError>& counts, const std::string& path);

}  // namespace candela
