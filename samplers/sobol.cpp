// sobol: one Owen-scrambled Sobol' sequence over the whole image (pbrt-v4's SobolSampler; the
// algorithm of Grünschloß, Raab and Keller 2012, "Enumerating Quasi-Monte Carlo Point Sequences
// in Elementary Intervals").
//
// Parameters: sample_count, seed, randomization (see samplers/sobol_base.h).
//
// The image is scaled into the unit square (its larger side rounded up to a power of two 2^m),
// so that each pixel is an elementary interval of dimensions 0 and 1. A pixel's sample i is the
// i-th point of the sequence that falls into that pixel: its index is (i << 2m) plus low bits
// found by inverting the 2m x 2m generator matrix of dimensions 0 and 1 over GF(2). Dimensions 0
// and 1 then give the position inside the pixel, randomized per pixel (pbrt-v4 leaves them
// unscrambled, so that every pixel has the same sub-pixel pattern and the pooled positions fall
// on a quarter of an 8 x 8 grid: a test of the 2D projections showed it; a scramble per pixel
// keeps each pixel's (0, m, 2)-net); dimensions 2 to 256 are the sequence's own, randomized per dimension; beyond the
// table, dimensions are padded with independent numbers hashed from (seed, pixel, sample,
// dimension).

#include "core/properties.h"
#include "core/registry.h"
#include "samplers/sobol_base.h"

#include <utility>
#include <vector>

namespace candela {

class SobolSampler final : public SobolSamplerBase {
public:
    explicit SobolSampler(const Properties& props) {
        read_parameters(props);
        film_changed();
    }

    Ref<Sampler> clone() const override { return std::make_shared<SobolSampler>(*this); }
    std::string to_string() const override { return "sobol"; }

    float next_1d() override { return value(dimension_++); }
    Vec2 next_2d() override {
        float x = value(dimension_);
        float y = value(dimension_ + 1);
        dimension_ += 2;
        return Vec2(x, y);
    }

protected:
    // The sequence spans the film and its sampled border: pixel p is cell p + border of a
    // 2^m x 2^m grid with 2^m >= size + 2 border.
    void film_changed() override {
        const Vec2i span = film_size_ + 2 * film_border_;
        log2_scale_ = 0;
        while ((1 << log2_scale_) < std::max(span.x, span.y)) ++log2_scale_;
        build_index_solver();
    }
    // A pixel's point i is index_in_pixel(i, cell), which is linear over GF(2) in i and the cell
    // (as are the Sobol' digits in the index), so its digits are those of the pixel's point 0
    // XOR those of index_in_pixel(i, 0). The first are kept per pixel for dimensions below 64,
    // the second are a table per (dimension, bit of i): a draw walks the few bits of the sample
    // index instead of the 2m + log2(spp) bits of the whole index.
    void start_sample(const Vec2i& pixel, uint32_t index) override {
        SobolSamplerBase::start_sample(pixel, index);
        if (columns_spp_bits_ != log2_spp_ || columns_scale_ != log2_scale_) build_sample_columns();
        const Vec2i cell = pixel + film_border_;
        if (pixel_digits_.keep_for({cell, log2_scale_})) pixel_index_ = index_in_pixel(0, cell);
        sample_index_ = index;
    }
    // Dimensions 0 and 1 are randomized per pixel: hashed once for the pixel's samples.
    void sequence_changed() override {
        pixel_hashes_[0] = hash_bits(sequence_, 0);
        pixel_hashes_[1] = hash_bits(sequence_, 1);
    }

private:
    float value(uint32_t dim) const {
        // Dimensions 0 and 1: the digits below the pixel's m leading ones, shifted up by m (in
        // reversed order, down).
        if (dim < 2) return bits_to_unit(randomize_reversed(digits_reversed(dim) >> log2_scale_, pixel_hashes_[dim]));
        if (dim < uint32_t(SobolDimensions))
            return bits_to_unit(randomize_reversed(digits_reversed(dim), uint32_t(dimension_hash(dim) >> 32)));
        return jitter(dim);
    }

    // sobol_bits_reversed(index_in_pixel(sample_index_, cell), dim), for dim below SobolDimensions.
    uint32_t digits_reversed(uint32_t dim) const {
        auto compute = [&] { return sobol_bits_reversed(pixel_index_, int(dim)); };
        uint32_t v = dim < pixel_digits_.size ? pixel_digits_.get(dim, compute) : compute();
        const uint32_t* columns = sample_columns_.data() + size_t(dim) * size_t(log2_spp_);
        for (uint32_t bits = sample_index_; bits != 0; bits &= bits - 1) v ^= columns[__builtin_ctz(bits)];
        return v;
    }

