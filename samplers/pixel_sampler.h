#pragma once
// What Mitsuba's samplers share (stratified, multijitter, orthogonal, ldsampler): each pixel has
// its own sequence, seeded by (seed, pixel); a dimension's points are a random permutation of
// the pixel's sample indices, so every dimension is stratified on its own and the dimensions are
// decorrelated; jitter inside a stratum is a hash of (sequence, sample index, dimension), never a
// number drawn in order, so a sample's numbers do not depend on the samples taken before it.

#include "core/sampler.h"
#include "samplers/kept_per_pixel.h"
#include "samplers/sequences.h"

#include <string>

namespace candela {

class Properties;

class PixelSequenceSampler : public Sampler {
public:
    // Sample indices are permuted over the strata per dimension (above).
    bool stratified_only_as_a_whole() const override { return true; }

    // The sample's sequence and key are saved as well, so that restore() hashes nothing.
    void save(SamplerState& state) const override {
        Sampler::save(state);
        state.words[0] = sequence_;
        state.words[1] = sample_key_;
    }
    void restore(const SamplerState& state) override {
        enter(state.words[0], state.index, state.words[1]);
        restore_position(state);
    }

protected:
    void start_sample(const Vec2i& pixel, uint32_t index) override {
        const uint64_t sequence = hash_combine(seed_, pixel_key(pixel));
        enter(sequence, index, hash_combine(sequence, index));
        dimension_ = 0;
    }
    // Reads sample_count (in [1, 2^30], default 4) and seed (default 0), then rounds the count with
    // set_sample_count(); a count that changes is a warning at the sampler's line naming `rule`
    // (e.g. "a square, as Mitsuba does").
    void read_count_and_seed(const Properties& props, const std::string& rule);
    // Called when start_sample() moves to another pixel's sequence (sequence_ is already the new
    // one): where a sampler computes what depends on the pixel alone.
    virtual void sequence_changed() {}

    // A 32-bit seed for the permutations of dimension `dim` in this pixel; `salt` (below 8) tells
    // apart the several permutations one dimension may use. One SplitMix64 step of the pixel's
    // sequence, as for the jitter below. They run once or twice per number drawn but depend only on
    // the pixel, so those of dimensions below 64 are kept for the pixel's other samples: a load in
    // place of three dependent multiplies before each permutation.
    uint32_t dimension_seed(uint32_t dim, uint32_t salt = 0) const {
        const uint64_t key = uint64_t(dim) * 8 + salt;
        auto compute = [&] { return uint32_t(splitmix(sequence_, key) >> 32); };
        return key < seeds_.size ? seeds_.get(key, compute) : compute();
    }
    // A uniform number in [0, 1) for (sample, dimension dim): the jitter in a stratum.
    float jitter(uint32_t dim) const { return bits_to_unit(uint32_t(splitmix(sample_key_, dim) >> 32)); }
    // Two independent jitters for a 2D dimension from one hash: its low and high 32 bits.
    Vec2 jitter_2d(uint32_t dim) const {
        uint64_t h = splitmix(sample_key_, dim);
        return Vec2(bits_to_unit(uint32_t(h)), bits_to_unit(uint32_t(h >> 32)));
    }

    uint64_t sequence_ = 0;    // the pixel's sequence
    uint32_t index_ = 0;       // the sample index within the pixel
    uint64_t sample_key_ = 0;  // hash_combine(sequence_, index_), hashed once per sample, not per number
    Divisor count_divisor_;    // sample_count_, for permute_index over the pixel's sample indices

private:
    // Makes sample `index` of the pixel with `sequence` (and key hash_combine(sequence, index))
    // the current one. A pixel's samples come one after another (the pixel loop), so what depends
    // only on the pixel's sequence is kept until the next pixel: the dimension seeds (below) and
    // what a sampler computes in sequence_changed().
    void enter(uint64_t sequence, uint32_t index, uint64_t sample_key) {
        if (seeds_.keep_for(sequence)) {
            sequence_ = sequence;
            sequence_changed();
        }
        // Whatever changed the count (set_sample_count), the divisor follows it.
        if (count_divisor_.n != uint32_t(sample_count_)) count_divisor_ = Divisor(uint32_t(sample_count_));
        index_ = index;
        sample_key_ = sample_key;
    }
    // The current pixel's dimension_seed() values, by key dim * 8 + salt (dimensions below 64),
    // kept for the pixel's sequence.
    mutable KeptPerPixel<uint64_t, uint32_t, 64 * 8> seeds_;
};

}  // namespace candela
