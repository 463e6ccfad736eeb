#pragma once
// The independent sampler: a PCG32 stream per sample, seeded by (seed, pixel, sample index). Its
// numbers are drawn in order and set_dimension() does not move them: every number is independent
// of every other, so which one a dimension gets changes nothing in distribution.

#include "core/sampler.h"

namespace candela {

class Properties;

class IndependentSampler : public Sampler {
public:
    explicit IndependentSampler(const Properties& props);

    Ref<Sampler> clone() const override { return std::make_shared<IndependentSampler>(*this); }
    std::string to_string() const override { return "independent"; }
    float next_1d() override { return rng_.next_float(); }
    void skip_1d() override { rng_.next_uint(); }
    Vec2 next_2d() override {
        float a = rng_.next_float();
        return Vec2(a, rng_.next_float());
    }

    // A stream: its state is the generator's, not the dimension.
    void save(SamplerState& state) const override {
        Sampler::save(state);
        rng_.get_state(state.words[0], state.words[1]);
    }
    void restore(const SamplerState& state) override {
        restore_position(state);
        rng_.set_state(state.words[0], state.words[1]);
    }

protected:
    void start_sample(const Vec2i& pixel, uint32_t index) override { seed_for_sample(rng_, seed_, pixel, index); }

private:
    PCG32 rng_;
};

}  // namespace candela
