// The resolve pass: the supersamples filtered into pixels by the `aa_filter` reconstruction
// filter (box: the pixel's own samples; tent and gaussian also reach into the neighbours),
// normalised by the sum of the weights; likewise the coverage (the film's alpha).

#include "core/parallel.h"
#include "integrators/raster/frame.h"

namespace candela::raster {

namespace {

// Filter weight per axis at distance d (pixels) from the pixel centre.
float resolve_weight(RasterSettings::AAFilter f, float d) {
    d = std::abs(d);
    switch (f) {
        case RasterSettings::AAFilter::Box: return d < 0.5f ? 1.0f : 0.0f;
        case RasterSettings::AAFilter::Tent: return std::max(0.0f, 1.0f - d);
        case RasterSettings::AAFilter::Gaussian:
            return d < 1.5f ? std::exp(-d * d / (2.0f * 0.25f)) - std::exp(-1.5f * 1.5f / (2.0f * 0.25f)) : 0.0f;
    }
    return 0.0f;
}

// How many neighbouring pixels the filter reaches on each side.
int resolve_reach(RasterSettings::AAFilter f) {
    switch (f) {
        case RasterSettings::AAFilter::Box: return 0;
        case RasterSettings::AAFilter::Tent: return 1;
        case RasterSettings::AAFilter::Gaussian: return 2;
    }
    return 0;
}

}  // namespace

void resolve_pass(const FrameSetup& f, FrameBuffers& b) {
    const RasterSettings::AAFilter filter = f.settings.aa_filter;
    const int reach = resolve_reach(filter), W = f.width, H = f.height;
    // Every pixel is written below, so a frame of the same size keeps the last one's storage.
    if (b.image.width() != W || b.image.height() != H || b.image.channel_count() != 3) b.image = Image::rgb(W, H);
    b.coverage.assign(size_t(W) * H, 0.0f);
    parallel_for(size_t(H), [&](int y) {
        for (int x = 0; x < W; ++x) {
            const Vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
            Spectrum sum(0.0f);
            float wsum = 0.0f, covered = 0.0f;
            for (int yy = std::max(0, y - reach); yy <= std::min(H - 1, y + reach); ++yy)
                for (int xx = std::max(0, x - reach); xx <= std::min(W - 1, x + reach); ++xx)
                    for (int s = 0; s < f.samples_per_pixel(); ++s) {
                        Vec2 d = f.sample_position(xx, yy, s) - centre;
                        float w = resolve_weight(filter, d.x) * resolve_weight(filter, d.y);
                        if (w <= 0.0f) continue;
                        size_t i = f.sample_index(xx, yy, s);
                        sum += w * b.color[i];
                        if (b.triangle[i] != NoTriangle) covered += w;
                        wsum += w;
                    }
            b.image.set_rgb(x, y, wsum > 0.0f ? sum / wsum : Spectrum(0.0f));
            b.coverage[size_t(y) * W + x] = wsum > 0.0f ? covered / wsum : 0.0f;
        }
    });
}

}  // namespace candela::raster
