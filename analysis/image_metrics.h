#pragma once
// Comparing a rendered image against a reference: whole-image and block metrics, the agreement
// test of the validation README (whole-image channel means within 1%, 16x16 block luminance
// within 2% mean absolute relative difference), and difference heatmaps.

#include "core/image.h"

namespace candela {

struct ImageComparison {
    int width = 0, height = 0;
    Spectrum mean_test{0.0f}, mean_reference{0.0f};
    Spectrum mean_relative_difference{0.0f};  // (mean_test - mean_ref) / mean_ref per channel
    double rmse = 0.0;                        // sqrt(mean over pixels and channels of (t - r)^2)
    double relmse = 0.0;                      // mean of (t - r)^2 / (r^2 + 0.01)
    double mare = 0.0;                        // mean of |t - r| / (|r| + 0.01), per pixel and channel
    // Mean absolute relative difference of 16x16 block luminances, over blocks whose reference
    // luminance is at least 1% of the image's mean luminance.
    double block_mare = 0.0;
    int blocks_used = 0, blocks_total = 0;
};

// Both images need the same size and at least RGB channels (the first three are used).
ImageComparison compare_images(const Image& test, const Image& reference, int block_size = 16);

struct AgreementThresholds {
    double mean = 0.01;   // per-channel whole-image mean
    double block = 0.02;  // block luminance mean absolute relative difference
};
// True when both criteria hold; `reason` explains the first failure.
bool images_agree(const ImageComparison& c, const AgreementThresholds& t, std::string* reason = nullptr);

// A per-pixel z-test of a render against a reference: z = (t - r) / sd per channel with
// sd^2 = var_t + var_r + (1e-4 max(|t|, |r|))^2: var_t from the render's "variance" layers (the
// variance of the pixel mean), var_r estimated as var_t * test_spp / reference_spp (both estimate
// the same pixel), and a floor for float32 accumulation over thousands of samples (about 1e-4
// relative), without which zero-variance pixels (a constant sky) could never agree. Rejections
// are counted at a Sidak-corrected significance over all pixels and channels.
//
// Caveat: Monte Carlo pixel estimates are heavy-tailed (rare bright paths), and a sample variance
// cannot see paths its samples missed; the test therefore rejects more often than its nominal
// level even between two correct renderers. Treat it as a map of where to look.
struct PixelZTest {
    double threshold = 0.0;  // |z| beyond which a pixel is rejected
    long long tested = 0, rejected = 0;
    double max_abs_z = 0.0;
    double fraction_beyond_3 = 0.0;  // share of |z| > 3 (0.27% for Gaussian noise)
};
PixelZTest pixel_z_test(const Image& test, const Image& reference, int test_spp, int reference_spp, double alpha = 0.01,
                        Image* z_map = nullptr);

// The largest per-pixel relative difference between two images of the same size and channels,
// layer by layer (R,G,B is one layer, "variance.R/G/B" another, ...): for each pixel and layer
// max_c |t_c - r_c| / max_c max(|t_c|, |r_c|), zero where both are zero. Relative to the layer's
// largest component, so that a component near zero (a normal's x) is judged at the pixel's scale.
// For checking that a merged farm render equals the single-machine one up to float rounding.
struct PixelDifference {
    double max_relative = 0.0;
    int x = -1, y = -1;  // where it is largest (-1 when the images are equal)
    std::string layer;   // "" for R, G, B
};
// InputError when sizes or channel names differ.
PixelDifference max_pixel_relative_difference(const Image& test, const Image& reference);

// Per-pixel relative luminance difference (t - r) / (r + eps) as a colour image with a legend
// bar; values beyond +-range saturate.
// The luminance difference (test - reference) / (|reference| + 0.01) of every pixel in a diverging
// colour map, full colour at +-range: the map alone (the image's size), and with its legend.
Image relative_difference_map(const Image& test, const Image& reference, float range = 0.1f);
Image relative_difference_heatmap(const Image& test, const Image& reference, float range = 0.1f);

}  // namespace candela
