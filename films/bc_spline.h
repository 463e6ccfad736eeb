#pragma once
// The Mitchell-Netravali family of cubic filters (Mitchell & Netravali 1988, "Reconstruction
// Filters in Computer Graphics", eq. 8), as Mitsuba 3's mitchell and catmullrom filters evaluate
// it: radius 2 pixels, x in pixels, no rescaling. For every B and C the piecewise cubic sums to
// one over integer shifts, so its integral over [-2, 2] is 1 as ReconstructionFilter asks.

#include <cmath>

namespace candela {

inline float bc_spline(float x, float b, float c) {
    x = std::abs(x);
    const float x2 = x * x, x3 = x2 * x;
    if (x < 1.0f) return ((12.0f - 9.0f * b - 6.0f * c) * x3 + (-18.0f + 12.0f * b + 6.0f * c) * x2 + (6.0f - 2.0f * b)) / 6.0f;
    if (x < 2.0f)
        return ((-b - 6.0f * c) * x3 + (6.0f * b + 30.0f * c) * x2 + (-12.0f * b - 48.0f * c) * x + (8.0f * b + 24.0f * c)) / 6.0f;
    return 0.0f;
}

}  // namespace candela
