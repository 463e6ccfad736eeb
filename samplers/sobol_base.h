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

namespace candela {

class SobolSamplerBase : public PixelSequenceSampler {
public:
    // Sample indices run along the Sobol sequence, not over permuted strata. Measured with sobol
    // (bench/bench_adaptive, Cornell box): adaptive sampling still reached uniform's error with
    // 0.87 to 0.98 of the samples. zsobol, which shares this, was not measured.
    bool stratified_only_as_a_whole() const override { return false; }

protected:
    int round_sample_count(int spp) override {
        log2_spp_ = 0;
        while ((int64_t(1) << log2_spp_) < spp) ++log2_spp_;
        return 1 << log2_spp_;  // at most 2^30 for spp <= 2^30
    }

    enum class Randomization { None, PermuteDigits, Owen };
    // Reads sample_count, seed and randomization.
    void read_parameters(const Properties& props);
    // The digits `bits` of one dimension randomized with `hash` (a per-dimension seed).
    uint32_t randomize(uint32_t bits, uint32_t hash) const {
        switch (randomization_) {
            case Randomization::None: return bits;
            case Randomization::PermuteDigits: return bits ^ hash;
            default: return owen_scramble(bits, hash);
        }
    }

    Randomization randomization_ = Randomization::Owen;
    int log2_spp_ = 2;
};

}  // namespace candela
