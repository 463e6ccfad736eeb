#include "core/distribution.h"

#include <numeric>

namespace candela {

Distribution1D::Distribution1D(std::vector<float> weights) {
    size_t n = weights.size();
    if (n == 0) return;
    cdf_.resize(n + 1);
    cdf_[0] = 0.0;
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        float w = std::isfinite(weights[i]) ? std::max(weights[i], 0.0f) : 0.0f;
        weights[i] = w;
        sum += w;
        cdf_[i + 1] = sum;
    }
    total_ = static_cast<float>(sum);
    pdf_.resize(n);
    if (sum <= 0.0) {
        // All-zero weights: fall back to uniform so that sampling stays defined.
        for (size_t i = 0; i <= n; ++i) cdf_[i] = double(i) / double(n);
        std::fill(pdf_.begin(), pdf_.end(), 1.0f / float(n));
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        pdf_[i] = static_cast<float>(weights[i] / sum);
        cdf_[i + 1] /= sum;
    }
    cdf_[n] = 1.0;
}

size_t Distribution1D::sample_discrete(float& u) const {
    // First bin whose upper cdf edge exceeds u; skip zero-probability bins.
    size_t n = pdf_.size();
    auto it = std::upper_bound(cdf_.begin() + 1, cdf_.end(), double(u));
    size_t i = std::min(size_t(it - cdf_.begin()) - 1, n - 1);
    while (i + 1 < n && pdf_[i] == 0.0f) ++i;
    double width = cdf_[i + 1] - cdf_[i];
    double t = width > 0.0 ? (double(u) - cdf_[i]) / width : 0.0;
    u = std::clamp(static_cast<float>(t), 0.0f, std::nextafter(1.0f, 0.0f));
    return i;
}

float Distribution1D::sample_continuous(float u, float* pdf, size_t* bin) const {
    float rescaled = u;
    size_t i = sample_discrete(rescaled);
    if (bin) *bin = i;
    size_t n = pdf_.size();
    if (pdf) *pdf = pdf_[i] * float(n);
    float x = (float(i) + rescaled) / float(n);
    return std::min(x, std::nextafter(1.0f, 0.0f));
}

float Distribution1D::pdf_continuous(float x) const {
    size_t n = pdf_.size();
    if (n == 0 || !(x >= 0.0f && x < 1.0f)) return 0.0f;
    size_t i = std::min(size_t(x * float(n)), n - 1);
    return pdf_[i] * float(n);
}

Distribution2D::Distribution2D(const std::vector<float>& weights, int width, int height)
    : width_(width), height_(height) {
    rows_.reserve(height);
    std::vector<float> row_sums(height);
    for (int y = 0; y < height; ++y) {
        std::vector<float> row(weights.begin() + size_t(y) * width, weights.begin() + size_t(y + 1) * width);
        rows_.emplace_back(std::move(row));
        row_sums[y] = rows_.back().total();
    }
    marginal_ = Distribution1D(std::move(row_sums));
}

Vec2 Distribution2D::sample(const Vec2& u, float* pdf) const {
    float pdf_y = 0.0f, pdf_x = 0.0f;
    size_t row = 0;
    float y = marginal_.sample_continuous(u.y, &pdf_y, &row);
    float x = rows_[row].sample_continuous(u.x, &pdf_x);
    if (pdf) *pdf = pdf_x * pdf_y;
    return Vec2(x, y);
}

float Distribution2D::pdf(const Vec2& p) const {
    if (!(p.x >= 0.0f && p.x < 1.0f && p.y >= 0.0f && p.y < 1.0f)) return 0.0f;
    size_t row = std::min(size_t(p.y * float(height_)), size_t(height_ - 1));
    return marginal_.pdf_continuous(p.y) * rows_[row].pdf_continuous(p.x);
}

}  // namespace candela
