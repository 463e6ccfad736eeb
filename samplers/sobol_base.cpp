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

}  // namespace candela
