#include "core/rgb2spec.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace candela {

namespace {

// S^-1(v) = (v - 1/2) / sqrt(v (1 - v)): the flat spectrum of value v; -inf at 0, +inf at 1.
SigmoidPolynomial flat_spectrum(float v) {
    double d = v;
    SigmoidPolynomial s;
    s.c2 = v <= 0.0f ? -Infinity : v >= 1.0f ? Infinity : float((d - 0.5) / std::sqrt(d * (1.0 - d)));
    return s;
}

}  // namespace

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

}  // namespace candela
