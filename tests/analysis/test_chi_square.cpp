// Pearson's chi-square test (analysis/statistics.h) on counts made by hand: cells expected below
// the minimum are pooled, and a pooled cell still below it joins the smallest tested cell.

#include "analysis/statistics.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace candela;

namespace {

// 100 cells whose expected counts rise from 8 to 404 and are observed exactly, then three cells
// expected 0.001 times each (a pooled cell of 0.003, far below 5) observed `stray` times.
ChiSquareResult with_stray_samples(double stray) {
    std::vector<double> observed, expected;
    for (int i = 0; i < 100; ++i) {
        expected.push_back(8.0 + 4.0 * i);
        observed.push_back(expected.back());
    }
    for (int i = 0; i < 3; ++i) {
        expected.push_back(0.001);
        observed.push_back(i == 0 ? stray : 0.0);
    }
    return chi_square(observed, expected);
}

}  // namespace

TEST_CASE("chi-square: a pooled cell below the minimum joins the smallest tested cell", "[statistics]") {
    // One sample where 0.003 were expected happens in 0.3% of runs of a correct sampler: no
    // failure (as its own cell it added (1 - 0.003)^2 / 0.003 = 332 to chi2).
    ChiSquareResult one = with_stray_samples(1.0);
    INFO(one.details);
    CHECK(one.pooled_cells == 3);
    CHECK(one.dof == 99);
    CHECK(one.chi2 == Approx((9.0 - 8.003) * (9.0 - 8.003) / 8.003));
    CHECK(one.p_value > 0.5);
    // Sixty samples there is a sampler putting mass where the pdf has almost none: a failure.
    ChiSquareResult sixty = with_stray_samples(60.0);
    INFO(sixty.details);
    CHECK(sixty.p_value < 1e-12);
    // Samples where the pdf is exactly zero fail whatever their number.
    ChiSquareResult zero = chi_square({10.0, 10.0, 1.0}, {10.0, 10.0, 0.0});
    CHECK(std::isinf(zero.chi2));
    CHECK(zero.p_value == 0.0);
    // Pooled cells that together reach the minimum are tested as one cell of their own.
    ChiSquareResult pooled = chi_square({10.0, 10.0, 3.0, 3.0}, {10.0, 10.0, 2.5, 2.5});
    CHECK(pooled.pooled_cells == 2);
    CHECK(pooled.dof == 2);
    CHECK(pooled.chi2 == Approx(1.0 / 5.0));
}
