#include "samplers/sequences.h"

#include "core/rng.h"

#include <array>
#include <vector>

namespace candela {

uint64_t pixel_key(const Vec2i& pixel) { return (uint64_t(uint32_t(pixel.y)) << 32) | uint32_t(pixel.x); }

namespace {

using SobolMatrix = std::array<uint32_t, SobolIndexBits>;

// Column j (index bit j, j = 0 the least significant) holds the direction number v_{j+1} as a
// 32-bit binary fraction: v_k = m_k / 2^k, with m_k from the recurrence of Bratley and Fox for
// k beyond the polynomial's degree s (Joe and Kuo 2008, section 2):
//   m_k = 2 a_1 m_{k-1} ^ 4 a_2 m_{k-2} ^ ... ^ 2^{s-1} a_{s-1} m_{k-s+1} ^ 2^s m_{k-s} ^ m_{k-s}.
SobolMatrix joe_kuo_matrix(const SobolDirections& d) {
    std::array<uint64_t, SobolIndexBits> m{};
    for (int k = 0; k < SobolIndexBits; ++k) {
        if (k < d.degree) {
            m[k] = d.m[k];
            continue;
        }
        uint64_t v = m[k - d.degree] ^ (m[k - d.degree] << d.degree);
        for (int i = 1; i < d.degree; ++i)
            if ((d.polynomial >> (d.degree - 1 - i)) & 1u) v ^= m[k - i] << i;
        m[k] = v;
    }
    SobolMatrix columns{};
    for (int j = 0; j < SobolIndexBits; ++j) {
        int k = j + 1;  // m_k has k bits; its binary point sits k places from the right
        columns[j] = k <= 32 ? uint32_t(m[j] << (32 - k)) : uint32_t(m[j] >> (k - 32));
    }
    return columns;
}

const std::vector<SobolMatrix>& sobol_matrices() {
    static const std::vector<SobolMatrix> matrices = [] {
        std::vector<SobolMatrix> all(SobolDimensions);
        for (int j = 0; j < 32; ++j) all[0][j] = 1u << (31 - j);  // van der Corput
        for (int d = 1; d < SobolDimensions; ++d) all[d] = joe_kuo_matrix(joe_kuo_directions[d - 1]);
        return all;
    }();
    return matrices;
}

// The same columns with their bits reversed (for sobol_bits_reversed).
const std::vector<SobolMatrix>& reversed_sobol_matrices() {
    static const std::vector<SobolMatrix> matrices = [] {
        std::vector<SobolMatrix> all = sobol_matrices();
        for (SobolMatrix& columns : all)
            for (uint32_t& column : columns) column = reverse_bits(column);
        return all;
    }();
    return matrices;
}

// The XOR of the columns of the index's set bits, visited by their positions (count trailing
// zeros): no branch on each bit, which the random bits of sample indices mispredict half the time
// (about 20% of a render's time with the sobol sampler went here).
uint32_t xor_columns(const SobolMatrix& columns, uint64_t index) {
    index &= (uint64_t(1) << SobolIndexBits) - 1;
    uint32_t v = 0;
    for (; index != 0; index &= index - 1) v ^= columns[size_t(__builtin_ctzll(index))];
    return v;
}

}  // namespace

const uint32_t* sobol_matrix(int dim) { return sobol_matrices()[dim].data(); }

uint32_t sobol_bits(uint64_t index, int dim) {
    if (dim == 0) return reverse_bits(uint32_t(index));  // van der Corput: index bits 32 and up fall below 2^-32
    if (dim == 1 && index >> 32 == 0) return sobol_dimension1(uint32_t(index));
    return xor_columns(sobol_matrices()[size_t(dim)], index);
}

uint32_t sobol_bits_reversed(uint64_t index, int dim) {
    if (dim == 0) return uint32_t(index);
    if (dim == 1 && index >> 32 == 0) return sobol_dimension1_reversed(uint32_t(index));
    return xor_columns(reversed_sobol_matrices()[size_t(dim)], index);
}

uint64_t morton_2d(uint32_t x, uint32_t y) {
    auto spread = [](uint64_t v) {
        v &= 0xffffffffu;
        v = (v | (v << 16)) & 0x0000ffff0000ffffull;
        v = (v | (v << 8)) & 0x00ff00ff00ff00ffull;
        v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0full;
        v = (v | (v << 2)) & 0x3333333333333333ull;
        v = (v | (v << 1)) & 0x5555555555555555ull;
        return v;
    };
    return spread(x) | (spread(y) << 1);
}

}  // namespace candela
