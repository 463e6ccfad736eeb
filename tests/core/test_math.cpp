// The helpers of core/math.h and core/fast_trig.h that replace library calls on the hot path
// must give the library's results exactly, or within the error each test states.

#include "core/fast_trig.h"
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
// |approx - exact| in units in the last place of the float nearest `exact`.
double ulp_error(float approx, double exact) {
    float e = float(exact);
    float ulp = std::nextafter(std::abs(e), Infinity) - std::abs(e);
    return std::abs(double(approx) - exact) / double(ulp);
}
float float_from_bits(uint32_t bits) {
    float x;
    std::memcpy(&x, &bits, sizeof x);
    return x;
}
uint32_t bits_of(float x) {
    uint32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    return bits;
}
}  // namespace

TEST_CASE("math: next_float_toward is std::nextafter toward +-infinity, and v itself for a direction of 0 or NaN", "[math]") {
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
        bool ok = same_bits(next_float_toward(v, 1.0f), std::nextafter(v, Infinity)) &&
                  same_bits(next_float_toward(v, -1.0f), std::nextafter(v, -Infinity)) &&
                  same_bits(next_float_toward(v, 0.25f), std::nextafter(v, Infinity)) &&
                  same_bits(next_float_toward(v, -3.0f), std::nextafter(v, -Infinity)) && same_bits(next_float_toward(v, 0.0f), v) &&
                  same_bits(next_float_toward(v, -0.0f), v) && same_bits(next_float_toward(v, std::nanf("")), v);
        if (!ok && wrong++ == 0) first_wrong = v;
    }
    INFO("first wrong value " << first_wrong);
    CHECK(wrong == 0);
}

// The polynomial stands in for std::sin and std::cos in the concentric disk warp: it must stay
// within 2 ulp of the exact values (in double) over all of [-pi/4, pi/4]. Checked on every 64th
// float of the interval (about 16 million arguments) and at its end; the symmetry in sign is exact.
TEST_CASE("math: sincos_quarter_pi is within 2 ulp of sin and cos on [-pi/4, pi/4]", "[math]") {
    const float limit = 0.78539818525f;  // the float nearest pi/4, just above it
    double worst_sin = 0.0, worst_cos = 0.0;
    long asymmetric = 0;
    auto check = [&](float x) {
        float s, c, s_neg, c_neg;
        sincos_quarter_pi(x, s, c);
        sincos_quarter_pi(-x, s_neg, c_neg);
        asymmetric += s_neg != -s || c_neg != c;  // by value: sin(-0) comes out +0
        if (x != 0.0f) worst_sin = std::max(worst_sin, ulp_error(s, std::sin(double(x))));
        worst_cos = std::max(worst_cos, ulp_error(c, std::cos(double(x))));
    };
    for (uint32_t bits = 0; bits < bits_of(limit); bits += 64) check(float_from_bits(bits));
    check(limit);
    INFO("worst sin error " << worst_sin << " ulp, worst cos error " << worst_cos << " ulp");
    CHECK(worst_sin <= 2.0);
    CHECK(worst_cos <= 2.0);
    CHECK(asymmetric == 0);
    // At zero exactly.
    float s0, c0;
    sincos_quarter_pi(0.0f, s0, c0);
    CHECK(same_bits(s0, 0.0f));
    CHECK(c0 == 1.0f);
}

TEST_CASE("math: ceil_to_int and floor_to_int are int(std::ceil) and int(std::floor)", "[math]") {
    // Integers, halves, the neighbours of integers and of zero, large floats (every float from
    // 2^23 on is an integer), and random values of every magnitude that fits in an int.
    std::vector<float> values = {0.0f,
                                 -0.0f,
                                 0.5f,
                                 -0.5f,
                                 1.0f,
                                 -1.0f,
                                 2.5f,
                                 -2.5f,
                                 0x1p23f,
                                 -0x1p23f,
                                 0x1p30f,
                                 -0x1p30f,
                                 std::numeric_limits<float>::denorm_min(),
                                 -std::numeric_limits<float>::denorm_min()};
    for (float k : {0.0f, 1.0f, -1.0f, 7.0f, -7.0f, 8388607.0f, -8388607.0f}) {
        values.push_back(next_float_toward(k, 1.0f));
        values.push_back(next_float_toward(k, -1.0f));
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

// acos4 stands in for std::acos in the spherical rectangle's four angles. Every 64th float of
// [0, 1] (about 17 million arguments; every float, measured once, gave 1.26 ulp at worst) with
// both signs, each lane given a different argument; arguments outside [-1, 1] are clamped, as
// safe_acos clamps them.
TEST_CASE("math: acos4 is within 2 ulp of acos on [-1 1] in every lane and clamps outside it", "[math]") {
    double worst = 0.0;
    float worst_at = 0.0f;
    for (uint32_t bits = 0; bits <= bits_of(1.0f); bits += 64) {
        const float x = float_from_bits(bits), y = float_from_bits(bits_of(1.0f) - bits);
        const Float4 lanes{x, -x, y, -y};
        const Float4 result = acos4(lanes);
        for (int lane = 0; lane < 4; ++lane) {
            const double error = ulp_error(result[lane], std::acos(double(lanes[lane])));
            if (error > worst) worst = error, worst_at = lanes[lane];
        }
    }
    INFO("worst error " << worst << " ulp at " << worst_at);
    CHECK(worst <= 2.0);
    const Float4 ends = acos4(Float4{1.0f, -1.0f, 1.5f, -7.0f});
    CHECK(ends[0] == 0.0f);
    CHECK(ends[1] == Pi);
    CHECK(ends[2] == 0.0f);
    CHECK(ends[3] == Pi);
    CHECK(acos4(splat4(0.0f))[0] == Pi / 2.0f);
}

// sincos_any stands in for std::sin and std::cos of the spherical rectangle's sampled angle, in
// [0, 4 pi]. Every 64th float of [0, 20] with both signs: the error is within 2^-23 absolute
// (an ulp of values in [1, 2), 1.5 ulp of those in [1/2, 1)), with the quadrants' signs right.
TEST_CASE("math: sincos_any is within 2^-23 of sin and cos on [-20 20]", "[math]") {
    double worst_sin = 0.0, worst_cos = 0.0;
    for (uint32_t bits = 0; bits <= bits_of(20.0f); bits += 64) {
        for (float x : {float_from_bits(bits), -float_from_bits(bits)}) {
            float s, c;
            sincos_any(x, s, c);
            worst_sin = std::max(worst_sin, std::abs(double(s) - std::sin(double(x))));
            worst_cos = std::max(worst_cos, std::abs(double(c) - std::cos(double(x))));
        }
    }
    INFO("worst sin error " << worst_sin << ", worst cos error " << worst_cos);
    CHECK(worst_sin <= 0x1p-23);
    CHECK(worst_cos <= 0x1p-23);
}
