// stratified (FALLBACK to independent, see samplers/fallback.h): one sample per cell of a
// square grid.
//
// Parameters (Mitsuba 3):
//   sample_count   integer   samples per pixel, rounded up to a square (default 4)
//   seed           integer   seed offset (default 0)
//   jitter         boolean   random position inside each stratum (default true)

#include "core/properties.h"
#include "core/registry.h"
#include "samplers/fallback.h"

namespace candela {

namespace {
// The smallest square at least n (Mitsuba's stratified sampler).
int round_to_square(int n) {
    int r = 1;
    while (r * r < n) ++r;
    return r * r;
}
}  // namespace

class StratifiedSampler final : public FallbackSampler {
public:
    explicit StratifiedSampler(const Properties& props) : FallbackSampler(props, round_to_square) { props.get_bool("jitter", true); }
};

CANDELA_REGISTER(StratifiedSampler, ObjectKind::Sampler, "stratified");

}  // namespace candela
