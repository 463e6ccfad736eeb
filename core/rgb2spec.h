#pragma once
// RGB reflectances turned into smooth spectra as Mitsuba 3's spectral variants do it: Jakob and
// Hanika 2019, "A Low-Dimensional Function Space for Efficient Spectral Upsampling". A spectrum is
// s(l) = S(c0 l^2 + c1 l + c2) with the sigmoid S(x) = 1/2 + x / (2 sqrt(1 + x^2)), l in nm; the
// coefficients of a linear sRGB colour (Rec. 709 primaries, D65 white) are interpolated
// trilinearly in a precomputed table.
//
// The table (compiled in by core/rgb2spec_table.cpp) is Candela's own, made when CMake
// configures (cmake/srgb_sigmoid_table.cmake) by core/data/gen_srgb_sigmoid.cpp from the CIE 1931
// and D65 tables of core/spectral.cpp. Its layout is the paper's: three tables, one per largest
// component z, indexed by the other two divided by z (x, y, 64 even steps in [0, 1]) and by z at
// smoothstep(smoothstep(k / 63)), k = 0..63, which samples both the dark and the bright end
// densely; 9,437,448 bytes of float32. Every node is fitted so that spectrum_to_rgb
// (weight_by_d65 = true) of its spectrum, sampled every 1 nm from 360 to 830 nm, is the node's
// colour; the fit is least squares in linear sRGB (generator: its opening comment).
//
// Fit error, measured (tests/core/test_rgb2spec.cpp checks these bounds): the absolute difference
// per channel between rgb and spectrum_to_rgb(weight_by_d65 = true, bounded = true) of
// rgb_to_reflectance_spectrum(rgb) sampled every 1 nm over 360-830 nm, in linear sRGB:
//   33^3 grid of the cube (greys apart):   max 2.35e-3 at (0.96875, 1, 1), mean 1.03e-4
//   20000 uniform random colours:          max 4.54e-3 at (0.9878, 0.9968, 0.7963), mean 1.31e-4
//   200000 of them, largest component <= 0.95: max 1.68e-3 at (0.0103, 0.0050, 0.9255), mean 1.35e-4
//   20000 random colours in [0.95, 1]^3:   max 1.97e-2 at (0.9912, 0.99994, 0.9525), mean 1.13e-3
// The fit at the nodes: mean |r| 1.3e-7 over the 786432 nodes, max 1.94e-3 at white (out of
// reach: see below); the rest is the trilinear interpolation of the coefficients, as in the paper and
// Mitsuba 3. Its error is largest where coefficients change fast: along z (dark colours are off by
// up to ~2% relative, e.g. 3.5e-4 at z = 0.016) and near white, the worst: there the fits change
// from a bump (concave, both ends lowered) to a valley (convex) between neighbouring nodes, and
// some colours are out of reach of reflectances altogether (spectrum_to_rgb makes the flat
// spectrum 1 (0.99899, 0.99887, 0.99880)), so their nodes are least-squares compromises.
// A grey (r == g == b) is the flat spectrum of its value, exactly; its colour is what spectrum_to_rgb
// gives a flat spectrum: v * (0.998985, 0.998874, 0.998802) (the 1000-point sum and the D65
// table's white; see tests/core/test_spectral.cpp), so greys round-trip within 1.2e-3 * v.

#include "core/math.h"

namespace candela {

// A smooth spectrum s(l) = S(c0 l^2 + c1 l + c2), l in nm (Jakob and Hanika 2019).
// S(+infinity) = 1 and S(-infinity) = 0: c2 = +-infinity with c0 = c1 = 0 are the constant
// spectra 1 and 0.
struct SigmoidPolynomial {
    float c0 = 0, c1 = 0, c2 = 0;
    float operator()(float lambda_nm) const {
        float x = (c0 * lambda_nm + c1) * lambda_nm + c2;  // Horner
        // S(-|x|) = (r - |x|) / (2 r) = 1 / (2 r (r + |x|)), r = sqrt(1 + x^2): no cancellation for
        // dark values (0.5 - 0.4999990 in float would keep one digit of 1e-6), and 0 or 1 for
        // infinite x and wherever x^2 overflows (never NaN).
        float r = std::sqrt(1.0f + x * x);
        float low = 0.5f / (r * (r + std::abs(x)));
        return x >= 0.0f ? 1.0f - low : low;
    }
};

// The smooth reflectance spectrum whose colour under D65 (as core/spectral.h's spectrum_to_rgb
// with weight_by_d65 = true computes it) is `rgb` (linear sRGB, clamped to [0, 1] first; NaN is
// taken as 0). Greys are the flat spectrum of their value: black and white exactly 0 and 1.
// Allocation-free and thread-safe (the table is read-only).
SigmoidPolynomial rgb_to_reflectance_spectrum(const Vec3& rgb);

// The coefficient table's layout, shared with its generator. `scale` holds the resolution z
// values; `coefficients` holds 3 * resolution^3 triples (c0, c1, c2), the triple of node
// (largest component l, z index k, y index j, x index i) at ((l * res + k) * res + j) * res + i,
// where the node's colour has component l = z = scale[k], component (l + 1) % 3 = z * i / (res - 1)
// and component (l + 2) % 3 = z * j / (res - 1).
struct SigmoidTable {
    int resolution = 0;
    const float* scale = nullptr;
    const float* coefficients = nullptr;
};
// The table compiled in (core/rgb2spec_table.cpp).
const SigmoidTable& srgb_sigmoid_table();
// rgb_to_reflectance_spectrum with another table (the generator checks its own with it).
SigmoidPolynomial fetch_sigmoid_polynomial(const SigmoidTable& table, const Vec3& rgb);

}  // namespace candela
