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
    double rmse = 0.0;    // sqrt(mean over pixels and channels of (t - r)^2)
    double relmse = 0.0;  // mean of (t - r)^2 / (r^2 + 0.01)
    double mare = 0.0;    // mean of |t - r| / (|r| + 0.01), per pixel and channel
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

// Per-pixel relative luminance difference (t - r) / (r + eps) as a colour image with a legend
// bar; values beyond +-range saturate.
Image relative_difference_heatmap(const Image& test, const Image& reference, float range = 0.1f);

}  // namespace candela
