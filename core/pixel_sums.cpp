#include "core/pixel_sums.h"

#include "core/error.h"
#include "core/math.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace candela {

bool rect_inside(const ImageRect& inner, const ImageRect& outer) {
    if (inner.empty()) return false;
    for (int axis = 0; axis < 2; ++axis) {
        const int64_t lo = inner.offset[axis], hi = lo + int64_t(inner.size[axis]);
        const int64_t outer_lo = outer.offset[axis], outer_hi = outer_lo + int64_t(outer.size[axis]);
        if (lo < outer_lo || hi > outer_hi) return false;
    }
    return true;
}

void PixelStats::add(const Spectrum& L, const FirstHitAovs& aov, uint32_t index) {
    n++;
    const bool a = in_class_a(index);
    n_a += a;
    for (int c = 0; c < 3; ++c) {
        sum[c] += L[c];
        sum_sq[c] += double(L[c]) * L[c];
        if (a) sum_a[c] += L[c];
        albedo[c] += aov.albedo[c];
        normal[c] += aov.normal[c];
    }
    depth += aov.depth;
}

void PixelStats::add(const PixelStats& o) {
    n += o.n;
    taken += o.taken;
    n_a += o.n_a;
    for (int c = 0; c < 3; ++c) {
        sum[c] += o.sum[c];
        sum_sq[c] += o.sum_sq[c];
        sum_a[c] += o.sum_a[c];
        albedo[c] += o.albedo[c];
        normal[c] += o.normal[c];
    }
    depth += o.depth;
}

bool PixelStats::in_class_a(uint32_t index) {
    uint32_t v = index & 0xaaaaaaaau;
    int ones = 0;
    for (; v; v &= v - 1) ++ones;
    return ones & 1;
}

double PixelStats::adaptive_error() const {
    if (n == 0 || n_a == 0) return Infinity;
    double difference = 0, total = 0;
    for (int c = 0; c < 3; ++c) {
        double mean = sum[c] / n;
        difference += std::abs(mean - sum_a[c] / n_a);
        total += mean;
    }
    return difference / (1e-4 + std::sqrt(std::max(total, 0.0)));
}

double PixelStats::variance_of_mean(int c) const {
    double count = n;
    double var = count > 1 ? (sum_sq[c] - sum[c] * sum[c] / count) / (count - 1) / count : 0.0;
    return std::max(var, 0.0);
}

SampleLayout::SampleLayout(PixelFormat format, std::vector<std::string> integrator_channels)
    : format_(format), alpha_(pixel_format_has_alpha(format)), extra_names_(std::move(integrator_channels)) {}

SampleLayout::SampleLayout(std::vector<std::string> band_names, std::vector<std::string> integrator_channels)
    : band_names_(std::move(band_names)), extra_names_(std::move(integrator_channels)) {}

SampleLayout SampleLayout::of_film(const Film& film, std::vector<std::string> integrator_channels) {
    if (const FilmBands* bands = film.bands()) return SampleLayout(bands->names, std::move(integrator_channels));
    return SampleLayout(film.pixel_format(), std::move(integrator_channels));
}

namespace {
const std::string BandsKey = "bands:";
}  // namespace

std::string SampleLayout::film_key() const {
    return has_bands() ? BandsKey + join_list(band_names_) : join_list(pixel_format_channels(format_));
}

SampleLayout SampleLayout::from_film_key(const std::string& key, std::vector<std::string> integrator_channels) {
    if (key.rfind(BandsKey, 0) == 0 && key.size() > BandsKey.size())
        return SampleLayout(split_list(key.substr(BandsKey.size())), std::move(integrator_channels));
    for (PixelFormat f :
         {PixelFormat::Luminance, PixelFormat::LuminanceAlpha, PixelFormat::RGB, PixelFormat::RGBA, PixelFormat::XYZ, PixelFormat::XYZA})
        if (join_list(pixel_format_channels(f)) == key) return SampleLayout(f, std::move(integrator_channels));
    throw InputError("film channels \"" + key + "\" name no pixel format");
}

std::vector<std::string> SampleLayout::value_names() const {
    std::vector<std::string> names = has_bands() ? band_names_ : std::vector<std::string>{"R", "G", "B"};
    if (alpha_) names.push_back("A");
    names.insert(names.end(), extra_names_.begin(), extra_names_.end());
    return names;
}

bool SampleLayout::fill(const Spectrum& L, bool valid, const float* integrator_values, float* out) const {
    // Each value is checked as it is written (the alpha, 0 or 1, needs no check), rather than
    // read back from `out` afterwards.
    bool storable = storable_sample_value(L);
    int c = 0;
    for (int k = 0; k < 3; ++k) out[c++] = L[k];
    if (alpha_) out[c++] = valid ? 1.0f : 0.0f;
    for (int k = 0; k < extras(); ++k) {
        out[c++] = integrator_values[k];
        storable = storable && storable_sample_value(integrator_values[k]);
    }
    return storable;
}

bool SampleLayout::fill_bands(const float* band_values, const float* integrator_values, float* out) const {
    bool storable = true;
    int c = 0;
    for (int k = 0; k < film_values(); ++k) {
        out[c++] = band_values[k];
        storable = storable && storable_sample_value(band_values[k]);
    }
    for (int k = 0; k < extras(); ++k) {
        out[c++] = integrator_values[k];
        storable = storable && storable_sample_value(integrator_values[k]);
    }
    return storable;
}

std::vector<std::string> SampleLayout::channels() const {
    std::vector<std::string> names = has_bands() ? band_names_ : pixel_format_channels(format_);
    names.insert(names.end(), extra_names_.begin(), extra_names_.end());
    return names;
}

