#pragma once
// Samplers hand out the random numbers of one pixel sample. A sample's numbers depend only on
// (seed, pixel, sample index), never on thread or tile order, so renders are reproducible bit
// for bit with any number of threads.

#include "core/math.h"
#include "core/object.h"
#include "core/rng.h"

namespace candela {

class Properties;

class Sampler : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Sampler; }

    int sample_count() const { return sample_count_; }
    void set_sample_count(int spp) { sample_count_ = spp; }
    uint64_t seed() const { return seed_; }
    void set_seed(uint64_t seed) { seed_ = seed; }

    // Each thread works on its own copy.
    virtual Ref<Sampler> clone() const = 0;
    // Positions the sampler at sample `index` of `pixel` (film coordinates, crop included).
    virtual void start(const Vec2i& pixel, uint32_t index) = 0;
    virtual float next_1d() = 0;
    virtual Vec2 next_2d() = 0;

protected:
    int sample_count_ = 4;
    uint64_t seed_ = 0;
};

// Seeds a PCG32 for one sample: state from (seed, pixel), stream from (seed, sample index).
inline void seed_for_sample(PCG32& rng, uint64_t seed, const Vec2i& pixel, uint32_t index) {
    uint64_t pixel_key = (uint64_t(uint32_t(pixel.y)) << 32) | uint32_t(pixel.x);
    rng.seed(hash_combine(seed, pixel_key), hash_combine(~seed, index));
}

}  // namespace candela
