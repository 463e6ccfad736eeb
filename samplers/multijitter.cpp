// multijitter (FALLBACK to independent, see samplers/fallback.h): Kensler's correlated
// multi-jittered sampling.
//
// Parameters (Mitsuba 3):
//   sample_count   integer   samples per pixel, rounded up to a near-square grid (default 4)
//   seed           integer   seed offset (default 0)
//   jitter         boolean   random position inside each substratum (default true)

#include "core/properties.h"
#include "core/registry.h"
#include "samplers/fallback.h"

#include <cmath>

namespace candela {

namespace {
// Mitsuba's grid: rows = floor(sqrt(n)), columns = ceil(n / rows); rows * columns samples.
int round_to_grid(int n) {
    int rows = std::max(1, int(std::sqrt(double(n))));
    int columns = (n + rows - 1) / rows;
    return rows * columns;
}
}  // namespace

class MultijitterSampler final : public FallbackSampler {
public:
    explicit MultijitterSampler(const Properties& props) : FallbackSampler(props, round_to_grid) { props.get_bool("jitter", true); }
};

CANDELA_REGISTER(MultijitterSampler, ObjectKind::Sampler, "multijitter");

}  // namespace candela
