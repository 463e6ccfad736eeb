#pragma once
// What a render accumulates before it divides. Per pixel: the filtered sums sum(w v) and sum(w)
// that make the image (v: R, G, B, alpha and the integrator's channels), and the unfiltered sums
// of the samples that landed in the pixel, from which the AOV layers come (albedo, normal and
// depth means, the variance of the pixel mean, the sample count). Sums over
// disjoint sample ranges add up to the sums of their union: a render split into sample ranges and
// image regions merges back exactly (farm/), up to the order of the floating-point additions.

#include "core/film.h"
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

// Whether `inner` is non-empty and lies inside `outer`, computed in 64 bits: a rectangle read from
// a file or a command line may reach beyond an int (offset + size). The one such test of the
// pixel loop, the resumable render and the part files.
bool rect_inside(const ImageRect& inner, const ImageRect& outer);
inline bool rect_inside_image(const ImageRect& rect, const Vec2i& image) { return rect_inside(rect, ImageRect{Vec2i(0), image}); }

// Sample indices `samples` of the pixels `rect`: what a part of a split render, or an
// interrupted render, holds. Sums hold every splat those samples make (also on pixels around
// `rect`, within the filter's reach), so that boxes that do not overlap add up.
struct CoverageBox {
    ImageRect rect;
    SampleRange samples;
};

// What a sample reports about its first hit, for the --aov layers.
struct FirstHitAovs {
    Spectrum albedo{0.0f};
    Vec3 normal{0.0f};
    float depth = 0.0f;
};

// Running sums of the samples that landed in one pixel (unfiltered), in double precision: the
// variance needs sum(L^2) - sum(L)^2 / n, which cancels. They give the variance of the pixel
// mean, the first-hit AOVs, the samples-per-pixel AOV and adaptive sampling's error estimate.
struct PixelStats {
    uint32_t n = 0;
    uint32_t taken = 0;  // sample indices taken (n plus the non-finite samples dropped)
    bool active = true;  // adaptive sampling has not stopped the pixel
    double sum[3] = {0, 0, 0}, sum_sq[3] = {0, 0, 0};
    // Adaptive sampling's half buffer: the samples of class A (see in_class_a).
    uint32_t n_a = 0;
    double sum_a[3] = {0, 0, 0};
    double albedo[3] = {0, 0, 0}, normal[3] = {0, 0, 0};
    double depth = 0.0;

    // A finite sample of index `index`.
    void add(const Spectrum& L, const FirstHitAovs& aov, uint32_t index);
    // The sums of other samples of the pixel (disjoint sample indices).
    void add(const PixelStats& other);
    // Half of the sample indices, chosen so that both halves of a stratified or (0, 2) pattern stay
    // well stratified: those with an odd number of ones at the odd bit positions (Christensen,
    // Kensler and Kilpatrick 2018, "Progressive Multi-Jittered Sample Sequences", section 10.2.1).
    static bool in_class_a(uint32_t index);
    // Cycles' per-pixel error (Dammertz et al. 2010, section 2.1): the L1 difference of the mean of
    // all samples and the mean of class A, over the square root of the mean's channel sum.
    double adaptive_error() const;
    // Unbiased sample variance divided by n: the variance of the pixel mean.
    double variance_of_mean(int c) const;
};

// What each sample splats into the image, filtered like the radiance (as Mitsuba films its alpha
// and AOVs): R, G, B, then alpha (1 for a valid sample, 0 otherwise) when the film's pixel format
// has one, then the integrator's channels; with a spectral film (specfilm), its bands' values in
// place of R, G, B and alpha. And how the image's first channels come from them.
class SampleLayout {
public:
    SampleLayout() = default;
    SampleLayout(PixelFormat format, std::vector<std::string> integrator_channels);
    // A spectral film's: the bands (core/film.h: FilmBands), named as their channels.
    SampleLayout(std::vector<std::string> band_names, std::vector<std::string> integrator_channels);
    // The film's: its bands when it has them, else its pixel format.
    static SampleLayout of_film(const Film& film, std::vector<std::string> integrator_channels);

