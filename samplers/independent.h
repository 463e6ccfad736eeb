#pragma once
// The independent sampler, also the stand-in for the stratified, multijitter, orthogonal and
// ldsampler plugins until Candela implements them (see samplers/fallback.h).

#include "core/sampler.h"

namespace candela {

class Properties;

class IndependentSampler : public Sampler {
public:
    explicit IndependentSampler(const Properties& props);
    IndependentSampler(int sample_count, uint64_t seed);

    Ref<Sampler> clone() const override { return std::make_shared<IndependentSampler>(*this); }
    void start(const Vec2i& pixel, uint32_t index) override { seed_for_sample(rng_, seed_, pixel, index); }
    float next_1d() override { return rng_.next_float(); }
    Vec2 next_2d() override {
        float a = rng_.next_float();
        return Vec2(a, rng_.next_float());
    }

private:
    PCG32 rng_;
};

}  // namespace candela