    // Row `dim`, column j: the reversed digits of dimension dim at index_in_pixel(2^j, 0).
    void build_sample_columns() {
        sample_columns_.assign(size_t(SobolDimensions) * size_t(log2_spp_), 0);
        for (int j = 0; j < log2_spp_; ++j) {
            const uint64_t index = index_in_pixel(uint32_t(1) << j, Vec2i(0));
            for (int dim = 0; dim < SobolDimensions; ++dim)
                sample_columns_[size_t(dim) * size_t(log2_spp_) + size_t(j)] = sobol_bits_reversed(index, dim);
        }
        columns_spp_bits_ = log2_spp_;
        columns_scale_ = log2_scale_;
    }

    // The leading m digits of dimensions 0 and 1 contributed by index bit j, as one 2m-bit word:
    // dimension 0's (the pixel's x) above dimension 1's (its y).
    uint64_t leading_digits(int j) const {
        const int m = log2_scale_;
        uint64_t x = sobol_matrix(0)[j] >> (32 - m), y = sobol_matrix(1)[j] >> (32 - m);
        return (x << m) | y;
    }

    // Precomputes the solution of "which low 2m index bits put a point into pixel p": the matrix
    // of leading digits of index bits 0 .. 2m-1 is invertible because dimensions 0 and 1 form a
    // (0, 2)-sequence. Gauss-Jordan elimination over GF(2) on rows [A | I].
    void build_index_solver() {
        const int m = log2_scale_, n = 2 * m;
        target_to_index_.assign(size_t(n), 0);
        frame_digits_.clear();
        if (m == 0) return;
        std::vector<uint64_t> rows(size_t(n), 0);  // bits 0..n-1: A's row; bits 32..32+n-1: identity
        for (int r = 0; r < n; ++r) {
            for (int j = 0; j < n; ++j)
                if ((leading_digits(j) >> r) & 1u) rows[size_t(r)] |= uint64_t(1) << j;
            rows[size_t(r)] |= uint64_t(1) << (32 + r);
        }
        for (int col = 0; col < n; ++col) {
            int pivot = col;
            while (!((rows[size_t(pivot)] >> col) & 1u)) ++pivot;  // exists: A is invertible
            std::swap(rows[size_t(col)], rows[size_t(pivot)]);
            for (int r = 0; r < n; ++r)
                if (r != col && ((rows[size_t(r)] >> col) & 1u)) rows[size_t(r)] ^= rows[size_t(col)];
        }
        // Row j of the inverse says which target digits sum to index bit j; store it by digit.
        for (int j = 0; j < n; ++j)
            for (int b = 0; b < n; ++b)
                if ((rows[size_t(j)] >> (32 + b)) & 1u) target_to_index_[size_t(b)] |= uint64_t(1) << j;
        for (int j = n; j < SobolIndexBits; ++j) frame_digits_.push_back(leading_digits(j));
    }

    // `cell` is in [0, 2^m)^2 (start()'s contract and film_changed()).
    uint64_t index_in_pixel(uint32_t frame, const Vec2i& cell) const {
        const int m = log2_scale_;
        if (m == 0) return frame;
        uint64_t target = (uint64_t(uint32_t(cell.x)) << m) | uint32_t(cell.y);
        uint64_t rest = frame;
        for (size_t c = 0; c < frame_digits_.size() && rest != 0; ++c, rest >>= 1)
            if (rest & 1u) target ^= frame_digits_[c];
        uint64_t low = 0;
        for (int b = 0; target != 0; target >>= 1, ++b)
            if (target & 1u) low ^= target_to_index_[size_t(b)];
        return (uint64_t(frame) << (2 * m)) | low;
    }

    int log2_scale_ = 0;
    std::vector<uint64_t> target_to_index_;  // per target digit: the index bits it flips
    std::vector<uint64_t> frame_digits_;     // per bit of i: the leading digits it contributes
    uint32_t pixel_hashes_[2] = {0, 0};      // hash_bits(sequence_, 0 and 1)

    // The sample columns (build_sample_columns) and what they were built for.
    std::vector<uint32_t> sample_columns_;
    int columns_spp_bits_ = -1, columns_scale_ = -1;
    // The current pixel: its cell, index_in_pixel(0, cell) and the reversed digits kept for it
    // (dimensions below 64).
    uint64_t pixel_index_ = 0;
    uint32_t sample_index_ = 0;
    mutable KeptPerPixel<std::pair<Vec2i, int>, uint32_t, 64> pixel_digits_;  // for the cell and the scale
};

CANDELA_REGISTER(SobolSampler, ObjectKind::Sampler, "sobol");

}  // namespace candela
