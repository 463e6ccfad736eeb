#pragma once
// Trigonometry for closed forms on the hot path, without libm's out-of-line calls: sin and cos
// of any moderate angle, and acos of four values at once in one SSE register (the spherical
// rectangle's four interior angles, shapes/rectangle.cpp). Each is within a few ulp of the
// exact value; tests/core/test_math.cpp measures how far.

#include "core/math.h"

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace candela {

// Four floats as one vector (GCC's and clang's vector extensions: + - * / element by element,
// comparisons give each lane all ones or all zeros as an Int4).
typedef float Float4 __attribute__((vector_size(16)));
typedef int32_t Int4 __attribute__((vector_size(16)));

inline Float4 splat4(float x) { return Float4{x, x, x, x}; }

inline Float4 sqrt4(Float4 x) {
#if defined(__SSE__)
    return _mm_sqrt_ps(x);
#else
    return Float4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}

// mask ? a : b lane by lane, by bit operations (a vector ?: is not portable between compilers).
inline Float4 select4(Int4 mask, Float4 a, Float4 b) { return Float4((Int4(a) & mask) | (Int4(b) & ~mask)); }

// acos of each lane, its argument clamped to [-1, 1]. With a = |x| (Moshier's Cephes asinf: the
// minimax polynomial P for asin(s) = s + s z P(z), z = s^2, on s <= 1/2):
//   a <= 1/2: acos a = pi/2 - asin a
//   a >  1/2: acos a = 2 asin(sqrt((1 - a) / 2)), which keeps its precision as a goes to 1;
// and acos x = pi - acos a for x < 0.
inline Float4 acos4(Float4 x) {
    x = select4(x < splat4(-1.0f), splat4(-1.0f), x);
    x = select4(x > splat4(1.0f), splat4(1.0f), x);
    const Float4 a = Float4(Int4(x) & Int4{0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff});
    const Int4 far = a > splat4(0.5f);
    const Float4 z = select4(far, splat4(0.5f) * (splat4(1.0f) - a), a * a);
    const Float4 s = select4(far, sqrt4(z), a);
    const Float4 p =
        (((splat4(4.2163199048e-2f) * z + splat4(2.4181311049e-2f)) * z + splat4(4.5470025998e-2f)) * z + splat4(7.4953002686e-2f)) * z +
        splat4(1.6666752422e-1f);
    const Float4 asin_s = s + s * z * p;
    const Float4 acos_a = select4(far, splat4(2.0f) * asin_s, splat4(Pi / 2.0f) - asin_s);
    return select4(x < splat4(0.0f), splat4(Pi) - acos_a, acos_a);
}

// sin x and cos x for |x| up to about 10^4 (beyond that the reduction loses bits): x = q pi/2 + r
// with |r| <= pi/4, pi/2 split in three parts (Cephes' constants, doubled) so that q pi/2 is
// subtracted exactly, then sincos_quarter_pi(r) and the quadrant's swap and signs, by bit
// operations (the quadrant of a sampled angle is unpredictable: a branch would often miss).
inline void sincos_any(float x, float& s, float& c) {
    const float q_float = x * (2.0f / Pi);
    const int q = int(q_float + std::copysign(0.5f, q_float));  // to the nearest integer
    const float r = ((x - float(q) * 1.5703125f) - float(q) * 4.837512969970703125e-4f) - float(q) * 7.54978995489188216e-8f;
    float s_r, c_r;
    sincos_quarter_pi(r, s_r, c_r);
    // Quadrant q: sin x = (s_r, c_r, -s_r, -c_r)[q mod 4], cos x = (c_r, -s_r, -c_r, s_r)[q mod 4].
    // Each choice an all-ones or all-zeros mask for select_float.
    const uint32_t swap = 0u - uint32_t(q & 1), negate_s = 0u - uint32_t((q >> 1) & 1), negate_c = 0u - uint32_t(((q + 1) >> 1) & 1);
    const float s_swapped = select_float(swap, c_r, s_r), c_swapped = select_float(swap, s_r, c_r);
    s = select_float(negate_s, -s_swapped, s_swapped);
    c = select_float(negate_c, -c_swapped, c_swapped);
}

}  // namespace candela
