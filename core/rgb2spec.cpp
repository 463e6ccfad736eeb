#include "core/rgb2spec.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

// The table file, compiled in by the assembler (no generated C array: 9 MB of it would take the
// compiler minutes). CMakeLists.txt defines its path, and its MD5 so that ccache, which does not
// read .incbin files, compiles this file again when the table changes. File format
// (little-endian): "CSG1", uint32 resolution, float32 scale[resolution], float32 coefficients
// [3 * resolution^3 * 3] (core/rgb2spec.h, SigmoidTable).
#ifndef CANDELA_SRGB_SIGMOID_TABLE
#error "CMakeLists.txt defines CANDELA_SRGB_SIGMOID_TABLE, the path of core/data/srgb_sigmoid.coeff"
#endif

asm(".pushsection .rodata, \"a\"\n"
    ".balign 16\n"
    ".globl candela_srgb_sigmoid_begin\n"
    ".hidden candela_srgb_sigmoid_begin\n"
    "candela_srgb_sigmoid_begin:\n"
    ".incbin \"" CANDELA_SRGB_SIGMOID_TABLE
    "\"\n"
    ".globl candela_srgb_sigmoid_end\n"
    ".hidden candela_srgb_sigmoid_end\n"
    "candela_srgb_sigmoid_end:\n"
    ".popsection\n");

extern "C" {
__attribute__((visibility("hidden"))) extern const unsigned char candela_srgb_sigmoid_begin[];
__attribute__((visibility("hidden"))) extern const unsigned char candela_srgb_sigmoid_end[];
}

namespace candela {

namespace {

SigmoidTable load_embedded_table() {
    static_assert(sizeof(float) == 4 && sizeof(uint32_t) == 4, "the table is float32");
    const unsigned char* data = candela_srgb_sigmoid_begin;
    size_t size = size_t(candela_srgb_sigmoid_end - candela_srgb_sigmoid_begin);
    uint32_t resolution = 0;
    const uint16_t endian_probe = 1;
    bool little_endian = *reinterpret_cast<const unsigned char*>(&endian_probe) == 1;
    if (size >= 8) std::memcpy(&resolution, data + 4, 4);
    size_t expected = 8 + 4 * size_t(resolution) + 4 * 9 * size_t(resolution) * resolution * resolution;
    if (!little_endian || size < 8 || std::memcmp(data, "CSG1", 4) != 0 || resolution < 2 || resolution > 1024 || size != expected)
        throw InternalError("the compiled-in RGB-to-spectrum table (core/data/srgb_sigmoid.coeff) is malformed (" + std::to_string(size) +
                            " bytes)");
    // The section is 16-byte aligned and the floats start at byte 8: aligned for float.
    SigmoidTable table;
    table.resolution = int(resolution);
    table.scale = reinterpret_cast<const float*>(data + 8);
    table.coefficients = table.scale + resolution;
    return table;
}

// S^-1(v) = (v - 1/2) / sqrt(v (1 - v)): the flat spectrum of value v; -inf at 0, +inf at 1.
SigmoidPolynomial flat_spectrum(float v) {
    double d = v;
    SigmoidPolynomial s;
    s.c2 = v <= 0.0f ? -Infinity : v >= 1.0f ? Infinity : float((d - 0.5) / std::sqrt(d * (1.0 - d)));
    return s;
}

}  // namespace

const SigmoidTable& srgb_sigmoid_table() {
    static const SigmoidTable table = load_embedded_table();
    return table;
}

SigmoidPolynomial fetch_sigmoid_polynomial(const SigmoidTable& table, const Vec3& rgb_in) {
    Vec3 rgb;
    for (int c = 0; c < 3; ++c) rgb[c] = rgb_in[c] > 0.0f ? std::min(rgb_in[c], 1.0f) : 0.0f;  // NaN -> 0
    if (rgb.x == rgb.y && rgb.y == rgb.z) return flat_spectrum(rgb.x);

    // The paper's layout: the largest component l is z; the others, divided by z, are x and y.
    int l = 0;
    if (rgb[1] > rgb[l]) l = 1;
    if (rgb[2] > rgb[l]) l = 2;
    const int res = table.resolution;
    float z = rgb[l];  // > 0: not all components are equal
    float x = rgb[(l + 1) % 3] / z * float(res - 1), y = rgb[(l + 2) % 3] / z * float(res - 1);
    int xi = std::min(int(x), res - 2), yi = std::min(int(y), res - 2);
    // z's nodes are uneven: the last one at or below z.
    int zi = int(std::upper_bound(table.scale, table.scale + res, z) - table.scale) - 1;
    zi = std::clamp(zi, 0, res - 2);
    float tx = x - float(xi), ty = y - float(yi);
    float tz = (z - table.scale[zi]) / (table.scale[zi + 1] - table.scale[zi]);

    const size_t dx = 3, dy = 3 * size_t(res), dz = 3 * size_t(res) * res;
    const float* base = table.coefficients + ((size_t(l) * res + zi) * res + yi) * dy + xi * dx;
    float c[3];
    for (int n = 0; n < 3; ++n) {
        const float* p = base + n;
        auto lerp = [](float a, float b, float t) { return a + t * (b - a); };
        float y0 = lerp(lerp(p[0], p[dx], tx), lerp(p[dy], p[dy + dx], tx), ty);
        float y1 = lerp(lerp(p[dz], p[dz + dx], tx), lerp(p[dz + dy], p[dz + dy + dx], tx), ty);
        c[n] = lerp(y0, y1, tz);
    }
    return SigmoidPolynomial{c[0], c[1], c[2]};
}

SigmoidPolynomial rgb_to_reflectance_spectrum(const Vec3& rgb) { return fetch_sigmoid_polynomial(srgb_sigmoid_table(), rgb); }

}  // namespace candela
