#pragma once
// What the Sobol' samplers (sobol, zsobol) share, after pbrt-v4: a power-of-two sample count,
// and the randomization of the sequence's digits.
//
// Parameters (shared):
//   sample_count    integer   samples per pixel, rounded up to a power of two (default 4)
//   seed            integer   seed of the scrambling (default 0)
//   randomization   string    owen (default): hashed Owen scrambling (Burley 2020), which keeps
//                             every net property and makes smooth integrands converge faster;
//                             permutedigits: a random XOR of the digits (a digital shift);
//                             none: the plain sequence (deterministic, biased for a fixed image)

#include "samplers/pixel_sampler.h"

#include <array>

namespace candela {

class SobolSamplerBase : public PixelSequenceSampler {
public:
    // Sample indices run along the Sobol sequence, not over permuted strata. Measured with sobol
    // (bench/bench_adaptive, Cornell box): adaptive sampling still reached uniform's error with
    // 0.87 to 0.98 of the samples. zsobol, which shares this, was not measured.
    bool stratified_only_as_a_whole() const override { return false; }
    // sobol and zsobol derive more per sample than the pixel sequence's save() keeps (their
    // point's index and what is kept per pixel for it): they restore by start().
    void save(SamplerState& state) const override { Sampler::save(state); }
    void restore(const SamplerState& state) override { Sampler::restore(state); }

protected:
    int round_sample_count(int spp) override {
        log2_spp_ = 0;
        while ((int64_t(1) << log2_spp_) < spp) ++log2_spp_;
        return 1 << log2_spp_;  // at most 2^30 for spp <= 2^30
    }

    enum class Randomization { None, PermuteDigits, Owen };
    // Reads sample_count, seed and randomization.
    void read_parameters(const Properties& props);
    // Sobol' digits given in reversed order (sobol_bits_reversed), randomized with `hash` (a
    // per-dimension seed) and returned in the usual order. Owen scrambling works on the reversed
    // digits, so the reversed generator matrices save it a reversal per number drawn.
    uint32_t randomize_reversed(uint32_t reversed, uint32_t hash) const {
        switch (randomization_) {
            case Randomization::None: return reverse_bits(reversed);
            case Randomization::PermuteDigits: return reverse_bits(reversed) ^ hash;
            default: return owen_scramble_reversed(reversed, hash);
        }
    }

    // hash_combine(seed_, dim): the randomization's hash of dimension `dim` (zsobol's 2D draws use
    // both halves, every other draw the high half, as hash_bits does). It depends only on the
    // seed, so below SobolDimensions it is looked up, not hashed on every number drawn (two mix64
    // chains each); the table follows set_seed() (checked in start_sample()).
    uint64_t dimension_hash(uint32_t dim) const {
        return dim < uint32_t(SobolDimensions) ? dimension_hashes_[dim] : hash_combine(seed_, dim);
    }
    void start_sample(const Vec2i& pixel, uint32_t index) override {
        if (!hashes_ready_ || hashed_seed_ != seed_) hash_dimensions();
        PixelSequenceSampler::start_sample(pixel, index);
    }

    Randomization randomization_ = Randomization::Owen;
    int log2_spp_ = 2;

private:
    void hash_dimensions();

    bool hashes_ready_ = false;
    uint64_t hashed_seed_ = 0;
    std::array<uint64_t, SobolDimensions> dimension_hashes_{};
};

}  // namespace candela
