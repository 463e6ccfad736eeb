// The spectral variant's two ends (core/wavelengths.h): the wavelength density and its sampling,
// the per-sample conversion to linear sRGB (unbiased: its average over the wavelength sample is
// the colour integral), and RGB inputs as spectra for each role.

#include "core/wavelengths.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

using namespace candela;

namespace {

// The colour of spectrum f: CIE_Y_NORMALIZATION * integral of cmf f over [360, 830] nm (a fine
// midpoint rule), in linear sRGB.
Vec3d colour_of(const std::function<double(double)>& f) {
    const int n = 47000;
    const double h = (CieMax - CieMin) / n;
    Vec3d xyz(0.0);
    for (int i = 0; i < n; ++i) {
        double l = CieMin + (i + 0.5) * h;
        xyz += cie1931_xyz(l) * (f(l) * h);
    }
    return xyz_to_linear_srgb(xyz * CieYNormalization);
}

// The average of spectral_to_linear_srgb over the wavelength sample u in [0, 1) (a midpoint rule
// in u): what a render converges to for radiance f at every wavelength.
Vec3d average_estimate(const std::function<Spectrum(const Wavelengths&)>& values, int n = 200000) {
    Vec3d sum(0.0);
    for (int i = 0; i < n; ++i) {
        Wavelengths w = sample_visible_wavelengths(float((i + 0.5) / n));
        sum += Vec3d(spectral_to_linear_srgb(values(w), w));
    }
    return sum / double(n);
}

}  // namespace

TEST_CASE("wavelengths: the visible density integrates to 1 and sampling inverts its distribution", "[spectral]") {
    double integral = 0.0;
    const int n = 47000;
    for (int i = 0; i < n; ++i) integral += visible_wavelength_pdf(float(CieMin + (i + 0.5) * (CieMax - CieMin) / n));
    integral *= (CieMax - CieMin) / n;
    CHECK(integral == Approx(1.0).epsilon(1e-5));
    CHECK(visible_wavelength_pdf(359.0f) == 0.0f);
    CHECK(visible_wavelength_pdf(831.0f) == 0.0f);
    // The distribution's value at the sampled wavelength is the sample: F(l(u)) = u.
    for (float u : {0.001f, 0.1f, 0.25f, 0.5f, 0.77f, 0.999f}) {
        Wavelengths w = sample_visible_wavelengths(u);
        double F = 0.0;
        const int m = 20000;
        const double h = (double(w.lambda[0]) - CieMin) / m;
        for (int i = 0; i < m; ++i) F += visible_wavelength_pdf(float(CieMin + (i + 0.5) * h)) * h;
        CHECK(F == Approx(u).margin(2e-5));
        // The others are shifted by 1/3 and 2/3 (mod 1): a stratified set.
        CHECK(w.lambda[0] >= CieMin);
        CHECK(w.lambda[2] <= CieMax);
        for (int j = 0; j < WavelengthSamples; ++j) CHECK(w.pdf[j] == visible_wavelength_pdf(w.lambda[j]));
    }
}

TEST_CASE("wavelengths: the per-sample colour averages to the colour integral", "[spectral]") {
    // An equal-energy spectrum, a smooth bump and D65 itself.
    const std::function<double(double)> spectra[] = {
        [](double) { return 1.0; },
        [](double l) { return std::exp(-0.5 * std::pow((l - 600.0) / 40.0, 2.0)); },
        [](double l) { return cie_d65(l); },
    };
    for (const auto& f : spectra) {
        Vec3d expected = colour_of(f);
        Vec3d got = average_estimate([&](const Wavelengths& w) {
            Spectrum s;
            for (int j = 0; j < WavelengthSamples; ++j) s[j] = float(f(w.lambda[j]));
            return s;
        });
        // The midpoint rule in u errs by O(1/n^2) where the integrand is smooth; the tables'
        // kinks and float rounding leave about 1e-5.
        for (int c = 0; c < 3; ++c) CHECK(got[c] == Approx(expected[c]).margin(1e-4));
    }
    // The equal-energy white is xyz_to_linear_srgb(1, 1, 1) (uniform_emission_rgb), D65 is white.
    Vec3d white = colour_of([](double l) { return cie_d65(l); });
    for (int c = 0; c < 3; ++c) CHECK(white[c] == Approx(1.0).margin(2e-3));
}

TEST_CASE("wavelengths: terminating the secondary wavelengths keeps the hero's estimate unbiased", "[spectral]") {
    // A path that keeps only its hero wavelength: the average over u still gives the colour.
    auto f = [](double l) { return 0.2 + 0.8 * std::exp(-0.5 * std::pow((l - 500.0) / 30.0, 2.0)); };
    Vec3d expected = colour_of(f);
    Vec3d sum(0.0);
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        Wavelengths w = sample_visible_wavelengths(float((i + 0.5) / n));
        w.terminate_secondary();
        Spectrum s(0.0f);
        s[0] = float(f(w.lambda[0]));
        sum += Vec3d(spectral_to_linear_srgb(s, w));
    }
    sum /= double(n);
    for (int c = 0; c < 3; ++c) CHECK(sum[c] == Approx(expected[c]).margin(1e-4));
}

TEST_CASE("wavelengths: RGB inputs as spectra for each role", "[spectral]") {
    Wavelengths w = sample_visible_wavelengths(0.3f);
    // Greys are flat reflectances, exactly.
    for (float v : {0.0f, 0.25f, 0.5f, 1.0f}) {
        Spectrum s = rgb_at_wavelengths(Spectrum(v), SpectrumRole::Reflectance, &w);
        for (int j = 0; j < WavelengthSamples; ++j) CHECK(s[j] == Approx(v).margin(1e-6));
    }
    // Without wavelengths (the RGB variant) a colour is itself.
    CHECK(rgb_at_wavelengths(Spectrum(0.2f, 0.5f, 3.0f), SpectrumRole::Emission, nullptr) == Spectrum(0.2f, 0.5f, 3.0f));
    // Unbounded: a grey of any size is flat at its value; emission adds D65.
    Spectrum eta = rgb_at_wavelengths(Spectrum(2.5f), SpectrumRole::Unbounded, &w);
    Spectrum emission = rgb_at_wavelengths(Spectrum(2.5f), SpectrumRole::Emission, &w);
    for (int j = 0; j < WavelengthSamples; ++j) {
        CHECK(eta[j] == Approx(2.5f).margin(1e-5));
        CHECK(emission[j] == Approx(2.5 * cie_d65(w.lambda[j])).epsilon(1e-5));
    }
    // A coloured emission renders its own colour: the spectrum's colour is the rgb it came from
    // (within the coefficient table's fit, core/rgb2spec.h).
    for (Spectrum rgb : {Spectrum(1.0f, 0.2f, 0.1f), Spectrum(0.1f, 0.6f, 4.0f), Spectrum(0.3f, 0.3f, 0.02f)}) {
        RGBSpectrum s(rgb, SpectrumRole::Emission);
        Vec3d colour = average_estimate([&](const Wavelengths& wl) { return s.at(wl); }, 100000);
        for (int c = 0; c < 3; ++c) CHECK(colour[c] == Approx(rgb[c]).margin(5e-3 * max_component(rgb)));
    }
}
