// independent: independent uniform random numbers for every dimension of every sample.
//
// Parameters:
//   sample_count   integer   samples per pixel (default 4)
//   seed           integer   seed of the random sequence (default 0)

#include "samplers/independent.h"

#include "core/properties.h"
#include "core/registry.h"

namespace candela {

IndependentSampler::IndependentSampler(int sample_count, uint64_t seed) {
    sample_count_ = sample_count;
    seed_ = seed;
}

IndependentSampler::IndependentSampler(const Properties& props) {
    sample_count_ = props.get_int("sample_count", 4);
    if (sample_count_ <= 0) props.fail("sample_count", "sample_count must be positive");
    int seed = props.get_int("seed", 0);
    seed_ = uint64_t(int64_t(seed));
}

CANDELA_REGISTER(IndependentSampler, ObjectKind::Sampler, "independent");

}  // namespace candela
