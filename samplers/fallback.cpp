#include "samplers/fallback.h"

#include "core/properties.h"
#include "core/warning.h"

namespace candela {

namespace {
int requested_count(const Properties& props) {
    int n = props.get_int("sample_count", 4);
    if (n <= 0) props.fail("sample_count", "sample_count must be positive");
    return n;
}
}  // namespace

FallbackSampler::FallbackSampler(const Properties& props, int (*round)(int))
    : IndependentSampler(round(requested_count(props)), uint64_t(int64_t(props.get_int("seed", 0)))) {
    int requested = props.get_int("sample_count", 4);
    std::string count = "sample_count " + std::to_string(sample_count_) +
                        (sample_count_ == requested ? "" : ": " + std::to_string(requested) + " rounded as Mitsuba does");
    warn(props.location(), "sampler \"" + props.plugin_type() + "\" is not implemented yet; using the independent sampler instead (" + count +
                               "): same expected image, different noise");
}

}  // namespace candela
