#include "analysis/statistics.h"

#include <cmath>

namespace candela {

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

namespace {
// The continued fraction of I_x(a, b), evaluated where it converges fast (x < (a + 1) / (a + b + 2)).
double beta_continued_fraction(double a, double b, double x) {
    const double tiny = 1e-300;
    double qab = a + b, qap = a + 1.0, qam = a - 1.0;
    double c = 1.0, d = 1.0 - qab * x / qap;
    if (std::abs(d) < tiny) d = tiny;
    d = 1.0 / d;
    double h = d;
    for (int m = 1; m < 10000; ++m) {
        int m2 = 2 * m;
        double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        if (std::abs(d) < tiny) d = tiny;
        c = 1.0 + aa / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        h *= d * c;
        aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        if (std::abs(d) < tiny) d = tiny;
        c = 1.0 + aa / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (std::abs(del - 1.0) < 1e-15) break;
    }
    return h;
}
}  // namespace

double incomplete_beta(double a, double b, double x) {
    if (x <= 0.0) return 0.0;
    if (x >= 1.0) return 1.0;
    double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
    if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_continued_fraction(a, b, x) / a;
    return 1.0 - front * beta_continued_fraction(b, a, 1.0 - x) / b;
}

double student_t_two_sided_p(double t, double dof) {
    if (!(dof > 0.0)) return 1.0;
    return incomplete_beta(0.5 * dof, 0.5, dof / (dof + t * t));
}

WelchResult welch_test(const std::vector<double>& a, const std::vector<double>& b) {
    WelchResult r;
    MeanAndError ma = mean_and_error(a), mb = mean_and_error(b);
    double va = ma.std_error * ma.std_error, vb = mb.std_error * mb.std_error, v = va + vb;
    double diff = ma.mean - mb.mean;
    if (!(v > 0.0)) {
        r.p_value = diff == 0.0 ? 1.0 : 0.0;
        return r;
    }
    r.t = diff / std::sqrt(v);
    double na = double(a.size()), nb = double(b.size());
    r.dof = v * v / (va * va / (na - 1.0) + vb * vb / (nb - 1.0));
    r.p_value = student_t_two_sided_p(r.t, r.dof);
    return r;
}

double chi2_survival(double chi2, int dof) { return dof > 0 ? gamma_q(0.5 * dof, 0.5 * chi2) : 1.0; }

double sidak(double alpha, int tests) { return 1.0 - std::pow(1.0 - alpha, 1.0 / std::max(tests, 1)); }

double normal_quantile(double p) {
    // Acklam's approximation (relative error 1.15e-9), then one Newton-Raphson step.
    static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                               1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02, 6.680131188771972e+01,
                               -1.328068155288572e+01};
    static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                               -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
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
    size_t smallest = observed.size();  // the tested cell with the smallest expectation
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
        if (smallest == observed.size() || expected[i] < expected[smallest]) smallest = i;
    }
    auto term = [](double o, double e) { return (o - e) * (o - e) / e; };
    if (pooled_exp >= min_expected || (pooled_exp > 0.0 && cells == 0)) {
        r.chi2 += term(pooled_obs, pooled_exp);
        ++cells;
    } else if (pooled_exp > 0.0) {
        // A pooled cell still below min_expected would break the chi-square approximation: one
        // sample where 0.004 were expected adds 250 to chi2, a false failure that grows more
        // likely as the sample count falls. It joins the smallest tested cell instead (Cochran's
        // rule); mass observed where almost nothing was expected still shows as a large excess there.
        r.chi2 += term(observed[smallest] + pooled_obs, expected[smallest] + pooled_exp) - term(observed[smallest], expected[smallest]);
    } else if (pooled_obs > 0.0) {
        r.chi2 = INFINITY;  // samples where the pdf is zero
    }
    r.dof = std::max(cells - 1, 1);
    r.p_value = std::isinf(r.chi2) ? 0.0 : chi2_survival(r.chi2, r.dof);
    r.details = "chi2 = " + std::to_string(r.chi2) + ", dof = " + std::to_string(r.dof) + ", p = " + std::to_string(r.p_value) +
                ", pooled cells = " + std::to_string(r.pooled_cells);
    return r;
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

}  // namespace candela