    int values() const { return film_values() + extras(); }
    // The values of the film's own: R, G, B and alpha, or one per band.
    int film_values() const { return has_bands() ? int(band_names_.size()) : 3 + (alpha_ ? 1 : 0); }
    int extras() const { return int(extra_names_.size()); }
    bool has_bands() const { return !band_names_.empty(); }
    const std::vector<std::string>& integrator_channels() const { return extra_names_; }
    // The splatted values' names: R, G, B, A (with alpha), or the bands, then the integrator's.
    std::vector<std::string> value_names() const;
    // What a part file records of the film's channels: the pixel format's channels ("R,G,B,A"),
    // or "bands:" and the band names; from_film_key() reads it back.
    std::string film_key() const;
    static SampleLayout from_film_key(const std::string& key, std::vector<std::string> integrator_channels);

    // The splatted values of one sample; false when any is not storable (storable_sample_value).
    bool fill(const Spectrum& L, bool valid, const float* integrator_values, float* out) const;
    // The same for a spectral film, from the sample's band values (FilmBands::values).
    bool fill_bands(const float* band_values, const float* integrator_values, float* out) const;
    // The image's first channels: the film's pixel format or bands, then the integrator's channels.
    std::vector<std::string> channels() const;
    // Writes those channels of one pixel from its normalised values.
    void write(const double* v, float* out) const;

private:
    PixelFormat format_ = PixelFormat::RGB;
    bool alpha_ = false;
    std::vector<std::string> band_names_;
    std::vector<std::string> extra_names_;
};

// The --aov layers of a render and their channels: albedo.RGB, normal.XYZ, depth.Z,
// variance.RGB and samples.N, each only when asked for, after the film's and the integrator's
// channels.
class AovLayout {
public:
    AovLayout() = default;
    // "albedo", "normal", "depth", "variance", "samples" in any order; InputError for another.
    explicit AovLayout(const std::vector<std::string>& names);

    bool albedo() const { return albedo_; }
    bool normal() const { return normal_; }
    bool depth() const { return depth_; }
    bool variance() const { return variance_; }
    bool samples() const { return samples_; }
    // Whether samples must report their first hit, and whether pixels keep running sums.
    bool first_hit() const { return albedo_ || normal_ || depth_; }
    bool pixel_stats() const { return first_hit() || variance_ || samples_; }
    int layer_count() const { return int(albedo_) + int(normal_) + int(depth_) + int(variance_) + int(samples_); }

    // The layers asked for, in channel order ("albedo,variance"); empty for none.
    std::string names() const;
    std::vector<std::string> channels() const;
    // Writes the AOV channels of pixel (x, y), from channel c on, from its statistics.
    void write(const PixelStats& ps, Image& img, int x, int y, int c) const;

private:
    bool albedo_ = false, normal_ = false, depth_ = false, variance_ = false, samples_ = false;
};

// The sums of a rectangle of the image's pixels.
class PixelSums {
public:
    PixelSums() = default;
    PixelSums(const ImageRect& rect, const SampleLayout& values, const AovLayout& layout);

    const ImageRect& rect() const { return rect_; }
    const Vec2i& size() const { return rect_.size; }
    const SampleLayout& values() const { return values_; }
    const AovLayout& layout() const { return layout_; }
    // Doubles per pixel in filtered(): the splatted values' sums sum(w v), then sum(w).
    int stride() const { return values_.values() + 1; }
    bool has_stats() const { return !stats_.empty(); }

    // stride() doubles per pixel, row by row: the buffer that ImageBlock::accumulate_into adds to.
    std::vector<double>& filtered() { return filtered_; }
    // (x, y) relative to rect().offset.
    double* filtered_at(int x, int y) { return &filtered_[(size_t(y) * rect_.size.x + x) * size_t(stride())]; }
    const double* filtered_at(int x, int y) const { return &filtered_[(size_t(y) * rect_.size.x + x) * size_t(stride())]; }
    // Only when layout().pixel_stats().
    PixelStats& stats_at(int x, int y) { return stats_[size_t(y) * rect_.size.x + x]; }
    const PixelStats& stats_at(int x, int y) const { return stats_[size_t(y) * rect_.size.x + x]; }

    // Adds `other` (same layouts) where its rectangle lies; InputError unless it lies inside this.
    void add(const PixelSums& other);

    // The image: the film's channels and the integrator's from sum(w v) / sum(w) (0 where no
    // sample reached), then the AOV layers.
    Image develop() const;

private:
    ImageRect rect_;
    SampleLayout values_;
    AovLayout layout_;
    std::vector<double> filtered_;
    std::vector<PixelStats> stats_;
};

}  // namespace candela
