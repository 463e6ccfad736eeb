#pragma once
// Candela's math vocabulary: GLM vectors in float, the constants and the small scalar helpers
// that every other file uses. Points, vectors and normals share glm::vec3; names say which.

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace candela {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using Vec2i = glm::ivec2;
using Vec3d = glm::dvec3;
using Mat3 = glm::mat3;
using Mat4 = glm::mat4;

constexpr float Pi = 3.14159265358979323846f;
constexpr float TwoPi = 2.0f * Pi;
constexpr float FourPi = 4.0f * Pi;
constexpr float InvPi = 1.0f / Pi;
constexpr float InvTwoPi = 1.0f / TwoPi;
constexpr float InvFourPi = 1.0f / FourPi;
constexpr float Infinity = std::numeric_limits<float>::infinity();
// Bound on the relative error of n floating-point operations: n u / (1 - n u) with u = 2^-24
// (Higham, "Accuracy and Stability of Numerical Algorithms", 3.1; pbrt-v4 section 6.8).
constexpr float gamma_bound(int n) {
    constexpr float u = 0x1p-24f;
    return float(n) * u / (1.0f - float(n) * u);
}

inline float sqr(float x) { return x * x; }
inline float safe_sqrt(float x) { return std::sqrt(std::max(x, 0.0f)); }
inline float safe_acos(float x) { return std::acos(std::clamp(x, -1.0f, 1.0f)); }

// sin x and cos x for |x| <= pi/4 by the minimax polynomials of Moshier's Cephes sinf/cosf, which
// need no argument reduction there: within 2 ulp of the exact values (tests/core/test_math.cpp),
// without libm's range reduction and out-of-line call (the concentric disk warp, at every bounce).
inline void sincos_quarter_pi(float x, float& s, float& c) {
    float x2 = x * x;
    s = x + x * x2 * (-1.6666654611e-1f + x2 * (8.3321608736e-3f + x2 * -1.9515295891e-4f));
    c = 1.0f - 0.5f * x2 + x2 * x2 * (4.166664568298827e-2f + x2 * (-1.388731625493765e-3f + x2 * 2.443315711809948e-5f));
}
// `mask` (all ones or all zeros) ? a : b, by bit operations: GCC turns a ?: on floats (and on
// their bits) into a branch, which costs a pipeline flush whenever the choice is unpredictable.
inline float select_float(uint32_t mask, float a, float b) {
    uint32_t ia, ib;
    std::memcpy(&ia, &a, sizeof ia);
    std::memcpy(&ib, &b, sizeof ib);
    const uint32_t bits = (ia & mask) | (ib & ~mask);
    float result;
    std::memcpy(&result, &bits, sizeof result);
    return result;
}
inline float safe_asin(float x) { return std::asin(std::clamp(x, -1.0f, 1.0f)); }
inline float radians(float deg) { return deg * (Pi / 180.0f); }
inline float degrees(float rad) { return rad * (180.0f / Pi); }
inline float lerp(float t, float a, float b) { return a + t * (b - a); }
inline float max_component(const Vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
inline float min_component(const Vec3& v) { return std::min(v.x, std::min(v.y, v.z)); }
// |v| per component by std::abs (one mask instruction each; glm::abs compares and negates, about
// five instructions each without SSE4.1). Error bounds of hit points take nine per hit.
inline Vec3 abs_components(const Vec3& v) { return Vec3(std::abs(v.x), std::abs(v.y), std::abs(v.z)); }
inline float max_abs_component(const Vec3& v) { return max_component(abs_components(v)); }
inline bool all_finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline float squared_length(const Vec3& v) { return glm::dot(v, v); }
// int(std::ceil(x)) and int(std::floor(x)) for x within int's range, by truncation and one
// correction: without SSE4.1 std::ceil and std::floor expand to about fifteen instructions each
// (a range test and a masked rounding), these to about five. Exact: the truncation is exact
// in float whenever it fits in 24 bits, and above that every float is an integer already.
inline int ceil_to_int(float x) {
    int i = int(x);
    return float(i) < x ? i + 1 : i;
}
inline int floor_to_int(float x) {
    int i = int(x);
    return float(i) > x ? i - 1 : i;
}

// The neighbouring float of v toward the sign of `direction` (v itself when direction is 0 or
// NaN): std::nextafter(v, direction * infinity), with zero of either sign stepping to the
// smallest subnormal of the direction's sign. By stepping the bit pattern, since libm's
// nextafterf is an out-of-line call and ray offsets take up to six per ray (pbrt-v4, 6.8.5);
// with integer selects only, because which way each coordinate of an offset ray origin moves
// depends on the surface and a branch on it was often mispredicted.
inline float next_float_toward(float v, float direction) {
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    const uint32_t magnitude = bits & 0x7fffffffu;
    const bool up = direction > 0.0f, keep = !(up || direction < 0.0f);
    const uint32_t from = magnitude == 0 ? (up ? 0u : 0x80000000u) : bits;  // zero takes the direction's sign
    const bool away_from_zero = up == ((from >> 31) == 0);
    // An infinity stepping further out stays where it is.
    const bool stays = keep || (magnitude == 0x7f800000u && away_from_zero);
    const uint32_t result = stays ? bits : (away_from_zero ? from + 1 : from - 1);
    std::memcpy(&v, &result, sizeof v);
    return v;
}

// Veach's power heuristic (beta = 2) for combining two sampling strategies; the weight of the
// strategy with density `pdf_a`. An infinite density (a delta) takes all the weight.
inline float power_heuristic(float pdf_a, float pdf_b) {
    if (std::isinf(pdf_a)) return 1.0f;
    float a2 = pdf_a * pdf_a, b2 = pdf_b * pdf_b;
    float w = a2 / (a2 + b2);
    return std::isfinite(w) ? w : 0.0f;
}

// Axis-aligned bounding box.
struct BoundingBox {
    Vec3 min = Vec3(Infinity);
    Vec3 max = Vec3(-Infinity);

    bool valid() const { return min.x <= max.x && min.y <= max.y && min.z <= max.z; }
    void expand(const Vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void expand(const BoundingBox& b) {
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
    }
    Vec3 center() const { return 0.5f * (min + max); }
    Vec3 extents() const { return max - min; }
    // Radius of a sphere around center() that encloses the box.
    float bounding_radius() const { return valid() ? 0.5f * glm::length(max - min) : 0.0f; }
};

}  // namespace candela
