// orthogonal (FALLBACK to independent, see samplers/fallback.h): Jarosz et al.'s orthogonal
// array sampling.
//
// Parameters (Mitsuba 3):
//   sample_count   integer   samples per pixel, rounded up to the square of a prime (default 4)
//   seed           integer   seed offset (default 0)
//   jitter         boolean   random position inside each substratum (default true)
//   strength       integer   strength of the orthogonal array (default 2)

#include "core/properties.h"
#include "core/registry.h"
#include "samplers/fallback.h"

namespace candela {

namespace {
bool is_prime(int x) {
    for (int i = 2; i <= x / 2; ++i)
        if (x % i == 0) return false;
    return true;
}
// The smallest p * p >= n with p a prime of at least 2 (Mitsuba's orthogonal sampler).
int round_to_prime_square(int n) {
    int p = 2;
    while (p * p < n || !is_prime(p)) ++p;
    return p * p;
}
}  // namespace

class OrthogonalSampler final : public FallbackSampler {
public:
    explicit OrthogonalSampler(const Properties& props) : FallbackSampler(props, round_to_prime_square) {
        props.get_bool("jitter", true);
        if (props.get_int("strength", 2) < 2) props.fail("strength", "the orthogonal array's strength must be at least 2");
    }
};

CANDELA_REGISTER(OrthogonalSampler, ObjectKind::Sampler, "orthogonal");

}  // namespace candela
