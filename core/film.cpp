#include "core/film.h"

#include "core/spectral.h"

#include <algorithm>

namespace candela {

std::vector<std::string> pixel_format_channels(PixelFormat format) {
    switch (format) {
        case PixelFormat::Luminance: return {"Y"};
        case PixelFormat::LuminanceAlpha: return {"Y", "A"};
        case PixelFormat::RGB: return {"R", "G", "B"};
        case PixelFormat::RGBA: return {"R", "G", "B", "A"};
        case PixelFormat::XYZ: return {"X", "Y", "Z"};
        case PixelFormat::XYZA: return {"X", "Y", "Z", "A"};
    }
    return {};
}

bool pixel_format_has_alpha(PixelFormat format) {
    return format == PixelFormat::LuminanceAlpha || format == PixelFormat::RGBA || format == PixelFormat::XYZA;
}

void write_pixel_format(PixelFormat format, const Spectrum& rgb, float alpha, float* out) {
    int c = 0;
    if (format == PixelFormat::RGB || format == PixelFormat::RGBA) {
        for (int k = 0; k < 3; ++k) out[c++] = rgb[k];
    } else {
        Vec3d xyz = linear_srgb_to_xyz(Vec3d(rgb));
        if (format == PixelFormat::Luminance || format == PixelFormat::LuminanceAlpha)
            out[c++] = float(xyz.y);
        else
            for (int k = 0; k < 3; ++k) out[c++] = float(xyz[k]);
    }
    if (pixel_format_has_alpha(format)) out[c] = alpha;
}

FilmBands::FilmBands(std::vector<std::string> band_names, std::vector<SampledSpectrum> band_responses)
    : names(std::move(band_names)), responses(std::move(band_responses)) {
    // Their sum, exact as a piecewise linear function on the union of their wavelengths.
    SampledSpectrum sum;
    for (const SampledSpectrum& r : responses) sum.wavelengths.insert(sum.wavelengths.end(), r.wavelengths.begin(), r.wavelengths.end());
    std::sort(sum.wavelengths.begin(), sum.wavelengths.end());
    sum.wavelengths.erase(std::unique(sum.wavelengths.begin(), sum.wavelengths.end()), sum.wavelengths.end());
    for (double l : sum.wavelengths) {
        double total = 0.0;
        for (const SampledSpectrum& r : responses) total += r.at(l);
        sum.values.push_back(total);
    }
    sampling = std::make_shared<SensorResponse>(std::move(sum));
}

void FilmBands::values(const Spectrum& L, const Wavelengths& w, float* out) const {
    for (int j = 0; j < count(); ++j) {
        double v = 0.0;
        for (int i = 0; i < WavelengthSamples; ++i)
            if (w.pdf[i] > 0.0f) v += responses[size_t(j)].at(w.lambda[i]) * double(L[i]) / double(w.pdf[i]);
        out[j] = float(v / WavelengthSamples);
    }
}

void require_colour_film(const Film& film, const std::string& use) {
    if (film.bands()) throw InputError(use + ", and a specfilm renders spectral bands, which have no colour: use hdrfilm for it");
}

std::string film_description(const Film& film) {
    Vec2i crop = film.crop_size();
    std::string size = std::to_string(crop.x) + " x " + std::to_string(crop.y);
    return crop == film.full_size() ? "film " + size : "film crop window " + size;
}

ImageBlock::ImageBlock(const Vec2i& offset, const Vec2i& size, const ReconstructionFilter* filter, int channels)
    : offset_(offset), size_(size), channels_(channels), filter_(filter) {
    border_ = reach(*filter);
    stored_size_ = size + Vec2i(2 * border_);
    data_.assign(size_t(stored_size_.x) * stored_size_.y * size_t(channels_ + 1), 0.0f);
}

int ImageBlock::reach(const ReconstructionFilter& filter) { return std::max(0, int(std::ceil(filter.radius() - 0.5f))); }

int film_sampled_border(const Film& film) { return film.sample_border() ? ImageBlock::reach(film.filter()) : 0; }

void ImageBlock::clear() { std::fill(data_.begin(), data_.end(), 0.0f); }

void ImageBlock::put(const Vec2& pos, const float* values) {
    const float r = filter_->radius();
    const int stride = channels_ + 1;
    // Position relative to the stored area's first pixel.
    Vec2 local = pos - Vec2(offset_) + Vec2(float(border_));
    int x0 = std::max(0, ceil_to_int(local.x - 0.5f - r));
    int x1 = std::min(stored_size_.x - 1, floor_to_int(local.x - 0.5f + r));
    int y0 = std::max(0, ceil_to_int(local.y - 0.5f - r));
    int y1 = std::min(stored_size_.y - 1, floor_to_int(local.y - 0.5f + r));
    // The common case, a footprint of one pixel (the box filter of radius 1/2 away from pixel
    // edges): one weight, no weight tables. Same products and sums as put_footprint(), so the
    // image is bit-identical.
    if (x0 == x1 && y0 == y1) {
        float w = filter_->eval(float(x0) + 0.5f - local.x) * filter_->eval(float(y0) + 0.5f - local.y);
        if (w == 0.0f) return;
        float* px = &data_[(size_t(y0) * stored_size_.x + x0) * stride];
        for (int c = 0; c < channels_; ++c) px[c] += w * values[c];
        px[channels_] += w;
        return;
    }
    put_footprint(local, Vec2i(x0, y0), Vec2i(x1, y1), values);
}

// Kept apart from put() so that the one-pixel case does not pay for this one's weight tables
// and registers on entry.
void ImageBlock::put_footprint(const Vec2& local, const Vec2i& first, const Vec2i& last, const float* values) {
    const int stride = channels_ + 1;
    const int x0 = first.x, y0 = first.y, x1 = last.x, y1 = last.y;
    // Filter weights per column and row (the filter is separable); radius <= 4 keeps this small.
    float wx[16], wy[16];
    int nx = std::min(x1 - x0 + 1, 16), ny = std::min(y1 - y0 + 1, 16);
    for (int i = 0; i < nx; ++i) wx[i] = filter_->eval(float(x0 + i) + 0.5f - local.x);
    for (int j = 0; j < ny; ++j) wy[j] = filter_->eval(float(y0 + j) + 0.5f - local.y);
    for (int j = 0; j < ny; ++j) {
        if (wy[j] == 0.0f) continue;
        float* row = &data_[(size_t(y0 + j) * stored_size_.x + x0) * stride];
        for (int i = 0; i < nx; ++i) {
            float w = wx[i] * wy[j];
            if (w == 0.0f) continue;
            float* px = row + size_t(i) * stride;
            for (int c = 0; c < channels_; ++c) px[c] += w * values[c];
            px[channels_] += w;
        }
    }
}

void ImageBlock::accumulate_into(std::vector<double>& buffer, const Vec2i& buffer_size) const {
    const int stride = channels_ + 1;
    for (int y = 0; y < stored_size_.y; ++y) {
        int by = offset_.y - border_ + y;
        if (by < 0 || by >= buffer_size.y) continue;
        for (int x = 0; x < stored_size_.x; ++x) {
            int bx = offset_.x - border_ + x;
            if (bx < 0 || bx >= buffer_size.x) continue;
            const float* src = &data_[(size_t(y) * stored_size_.x + x) * stride];
            double* dst = &buffer[(size_t(by) * buffer_size.x + bx) * stride];
            for (int c = 0; c < stride; ++c) dst[c] += src[c];
        }
    }
}

}  // namespace candela
