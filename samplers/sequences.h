#pragma once
// The building blocks of the stratified and low-discrepancy samplers: hashed permutations
// (Kensler 2013), bit reversal, Owen scrambling by hashing (Burley 2020), the Sobol' sequence
// with Joe and Kuo's direction numbers, and Morton codes. All are pure functions of their
// arguments, so a sample's numbers depend only on (seed, pixel, sample index, dimension).

#include "core/math.h"
#include "core/rng.h"

#include <cstdint>

namespace candela {

// The largest float below 1.
constexpr float OneMinusEpsilon = 0x1.fffffep-1f;

// A uniform float in [0, 1) from the top 24 bits of `bits` (exact, never 1).
inline float bits_to_unit(uint32_t bits) { return float(bits >> 8) * 0x1p-24f; }
inline float clamp_below_one(float x) { return x < OneMinusEpsilon ? x : OneMinusEpsilon; }

// 32 well-mixed bits from two keys.
inline uint32_t hash_bits(uint64_t a, uint64_t b) { return uint32_t(hash_combine(a, b) >> 32); }
// A per-pixel key for hashing (x and y in one 64-bit word).
uint64_t pixel_key(const Vec2i& pixel);

// A divisor fixed for many divisions (a sampler's counts): x / n and x % n for every 32-bit x
// without a division instruction, and the mask of the next power of two at least n, which
// Kensler's permutation walks. For n not a power of two, M = floor((2^64 - 1) / n) + 1 makes x / n
// the high 64 bits of M x and x % n the high 64 bits of (M x mod 2^64) n, exact for every 32-bit
// x (Lemire, Kaser and Kurz 2019, "Faster remainder by direct computation").
struct Divisor {
    Divisor() : Divisor(1) {}
    explicit Divisor(uint32_t n) : n(n) {
        // n must be at least 1; the callers' counts are.
        mask = n - 1;
        mask |= mask >> 1;
        mask |= mask >> 2;
        mask |= mask >> 4;
        mask |= mask >> 8;
        mask |= mask >> 16;
        power_of_two = (n & (n - 1)) == 0;
        shift = power_of_two ? __builtin_ctz(n) : 0;
        multiplier = power_of_two ? 0 : ~uint64_t(0) / n + 1;
    }
    uint32_t quotient(uint32_t x) const { return power_of_two ? x >> shift : uint32_t((unsigned __int128)multiplier * x >> 64); }
    uint32_t remainder(uint32_t x) const { return power_of_two ? x & mask : uint32_t((unsigned __int128)(multiplier * x) * n >> 64); }

