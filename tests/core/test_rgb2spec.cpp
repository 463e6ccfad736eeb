// RGB to smooth spectra (core/rgb2spec.h): the round trip RGB -> spectrum -> RGB through
// core/spectral.h's spectrum_to_rgb, within the fit error core/rgb2spec.h states; greys, black
// and white exact; reflectances in [0, 1].

#include "core/rgb2spec.h"
#include "core/spectral.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

using namespace candela;

namespace {

// The spectrum sampled every 1 nm over 360-830 nm, as a reflectance: D65-weighted, bounded.
Vec3d round_trip(const Vec3& rgb) {
    SigmoidPolynomial s = rgb_to_reflectance_spectrum(rgb);
    SampledSpectrum sampled;
    for (int lambda = 360; lambda <= 830; ++lambda) {
        sampled.wavelengths.push_back(lambda);
        sampled.values.push_back(s(float(lambda)));
    }
    return Vec3d(spectrum_to_rgb(sampled, true, true));
}

struct ErrorSummary {
    double max = 0, sum = 0;
    long count = 0;
    Vec3 worst{0.0f};
    void add(const Vec3& rgb) {
        Vec3d back = round_trip(rgb);
        for (int c = 0; c < 3; ++c) {
            double e = std::abs(back[c] - double(rgb[c]));
            sum += e;
            if (e > max) max = e, worst = rgb;
        }
        count += 3;
    }
    double mean() const { return sum / double(count); }
};

// Uniform in [lo, hi) from the raw 32-bit output of mt19937 (its sequence is fixed by the
// standard; the distributions' are not).
float uniform(std::mt19937& rng, float lo, float hi) { return lo + (hi - lo) * float(double(rng()) / 4294967296.0); }

Vec3 random_colour(std::mt19937& rng, float lo = 0.0f, float hi = 1.0f) {
    float r = uniform(rng, lo, hi);
    float g = uniform(rng, lo, hi);
    float b = uniform(rng, lo, hi);
    return Vec3(r, g, b);
}

}  // namespace

TEST_CASE("rgb2spec: the round trip over a 33^3 grid of the sRGB cube", "[rgb2spec]") {
    // core/rgb2spec.h: max 2.35e-3 at (0.96875, 1, 1), mean 1.03e-4.
    ErrorSummary e;
    const int n = 33;
    for (int b = 0; b < n; ++b)
        for (int g = 0; g < n; ++g)
            for (int r = 0; r < n; ++r)
                if (!(r == g && g == b)) e.add(Vec3(r, g, b) / float(n - 1));  // greys: the test below
    CAPTURE(e.max, e.worst.x, e.worst.y, e.worst.z, e.mean());
    CHECK(e.max <= 2.4e-3);
    CHECK(e.mean() <= 1.1e-4);
}

TEST_CASE("rgb2spec: the round trip of random colours", "[rgb2spec]") {
    // core/rgb2spec.h: max 4.54e-3 at (0.9878, 0.9968, 0.7963), mean 1.31e-4; in [0.95, 1]^3
    // max 1.97e-2 at (0.9912, 0.99994, 0.9525), mean 1.13e-3.
    std::mt19937 rng(20190701);
    ErrorSummary e;
    for (int i = 0; i < 20000; ++i) e.add(random_colour(rng));
    CAPTURE(e.max, e.worst.x, e.worst.y, e.worst.z, e.mean());
    CHECK(e.max <= 4.6e-3);
    CHECK(e.mean() <= 1.4e-4);
    // Near white, where some colours are out of reach of reflectances (spectrum_to_rgb makes the
    // flat spectrum 1 (0.99899, 0.99887, 0.99880)) and the coefficients grow fast.
    ErrorSummary bright;
    for (int i = 0; i < 20000; ++i) bright.add(random_colour(rng, 0.95f, 1.0f));
    CAPTURE(bright.max, bright.worst.x, bright.worst.y, bright.worst.z, bright.mean());
    CHECK(bright.max <= 2.0e-2);
    CHECK(bright.mean() <= 1.2e-3);
}

