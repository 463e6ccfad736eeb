#include "analysis/image_metrics.h"

#include "analysis/statistics.h"
#include "core/error.h"
#include "core/image_draw.h"

#include <algorithm>
#include <cstdio>
#include <map>

namespace candela {

ImageComparison compare_images(const Image& test, const Image& ref, int block_size) {
    if (test.width() != ref.width() || test.height() != ref.height())
        throw InputError("images differ in size: " + std::to_string(test.width()) + "x" + std::to_string(test.height()) + " vs " +
                         std::to_string(ref.width()) + "x" + std::to_string(ref.height()));
    if (test.channel_count() < 3 || ref.channel_count() < 3) throw InputError("images need at least three (RGB) channels");
    ImageComparison c;
    c.width = test.width();
    c.height = test.height();
    const double n = double(c.width) * c.height;
    double sum_t[3] = {0, 0, 0}, sum_r[3] = {0, 0, 0}, se = 0, rel = 0, are = 0;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x)
            for (int k = 0; k < 3; ++k) {
                double t = test.at(x, y, k), r = ref.at(x, y, k);
                sum_t[k] += t;
                sum_r[k] += r;
                double d = t - r;
                se += d * d;
                rel += d * d / (r * r + 0.01);
                are += std::abs(d) / (std::abs(r) + 0.01);
            }
    for (int k = 0; k < 3; ++k) {
        c.mean_test[k] = float(sum_t[k] / n);
        c.mean_reference[k] = float(sum_r[k] / n);
        c.mean_relative_difference[k] = float(sum_r[k] != 0.0 ? (sum_t[k] - sum_r[k]) / sum_r[k] : (sum_t[k] == 0.0 ? 0.0 : INFINITY));
    }
    c.rmse = std::sqrt(se / (3.0 * n));
    c.relmse = rel / (3.0 * n);
    c.mare = are / (3.0 * n);

    // Block luminance metric of the validation README.
    double mean_lum = luminance(c.mean_reference);
    double block_sum = 0.0;
    for (int by = 0; by < c.height; by += block_size)
        for (int bx = 0; bx < c.width; bx += block_size) {
            double lt = 0.0, lr = 0.0;
            int count = 0;
            for (int y = by; y < std::min(by + block_size, c.height); ++y)
                for (int x = bx; x < std::min(bx + block_size, c.width); ++x) {
                    lt += luminance(test.rgb_at(x, y));
                    lr += luminance(ref.rgb_at(x, y));
                    ++count;
                }
            ++c.blocks_total;
            lt /= count;
            lr /= count;
            if (lr < 0.01 * mean_lum || lr <= 0.0) continue;
            block_sum += std::abs(lt - lr) / lr;
            ++c.blocks_used;
        }
    c.block_mare = c.blocks_used ? block_sum / c.blocks_used : 0.0;
    return c;
}

bool images_agree(const ImageComparison& c, const AgreementThresholds& t, std::string* reason) {
    char buf[256];
    for (int k = 0; k < 3; ++k) {
        if (!(std::abs(c.mean_relative_difference[k]) <= t.mean)) {
            if (reason) {
                std::snprintf(buf, sizeof buf, "channel %c mean differs by %+.2f%% (tolerance %.2f%%)", "RGB"[k],
                              100.0 * c.mean_relative_difference[k], 100.0 * t.mean);
                *reason = buf;
            }
            return false;
        }
    }
    if (!(c.block_mare <= t.block)) {
        if (reason) {
            std::snprintf(buf, sizeof buf, "16x16 block luminance differs by %.2f%% on average (tolerance %.2f%%)", 100.0 * c.block_mare,
                          100.0 * t.block);
            *reason = buf;
        }
        return false;
    }
    return true;
}

