// zsobol: blue-noise screen-space sampling with one Owen-scrambled (0, 2)-sequence in Morton
// (Z) order (Ahmed and Wonka 2020, "Screen-Space Blue-Noise Diffusion of Monte Carlo Sampling
// Error via Hierarchical Ordering of Pixels"; pbrt-v4's ZSobolSampler).
//
// Parameters: sample_count, seed, randomization (see samplers/sobol_base.h).
//
// The pixels are numbered in Morton order and pixel p's samples are the sequence indices
// (morton(p) << log2(spp)) + i: every pixel gets an aligned block of the (0, 2)-sequence (the
// first two Sobol' dimensions), so each 2D dimension of a pixel is a (0, m, 2)-net. The base-4
// digits of that index are shuffled, each by a permutation of {0, 1, 2, 3} chosen by a hash of
// the digits above it and of the dimension: neighbouring pixels (sharing higher digits) still
// take complementary parts of the sequence, so their errors are negatively correlated (blue
// noise), while every dimension sees its own shuffle and the dimensions are decorrelated. Each
// dimension's digits are then randomized (Owen-scrambled by default) with a hash of (seed,
// dimension).

#include "core/properties.h"
#include "core/registry.h"
#include "samplers/sobol_base.h"

#include <algorithm>
#include <array>

namespace candela {

namespace {
// The 24 permutations of {0, 1, 2, 3} in lexicographic order (std::next_permutation's), each
// packed in a byte: digit d goes to bits 2d and 2d + 1. A constant table: no guard on each read.
constexpr uint8_t DigitPermutations[24] = {
    0xE4, 0xB4, 0xD8, 0x78, 0x9C, 0x6C, 0xE1, 0xB1, 0xC9, 0x39, 0x8D, 0x2D,
    0xD2, 0x72, 0xC6, 0x36, 0x4E, 0x1E, 0x93, 0x63, 0x87, 0x27, 0x4B, 0x1B,
};
}  // namespace

class ZSobolSampler final : public SobolSamplerBase {
public:
    explicit ZSobolSampler(const Properties& props) {
        read_parameters(props);
        film_changed();
    }

    Ref<Sampler> clone() const override { return std::make_shared<ZSobolSampler>(*this); }
    std::string to_string() const override { return "zsobol"; }

    float next_1d() override {
        uint32_t dim = dimension_++;
        uint32_t reversed[2];
        sobol_point_reversed(dim, reversed);
        return bits_to_unit(randomize_reversed(reversed[0], uint32_t(dimension_hash(dim) >> 32)));
    }
    Vec2 next_2d() override {
        uint32_t dim = dimension_;
        dimension_ += 2;
        uint32_t reversed[2];
        sobol_point_reversed(dim, reversed);
        uint64_t h = dimension_hash(dim);
        return Vec2(bits_to_unit(randomize_reversed(reversed[0], uint32_t(h))),
                    bits_to_unit(randomize_reversed(reversed[1], uint32_t(h >> 32))));
    }

protected:
    // The Morton order spans the film and its sampled border (pixel p is cell p + border), so
    // that no two pixels share a cell.
    void film_changed() override {
        const Vec2i span = film_size_ + 2 * film_border_;
        log2_resolution_ = 0;
        while ((1 << log2_resolution_) < std::max(span.x, span.y)) ++log2_resolution_;
    }
    void start_sample(const Vec2i& pixel, uint32_t index) override {
        SobolSamplerBase::start_sample(pixel, index);
        const Vec2i cell = pixel + film_border_;
        const uint64_t pixel_morton = morton_2d(uint32_t(cell.x), uint32_t(cell.y));
        morton_index_ = (pixel_morton << log2_spp_) | index;
        // What the kept pixel parts depend on: a change to any of them makes them stale.
        pixel_parts_.keep_for({pixel_morton, seed_, log2_spp_, log2_resolution_});
    }

private:
    // Dimensions 0 and 1 of this sample's point of the (0, 2)-sequence in dimension `dim`, as
    // reversed digits (sobol_bits_reversed). Its sequence index is the Morton index with every
    // base-4 digit permuted by a hash of the digits above it; with an odd log2(spp) the lowest
    // digit is binary and is flipped (or not) the same way. The digits at and above the first
    // pixel digit depend only on the pixel (the sample index fills the low log2(spp) bits), and
    // the Sobol' digits are linear over GF(2) in the index's bits, so the point is the XOR of a
    // pixel part and a sample part. For dimensions below 64 the pixel part is kept for the
    // pixel's other samples, with the permutation of the top sample digit (which hashes only
    // pixel digits): at 64 spp a draw hashes 2 digits in place of 3 plus log2 of the resolution,
    // and dimension 1's matrix product reads one byte table row in place of a walk over the
    // index's bits.
    void sobol_point_reversed(uint32_t dim, uint32_t reversed[2]) const {
        const int first_pixel_digit = (log2_spp_ + 1) / 2;
        auto compute = [&] { return pixel_part(dim, first_pixel_digit); };
        PixelPart computed;
        const PixelPart* pixel = &computed;
        if (dim < pixel_parts_.size)
            pixel = &pixel_parts_.get(dim, compute);
        else
            computed = compute();
        const bool binary_last = log2_spp_ & 1;
        const uint64_t salt = pixel->mixed_salt;
        uint64_t sample = permuted_digits(salt, binary_last ? 1 : 0, first_pixel_digit - 1);
        // The top sample digit's permutation hashes only the pixel's digits above it: kept too.
        if (first_pixel_digit > (binary_last ? 1 : 0)) sample |= permuted_digit(first_pixel_digit - 1, pixel->top_sample_permutation);
        if (binary_last) sample |= (morton_index_ & 1u) ^ (uint32_t(hash_combine_mixed(morton_index_ >> 1, salt) >> 32) & 1u);
        // Sample indices are below 2^30. Reversed, dimension 0 is the index's own bits.
        reversed[0] = pixel->reversed[0] ^ uint32_t(sample);
        reversed[1] = pixel->reversed[1] ^ sobol_dimension1_reversed(uint32_t(sample));
    }