TEST_CASE("rgb2spec: greys are flat spectra and black and white are exact", "[rgb2spec]") {
    for (float v : {0.0f, 1e-6f, 0.01f, 0.18f, 0.5f, 0.75f, 0.999f, 1.0f}) {
        SigmoidPolynomial s = rgb_to_reflectance_spectrum(Vec3(v));
        CAPTURE(v, s.c2);
        CHECK(s.c0 == 0.0f);
        CHECK(s.c1 == 0.0f);
        for (int lambda = 360; lambda <= 830; ++lambda) {
            if (v == 0.0f || v == 1.0f)
                REQUIRE(s(float(lambda)) == v);
            else
                REQUIRE(s(float(lambda)) == Approx(v).epsilon(1e-6));
        }
        // Its colour is that of the flat spectrum v (core/rgb2spec.h).
        Vec3d back = round_trip(Vec3(v)), flat = Vec3d(spectrum_to_rgb(SampledSpectrum{{360.0, 830.0}, {v, v}}, true, true));
        for (int c = 0; c < 3; ++c) CHECK(back[c] == Approx(flat[c]).margin(1e-6));
    }
    // Inputs are clamped to [0, 1] first (NaN taken as 0): these are greys too.
    CHECK(rgb_to_reflectance_spectrum(Vec3(-1.0f, -0.5f, 0.0f))(550.0f) == 0.0f);
    CHECK(rgb_to_reflectance_spectrum(Vec3(2.0f, 1.0f, 7.0f))(550.0f) == 1.0f);
    CHECK(rgb_to_reflectance_spectrum(Vec3(std::nanf(""), 0.0f, 0.0f))(550.0f) == 0.0f);
    // Infinite arguments are no NaN.
    CHECK(SigmoidPolynomial{0.0f, 0.0f, Infinity}(500.0f) == 1.0f);
    CHECK(SigmoidPolynomial{0.0f, 0.0f, -Infinity}(500.0f) == 0.0f);
    CHECK(SigmoidPolynomial{1e30f, 0.0f, 0.0f}(500.0f) == 1.0f);
}

TEST_CASE("rgb2spec: reflectances stay in [0, 1] at every wavelength", "[rgb2spec]") {
    std::mt19937 rng(7);
    for (int i = 0; i < 5000; ++i) {
        // Uniform colours, and saturated ones with components at 0 and 1.
        Vec3 rgb = random_colour(rng);
        if (i % 2) rgb[i % 3] = 1.0f, rgb[(i + 1) % 3] = 0.0f;
        SigmoidPolynomial s = rgb_to_reflectance_spectrum(rgb);
        CAPTURE(rgb.x, rgb.y, rgb.z, s.c0, s.c1, s.c2);
        REQUIRE(std::isfinite(s.c0));
        REQUIRE(std::isfinite(s.c1));
        REQUIRE(std::isfinite(s.c2));
        for (int lambda = 360; lambda <= 830; ++lambda) {
            float v = s(float(lambda));
            REQUIRE(v >= 0.0f);
            REQUIRE(v <= 1.0f);
        }
    }
}

TEST_CASE("rgb2spec: the compiled-in table", "[rgb2spec]") {
    const SigmoidTable& t = srgb_sigmoid_table();
    REQUIRE(t.resolution == 64);
    // z is sampled at smoothstep(smoothstep(k / 63)) (Jakob and Hanika 2019).
    auto smoothstep = [](double x) { return x * x * (3.0 - 2.0 * x); };
    for (int k = 0; k < t.resolution; ++k) CHECK(t.scale[k] == Approx(smoothstep(smoothstep(k / 63.0))).margin(1e-7));
    const size_t count = size_t(3) * 64 * 64 * 64 * 3;
    for (size_t i = 0; i < count; ++i) REQUIRE(std::isfinite(t.coefficients[i]));
}
