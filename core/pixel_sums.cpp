#include "core/pixel_sums.h"

#include "core/error.h"

namespace candela {

void PixelStats::add(const Spectrum& L, const FirstHitAovs& aov) {
    n++;
    for (int c = 0; c < 3; ++c) {
        sum[c] += L[c];
        sum_sq[c] += double(L[c]) * L[c];
        albedo[c] += aov.albedo[c];
        normal[c] += aov.normal[c];
    }
    depth += aov.depth;
}

void PixelStats::add(const PixelStats& o) {
    n += o.n;
    for (int c = 0; c < 3; ++c) {
        sum[c] += o.sum[c];
        sum_sq[c] += o.sum_sq[c];
        albedo[c] += o.albedo[c];
        normal[c] += o.normal[c];
    }
    depth += o.depth;
}

double PixelStats::variance_of_mean(int c) const {
    double count = n;
    double var = count > 1 ? (sum_sq[c] - sum[c] * sum[c] / count) / (count - 1) / count : 0.0;
    return std::max(var, 0.0);
}

AovLayout::AovLayout(const std::vector<std::string>& names) {
    for (const auto& a : names) {
        if (a == "albedo") albedo_ = true;
        else if (a == "normal") normal_ = true;
        else if (a == "depth") depth_ = true;
        else if (a == "variance") variance_ = true;
        else throw InputError("unknown AOV \"" + a + "\" (known: albedo, normal, depth, variance)");
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
    return out;
}

std::vector<std::string> AovLayout::channels() const {
    std::vector<std::string> channels = {"R", "G", "B"};
    const char* rgb[3] = {"R", "G", "B"};
    if (albedo_)
        for (auto c : rgb) channels.push_back(std::string("albedo.") + c);
    if (normal_)
        for (auto c : {"X", "Y", "Z"}) channels.push_back(std::string("normal.") + c);
    if (depth_) channels.push_back("depth.Z");
    if (variance_)
        for (auto c : rgb) channels.push_back(std::string("variance.") + c);
    return channels;
}

void AovLayout::write(const PixelStats& ps, Image& img, int x, int y) const {
    int c = 3;
    double inv_n = ps.n ? 1.0 / double(ps.n) : 0.0;
    if (albedo_)
        for (int k = 0; k < 3; ++k) img.at(x, y, c++) = float(ps.albedo[k] * inv_n);
    if (normal_)
        for (int k = 0; k < 3; ++k) img.at(x, y, c++) = float(ps.normal[k] * inv_n);
    if (depth_) img.at(x, y, c++) = float(ps.depth * inv_n);
    if (variance_)
        for (int k = 0; k < 3; ++k) img.at(x, y, c++) = float(ps.variance_of_mean(k));
}

PixelSums::PixelSums(const ImageRect& rect, const AovLayout& layout)
    : rect_(rect), layout_(layout), filtered_(size_t(rect.size.x) * rect.size.y * 4, 0.0) {
    if (layout.pixel_stats()) stats_.resize(size_t(rect.size.x) * rect.size.y);
}

void PixelSums::add(const PixelSums& other) {
    const Vec2i at = other.rect_.offset - rect_.offset;
    const Vec2i end = at + other.rect_.size;
    if (at.x < 0 || at.y < 0 || end.x > rect_.size.x || end.y > rect_.size.y || other.has_stats() != has_stats())
        throw InputError("sums of another region or layout cannot be added");
    for (int y = 0; y < other.rect_.size.y; ++y)
        for (int x = 0; x < other.rect_.size.x; ++x) {
            const double* src = other.filtered_at(x, y);
            double* dst = filtered_at(at.x + x, at.y + y);
            for (int c = 0; c < 4; ++c) dst[c] += src[c];
            if (has_stats()) stats_at(at.x + x, at.y + y).add(other.stats_at(x, y));
        }
}

Image PixelSums::develop() const {
    Image img(rect_.size.x, rect_.size.y, layout_.channels());
    for (int y = 0; y < rect_.size.y; ++y)
        for (int x = 0; x < rect_.size.x; ++x) {
            const double* a = filtered_at(x, y);
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = a[3] > 0.0 ? float(a[c] / a[3]) : 0.0f;
            if (has_stats()) layout_.write(stats_at(x, y), img, x, y);
        }
    return img;
}

}  // namespace candela
