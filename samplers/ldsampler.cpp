// ldsampler (FALLBACK to independent, see samplers/fallback.h): Kollig and Keller's scrambled
// (0, 2)-sequence.
//
// Parameters (Mitsuba 3):
//   sample_count   integer   samples per pixel, rounded up to the square of a power of two
//                            (default 4)
//   seed           integer   seed offset (default 0)

#include "core/properties.h"
#include "core/registry.h"
#include "samplers/fallback.h"

namespace candela {

namespace {
// The smallest r * r >= n with r a power of two of at least 2 (Mitsuba's ldsampler).
int round_to_power_of_two_square(int n) {
    int r = 2;
    while (r * r < n) r *= 2;
    return r * r;
}
}  // namespace

class LowDiscrepancySampler final : public FallbackSampler {
public:
    explicit LowDiscrepancySampler(const Properties& props) : FallbackSampler(props, round_to_power_of_two_square) {}
};

CANDELA_REGISTER(LowDiscrepancySampler, ObjectKind::Sampler, "ldsampler");

}  // namespace candela
