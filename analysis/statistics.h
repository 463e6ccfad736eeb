#pragma once
// Statistics for honest checks (tests, converge, validate): chi-square goodness of fit with
// p-values, Sidak-corrected significance levels, normal quantiles, means with standard errors.
// Thresholds come from an estimator's own variance and a stated significance.

#include "core/math.h"

#include <string>
#include <vector>

namespace candela {

// Regularised upper incomplete gamma function Q(a, x) (series for x < a + 1, else Lentz's
// continued fraction; Press et al., Numerical Recipes, section 6.2).
double gamma_q(double a, double x);
// P(X >= chi2) for a chi-square variable with `dof` degrees of freedom.
double chi2_survival(double chi2, int dof);
// Regularised incomplete beta function I_x(a, b) (continued fraction by modified Lentz; Press et
// al., Numerical Recipes, section 6.4).
double incomplete_beta(double a, double b, double x);
// P(|T| >= |t|) for Student's t with `dof` (not necessarily integer) degrees of freedom: the
// two-sided p-value of a t statistic.
double student_t_two_sided_p(double t, double dof);

// Welch's test that two sets of independent estimates share their mean: the t statistic, the
// Welch-Satterthwaite degrees of freedom and the two-sided p-value. Needs two or more values in
// each set; a set without spread against one without spread gives p = 1 when the means are
// equal and 0 otherwise.
struct WelchResult {
    double t = 0.0, dof = 0.0, p_value = 1.0;
};
WelchResult welch_test(const std::vector<double>& a, const std::vector<double>& b);
// The per-test significance that keeps the family-wise error rate at `alpha` over `tests`
// independent tests (Sidak): 1 - (1 - alpha)^(1 / tests).
double sidak(double alpha, int tests);
// Standard normal quantile (inverse CDF), Acklam's rational approximation refined by one
// Newton step on erfc.
double normal_quantile(double p);
// |z| above which a two-sided test at per-test level `alpha_per_test` rejects.
inline double two_sided_z(double alpha_per_test) { return normal_quantile(1.0 - alpha_per_test / 2.0); }

struct ChiSquareResult {
    double chi2 = 0.0;
    int dof = 0;
    double p_value = 1.0;
    int pooled_cells = 0;
    std::string details;
};
// Pearson's test of observed counts against expected counts; cells with expected count below
// `min_expected` are pooled into one (as the protocol asks), which joins the smallest
// tested cell when its own expectation is still below `min_expected`.
ChiSquareResult chi_square(const std::vector<double>& observed, const std::vector<double>& expected, double min_expected = 5.0);

// Mean and standard error of the mean of a list of values.
struct MeanAndError {
    double mean = 0.0, std_error = 0.0;
};
MeanAndError mean_and_error(const std::vector<double>& values);

}  // namespace candela
