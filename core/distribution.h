#pragma once
// Piecewise-constant distributions in one and two dimensions (pbrt-v4, section A.4.2), for
// picking mesh triangles by area, lights by power and environment-map texels by luminance.

#include "core/math.h"

#include <array>
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
    std::vector<float> pdf_;   // normalised bin probabilities
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

// A density on [0, 1]^2 that interpolates a width x height grid of values bilinearly (node (i, j)
// at (i / (width - 1), j / (height - 1))), sampled by inverting its marginal CDF over y and then
// its conditional CDF over x, both exactly for the bilinear interpolant (Mitsuba 3's
// Marginal2D<Float, Dimension, Continuous = true>, include/mitsuba/core/distr_2d.h).
//
// It may depend on up to three parameters: the data is then a stack of grids, N0 x N1 x N2 x
// height x width (last fastest), one per combination of the parameter values given, and a query
// between them blends the neighbouring grids (and their CDFs) linearly, clamped at the ends. As
// each grid is normalised on its own, the blend is again a normalised density, and sample() draws
// exactly from the density that eval() returns.
//
// As an Interpolant (not normalised, no CDFs) eval() returns the blended bilinear interpolation
// of the values as given.
class Marginal2D {
public:
    enum class Mode { Distribution, Interpolant };
    static constexpr int MaxParams = 3;

    Marginal2D() = default;
    // `data` has params' sizes x height x width values; width, height >= 2; each parameter's values
    // strictly increase. Throws std::invalid_argument when a grid of a Distribution has a negative
    // or non-finite value or integrates to zero.
    Marginal2D(const float* data, int width, int height, std::vector<std::vector<float>> params, Mode mode);

    // The grids a query at some parameter values blends (2^k for k parameters with more than one
    // value) and their weights. It depends on the parameters' values only: Marginal2Ds built with
    // the same parameter values may share one.
    struct Blend {
        int count = 1;
        std::array<size_t, 1 << MaxParams> slice{};
        std::array<float, 1 << MaxParams> weight{};
    };
    Blend blend(const float* params) const;
    // For a last parameter that is only ever queried at its nodes (a channel index, say): the
    // blend of the leading parameters' values `params` alone, and from it, without searching or
    // weighing the last parameter, the blend with that parameter at node `last_node`; equal to
    // blend() at that node's value.
    Blend blend_leading(const float* params) const;
    Blend at_node(Blend leading, int last_node) const;

    // The interpolated value at p in [0, 1]^2 (a density in Distribution mode).
    float eval(const Vec2& p, const float* params = nullptr) const { return eval(p, blend(params)); }
    float eval(const Vec2& p, const Blend& b) const;
    // Distribution mode: maps u in [0, 1)^2 to a point with density *pdf.
    Vec2 sample(Vec2 u, const float* params, float* pdf) const { return sample(u, blend(params), pdf); }
    Vec2 sample(Vec2 u, const Blend& b, float* pdf) const;
    // The inverse of sample(): the u that sample() maps to p, and the density at p.
    Vec2 invert(Vec2 p, const float* params, float* pdf) const { return invert(p, blend(params), pdf); }
    Vec2 invert(Vec2 p, const Blend& b, float* pdf) const;

    int width() const { return width_; }
    int height() const { return height_; }

private:
    // blend() of the first `count` parameters.
    Blend blend_first(const float* params, size_t count) const;
    // Element i of every blended grid of `array` (grids of `stride` elements), weighted.
    static float lookup(const std::vector<float>& array, size_t stride, const Blend& b, size_t i);
    // The values at height t (in [0, 1] between rows `row` and `row` + 1) of columns col, col + 1.
    void values_at_height(const Blend& b, size_t row, size_t col, float t, float& c0, float& c1) const;
    // The patch holding p, p's position in it (s, t) and the values at height t of its columns.
    struct Patch {
        size_t col = 0, row = 0;
        float s = 0.0f, t = 0.0f, c0 = 0.0f, c1 = 0.0f;
    };
    Patch patch_at(const Vec2& p, const Blend& b) const;

    int width_ = 0, height_ = 0;
    Mode mode_ = Mode::Interpolant;
    std::vector<std::vector<float>> params_;
    std::vector<size_t> param_strides_;   // in grids
    std::vector<float> data_;             // normalised (Distribution) or as given
    std::vector<float> conditional_cdf_;  // per row, running integral along x (index units)
    std::vector<float> marginal_cdf_;     // per grid, running integral over rows
};

}  // namespace candela
