#include "analysis/convergence.h"

#include "analysis/image_metrics.h"
#include "analysis/plot.h"
#include "analysis/statistics.h"
#include "core/scene.h"

#include <cstdio>

namespace candela {

namespace {

// Relative share of the answer's scale within which float32 accumulation errors lie: 1e-5 for a
// mean (the bias allowance), 1e-4 for an RMSE (the rounding floor of the slope fit).
constexpr double BiasAllowance = 1e-5, RoundingFloor = 1e-4;

std::string bias_failure(const CountError& c, double z) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "bias %+.6g at %d spp is significant (%.1f standard errors; threshold %.2f)", c.bias, c.spp,
                  c.bias_se > 0 ? std::abs(c.bias) / c.bias_se : INFINITY, z);
    return buf;
}

}  // namespace

ConvergenceTarget constant_target(double value) {
    ConvergenceTarget t;
    t.value = value;
    t.scale = std::abs(value);
    return t;
}

ConvergenceTarget reference_target(const Image& reference) {
    ConvergenceTarget t;
    t.reference = &reference;
    t.scale = std::max(1e-12, double(std::abs(luminance(compare_images(reference, reference).mean_reference))));
    // A reference with its own variance layers: its noise is subtracted from the MSE.
    if (reference.channel_index("variance.R") >= 0) {
        Image v = reference.select_channels({"variance.R", "variance.G", "variance.B"});
        for (float x : v.data()) t.reference_noise += x;
        t.reference_noise /= double(v.data().size());
    }
    return t;
}

CountError measure_error(const Image& img, const ConvergenceTarget& target) {
    const Image* ref = target.reference;
    size_t n = size_t(img.width()) * img.height();
    double s_sum = 0, s_sq = 0, b_sum = 0, b_sq = 0, rel = 0;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            double s = 0, b = 0;
            for (int c = 0; c < 3; ++c) {
                double v = ref ? ref->at(x, y, c) : target.value, e = img.at(x, y, c) - v;
                s += e * e / 3.0;
                b += e / 3.0;
                rel += e * e / (v * v + 0.01) / 3.0;
            }
            s_sum += s;
            s_sq += s * s;
            b_sum += b;
            b_sq += b * b;
        }
    CountError r;
    double mse = s_sum / n;
    double mse_se = std::sqrt(std::max(0.0, (s_sq / n - mse * mse) / double(n - 1)));
    r.rmse = std::sqrt(mse);
    r.rmse_se = r.rmse > 0 ? mse_se / (2.0 * r.rmse) : 0.0;
    r.relmse = rel / n;
    r.bias = b_sum / n;
    r.bias_se = std::sqrt(std::max(0.0, (b_sq / n - r.bias * r.bias) / double(n - 1)));
    return r;
}

SlopeFit fit_convergence_slope(const std::vector<CountError>& counts, const ConvergenceTarget& target) {
    SlopeFit fit;
    fit.rounding_floor = RoundingFloor * target.scale;
    bool exact_everywhere = true;
    std::vector<double> lx, ly, w;
    for (const auto& c : counts) {
        if (c.rmse > fit.rounding_floor) exact_everywhere = false;
        double mse = c.rmse * c.rmse - target.reference_noise;
        if (mse <= 0.0 || c.rmse_se <= 0.0) continue;
        double mse_se = 2.0 * c.rmse * c.rmse_se;
        lx.push_back(std::log(double(c.spp)));
        ly.push_back(0.5 * std::log(mse));
        double sigma = 0.5 * mse_se / mse;
        w.push_back(1.0 / (sigma * sigma));
    }
    if (exact_everywhere) {
        fit.status = SlopeFit::Status::NoVariance;
        return fit;
    }
    if (lx.size() < 2) return fit;
    double sw = 0, mx = 0, my = 0;
    for (size_t i = 0; i < lx.size(); ++i) sw += w[i], mx += w[i] * lx[i], my += w[i] * ly[i];
    mx /= sw;
    my /= sw;
    double sxx = 0, sxy = 0;
    for (size_t i = 0; i < lx.size(); ++i) sxx += w[i] * (lx[i] - mx) * (lx[i] - mx), sxy += w[i] * (lx[i] - mx) * (ly[i] - my);
    fit.status = SlopeFit::Status::Fitted;
    fit.slope = sxy / sxx;
    fit.slope_se = std::sqrt(1.0 / sxx);
    return fit;
}

ConvergenceStudy study_convergence(const Scene& scene, const ConvergenceTarget& target, const std::vector<int>& spp_counts,
                                   const RenderOptions& base, const ConvergenceCriteria& criteria,
                                   const std::function<void(const CountError&, double bias_z)>& on_count) {
    ConvergenceStudy study;
    study.bias_z = two_sided_z(sidak(criteria.alpha, int(spp_counts.size())));
    study.slope_z = two_sided_z(criteria.alpha);
    for (size_t i = 0; i < spp_counts.size(); ++i) {
        RenderOptions o = base;
        o.spp = spp_counts[i];
        o.seed = base.seed.value_or(0) + i;
        RenderResult r = scene.integrator().render(scene, o);
        CountError c = measure_error(r.image, target);
        c.spp = r.stats.spp;
        c.seconds = r.stats.seconds;
        study.counts.push_back(c);
        if (on_count) on_count(c, study.bias_z);
        if (std::abs(c.bias) > study.bias_z * c.bias_se + BiasAllowance * target.scale)
            study.failures.push_back(bias_failure(c, study.bias_z));
    }
    study.slope = fit_convergence_slope(study.counts, target);
    const SlopeFit& s = study.slope;
    if (s.status == SlopeFit::Status::TooFewPoints) {
        study.failures.push_back("too few sample counts with a measurable error to fit a slope");
    } else if (s.status == SlopeFit::Status::Fitted &&
               (s.slope < criteria.slope_low - study.slope_z * s.slope_se || s.slope > criteria.slope_high + study.slope_z * s.slope_se)) {
        char buf[256];
        std::snprintf(buf, sizeof buf, "slope %.4f +- %.4f lies outside [%g, %g]", s.slope, s.slope_se, criteria.slope_low,
                      criteria.slope_high);
        study.failures.push_back(buf);
    }
    return study;
}

void write_convergence_plot(const std::vector<CountError>& counts, const std::string& path) {
    LogLogPlot plot;
    plot.title = "Convergence";
    plot.x_label = "samples per pixel";
    plot.y_label = "RMSE";
    PlotSeries measured{"measured RMSE", {}, {}, Spectrum(0.1f, 0.3f, 0.8f)},
        ideal{"ideal N^-1/2", {}, {}, Spectrum(0.8f, 0.2f, 0.1f), true, false};
    for (const auto& c : counts) {
        measured.x.push_back(c.spp);
        measured.y.push_back(c.rmse);
        ideal.x.push_back(c.spp);
        ideal.y.push_back(counts.front().rmse * std::sqrt(double(counts.front().spp) / c.spp));
    }
    plot.series = {measured, ideal};
    plot.write(path);
}

}  // namespace candela
