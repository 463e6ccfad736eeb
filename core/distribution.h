#pragma once
// Piecewise-constant distributions in one and two dimensions (pbrt-v4, section A.4.2), for
// picking mesh triangles by area, lights by power and environment-map texels by luminance.

#include "core/math.h"

#include <vector>

namespace candela {

// A discrete distribution over n bins with probabilities proportional to the given weights; also
// usable as a piecewise-constant density on [0, 1).
class Distribution1D {
public:
    Distribution1D() = default;
    explicit Distribution1D(std::vector<float> weights);

    size_t size() const { return pdf_.size(); }
    float total() const { return total_; }  // sum of the weights as given
    bool empty() const { return pdf_.empty(); }

    // Probability of bin i (sums to 1 over all bins).
    float pmf(size_t i) const { return pdf_[i]; }
    // Picks a bin; `u` is rescaled in place to a fresh uniform number within the bin.
    size_t sample_discrete(float& u) const;
    // Samples a position in [0, 1) with density pdf_continuous(x).
    float sample_continuous(float u, float* pdf, size_t* bin = nullptr) const;
    float pdf_continuous(float x) const;

private:
    std::vector<float> pdf_;  // normalised bin probabilities
    std::vector<double> cdf_;  // size n + 1, cdf_[0] = 0, cdf_[n] = 1
    float total_ = 0.0f;
};

// A density over [0, 1)^2 proportional to a width x height grid of non-negative weights,
// sampled by a marginal over rows and a conditional within the row.
class Distribution2D {
public:
    Distribution2D() = default;
    Distribution2D(const std::vector<float>& weights, int width, int height);

    // Returns a point in [0, 1)^2 and its density with respect to area on [0, 1)^2.
    Vec2 sample(const Vec2& u, float* pdf) const;
    float pdf(const Vec2& p) const;
    int width() const { return width_; }
    int height() const { return height_; }

private:
    int width_ = 0, height_ = 0;
    std::vector<Distribution1D> rows_;
    Distribution1D marginal_;
};

}  // namespace candela
