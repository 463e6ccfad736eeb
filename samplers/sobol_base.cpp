#include "samplers/sobol_base.h"

#include "core/properties.h"

namespace candela {

void SobolSamplerBase::read_parameters(const Properties& props) {
    std::string r = props.get_string("randomization", "owen");
    if (r == "owen")
        randomization_ = Randomization::Owen;
    else if (r == "permutedigits")
        randomization_ = Randomization::PermuteDigits;
    else if (r == "none")
        randomization_ = Randomization::None;
    else
        props.fail("randomization", "unknown randomization \"" + r + "\" (owen, permutedigits or none)");
    read_count_and_seed(props, "a power of two, as pbrt-v4 does");
}

void SobolSamplerBase::hash_dimensions() {
    for (uint32_t dim = 0; dim < uint32_t(SobolDimensions); ++dim) dimension_hashes_[dim] = hash_combine(seed_, dim);
    hashed_seed_ = seed_;
    hashes_ready_ = true;
}

}  // namespace candela
