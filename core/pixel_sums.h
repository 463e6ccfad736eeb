#pragma once
// What a render accumulates before it divides. Per pixel: the filtered sums sum(w L) and sum(w)
// that make the image, and the unfiltered sums of the samples that landed in the pixel, from which
// the AOV layers come (albedo, normal and depth means, the variance of the pixel mean). Sums over
// disjoint sample ranges add up to the sums of their union: a render split into sample ranges and
// image regions merges back exactly (farm/), up to the order of the floating-point additions.

#include "core/image.h"
#include "core/spectrum.h"

#include <string>
#include <vector>

namespace candela {

// A half-open range of sample indices [begin, end); empty (0, 0) means all of them.
struct SampleRange {
    int begin = 0, end = 0;
    bool empty() const { return end <= begin; }
};

// A rectangle of the rendered image, in its pixels (the film's crop window starts at 0, 0).
struct ImageRect {
    Vec2i offset{0}, size{0};
    bool empty() const { return size.x <= 0 || size.y <= 0; }
};

// Sample indices `samples` of the pixels `rect`: what a part of a split render, or an
// interrupted render, holds. Sums hold every splat those samples make (also on pixels around
// `rect`, within the filter's reach), so that boxes that do not overlap add up.
struct CoverageBox {
    ImageRect rect;
    SampleRange samples;
};

// What a sample reports about its first hit, for AOVs.
struct FirstHitAovs {
    Spectrum albedo{0.0f};
    Vec3 normal{0.0f};
    float depth = 0.0f;
};

// Running sums of the samples that landed in one pixel (unfiltered), in double precision: the
// variance needs sum(L^2) - sum(L)^2 / n, which cancels.
struct PixelStats {
    uint32_t n = 0;
    double sum[3] = {0, 0, 0}, sum_sq[3] = {0, 0, 0};
    double albedo[3] = {0, 0, 0}, normal[3] = {0, 0, 0};
    double depth = 0.0;

    void add(const Spectrum& L, const FirstHitAovs& aov);
    void add(const PixelStats& other);
    // Unbiased sample variance divided by n: the variance of the pixel mean.
    double variance_of_mean(int c) const;
};

// The extra layers of a render and their channels: R, G, B, then albedo.RGB, normal.XYZ, depth.Z
// and variance.RGB, each only when asked for.
class AovLayout {
public:
    AovLayout() = default;
    // "albedo", "normal", "depth", "variance" in any order; InputError for another name.
    explicit AovLayout(const std::vector<std::string>& names);

    bool albedo() const { return albedo_; }
    bool normal() const { return normal_; }
    bool depth() const { return depth_; }
    bool variance() const { return variance_; }
    // Whether samples must report their first hit, and whether pixels keep running sums.
    bool first_hit() const { return albedo_ || normal_ || depth_; }
    bool pixel_stats() const { return first_hit() || variance_; }

    // The layers asked for, in channel order ("albedo,variance"); empty for none.
    std::string names() const;
    std::vector<std::string> channels() const;
    // Writes the AOV channels (after R, G, B) of pixel (x, y) from its statistics.
    void write(const PixelStats& ps, Image& img, int x, int y) const;

private:
    bool albedo_ = false, normal_ = false, depth_ = false, variance_ = false;
};

// The sums of a rectangle of the image's pixels.
class PixelSums {
public:
    PixelSums() = default;
    PixelSums(const ImageRect& rect, const AovLayout& layout);

    const ImageRect& rect() const { return rect_; }
    const Vec2i& size() const { return rect_.size; }
    const AovLayout& layout() const { return layout_; }
    bool has_stats() const { return !stats_.empty(); }

    // (sum(w r), sum(w g), sum(w b), sum(w)) per pixel, row by row: the buffer that
    // ImageBlock::accumulate_into adds to.
    std::vector<double>& filtered() { return filtered_; }
    // (x, y) relative to rect().offset.
    double* filtered_at(int x, int y) { return &filtered_[(size_t(y) * rect_.size.x + x) * 4]; }
    const double* filtered_at(int x, int y) const { return &filtered_[(size_t(y) * rect_.size.x + x) * 4]; }
    // Only when layout().pixel_stats().
    PixelStats& stats_at(int x, int y) { return stats_[size_t(y) * rect_.size.x + x]; }
    const PixelStats& stats_at(int x, int y) const { return stats_[size_t(y) * rect_.size.x + x]; }

    // Adds `other` (same layout) where its rectangle lies; InputError unless it lies inside this.
    void add(const PixelSums& other);

    // The image: R, G, B = sum(w L) / sum(w) (black where no sample reached), then the AOVs.
    Image develop() const;

private:
    ImageRect rect_;
    AovLayout layout_;
    std::vector<double> filtered_;
    std::vector<PixelStats> stats_;
};

}  // namespace candela