namespace {
// A developed value as a float: finite sums can have a mean beyond float range (a weight sum
// near zero, from a filter's negative lobes cancelling or from a damaged part file, fuzz_part),
// which a plain conversion would make infinite; it saturates at the largest float instead, so
// no image developed from sums holds an infinity.
float saturated(double v) {
    constexpr double Largest = double(std::numeric_limits<float>::max());
    return float(std::clamp(v, -Largest, Largest));
}
}  // namespace

void SampleLayout::write(const double* v, float* out) const {
    if (has_bands()) {
        for (int k = 0; k < values(); ++k) out[k] = saturated(v[k]);
        return;
    }
    const Spectrum rgb{saturated(v[0]), saturated(v[1]), saturated(v[2])};
    write_pixel_format(format_, rgb, alpha_ ? saturated(v[3]) : 1.0f, out);
    // The format's conversion (XYZ's Z row sums to 1.09) can carry the largest floats past range.
    const size_t written = pixel_format_channels(format_).size();
    for (size_t k = 0; k < written; ++k) out[k] = saturated(double(out[k]));
    out += written;
    for (int k = 0, first = alpha_ ? 4 : 3; k < extras(); ++k) out[k] = saturated(v[first + k]);
}

AovLayout::AovLayout(const std::vector<std::string>& names) {
    for (const auto& a : names) {
        if (a == "albedo")
            albedo_ = true;
        else if (a == "normal")
            normal_ = true;
        else if (a == "depth")
            depth_ = true;
        else if (a == "variance")
            variance_ = true;
        else if (a == "samples")
            samples_ = true;
        else
            throw InputError("unknown AOV \"" + a + "\" (known: albedo, normal, depth, variance, samples)");
    }
}

std::string AovLayout::names() const {
    std::string out;
    auto add = [&](bool on, const char* name) {
        if (!on) return;
        if (!out.empty()) out += ",";
        out += name;
    };
    add(albedo_, "albedo");
    add(normal_, "normal");
    add(depth_, "depth");
    add(variance_, "variance");
    add(samples_, "samples");
    return out;
}

std::vector<std::string> AovLayout::channels() const {
    std::vector<std::string> channels;
    const char* rgb[3] = {"R", "G", "B"};
    if (albedo_)
        for (auto c : rgb) channels.push_back(std::string("albedo.") + c);
    if (normal_)
        for (auto c : {"X", "Y", "Z"}) channels.push_back(std::string("normal.") + c);
    if (depth_) channels.push_back("depth.Z");
    if (variance_)
        for (auto c : rgb) channels.push_back(std::string("variance.") + c);
    if (samples_) channels.push_back("samples.N");
    return channels;
}

void AovLayout::write(const PixelStats& ps, Image& img, int x, int y, int c) const {
    double inv_n = ps.n ? 1.0 / double(ps.n) : 0.0;
    if (albedo_)
        for (int k = 0; k < 3; ++k) img.at(x, y, c++) = saturated(ps.albedo[k] * inv_n);
    if (normal_)
        for (int k = 0; k < 3; ++k) img.at(x, y, c++) = saturated(ps.normal[k] * inv_n);
    if (depth_) img.at(x, y, c++) = saturated(ps.depth * inv_n);
    if (variance_)
        for (int k = 0; k < 3; ++k) img.at(x, y, c++) = saturated(ps.variance_of_mean(k));
    if (samples_) img.at(x, y, c++) = float(ps.taken);
}

PixelSums::PixelSums(const ImageRect& rect, const SampleLayout& values, const AovLayout& layout)
    : rect_(rect), values_(values), layout_(layout), filtered_(size_t(rect.size.x) * rect.size.y * size_t(values.values() + 1), 0.0) {
    if (layout.pixel_stats()) stats_.resize(size_t(rect.size.x) * rect.size.y);
}

void PixelSums::add(const PixelSums& other) {
    if ((!other.rect_.empty() && !rect_inside(other.rect_, rect_)) || other.has_stats() != has_stats() || other.stride() != stride())
        throw InputError("sums of another region or layout cannot be added");
    const Vec2i at = other.rect_.offset - rect_.offset;
    const int n = stride();
    for (int y = 0; y < other.rect_.size.y; ++y)
        for (int x = 0; x < other.rect_.size.x; ++x) {
            const double* src = other.filtered_at(x, y);
            double* dst = filtered_at(at.x + x, at.y + y);
            for (int c = 0; c < n; ++c) dst[c] += src[c];
            if (has_stats()) stats_at(at.x + x, at.y + y).add(other.stats_at(x, y));
        }
}

Image PixelSums::develop() const {
    std::vector<std::string> channels = values_.channels();
    const int first_layer = int(channels.size());
    std::vector<std::string> layer_channels = layout_.channels();
    channels.insert(channels.end(), layer_channels.begin(), layer_channels.end());
    Image img(rect_.size.x, rect_.size.y, channels);
    const int n = stride();
    std::vector<double> normalised(size_t(n - 1));
    for (int y = 0; y < rect_.size.y; ++y)
        for (int x = 0; x < rect_.size.x; ++x) {
            const double* a = filtered_at(x, y);
            const double w = a[n - 1];
            for (int c = 0; c + 1 < n; ++c) normalised[c] = w > 0.0 ? a[c] / w : 0.0;
            values_.write(normalised.data(), &img.at(x, y, 0));
            if (has_stats()) layout_.write(stats_at(x, y), img, x, y, first_layer);
        }
    return img;
}

}  // namespace candela
