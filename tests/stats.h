#pragma once
// Test-only statistics: a histogram of sampled directions on the sphere with expected counts
// integrated from a pdf, and block means of renders with their variance. The general tools (chi-square, Sidak, quantiles, mean and standard
// error) are in core/statistics.h.

#include "analysis/statistics.h"
#include "core/image.h"

#include <functional>
#include <vector>

namespace candela::test {

using namespace candela;

// Histogram of sampled unit vectors over (cos theta, phi) cells, and the expected counts obtained
// by integrating a solid-angle pdf over each cell (nested adaptive Simpson quadrature).
struct SphericalHistogram {
    int theta_bins, phi_bins;
    std::vector<double> counts;
    SphericalHistogram(int theta_bins_, int phi_bins_);
    void add(const Vec3& w);
    std::vector<double> expected(const std::function<double(const Vec3&)>& pdf, double samples) const;
};

struct MeanAndVariance {
    double mean = 0.0, variance_of_mean = 0.0;
};
// The mean of channel `ch` (R, G or B) over a block of size x size pixels, and its variance from
// the render's variance AOV (the pixels of a box-filtered render are independent).
MeanAndVariance block_mean(const Image& img, int ch, int x0, int y0, int size);

}  // namespace candela::test
