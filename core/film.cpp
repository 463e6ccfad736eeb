#include "core/film.h"

namespace candela {

ImageBlock::ImageBlock(const Vec2i& offset, const Vec2i& size, const ReconstructionFilter* filter)
    : offset_(offset), size_(size), filter_(filter) {
    border_ = reach(*filter);
    stored_size_ = size + Vec2i(2 * border_);
    data_.assign(size_t(stored_size_.x) * stored_size_.y * 4, 0.0f);
}

int ImageBlock::reach(const ReconstructionFilter& filter) { return std::max(0, int(std::ceil(filter.radius() - 0.5f))); }

void ImageBlock::clear() { std::fill(data_.begin(), data_.end(), 0.0f); }

void ImageBlock::put(const Vec2& pos, const Spectrum& L) {
    const float r = filter_->radius();
    // Position relative to the stored area's first pixel.
    Vec2 local = pos - Vec2(offset_) + Vec2(float(border_));
    int x0 = std::max(0, int(std::ceil(local.x - 0.5f - r)));
    int x1 = std::min(stored_size_.x - 1, int(std::floor(local.x - 0.5f + r)));
    int y0 = std::max(0, int(std::ceil(local.y - 0.5f - r)));
    int y1 = std::min(stored_size_.y - 1, int(std::floor(local.y - 0.5f + r)));
    // Filter weights per column and row (the filter is separable); radius <= 4 keeps this small.
    float wx[16], wy[16];
    int nx = std::min(x1 - x0 + 1, 16), ny = std::min(y1 - y0 + 1, 16);
    for (int i = 0; i < nx; ++i) wx[i] = filter_->eval(float(x0 + i) + 0.5f - local.x);
    for (int j = 0; j < ny; ++j) wy[j] = filter_->eval(float(y0 + j) + 0.5f - local.y);
    for (int j = 0; j < ny; ++j) {
        if (wy[j] == 0.0f) continue;
        float* row = &data_[(size_t(y0 + j) * stored_size_.x + x0) * 4];
        for (int i = 0; i < nx; ++i) {
            float w = wx[i] * wy[j];
            if (w == 0.0f) continue;
            row[4 * i + 0] += w * L.x;
            row[4 * i + 1] += w * L.y;
            row[4 * i + 2] += w * L.z;
            row[4 * i + 3] += w;
        }
    }
}

void ImageBlock::accumulate_into(std::vector<double>& buffer, const Vec2i& buffer_size) const {
    for (int y = 0; y < stored_size_.y; ++y) {
        int by = offset_.y - border_ + y;
        if (by < 0 || by >= buffer_size.y) continue;
        for (int x = 0; x < stored_size_.x; ++x) {
            int bx = offset_.x - border_ + x;
            if (bx < 0 || bx >= buffer_size.x) continue;
            const float* src = &data_[(size_t(y) * stored_size_.x + x) * 4];
            double* dst = &buffer[(size_t(by) * buffer_size.x + bx) * 4];
            for (int c = 0; c < 4; ++c) dst[c] += src[c];
        }
    }
}

}  // namespace candela
