// Spectra to RGB as Mitsuba 3's RGB variants compute them, and the named conductors built from
// the measured IOR data. Anchors: numbers published in Mitsuba 3's own tests, the CIE
// chromaticity of Planckian radiators, and an independent integration of the same data.

#include "core/spectral.h"
#include "materials/ior.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

using namespace candela;
using namespace candela::test;

namespace {

// Linear sRGB (Rec. 709, D65) back to XYZ: Mitsuba's srgb_to_xyz matrix.
Vec3d srgb_to_xyz(const Spectrum& c) {
    return Vec3d(0.412453 * c.x + 0.357580 * c.y + 0.180423 * c.z, 0.212671 * c.x + 0.715160 * c.y + 0.072169 * c.z,
                 0.019334 * c.x + 0.119193 * c.y + 0.950227 * c.z);
}

// The test's own reading of an .spd file (two numbers per line, '#' comments).
SampledSpectrum read_spd_independently(const std::string& path) {
    std::istringstream in(read_text(path));
    SampledSpectrum s;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream f(line);
        double w, v;
        if (f >> w >> v) s.wavelengths.push_back(w), s.values.push_back(v);
    }
    return s;
}

// An independent integral of the colour of a spectrum without an illuminant: a 0.01 nm midpoint
// rule over 360-830 nm (Mitsuba's 1000-point sum approximates the same integral), the CIE table
// interpolated linearly, and the inverse of the sRGB-to-XYZ matrix solved by Cramer's rule.
Vec3d independent_rgb(const SampledSpectrum& s) {
    auto interp = [&](double x) {
        if (x < s.wavelengths.front() || x > s.wavelengths.back()) return 0.0;
        size_t i = 0;
        while (i + 2 < s.wavelengths.size() && s.wavelengths[i + 1] <= x) ++i;
        double t = (x - s.wavelengths[i]) / (s.wavelengths[i + 1] - s.wavelengths[i]);
        return s.values[i] + t * (s.values[i + 1] - s.values[i]);
    };
    Vec3d xyz(0.0);
    const double h = 0.01;
    for (double x = 360.0 + h / 2; x < 830.0; x += h) xyz += cie1931_xyz(x) * interp(x) * h;
    xyz /= 106.7502593994140625;  // luminance of a unit flat spectrum is 1
    const double m[3][3] = {{0.412453, 0.357580, 0.180423}, {0.212671, 0.715160, 0.072169}, {0.019334, 0.119193, 0.950227}};
    auto det = [](const double a[3][3]) {
        return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
               a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    };
    Vec3d rgb;
    for (int c = 0; c < 3; ++c) {
        double a[3][3];
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k) a[r][k] = k == c ? xyz[r] : m[r][k];
        rgb[c] = det(a) / det(m);
    }
    return rgb;
}

}  // namespace

TEST_CASE("spectra: the CIE tables and Mitsuba's normalisations", "[spectral]") {
    // Mitsuba 3's test_spectrum.py, test01_cie1931.
    Vec3d xyz = cie1931_xyz(600.0);
    CHECK(xyz.x == Approx(1.0622).margin(1e-3));
    CHECK(xyz.y == Approx(0.631).margin(1e-3));
    CHECK(xyz.z == Approx(0.0).margin(1e-3));
    CHECK(cie1931_xyz(359.0) == Vec3d(0.0));
    CHECK(cie1931_xyz(831.0) == Vec3d(0.0));
    // Mitsuba's test02_d65: D65 at 456 nm and 700 nm, times the normalisation.
    CHECK(cie_d65(456.0) == Approx(117.49 * CieD65Normalization).epsilon(1e-4));
    CHECK(cie_d65(700.0) == Approx(71.6091 * CieD65Normalization).epsilon(1e-4));
}

TEST_CASE("spectra: a flat reflectance is grey, a flat emission is the equal-energy white", "[spectral]") {
    SampledSpectrum flat{{300.0, 900.0}, {0.5, 0.5}};
    Spectrum grey = spectrum_to_rgb(flat, true, true);
    // Mitsuba's 1000-point sum weights 1000 points spaced 470/999 nm by 470/1000 nm: 0.1% low.
    CHECK(grey.x == Approx(0.5).epsilon(2e-3));
    CHECK(grey.y == Approx(grey.x).epsilon(3e-4));
    CHECK(grey.z == Approx(grey.x).epsilon(3e-4));
    // As an emission the same spectrum is XYZ = (1, 1, 1) * 0.5: pink against sRGB's D65 white,
    // the colour Mitsuba gives a single-valued emission.
    Spectrum e = spectrum_to_rgb(flat, false, false);
    Spectrum u = uniform_emission_rgb(0.5);
    for (int c = 0; c < 3; ++c) CHECK(e[c] == Approx(u[c]).epsilon(2e-3));
    CHECK(u.x == Approx(0.5 * 1.204794).epsilon(1e-6));
    CHECK(u.y == Approx(0.5 * 0.948291).epsilon(1e-6));
    CHECK(u.z == Approx(0.5 * 0.908916).epsilon(1e-6));
}