    // The last permutation hashed for each pixel digit (level above the sample digits) of
    // dimensions below 64, with the Morton digits above it that chose it. A tile's pixels come
    // row by row and neighbours share their higher digits, so a new pixel's part rehashes about
    // two digits in place of log2 of the resolution (the parts are computed once per pixel and
    // pass: 7 passes at 64 spp).
    // Each is kept with the exact input of its hash (digit_permutation), so that it is valid
    // whatever changed since (pixel, seed, sample count): nothing has to clear them.
    struct RecentPermutation {
        uint64_t hashed = ~uint64_t(0);  // none: the digits above a digit are below 2^62, i below 64
        uint64_t mixed_salt = 0;
        uint32_t permutation = 0;
    };
    static constexpr int RecentLevels = 16;

    // The permuted pixel digits of dimension `dim`: their share of Sobol' dimensions 0 and 1,
    // reversed, the permutation of the sample digit below them, and the dimension's salt for the
    // digits' hashes, (dim << 32) ^ seed, already mixed (hash_combine_mixed).
    struct PixelPart {
        uint32_t reversed[2] = {0, 0};
        uint32_t top_sample_permutation = 0;
        uint64_t mixed_salt = 0;
    };
    // Out of line (GCC, clang): it runs once per pixel, pass and dimension, and inlined it made
    // sobol_point_reversed, which runs at every draw, too large to inline into next_1d/next_2d
    // (3% of a render's time).
    [[gnu::noinline]] PixelPart pixel_part(uint32_t dim, int first_pixel_digit) const {
        const uint64_t salt = mix64((uint64_t(dim) << 32) ^ seed_);
        RecentPermutation* recent = dim < recent_permutations_.size() ? recent_permutations_[dim].data() : nullptr;
        const uint64_t index = permuted_digits(salt, first_pixel_digit, first_pixel_digit + log2_resolution_, recent);
        PixelPart part;
        part.mixed_salt = salt;
        part.reversed[0] = sobol_bits_reversed(index, 0);
        part.reversed[1] = sobol_bits_reversed(index, 1);
        if (first_pixel_digit > (log2_spp_ & 1)) part.top_sample_permutation = digit_permutation(first_pixel_digit - 1, salt);
        return part;
    }

    // Base-4 digits [lowest, end) of the Morton index, each permuted by a hash of the digits
    // above it and of `mixed_salt` (PixelPart), in place. With `recent` (the pixel digits of a
    // dimension below 64: recent_permutations_), digit lowest + k reuses entry k's permutation
    // while its hash's input and salt are those it was computed from (k below RecentLevels).
    uint64_t permuted_digits(uint64_t mixed_salt, int lowest, int end, RecentPermutation* recent = nullptr) const {
        uint64_t index = 0;
        for (int i = end - 1; i >= lowest; --i) {
            if (!recent || i - lowest >= RecentLevels) {
                index |= permuted_digit(i, digit_permutation(i, mixed_salt));
                continue;
            }
            RecentPermutation& kept = recent[i - lowest];
            const uint64_t hashed = permutation_input(i);
            if (kept.hashed != hashed || kept.mixed_salt != mixed_salt)
                kept = RecentPermutation{hashed, mixed_salt, digit_permutation(i, mixed_salt)};
            index |= permuted_digit(i, kept.permutation);
        }
        return index;
    }
    // Where base-4 digit i starts: an odd log2(spp) shifts the base-4 digits up one bit.
    int digit_shift(int i) const { return 2 * i - (log2_spp_ & 1); }
    // Which of the 24 permutations digit i takes: a hash of the digits above it (and of i).
    uint64_t permutation_input(int i) const { return (morton_index_ >> (digit_shift(i) + 2)) ^ (uint64_t(i) << 56); }
    uint32_t digit_permutation(int i, uint64_t mixed_salt) const {
        return uint32_t(hash_combine_mixed(permutation_input(i), mixed_salt) >> 32) % 24;
    }
    // Digit i of the Morton index under permutation p, in place.
    uint64_t permuted_digit(int i, uint32_t p) const {
        const int shift = digit_shift(i);
        const uint32_t digit = uint32_t(morton_index_ >> shift) & 3u;
        return uint64_t((DigitPermutations[p] >> (2 * digit)) & 3u) << shift;
    }

    struct PixelPartKey {
        uint64_t pixel_morton = 0, seed = 0;
        int log2_spp = 0, log2_resolution = 0;
        bool operator==(const PixelPartKey& o) const {
            return pixel_morton == o.pixel_morton && seed == o.seed && log2_spp == o.log2_spp && log2_resolution == o.log2_resolution;
        }
    };
    mutable KeptPerPixel<PixelPartKey, PixelPart, 64> pixel_parts_;  // dimensions below 64
    mutable std::array<std::array<RecentPermutation, RecentLevels>, 64> recent_permutations_{};
    int log2_resolution_ = 0;
    uint64_t morton_index_ = 0;
};

CANDELA_REGISTER(ZSobolSampler, ObjectKind::Sampler, "zsobol");

}  // namespace candela
