#include "tests/stats.h"

#include <cmath>

namespace candela::test {

double gamma_q(double a, double x) {
    if (x <= 0.0) return 1.0;
    double gln = std::lgamma(a);
    if (x < a + 1.0) {
        // Series for P(a, x).
        double ap = a, sum = 1.0 / a, del = sum;
        for (int n = 0; n < 10000; ++n) {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if (std::abs(del) < std::abs(sum) * 1e-15) break;
        }
        return 1.0 - sum * std::exp(-x + a * std::log(x) - gln);
    }
    // Continued fraction for Q(a, x) (modified Lentz).
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (std::abs(del - 1.0) < 1e-15) break;
    }
    return std::exp(-x + a * std::log(x) - gln) * h;
}

double chi2_survival(double chi2, int dof) { return dof > 0 ? gamma_q(0.5 * dof, 0.5 * chi2) : 1.0; }

double sidak(double alpha, int tests) { return 1.0 - std::pow(1.0 - alpha, 1.0 / std::max(tests, 1)); }

double normal_quantile(double p) {
    // Acklam's approximation (relative error 1.15e-9), then one Newton-Raphson step.
    static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                               1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                               6.680131188771972e+01, -1.328068155288572e+01};
    static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                               -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
    static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00, 3.754408661907416e+00};
    double q, r, x;
    if (p < 0.02425) {
        q = std::sqrt(-2 * std::log(p));
        x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) / ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    } else if (p <= 1 - 0.02425) {
        q = p - 0.5;
        r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
    } else {
        q = std::sqrt(-2 * std::log(1 - p));
        x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) / ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    }
    double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - p;
    double u = e * std::sqrt(2 * 3.14159265358979323846) * std::exp(x * x / 2);
    return x - u / (1 + x * u / 2);
}

ChiSquareResult chi_square(const std::vector<double>& observed, const std::vector<double>& expected, double min_expected) {
    ChiSquareResult r;
    double pooled_obs = 0.0, pooled_exp = 0.0;
    int cells = 0;
    for (size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] < min_expected) {
            pooled_obs += observed[i];
            pooled_exp += expected[i];
            ++r.pooled_cells;
            continue;
        }
        double d = observed[i] - expected[i];
        r.chi2 += d * d / expected[i];
        ++cells;
    }
    if (pooled_exp > 0.0) {
        double d = pooled_obs - pooled_exp;
        // A pooled cell too small to test keeps its (tiny) expectation; mass observed where
        // nothing was expected is still caught because d^2 / e grows without bound.
        r.chi2 += d * d / std::max(pooled_exp, 1e-12);
        ++cells;
    } else if (pooled_obs > 0.0) {
        r.chi2 = INFINITY;  // samples where the pdf is zero
    }
    r.dof = std::max(cells - 1, 1);
    r.p_value = chi2_survival(r.chi2, r.dof);
    r.details = "chi2 = " + std::to_string(r.chi2) + ", dof = " + std::to_string(r.dof) + ", p = " + std::to_string(r.p_value) +
                ", pooled cells = " + std::to_string(r.pooled_cells);
    return r;
}

SphericalHistogram::SphericalHistogram(int t, int p) : theta_bins(t), phi_bins(p), counts(size_t(t) * p, 0.0) {}

void SphericalHistogram::add(const Vec3& w) {
    // Bins uniform in cos(theta) over [-1, 1] (equal solid angle per cell) and in phi.
    double z = std::clamp(double(w.z), -1.0, 1.0);
    int ti = std::min(int((1.0 - z) * 0.5 * theta_bins), theta_bins - 1);
    double phi = std::atan2(double(w.y), double(w.x));
    if (phi < 0.0) phi += 2.0 * 3.14159265358979323846;
    int pi = std::min(int(phi / (2.0 * 3.14159265358979323846) * phi_bins), phi_bins - 1);
    counts[size_t(ti) * phi_bins + pi] += 1.0;
}

namespace {
// Adaptive Simpson quadrature (Lyness 1969): splits until the two halves agree, which resolves
// jumps of the integrand (hemisphere edges, cone cut-offs) inside a cell.
double adaptive_simpson(const std::function<double(double)>& f, double a, double b, double fa, double fm, double fb, double whole,
                        double eps, int depth) {
    double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    double flm = f(lm), frm = f(rm);
    double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm), right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    double delta = left + right - whole;
    if (depth <= 0 || std::abs(delta) <= 15.0 * eps) return left + right + delta / 15.0;
    return adaptive_simpson(f, a, m, fa, flm, fm, left, eps / 2.0, depth - 1) +
           adaptive_simpson(f, m, b, fm, frm, fb, right, eps / 2.0, depth - 1);
}

double integrate(const std::function<double(double)>& f, double a, double b, double eps, int depth) {
    // Start from a few panels so that a narrow feature is not missed by the first estimate.
    const int panels = 4;
    double sum = 0.0, h = (b - a) / panels;
    for (int i = 0; i < panels; ++i) {
        double x0 = a + i * h, x1 = x0 + h, xm = 0.5 * (x0 + x1);
        double f0 = f(x0), fm = f(xm), f1 = f(x1);
        sum += adaptive_simpson(f, x0, x1, f0, fm, f1, h / 6.0 * (f0 + 4.0 * fm + f1), eps / panels, depth);
    }
    return sum;
}
}  // namespace

std::vector<double> SphericalHistogram::expected(const std::function<double(const Vec3&)>& pdf, double samples) const {
    std::vector<double> out(counts.size(), 0.0);
    const double two_pi = 2.0 * 3.14159265358979323846;
    // dOmega = dz dphi: integrate the pdf over each (z, phi) cell, phi inside z.
    for (int ti = 0; ti < theta_bins; ++ti) {
        double z0 = 1.0 - 2.0 * (ti + 1) / theta_bins, z1 = 1.0 - 2.0 * ti / theta_bins;
        for (int pi = 0; pi < phi_bins; ++pi) {
            double p0 = two_pi * pi / phi_bins, p1 = two_pi * (pi + 1) / phi_bins;
            auto over_phi = [&](double z) {
                double r = std::sqrt(std::max(0.0, 1.0 - z * z));
                auto g = [&](double phi) { return pdf(Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z))); };
                return integrate(g, p0, p1, 1e-8, 12);
            };
            out[size_t(ti) * phi_bins + pi] = std::max(0.0, integrate(over_phi, z0, z1, 1e-7, 14)) * samples;
        }
    }
    return out;
}

MeanAndError mean_and_error(const std::vector<double>& v) {
    MeanAndError r;
    if (v.empty()) return r;
    double sum = 0.0;
    for (double x : v) sum += x;
    r.mean = sum / double(v.size());
    double ss = 0.0;
    for (double x : v) ss += (x - r.mean) * (x - r.mean);
    r.std_error = v.size() > 1 ? std::sqrt(ss / double(v.size() - 1) / double(v.size())) : 0.0;
    return r;
}

}  // namespace candela::test