PixelZTest pixel_z_test(const Image& test, const Image& ref, int test_spp, int reference_spp, double alpha, Image* z_map) {
    int v0 = test.channel_index("variance.R");
    if (v0 < 0) throw InputError("the z-test needs the render's variance layers (--aov variance)");
    PixelZTest r;
    long long n = 3LL * test.width() * test.height();
    r.threshold = two_sided_z(sidak(alpha, int(std::min<long long>(n, INT32_MAX))));
    double ratio = double(test_spp) / double(std::max(reference_spp, 1));
    long long beyond3 = 0;
    Image map = Image::rgb(test.width(), test.height());
    for (int y = 0; y < test.height(); ++y)
        for (int x = 0; x < test.width(); ++x) {
            double worst = 0.0;
            for (int c = 0; c < 3; ++c) {
                double t = test.at(x, y, c), rv = ref.at(x, y, c), var = test.at(x, y, v0 + c);
                double rounding = 1e-4 * std::max(std::abs(t), std::abs(rv));
                double sd = std::sqrt(var * (1.0 + ratio) + rounding * rounding);
                double z = sd > 0.0 ? std::abs(t - rv) / sd : 0.0;
                ++r.tested;
                worst = std::max(worst, z);
                if (z > 3.0) ++beyond3;
                if (z > r.threshold) ++r.rejected;
            }
            r.max_abs_z = std::max(r.max_abs_z, worst);
            // Colour: grey where consistent, yellow to red as |z| grows, white when rejected.
            Spectrum c = worst > r.threshold ? Spectrum(1.0f) : draw::colormap_sequential(float(worst / r.threshold));
            map.set_rgb(x, y, c);
        }
    r.fraction_beyond_3 = r.tested ? double(beyond3) / double(r.tested) : 0.0;
    if (z_map) {
        char hi[32], mid[32];
        std::snprintf(hi, sizeof hi, "%.1f", r.threshold);
        std::snprintf(mid, sizeof mid, "%.1f", 0.5 * r.threshold);
        *z_map = draw::with_legend(map, draw::colormap_sequential, false, {hi, mid, "0"}, "ABS Z (WHITE: REJECTED)");
    }
    return r;
}

Image relative_difference_map(const Image& test, const Image& ref, float range) {
    Image map = Image::rgb(test.width(), test.height());
    for (int y = 0; y < test.height(); ++y)
        for (int x = 0; x < test.width(); ++x) {
            float lt = luminance(test.rgb_at(x, y)), lr = luminance(ref.rgb_at(x, y));
            float rel = (lt - lr) / (std::abs(lr) + 0.01f);
            map.set_rgb(x, y, draw::colormap_diverging(rel / range));
        }
    return map;
}

Image relative_difference_heatmap(const Image& test, const Image& ref, float range) {
    const Image map = relative_difference_map(test, ref, range);
    char hi[32], lo[32];
    std::snprintf(hi, sizeof hi, "+%.0f%%", 100.0 * range);
    std::snprintf(lo, sizeof lo, "-%.0f%%", 100.0 * range);
    return draw::with_legend(map, draw::colormap_diverging, true, {hi, "0%", lo}, "(A-B)/B");
}

PixelDifference max_pixel_relative_difference(const Image& test, const Image& reference) {
    if (test.width() != reference.width() || test.height() != reference.height() || test.channels() != reference.channels())
        throw InputError("images differ in size or channels: " + std::to_string(test.width()) + " x " + std::to_string(test.height()) +
                         " with " + std::to_string(test.channel_count()) + " channels against " + std::to_string(reference.width()) +
                         " x " + std::to_string(reference.height()) + " with " + std::to_string(reference.channel_count()));
    // Channels grouped by layer: the name up to its last dot.
    std::map<std::string, std::vector<int>> layers;
    for (int c = 0; c < test.channel_count(); ++c) {
        const std::string& name = test.channels()[c];
        size_t dot = name.rfind('.');
        layers[dot == std::string::npos ? "" : name.substr(0, dot)].push_back(c);
    }
    PixelDifference worst;
    for (int y = 0; y < test.height(); ++y)
        for (int x = 0; x < test.width(); ++x)
            for (const auto& [layer, channels] : layers) {
                double scale = 0.0, diff = 0.0;
                for (int c : channels) {
                    double t = test.at(x, y, c), r = reference.at(x, y, c);
                    scale = std::max({scale, std::abs(t), std::abs(r)});
                    diff = std::max(diff, std::abs(t - r));
                }
                double relative = diff > 0.0 ? diff / scale : 0.0;
                if (!(relative <= worst.max_relative)) worst = PixelDifference{relative, x, y, layer};
            }
    return worst;
}

}  // namespace candela
