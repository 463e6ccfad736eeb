#pragma once
// Test-only statistics: a histogram of sampled directions on the sphere with expected counts
// integrated from a pdf, and block means of renders with their variance. The general tools (chi-square, Sidak, quantiles, mean and standard
// error) are in core/statistics.h.

#include "analysis/statistics.h"
#include "core/image.h"

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace candela {
class Scene;
}

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
// The mean of channel `ch` over a w x h block of pixels (the whole image by default) and its
// standard error from the pixels' spread (independent pixels: a box-filtered render).
MeanAndError channel_mean(const Image& img, int ch, int x0 = 0, int y0 = 0, int w = -1, int h = -1);
// The same for the pixels' differences a - b (paired, so what the two images share cancels).
MeanAndError mean_difference(const Image& a, const Image& b, int ch, int x0 = 0, int y0 = 0, int w = -1, int h = -1);
// Two independent 32 x 32 renders of one expectation: per channel, the mean pixel difference
// over the whole image and over each of 16 blocks of 8 x 8 pixels, in units of its standard
// error; the largest |z| of those 51 (3 x 17) z-tests, and where it was (`where`).
double largest_block_z(const Image& a, const Image& b, std::string* where = nullptr);

// Per block of `block` x `block` pixels (row-major) and channel, the block's mean in each of
// `seeds` renders of `scene` by its integrator with seeds 1000, 1001, ...: independent renders,
// so the spread of a block's means is its error whatever correlates the pixels of one render
// (a light tracer's splats, a photon map).
using SeedBlockMeans = std::vector<std::array<std::vector<double>, 3>>;
SeedBlockMeans seed_block_means(const Scene& scene, int seeds, int block);
// The smallest two-sided p-value of Welch's test over the blocks and channels of two such sets
// (same image size and block), and where it was with both means (`where`).
double smallest_welch_p(const SeedBlockMeans& a, const SeedBlockMeans& b, std::string& where);

}  // namespace candela::test
