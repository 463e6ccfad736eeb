// independent: independent uniform random numbers for every dimension of every sample.
//
// Parameters:
//   sample_count   integer   samples per pixel (default 4)
//   seed           integer   seed of the random sequence (default 0)

#include "samplers/independent.h"

#include "core/properties.h"
#include "core/registry.h"

namespace candela {

IndependentSampler::IndependentSampler(const Properties& props) {
    const int64_t requested = props.get_int("sample_count", 4);
    if (std::string problem = sample_count_problem(requested); !problem.empty()) props.fail("sample_count", "sample_count: " + problem);
    sample_count_ = int(requested);
    int seed = props.get_int("seed", 0);
    seed_ = uint64_t(int64_t(seed));
}

CANDELA_REGISTER(IndependentSampler, ObjectKind::Sampler, "independent");

}  // namespace candela
