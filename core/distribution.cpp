#include "core/distribution.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

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

Distribution2D::Distribution2D(const std::vector<float>& weights, int width, int height) : width_(width), height_(height) {
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

namespace candela {

namespace {

// The largest i in [0, size - 2] with below(i) true (0 when none is), by bisection; `below` must
// be monotone (true, then false).
template <typename Below>
size_t find_interval(size_t size, const Below& below) {
    size_t lo = 0, hi = size - 1;  // below(lo) is assumed; the answer lies in [lo, hi)
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (below(mid))
            lo = mid;
        else
            hi = mid;
    }
    return std::min(lo, size - 2);
}

// Solves integral_0^t (a (1 - x) + b x) dx = a t + (b - a) t^2 / 2 = v for t in [0, 1]: the
// inverse CDF of a linear density on one interval. Mitsuba writes the root as
// (a - sqrt(a^2 + 2 v (b - a))) / (a - b), which cancels badly when a and b are close; the same
// root as 2 v / (a + sqrt(...)) does not (a, b >= 0), and needs no case for a = b.
float invert_linear(float a, float b, float v) {
    float denominator = a + std::sqrt(std::max(a * a + 2.0f * v * (b - a), 0.0f));
    return denominator > 0.0f ? 2.0f * v / denominator : 0.5f;
}

}  // namespace

Marginal2D::Marginal2D(const float* data, int width, int height, std::vector<std::vector<float>> params, Mode mode)
    : width_(width), height_(height), mode_(mode), params_(std::move(params)) {
    if (width < 2 || height < 2) throw std::invalid_argument("a grid needs at least 2 x 2 values");
    if (params_.size() > size_t(MaxParams)) throw std::invalid_argument("at most three parameters");
    size_t slices = 1;
    param_strides_.assign(params_.size(), 0);
    for (size_t d = params_.size(); d-- > 0;) {
        const std::vector<float>& v = params_[d];
        if (v.empty()) throw std::invalid_argument("a parameter without values");
        for (size_t i = 0; i < v.size(); ++i)
            if (!std::isfinite(v[i]) || (i > 0 && !(v[i] > v[i - 1])))
                throw std::invalid_argument("parameter values must be finite and increase");
        param_strides_[d] = slices;
        slices *= v.size();
    }
    size_t n = size_t(width) * size_t(height);
    data_.assign(data, data + slices * n);
    if (mode == Mode::Interpolant) return;

    conditional_cdf_.resize(slices * n);
    marginal_cdf_.resize(slices * size_t(height));
    for (size_t s = 0; s < slices; ++s) {
        float* values = &data_[s * n];
        float* conditional = &conditional_cdf_[s * n];
        float* marginal = &marginal_cdf_[s * size_t(height)];
        for (size_t i = 0; i < n; ++i)
            if (!(values[i] >= 0.0f) || !std::isfinite(values[i])) throw std::invalid_argument("a density value is negative or not finite");
        // Trapezoidal running sums are the exact integrals of the linear interpolant.
        for (int y = 0; y < height; ++y) {
            double sum = 0.0;
            size_t row = size_t(y) * size_t(width);
            conditional[row] = 0.0f;
            for (int x = 0; x + 1 < width; ++x) {
                sum += 0.5 * (double(values[row + size_t(x)]) + double(values[row + size_t(x) + 1]));
                conditional[row + size_t(x) + 1] = float(sum);
            }
        }
        double sum = 0.0;
        marginal[0] = 0.0f;
        for (int y = 0; y + 1 < height; ++y) {
            sum += 0.5 * (double(conditional[size_t(y + 1) * size_t(width) - 1]) + double(conditional[size_t(y + 2) * size_t(width) - 1]));
            marginal[y + 1] = float(sum);
        }
        if (!(sum > 0.0) || !std::isfinite(sum)) throw std::invalid_argument("a density integrates to zero");
        float scale = float(1.0 / sum);
        for (size_t i = 0; i < n; ++i) {
            values[i] *= scale;
            conditional[i] *= scale;
        }
        for (int y = 0; y < height; ++y) marginal[y] *= scale;
    }
}

Marginal2D::Blend Marginal2D::blend(const float* params) const { return blend_first(params, params_.size()); }

Marginal2D::Blend Marginal2D::blend_leading(const float* params) const {
    if (params_.empty()) throw std::invalid_argument("blend_leading: the table has no parameters");
    return blend_first(params, params_.size() - 1);
}

Marginal2D::Blend Marginal2D::at_node(Blend leading, int last_node) const {
    if (params_.empty() || last_node < 0 || size_t(last_node) >= params_.back().size())
        throw std::invalid_argument("at_node: no such node of the last parameter");
    // At a node the last parameter's interpolation weights are exactly 1 and 0, and lookup()
    // skips the grids of weight 0: the same grids, weights and order as blend() gives.
    for (int k = 0; k < leading.count; ++k) leading.slice[size_t(k)] += param_strides_.back() * size_t(last_node);
    return leading;
}

Marginal2D::Blend Marginal2D::blend_first(const float* params, size_t count) const {
    Blend b;
    b.slice[0] = 0;
    b.weight[0] = 1.0f;
    for (size_t d = 0; d < count; ++d) {
        const std::vector<float>& v = params_[d];
        if (v.size() == 1) continue;
        float p = params[d];
        size_t i = find_interval(v.size(), [&](size_t k) { return v[k] < p; });
        float t = (p - v[i]) / (v[i + 1] - v[i]);
        t = t > 0.0f ? std::min(t, 1.0f) : 0.0f;  // clamped (and 0 for NaN)
        for (int k = 0; k < b.count; ++k) {
            b.slice[size_t(b.count + k)] = b.slice[size_t(k)] + param_strides_[d] * (i + 1);
            b.weight[size_t(b.count + k)] = b.weight[size_t(k)] * t;
            b.slice[size_t(k)] += param_strides_[d] * i;
            b.weight[size_t(k)] *= 1.0f - t;
        }
        b.count *= 2;
    }
    return b;
}

float Marginal2D::lookup(const std::vector<float>& array, size_t stride, const Blend& b, size_t i) {
    float v = 0.0f;
    for (int k = 0; k < b.count; ++k)
        if (b.weight[size_t(k)] != 0.0f) v += b.weight[size_t(k)] * array[b.slice[size_t(k)] * stride + i];
    return v;
}

void Marginal2D::values_at_height(const Blend& b, size_t row, size_t col, float t, float& c0, float& c1) const {
    size_t n = size_t(width_) * size_t(height_), w = size_t(width_), i = row * w + col;
    c0 = (1.0f - t) * lookup(data_, n, b, i) + t * lookup(data_, n, b, i + w);
    c1 = (1.0f - t) * lookup(data_, n, b, i + 1) + t * lookup(data_, n, b, i + w + 1);
}

Marginal2D::Patch Marginal2D::patch_at(const Vec2& p, const Blend& b) const {
    Patch q;
    // Clamped to the square, NaN to 0 (std::clamp passes NaN through, and NaN to size_t is
    // undefined: fuzz_measured's tables gave a NaN point).
    auto unit = [](float v) { return v > 0.0f ? std::min(v, 1.0f) : 0.0f; };
    float x = unit(p.x) * float(width_ - 1), y = unit(p.y) * float(height_ - 1);
    q.col = std::min(size_t(x), size_t(width_ - 2));
    q.row = std::min(size_t(y), size_t(height_ - 2));
    q.s = x - float(q.col);
    q.t = y - float(q.row);
    values_at_height(b, q.row, q.col, q.t, q.c0, q.c1);
    return q;
}

float Marginal2D::eval(const Vec2& p, const Blend& b) const {
    Patch q = patch_at(p, b);
    float value = (1.0f - q.s) * q.c0 + q.s * q.c1;
    return mode_ == Mode::Distribution ? value * float(width_ - 1) * float(height_ - 1) : value;
}

Vec2 Marginal2D::sample(Vec2 u, const Blend& b, float* pdf) const {
    size_t n = size_t(width_) * size_t(height_), w = size_t(width_);
    u = glm::clamp(u, Vec2(1e-7f), Vec2(0.99999994f));
    // The row: the marginal density is linear between the totals of rows `row` and `row` + 1.
    size_t row = find_interval(size_t(height_), [&](size_t k) { return lookup(marginal_cdf_, size_t(height_), b, k) < u.y; });
    float v = u.y - lookup(marginal_cdf_, size_t(height_), b, row);
    float r0 = lookup(conditional_cdf_, n, b, row * w + w - 1), r1 = lookup(conditional_cdf_, n, b, (row + 1) * w + w - 1);
    float t = std::clamp(invert_linear(r0, r1, v), 0.0f, 1.0f);
    // The column, in the row interpolated at t.
    float target = u.x * ((1.0f - t) * r0 + t * r1);
    auto conditional = [&](size_t k) {
        return (1.0f - t) * lookup(conditional_cdf_, n, b, row * w + k) + t * lookup(conditional_cdf_, n, b, (row + 1) * w + k);
    };
    size_t col = find_interval(w, [&](size_t k) { return conditional(k) < target; });
    float c0, c1;
    values_at_height(b, row, col, t, c0, c1);
    float s = std::clamp(invert_linear(c0, c1, target - conditional(col)), 0.0f, 1.0f);
    *pdf = ((1.0f - s) * c0 + s * c1) * float(width_ - 1) * float(height_ - 1);
    return Vec2((float(col) + s) / float(width_ - 1), (float(row) + t) / float(height_ - 1));
}

Vec2 Marginal2D::invert(Vec2 p, const Blend& b, float* pdf) const {
    size_t n = size_t(width_) * size_t(height_), w = size_t(width_);
    Patch q = patch_at(p, b);
    float s = q.s, t = q.t;
    *pdf = ((1.0f - s) * q.c0 + s * q.c1) * float(width_ - 1) * float(height_ - 1);
    size_t i = q.row * w + q.col;
    float r0 = lookup(conditional_cdf_, n, b, q.row * w + w - 1), r1 = lookup(conditional_cdf_, n, b, (q.row + 1) * w + w - 1);
    // The conditional CDF at x: the row's integral up to the patch, then within it.
    float ux =
        (1.0f - t) * lookup(conditional_cdf_, n, b, i) + t * lookup(conditional_cdf_, n, b, i + w) + s * (q.c0 + 0.5f * s * (q.c1 - q.c0));
    float total = (1.0f - t) * r0 + t * r1;
    ux = total > 0.0f ? ux / total : 0.0f;
    float uy = lookup(marginal_cdf_, size_t(height_), b, q.row) + t * (r0 + 0.5f * t * (r1 - r0));
    return Vec2(ux, uy);
}

}  // namespace candela
