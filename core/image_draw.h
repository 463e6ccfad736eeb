#pragma once
// Drawing on display images (values in [0, 1]): colour maps, a 5x7 bitmap font for labels, and
// colour-bar legends. Used for heatmaps, comparison sheets and plots.

#include "core/image.h"

#include <string>

namespace candela::draw {

// Perceptually ordered map from [0, 1] (viridis control points, linearly interpolated).
Spectrum colormap_sequential(float t);
// Diverging map from [-1, 1]: blue - white - red.
Spectrum colormap_diverging(float t);

// Draws text with its top-left corner at (x, y), each font pixel `scale` image pixels.
void text(Image& img, int x, int y, const std::string& s, const Spectrum& color, int scale = 1);
int text_width(const std::string& s, int scale = 1);
constexpr int GlyphHeight = 7;

void fill_rect(Image& img, int x0, int y0, int x1, int y1, const Spectrum& color);
// Copies `src` (RGB) into `dst` with its top-left corner at (x, y).
void blit(Image& dst, const Image& src, int x, int y);

// A vertical colour bar of the given map with labelled ticks, appended to the right of `img`.
// `labels` are placed top (max) to bottom (min), evenly spaced.
Image with_legend(const Image& img, Spectrum (*map)(float), bool diverging, const std::vector<std::string>& labels,
                  const std::string& title);

}  // namespace candela::draw