TEST_CASE("spectra: a D65 emission spectrum is white", "[spectral]") {
    // CIE D65 (relative power, 100 at 560 nm) as emitted light: sRGB's white point, equal RGB.
    SampledSpectrum d65;
    for (int i = 0; i < 95; ++i) {
        double w = 360.0 + 5.0 * i;
        d65.wavelengths.push_back(w);
        d65.values.push_back(cie_d65(w) / CieD65Normalization);
    }
    Spectrum white = spectrum_to_rgb(d65, false, false);
    CHECK(white.x == Approx(white.y).epsilon(2e-3));
    CHECK(white.z == Approx(white.y).epsilon(2e-3));
    // Its luminance is that of D65 at relative power 100: 1 / CIE_D65_NORMALIZATION, within the sum's 0.1%.
    CHECK(luminance(white) == Approx(1.0 / CieD65Normalization).epsilon(2e-3));
}

TEST_CASE("spectra: Mitsuba 3's published reflectance conversion", "[spectral]") {
    // Mitsuba 3's test_dict.py, test11_dict_spectrum_srgb: this reflectance spectrum is
    // srgb (0.380475, 0.289928, 0.134294).
    SampledSpectrum s{{400.0, 500.0, 600.0, 700.0}, {0.1, 0.2, 0.4, 0.1}};
    Spectrum rgb = spectrum_to_rgb(s, true, true);
    CHECK(rgb.x == Approx(0.380475).margin(2e-6));
    CHECK(rgb.y == Approx(0.289928).margin(2e-6));
    CHECK(rgb.z == Approx(0.134294).margin(2e-6));
    // Out of gamut: bounded colours are clamped into [0, 1] and say so; unbounded only at 0.
    SampledSpectrum bright{{400.0, 700.0}, {3.0, 3.0}};
    bool clamped = false;
    CHECK(spectrum_to_rgb(bright, true, true, &clamped) == Spectrum(1.0f));
    CHECK(clamped);
    CHECK(spectrum_to_rgb(bright, true, false, &clamped).x > 2.9f);
    CHECK_FALSE(clamped);
    SampledSpectrum narrow{{540.0, 545.0, 550.0}, {0.0, 1.0, 0.0}};  // green beyond sRGB: red < 0
    spectrum_to_rgb(narrow, false, false, &clamped);
    CHECK(clamped);
}

TEST_CASE("spectra: black bodies follow Planck's law and the Planckian locus", "[spectral]") {
    // Mitsuba 3's test03_blackbody: 5000 K at 456 and 700 nm, W m^-2 sr^-1 nm^-1.
    CHECK(blackbody_radiance(456.0, 5000.0) == Approx(10997.9).epsilon(1e-4));
    CHECK(blackbody_radiance(700.0, 5000.0) == Approx(11812.0).epsilon(1e-4));
    // CIE 1931 chromaticities of Planckian radiators: 2856 K (illuminant A: x 0.44757,
    // y 0.40745) and 6500 K (x 0.3135, y 0.3236). The 5 nm table and the 360-830 nm range
    // limit the agreement to about 1e-3.
    struct Case {
        double t, x, y;
    };
    for (Case c : {Case{2856.0, 0.44757, 0.40745}, Case{6500.0, 0.3135, 0.3236}}) {
        Vec3d xyz = srgb_to_xyz(blackbody_rgb(c.t));
        double sum = xyz.x + xyz.y + xyz.z;
        INFO("T = " << c.t);
        CHECK(xyz.x / sum == Approx(c.x).margin(1.5e-3));
        CHECK(xyz.y / sum == Approx(c.y).margin(1.5e-3));
    }
    // Restricting the range removes light: nothing below 600 nm leaves mostly red.
    Spectrum red = blackbody_rgb(3000.0, 600.0, 830.0);
    CHECK(red.x > 5.0f * red.z);
}

TEST_CASE("spectra: .spd files with comments and malformed spectra", "[spectral][errors]") {
    SampledSpectrum s = parse_spd("# measured\n\n400 0.5  # blue\n  500\t0.25\n600 0.125\n");
    CHECK(s.wavelengths == std::vector<double>{400, 500, 600});
    CHECK(s.values == std::vector<double>{0.5, 0.25, 0.125});
    SampledSpectrum p = parse_spectrum_pairs("400:0.5, 500:0.25 600:0.125");
    CHECK(p.wavelengths == s.wavelengths);
    CHECK(p.values == s.values);
    CHECK_THROWS_WITH(parse_spd("400 0.5\n500 0.2 9\n"), Catch::Contains("line 2") && Catch::Contains("3 fields"));
    CHECK_THROWS_WITH(parse_spd("400 0.5\n500 x\n"), Catch::Contains("line 2") && Catch::Contains("not a number"));
    CHECK_THROWS_WITH(parse_spd("# nothing\n"), Catch::Contains("at least two"));
    CHECK_THROWS_WITH(parse_spectrum_pairs("500:0.5, 400:0.5"), Catch::Contains("wavelengths must increase"));
    CHECK_THROWS_WITH(parse_spectrum_pairs("400-0.5, 500:0.5"), Catch::Contains("not a wavelength:value pair"));
    CHECK_THROWS_WITH(parse_spectrum_pairs("400:0.5"), Catch::Contains("at least two"));
}

