// The scalar helpers of core/math.h that replace library calls on the hot path must give the
// library's results exactly.

#include "core/math.h"
#include "core/rng.h"

#include <catch2/catch.hpp>

#include <cstring>

using namespace candela;

namespace {
bool same_bits(float a, float b) {
    uint32_t x, y;
    std::memcpy(&x, &a, sizeof x);
    std::memcpy(&y, &b, sizeof y);
    return x == y;
}
}  // namespace

TEST_CASE("math: next_float_up and next_float_down are std::nextafter toward +-infinity", "[math]") {
    const float denorm = std::numeric_limits<float>::denorm_min(), largest = std::numeric_limits<float>::max();
    std::vector<float> values = {0.0f, -0.0f, denorm, -denorm, 1.0f, -1.0f, 0x1p-126f, -0x1p-126f, largest, -largest, Infinity, -Infinity};
    // Random bit patterns cover every exponent and sign; NaNs are left out (no ray offset sees one).
    PCG32 rng(7, 11);
    for (int i = 0; i < 100000; ++i) {
        uint32_t bits = rng.next_uint();
        float v;
        std::memcpy(&v, &bits, sizeof v);
        if (!std::isnan(v)) values.push_back(v);
    }
    int wrong = 0;
    float first_wrong = 0.0f;
    for (float v : values) {
        bool ok = same_bits(next_float_up(v), std::nextafter(v, Infinity)) && same_bits(next_float_down(v), std::nextafter(v, -Infinity));
        if (!ok && wrong++ == 0) first_wrong = v;
    }
    INFO("first wrong value " << first_wrong);
    CHECK(wrong == 0);
}