    uint32_t n = 1;
    uint32_t mask = 0;  // the bits below the next power of two at least n
    bool power_of_two = true;
    int shift = 0;  // log2(n) for a power of two
    uint64_t multiplier = 0;
};

// Element i of a pseudo-random permutation of [0, n) chosen by `seed` (Kensler 2013, "Correlated
// Multi-Jittered Sampling", section 3: an invertible hash on the next power of two, walked until
// it lands below n, then rotated). i must be below n. Inline: the pixel-sequence samplers call
// it once per number drawn, and the call cost about 7% of its instructions (callgrind).
inline uint32_t permute_index(uint32_t i, const Divisor& n, uint32_t seed) {
    const uint32_t mask = n.mask;
    // Every step is invertible on the masked bits (xor with a constant, multiplication by an odd
    // constant, xor with a right shift of the masked value), so the loop is a permutation of
    // [0, mask]; cycle walking restricts it to [0, n). Constants from Kensler's paper.
    do {
        i ^= seed;
        i *= 0xe170893du;
        i ^= seed >> 16;
        i ^= (i & mask) >> 4;
        i ^= seed >> 8;
        i *= 0x0929eb3fu;
        i ^= seed >> 23;
        i ^= (i & mask) >> 1;
        i *= 1u | seed >> 27;
        i *= 0x6935fa69u;
        i ^= (i & mask) >> 11;
        i *= 0x74dcb303u;
        i ^= (i & mask) >> 2;
        i *= 0x9e501cc3u;
        i ^= (i & mask) >> 2;
        i *= 0xc860a3dfu;
        i &= mask;
        i ^= i >> 5;
    } while (i >= n.n);
    return n.remainder(i + seed);
}

constexpr uint32_t reverse_bits(uint32_t v) {
    // Inline: every Sobol and Owen-scrambled draw reverses bits once or twice. (constexpr: the
    // byte tables of Sobol' dimension 1 below are built at compile time.)
    v = __builtin_bswap32(v);
    v = ((v & 0x0f0f0f0fu) << 4) | ((v & 0xf0f0f0f0u) >> 4);
    v = ((v & 0x33333333u) << 2) | ((v & 0xccccccccu) >> 2);
    v = ((v & 0x55555555u) << 1) | ((v & 0xaaaaaaaau) >> 1);
    return v;
}

// A nested uniform (Owen) scramble of the binary digits of v, seen as a fraction v / 2^32: each
// digit is flipped by a hash of the digits above it (Burley 2020, "Practical Hash-based Owen
// Scrambling", JCGT 9(4): Laine and Karras's hash on the reversed bits, with his constants).
// It keeps every (t, m, s)-net property of the points it scrambles.
// owen_scramble_reversed takes v's digits already reversed (sobol_bits_reversed), saving a
// reversal; both return the scrambled digits in the usual order.
inline uint32_t owen_scramble_reversed(uint32_t v, uint32_t seed) {
    // In reversed order the most significant digit is bit 0, and each step below changes a bit
    // only by a function of the bits beneath it: a flip of each digit that depends only on the
    // digits before it, which is Owen's nested uniform scramble.
    v ^= v * 0x3d20adeau;
    v += seed;
    v *= (seed >> 16) | 1u;
    v ^= v * 0x05526c56u;
    v ^= v * 0x53a22864u;
    return reverse_bits(v);
}
inline uint32_t owen_scramble(uint32_t v, uint32_t seed) { return owen_scramble_reversed(reverse_bits(v), seed); }

// The Sobol' sequence: dimension 0 is van der Corput's, dimensions 1 to 256 come from Joe and
// Kuo's direction numbers (samplers/sobol_directions.cpp). Dimensions 0 and 1 form a
// (0, 2)-sequence: every 2^m consecutive points starting at a multiple of 2^m have exactly one
// point in each elementary interval of area 2^-m.
constexpr int SobolDimensions = 257;
constexpr int SobolIndexBits = 52;
// The 32 bits (a binary fraction) of dimension `dim` of point `index`, unscrambled.
uint32_t sobol_bits(uint64_t index, int dim);
// reverse_bits(sobol_bits(index, dim)), from bit-reversed generator matrices: the order Owen
// scrambling works in, without reversing each point.
uint32_t sobol_bits_reversed(uint64_t index, int dim);
// The generator matrix of dimension `dim`: column j is the contribution of bit j of the index.
const uint32_t* sobol_matrix(int dim);

// Sobol' dimension 1 for indices below 2^32 by byte tables, in place of a walk over the index's
// set bits: entry [byte][v] is the XOR of the columns of v's set bits at that byte position, in
// the usual and in reversed bit order. Built at compile time from the dimension's direction
// numbers (Joe and Kuo's first polynomial, x + 1: m_1 = 1, m_k = m_{k-1} ^ 2 m_{k-1}; column j
// is m_{j+1} / 2^{j+1}), so that the inline look-up has no initialisation guard: zsobol draws
// dimensions 0 and 1 at every draw, ldsampler dimension 1 at every 2D draw.
struct SobolDimension1Bytes {
    uint32_t plain[4][256], reversed[4][256];
};
constexpr SobolDimension1Bytes make_sobol_dimension1_bytes() {
    uint32_t columns[32] = {};
    uint64_t m = 1;
    for (int j = 0; j < 32; ++j) {
        if (j > 0) m ^= m << 1;
        columns[j] = uint32_t(m << (31 - j));
    }
    SobolDimension1Bytes t{};
    for (int byte = 0; byte < 4; ++byte)
        for (uint32_t v = 0; v < 256; ++v) {
            uint32_t x = 0;
            for (int bit = 0; bit < 8; ++bit)
                if ((v >> bit) & 1u) x ^= columns[8 * byte + bit];
            t.plain[byte][v] = x;
            t.reversed[byte][v] = reverse_bits(x);
        }
    return t;
}
inline constexpr SobolDimension1Bytes SobolDimension1 = make_sobol_dimension1_bytes();
inline uint32_t xor_sobol_bytes(const uint32_t (&table)[4][256], uint32_t index) {
    uint32_t v = 0;
    for (int byte = 0; byte < 4 && (index >> (8 * byte)) != 0; ++byte) v ^= table[byte][(index >> (8 * byte)) & 255u];
    return v;
}
// sobol_bits(index, 1) and sobol_bits_reversed(index, 1).
inline uint32_t sobol_dimension1(uint32_t index) { return xor_sobol_bytes(SobolDimension1.plain, index); }
inline uint32_t sobol_dimension1_reversed(uint32_t index) { return xor_sobol_bytes(SobolDimension1.reversed, index); }

// One dimension of Joe and Kuo's table: the primitive polynomial's degree and inner
// coefficients, and the initial direction numbers m_1 ... m_degree.
struct SobolDirections {
    uint8_t degree;
    uint16_t polynomial;
    uint16_t m[11];
};
constexpr int JoeKuoDimensions = SobolDimensions - 1;
extern const SobolDirections joe_kuo_directions[JoeKuoDimensions];

// Interleaves the bits of x (even positions) and y (odd positions).
uint64_t morton_2d(uint32_t x, uint32_t y);

}  // namespace candela
