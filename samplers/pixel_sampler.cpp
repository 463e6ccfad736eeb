#include "samplers/pixel_sampler.h"

#include "core/properties.h"
#include "core/warning.h"

namespace candela {

void PixelSequenceSampler::read_count_and_seed(const Properties& props, const std::string& rule) {
    const int64_t requested = props.get_int("sample_count", 4);
    if (std::string problem = sample_count_problem(requested); !problem.empty()) props.fail("sample_count", "sample_count: " + problem);
    seed_ = uint64_t(int64_t(props.get_int("seed", 0)));
    set_sample_count(int(requested));
    if (sample_count_ != requested)
        warn(props.location(), "sampler \"" + props.plugin_type() + "\": sample_count " + std::to_string(requested) + " rounded up to " +
                                   std::to_string(sample_count_) + " (" + rule + ")");
}

}  // namespace candela
