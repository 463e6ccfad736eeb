// independent: independent uniform random numbers for every dimension of every sample.
//
// Parameters:
//   sample_count   integer   samples per pixel (default 4)
//   seed           integer   seed of the random sequence (default 0)

#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"

namespace candela {

class IndependentSampler final : public Sampler {
public:
    explicit IndependentSampler(const Properties& props) {
        sample_count_ = props.get_int("sample_count", 4);
        if (sample_count_ <= 0) props.fail("sample_count", "sample_count must be positive");
        int seed = props.get_int("seed", 0);
        seed_ = uint64_t(int64_t(seed));
    }
    IndependentSampler(const IndependentSampler&) = default;

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

CANDELA_REGISTER(IndependentSampler, ObjectKind::Sampler, "independent");

}  // namespace candela