TEST_CASE("named conductors: every name of Mitsuba 3's table, integrated as Mitsuba does", "[spectral][ior]") {
    // The conductor presets listed in Mitsuba 3's conductor plugin documentation.
    const std::vector<std::string> mitsuba = {
        "a-C",       "Ag",      "Al",         "AlAs",     "AlAs_palik", "AlSb",     "AlSb_palik", "Au",       "Be",         "Be_palik",
        "Cr",        "CsI",     "CsI_palik",  "Cu",       "Cu_palik",   "Cu2O",     "Cu2O_palik", "CuO",      "CuO_palik",  "d-C",
        "d-C_palik", "Hg",      "Hg_palik",   "HgTe",     "HgTe_palik", "Ir",       "Ir_palik",   "K",        "K_palik",    "Li",
        "Li_palik",  "MgO",     "MgO_palik",  "Mo",       "Mo_palik",   "Na_palik", "Nb",         "Nb_palik", "Ni_palik",   "Rh",
        "Rh_palik",  "Se",      "Se_palik",   "SiC",      "SiC_palik",  "SnTe",     "SnTe_palik", "Ta",       "Ta_palik",   "Te",
        "Te_palik",  "ThF4",    "ThF4_palik", "TiC",      "TiC_palik",  "TiN",      "TiN_palik",  "TiO2",     "TiO2_palik", "VC",
        "VC_palik",  "V_palik", "VN",         "VN_palik", "W",          "none"};
    for (const std::string& name : mitsuba) {
        INFO(name);
        auto ior = named_conductor(name);
        REQUIRE(ior);
        CHECK(min_component(ior->eta) >= 0.0f);
        CHECK(min_component(ior->k) >= 0.0f);
    }
    CHECK(named_conductors().size() == mitsuba.size());
    CHECK(named_conductor("au"));  // names match ignoring case
    CHECK_FALSE(named_conductor("Unobtainium"));

    // The RGB eta and k of Au, Cu, Ag, Al equal an independent integration of the same data files
    // (no illuminant, as Mitsuba's complex_ior_from_file). Mitsuba's 1000-point sum sits 0.1%
    // below the integral (points 470/999 nm apart weighted 470/1000 nm); 0.3% leaves room for
    // the sum's discretisation, while a D65 weighting or a wrong normalisation is off by percents.
    for (const char* name : {"Au", "Cu", "Ag", "Al"}) {
        auto ior = *named_conductor(name);
        std::string base = source_path(std::string("materials/data/ior/") + name);
        Vec3d eta = independent_rgb(read_spd_independently(base + ".eta.spd"));
        Vec3d k = independent_rgb(read_spd_independently(base + ".k.spd"));
        for (int c = 0; c < 3; ++c) {
            INFO(name << " channel " << c);
            CHECK(ior.eta[c] == Approx(eta[c]).epsilon(3e-3));
            CHECK(ior.k[c] == Approx(k[c]).epsilon(3e-3));
        }
    }
    // Mitsuba 3's ior_from_file("Ag") as reproduced in public code (spectrum_list_to_srgb with
    // bounded = false, d65 = false): agreement to float precision.
    auto ag = *named_conductor("Ag");
    const double eta_ag[3] = {0.15527619421482086, 0.11672795563936234, 0.13838763535022736};
    const double k_ag[3] = {4.828354358673096, 3.122222423553467, 2.1469011306762695};
    for (int c = 0; c < 3; ++c) {
        CHECK(ag.eta[c] == Approx(eta_ag[c]).epsilon(2e-5));
        CHECK(ag.k[c] == Approx(k_ag[c]).epsilon(2e-5));
    }
}

TEST_CASE("spectra: the linear weights reproduce spectrum_to_rgb", "[spectral]") {
    // A smooth reflectance whose colour lies inside sRGB (no clamping), on an uneven grid
    // reaching past the CIE range (as RGL's 360-1000 nm measurements do).
    std::vector<double> w = {360, 380, 430, 455, 500, 560, 600, 700, 780, 900, 1000};
    SampledSpectrum s{w, {}};
    for (double x : w) s.values.push_back(0.4 + 0.3 * std::sin(x / 70.0));
    bool clamped = true;
    Spectrum reference = spectrum_to_rgb(s, true, false, &clamped);
    REQUIRE(!clamped);
    std::vector<Vec3d> weights = spectrum_to_rgb_weights(w, true);
    Vec3d sum(0.0);
    for (size_t j = 0; j < w.size(); ++j) sum += weights[j] * s.values[j];
    for (int c = 0; c < 3; ++c) CHECK(sum[c] == Approx(reference[c]).epsilon(1e-6));
    CHECK_THROWS_AS(spectrum_to_rgb_weights({500.0}, true), SpectrumFormatError);
}
