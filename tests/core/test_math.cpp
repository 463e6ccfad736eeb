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

TEST_CASE("math: ceil_to_int and floor_to_int are int(std::ceil) and int(std::floor)", "[math]") {
    // Integers, halves, the neighbours of integers and of zero, large floats (every float from
    // 2^23 on is an integer), and random values of every magnitude that fits in an int.
    std::vector<float> values = {0.0f, -0.0f, 0.5f, -0.5f, 1.0f, -1.0f, 2.5f, -2.5f, 0x1p23f, -0x1p23f, 0x1p30f, -0x1p30f,
                                 std::numeric_limits<float>::denorm_min(), -std::numeric_limits<float>::denorm_min()};
    for (float k : {0.0f, 1.0f, -1.0f, 7.0f, -7.0f, 8388607.0f, -8388607.0f}) {
        values.push_back(next_float_up(k));
        values.push_back(next_float_down(k));
    }
    PCG32 rng(3, 5);
    for (int i = 0; i < 100000; ++i) {
        float magnitude = std::ldexp(1.0f, int(rng.next_uint() % 31u) - 1);  // 2^-1 .. 2^29
        values.push_back((rng.next_float() * 2.0f - 1.0f) * magnitude);
    }
    int wrong = 0;
    float first_wrong = 0.0f;
    for (float v : values) {
        bool ok = ceil_to_int(v) == int(std::ceil(v)) && floor_to_int(v) == int(std::floor(v));
        if (!ok && wrong++ == 0) first_wrong = v;
    }
    INFO("first wrong value " << first_wrong);
    CHECK(wrong == 0);
}
