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
// The 24 permutations of {0, 1, 2, 3}.
const std::array<std::array<uint8_t, 4>, 24>& digit_permutations() {
    static const std::array<std::array<uint8_t, 4>, 24> all = [] {
        std::array<std::array<uint8_t, 4>, 24> p{};
        std::array<uint8_t, 4> digits = {0, 1, 2, 3};
        for (auto& row : p) {
            row = digits;
            std::next_permutation(digits.begin(), digits.end());
        }
        return p;
    }();
    return all;
}
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
        uint64_t i = sequence_index(dim);
        return bits_to_unit(randomize(sobol_bits(i, 0), hash_bits(seed_, dim)));
    }
    Vec2 next_2d() override {
        uint32_t dim = dimension_;
        dimension_ += 2;
        uint64_t i = sequence_index(dim);
        uint64_t h = hash_combine(seed_, dim);
        return Vec2(bits_to_unit(randomize(sobol_bits(i, 0), uint32_t(h))), bits_to_unit(randomize(sobol_bits(i, 1), uint32_t(h >> 32))));
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
        PixelSequenceSampler::start_sample(pixel, index);
        const Vec2i cell = pixel + film_border_;
        morton_index_ = (morton_2d(uint32_t(cell.x), uint32_t(cell.y)) << log2_spp_) | index;
    }

private:
    // The sequence index of this sample in dimension `dim`: the Morton index with every base-4
    // digit permuted by a hash of the digits above it. With an odd log2(spp) the lowest digit is
    // binary and is flipped (or not) the same way.
    uint64_t sequence_index(uint32_t dim) const {
        const bool binary_last = log2_spp_ & 1;
        const int digits = log2_resolution_ + (log2_spp_ + 1) / 2;
        const uint64_t salt = (uint64_t(dim) << 32) ^ seed_;
        const auto& permutations = digit_permutations();  // once: a function-local static is guarded
        uint64_t index = 0;
        for (int i = digits - 1; i >= (binary_last ? 1 : 0); --i) {
            int shift = 2 * i - (binary_last ? 1 : 0);
            uint32_t digit = uint32_t(morton_index_ >> shift) & 3u;
            uint64_t higher = morton_index_ >> (shift + 2);
            uint32_t p = hash_bits(higher ^ (uint64_t(i) << 56), salt) % 24;
            index |= uint64_t(permutations[p][digit]) << shift;
        }
        if (binary_last) index |= (morton_index_ & 1u) ^ (hash_bits(morton_index_ >> 1, salt) & 1u);
        return index;
    }

    int log2_resolution_ = 0;
    uint64_t morton_index_ = 0;
};

CANDELA_REGISTER(ZSobolSampler, ObjectKind::Sampler, "zsobol");

}  // namespace candela
