#pragma once
// PCG32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
// Algorithms for Random Number Generation") and the integer hashes that seed it per sample.

#include <cstdint>

namespace candela {

// 64-bit finaliser of MurmurHash3: spreads structured inputs (pixel indices) over all bits.
inline uint64_t mix64(uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    x ^= x >> 33;
    return x;
}

// hash_combine(a, b) with mix64(b) given: for a b hashed with many a.
inline uint64_t hash_combine_mixed(uint64_t a, uint64_t mixed_b) {
    return mix64(a ^ (mixed_b + 0x9e3779b97f4a7c15ULL + (a << 6) + (a >> 2)));
}
inline uint64_t hash_combine(uint64_t a, uint64_t b) { return hash_combine_mixed(a, mix64(b)); }

// Output n (from 0) of the SplitMix64 generator started at state `key` (Steele, Lea and Flood
// 2014, "Fast Splittable Pseudorandom Number Generators"): a Weyl step by the golden-ratio
// increment, then Stafford's "Mix13" finaliser. One mixing pass where hash_combine takes two: for
// a key that is already a hash (a pixel's sequence, a sample's key), consecutive n are as
// independent as consecutive outputs of the generator, which passes BigCrush.
inline uint64_t splitmix(uint64_t key, uint64_t n) {
    uint64_t z = key + (n + 1) * 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

class PCG32 {
public:
    PCG32() { seed(0x853c49e6748fea9bULL, 0xda3e39cb94b95bdbULL); }
    PCG32(uint64_t initstate, uint64_t initseq) { seed(initstate, initseq); }

    // Selects the stream `initseq` and the starting point `initstate` within it.
    void seed(uint64_t initstate, uint64_t initseq) {
        state_ = 0;
        inc_ = (initseq << 1u) | 1u;
        next_uint();
        state_ += initstate;
        next_uint();
    }

    uint32_t next_uint() {
        uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        uint32_t rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
    }

    // Uniform in [0, 1): the top 24 bits, so the result is exactly representable and never 1.
    float next_float() { return static_cast<float>(next_uint() >> 8) * 0x1p-24f; }
    // Uniform integer in [0, bound), unbiased (Lemire's rejection is overkill here; use modulo
    // rejection as in the PCG reference).
    uint32_t next_bounded(uint32_t bound) {
        uint32_t threshold = (~bound + 1u) % bound;
        for (;;) {
            uint32_t r = next_uint();
            if (r >= threshold) return r % bound;
        }
    }

    // The generator's whole state, to be set again later (a sampler's save and restore).
    void get_state(uint64_t& state, uint64_t& inc) const {
        state = state_;
        inc = inc_;
    }
    void set_state(uint64_t state, uint64_t inc) {
        state_ = state;
        inc_ = inc;
    }

private:
    uint64_t state_ = 0, inc_ = 1;
};

}  // namespace candela
