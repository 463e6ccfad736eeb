#include "core/spectral.h"

#include "core/text.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

namespace candela {

namespace {

constexpr int CieSamples = 95;  // 360, 365, ..., 830 nm

// CIE 1931 2-degree standard observer colour matching functions x, y, z at 5 nm from 360 to
// 830 nm: measured data of the CIE (CIE 015:2004, Colorimetry, table T.4; also CVRL,
// cvrl.org), as tabulated in Mitsuba 3's src/core/spectrum.cpp.
const float CieX[CieSamples] = {
    0.000129900000f, 0.000232100000f, 0.000414900000f, 0.000741600000f, 0.001368000000f, 0.002236000000f, 0.004243000000f, 0.007650000000f,
    0.014310000000f, 0.023190000000f, 0.043510000000f, 0.077630000000f, 0.134380000000f, 0.214770000000f, 0.283900000000f, 0.328500000000f,
    0.348280000000f, 0.348060000000f, 0.336200000000f, 0.318700000000f, 0.290800000000f, 0.251100000000f, 0.195360000000f, 0.142100000000f,
    0.095640000000f, 0.057950010000f, 0.032010000000f, 0.014700000000f, 0.004900000000f, 0.002400000000f, 0.009300000000f, 0.029100000000f,
    0.063270000000f, 0.109600000000f, 0.165500000000f, 0.225749900000f, 0.290400000000f, 0.359700000000f, 0.433449900000f, 0.512050100000f,
    0.594500000000f, 0.678400000000f, 0.762100000000f, 0.842500000000f, 0.916300000000f, 0.978600000000f, 1.026300000000f, 1.056700000000f,
    1.062200000000f, 1.045600000000f, 1.002600000000f, 0.938400000000f, 0.854449900000f, 0.751400000000f, 0.642400000000f, 0.541900000000f,
    0.447900000000f, 0.360800000000f, 0.283500000000f, 0.218700000000f, 0.164900000000f, 0.121200000000f, 0.087400000000f, 0.063600000000f,
    0.046770000000f, 0.032900000000f, 0.022700000000f, 0.015840000000f, 0.011359160000f, 0.008110916000f, 0.005790346000f, 0.004109457000f,
    0.002899327000f, 0.002049190000f, 0.001439971000f, 0.000999949300f, 0.000690078600f, 0.000476021300f, 0.000332301100f, 0.000234826100f,
    0.000166150500f, 0.000117413000f, 0.000083075270f, 0.000058706520f, 0.000041509940f, 0.000029353260f, 0.000020673830f, 0.000014559770f,
    0.000010253980f, 0.000007221456f, 0.000005085868f, 0.000003581652f, 0.000002522525f, 0.000001776509f, 0.000001251141f};
const float CieY[CieSamples] = {
    0.000003917000f, 0.000006965000f, 0.000012390000f, 0.000022020000f, 0.000039000000f, 0.000064000000f, 0.000120000000f, 0.000217000000f,
    0.000396000000f, 0.000640000000f, 0.001210000000f, 0.002180000000f, 0.004000000000f, 0.007300000000f, 0.011600000000f, 0.016840000000f,
    0.023000000000f, 0.029800000000f, 0.038000000000f, 0.048000000000f, 0.060000000000f, 0.073900000000f, 0.090980000000f, 0.112600000000f,
    0.139020000000f, 0.169300000000f, 0.208020000000f, 0.258600000000f, 0.323000000000f, 0.407300000000f, 0.503000000000f, 0.608200000000f,
    0.710000000000f, 0.793200000000f, 0.862000000000f, 0.914850100000f, 0.954000000000f, 0.980300000000f, 0.994950100000f, 1.000000000000f,
    0.995000000000f, 0.978600000000f, 0.952000000000f, 0.915400000000f, 0.870000000000f, 0.816300000000f, 0.757000000000f, 0.694900000000f,
    0.631000000000f, 0.566800000000f, 0.503000000000f, 0.441200000000f, 0.381000000000f, 0.321000000000f, 0.265000000000f, 0.217000000000f,
    0.175000000000f, 0.138200000000f, 0.107000000000f, 0.081600000000f, 0.061000000000f, 0.044580000000f, 0.032000000000f, 0.023200000000f,
    0.017000000000f, 0.011920000000f, 0.008210000000f, 0.005723000000f, 0.004102000000f, 0.002929000000f, 0.002091000000f, 0.001484000000f,
    0.001047000000f, 0.000740000000f, 0.000520000000f, 0.000361100000f, 0.000249200000f, 0.000171900000f, 0.000120000000f, 0.000084800000f,
    0.000060000000f, 0.000042400000f, 0.000030000000f, 0.000021200000f, 0.000014990000f, 0.000010600000f, 0.000007465700f, 0.000005257800f,
    0.000003702900f, 0.000002607800f, 0.000001836600f, 0.000001293400f, 0.000000910930f, 0.000000641530f, 0.000000451810f};
const float CieZ[CieSamples] = {0.000606100000f,
                                0.001086000000f,
                                0.001946000000f,
                                0.003486000000f,
                                0.006450001000f,
                                0.010549990000f,
                                0.020050010000f,
                                0.036210000000f,
                                0.067850010000f,
                                0.110200000000f,
                                0.207400000000f,
                                0.371300000000f,
                                0.645600000000f,
                                1.039050100000f,
                                1.385600000000f,
                                1.622960000000f,
                                1.747060000000f,
                                1.782600000000f,
                                1.772110000000f,
                                1.744100000000f,
                                1.669200000000f,
                                1.528100000000f,
                                1.287640000000f,
                                1.041900000000f,
                                0.812950100000f,
                                0.616200000000f,
                                0.465180000000f,
                                0.353300000000f,
                                0.272000000000f,
                                0.212300000000f,
                                0.158200000000f,
                                0.111700000000f,
                                0.078249990000f,
                                0.057250010000f,
                                0.042160000000f,
                                0.029840000000f,
                                0.020300000000f,
                                0.013400000000f,
                                0.008749999000f,
                                0.005749999000f,
                                0.003900000000f,
                                0.002749999000f,
                                0.002100000000f,
                                0.001800000000f,
                                0.001650001000f,
                                0.001400000000f,
                                0.001100000000f,
                                0.001000000000f,
                                0.000800000000f,
                                0.000600000000f,
                                0.000340000000f,
                                0.000240000000f,
                                0.000190000000f,
                                0.000100000000f,
                                0.000049999990f,
                                0.000030000000f,
                                0.000020000000f,
                                0.000010000000f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f,
                                0.0f};

// CIE standard illuminant D65, relative spectral power (100 at 560 nm), 5 nm from 360 to 830 nm:
// measured data of the CIE (CIE 015:2004, table T.1; ISO 11664-2), as tabulated in Mitsuba 3.
const float D65[CieSamples] = {46.6383f, 49.3637f, 52.0891f, 51.0323f, 49.9755f, 52.3118f, 54.6482f, 68.7015f, 82.7549f, 87.1204f, 91.486f,
                               92.4589f, 93.4318f, 90.057f,  86.6823f, 95.7736f, 104.865f, 110.936f, 117.008f, 117.41f,  117.812f, 116.336f,
                               114.861f, 115.392f, 115.923f, 112.367f, 108.811f, 109.082f, 109.354f, 108.578f, 107.802f, 106.296f, 104.79f,
                               106.239f, 107.689f, 106.047f, 104.405f, 104.225f, 104.046f, 102.023f, 100.0f,   98.1671f, 96.3342f, 96.0611f,
                               95.788f,  92.2368f, 88.6856f, 89.3459f, 90.0062f, 89.8026f, 89.5991f, 88.6489f, 87.6987f, 85.4936f, 83.2886f,
                               83.4939f, 83.6992f, 81.863f,  80.0268f, 80.1207f, 80.2146f, 81.2462f, 82.2778f, 80.281f,  78.2842f, 74.0027f,
                               69.7213f, 70.6652f, 71.6091f, 72.979f,  74.349f,  67.9765f, 61.604f,  65.7448f, 69.8856f, 72.4863f, 75.087f,
                               69.3398f, 63.5927f, 55.0054f, 46.4182f, 56.6118f, 66.8054f, 65.0941f, 63.3828f, 63.8434f, 64.304f,  61.8779f,
                               59.4519f, 55.7054f, 51.959f,  54.6998f, 57.4406f, 58.8765f, 60.3125f};

// Linear interpolation in a 5 nm table, as Mitsuba's cie1931_xyz does (zero outside the range).
double lookup(const float* table, double wavelength) {
    if (!(wavelength >= CieMin && wavelength <= CieMax)) return 0.0;
    double t = (wavelength - CieMin) * ((CieSamples - 1) / (CieMax - CieMin));
    int i0 = std::clamp(int(t), 0, CieSamples - 2);
    double w1 = t - i0;
    return (1.0 - w1) * double(table[i0]) + w1 * double(table[i0 + 1]);
}

// Mitsuba's 1000-point rule over [360, 830] nm, restricted to [lo, hi]: sample points
// 360 + i * 470 / 999, each weighted 470 / 1000 (the sum is not quite a Riemann sum; matching it
// keeps Candela's colours equal to Mitsuba's to float precision).
Vec3d integrate_xyz(const std::function<double(double)>& value, bool weight_by_d65, double lo, double hi) {
    const int steps = 1000;
    Vec3d xyz(0.0);
    for (int i = 0; i < steps; ++i) {
        double w = CieMin + (i / double(steps - 1)) * (CieMax - CieMin);
        if (w < lo || w > hi) continue;
        double v = value(w);
        if (weight_by_d65) v *= cie_d65(w);
        xyz += cie1931_xyz(w) * v;
    }
    return xyz * ((CieMax - CieMin) / steps) * CieYNormalization;
}

Spectrum finish(const Vec3d& xyz, bool bounded, bool* clamped) {
    Vec3d rgb = xyz_to_linear_srgb(xyz), out = rgb;
    for (int c = 0; c < 3; ++c) out[c] = bounded ? std::clamp(out[c], 0.0, 1.0) : std::max(out[c], 0.0);
    if (clamped) *clamped = out != rgb;
    return Spectrum(out);
}

// Sample lists are read as doubles; anything else in a token is an error.
double parse_number(const std::string& token, const std::string& what) {
    char* end = nullptr;
    double v = std::strtod(token.c_str(), &end);
    if (token.empty() || end != token.c_str() + token.size() || !std::isfinite(v))
        throw SpectrumFormatError("\"" + token + "\" is not a number (" + what + ")");
    return v;
}

}  // namespace

Vec3d cie1931_xyz(double wavelength) { return Vec3d(lookup(CieX, wavelength), lookup(CieY, wavelength), lookup(CieZ, wavelength)); }

double cie_d65(double wavelength) { return lookup(D65, wavelength) * CieD65Normalization; }

Vec3d xyz_to_linear_srgb(const Vec3d& xyz) {
    // The XYZ to linear Rec. 709 matrix of Mitsuba 3 (float literals, as there).
    const double m[3][3] = {{3.240479f, -1.537150f, -0.498535f}, {-0.969256f, 1.875991f, 0.041556f}, {0.055648f, -0.204043f, 1.057311f}};
    Vec3d out;
    for (int r = 0; r < 3; ++r) out[r] = m[r][0] * xyz.x + m[r][1] * xyz.y + m[r][2] * xyz.z;
    return out;
}

Vec3d linear_srgb_to_xyz(const Vec3d& rgb) {
    // Mitsuba 3's matrix (float literals, as there); its middle row is the luminance of
    // core/spectrum.h.
    const double m[3][3] = {{0.412453f, 0.357580f, 0.180423f}, {0.212671f, 0.715160f, 0.072169f}, {0.019334f, 0.119193f, 0.950227f}};
    Vec3d out;
    for (int r = 0; r < 3; ++r) out[r] = m[r][0] * rgb.x + m[r][1] * rgb.y + m[r][2] * rgb.z;
    return out;
}

void check_spectrum(const SampledSpectrum& s) {
    if (s.wavelengths.size() != s.values.size()) throw SpectrumFormatError("wavelengths and values differ in number");
    if (s.wavelengths.size() < 2) throw SpectrumFormatError("a sampled spectrum needs at least two wavelength:value pairs");
    for (size_t i = 0; i < s.wavelengths.size(); ++i) {
        if (!std::isfinite(s.wavelengths[i]) || !std::isfinite(s.values[i])) throw SpectrumFormatError("non-finite sample");
        // Values become floats where they are used: beyond float's range they would be infinite.
        if (std::fabs(s.values[i]) > double(std::numeric_limits<float>::max()))
            throw SpectrumFormatError("a value beyond the range of a 32-bit float (" + std::to_string(s.values[i]) + ")");
        if (i > 0 && s.wavelengths[i] < s.wavelengths[i - 1])
            throw SpectrumFormatError("wavelengths must increase (" + std::to_string(s.wavelengths[i]) + " nm follows " +
                                      std::to_string(s.wavelengths[i - 1]) + " nm)");
    }
}

SampledSpectrum parse_spectrum_pairs(const std::string& text) {
    SampledSpectrum s;
    for (const std::string& item : split_list(text)) {
        size_t colon = item.find(':');
        if (colon == std::string::npos || item.find(':', colon + 1) != std::string::npos)
            throw SpectrumFormatError("\"" + item + "\" is not a wavelength:value pair");
        s.wavelengths.push_back(parse_number(item.substr(0, colon), "wavelength"));
        s.values.push_back(parse_number(item.substr(colon + 1), "value"));
    }
    check_spectrum(s);
    return s;
}

SampledSpectrum parse_spd(const std::string& text) {
    SampledSpectrum s;
    std::istringstream in(text);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        line = line.substr(0, line.find('#'));
        std::istringstream fields(line);
        std::vector<std::string> tokens;
        for (std::string t; fields >> t;) tokens.push_back(t);
        if (tokens.empty()) continue;
        std::string where = "line " + std::to_string(number);
        if (tokens.size() != 2)
            throw SpectrumFormatError(where + ": expected \"wavelength value\", found " + std::to_string(tokens.size()) + " fields");
        s.wavelengths.push_back(parse_number(tokens[0], where));
        s.values.push_back(parse_number(tokens[1], where));
    }
    check_spectrum(s);
    return s;
}

namespace {
// The sampled spectrum's value at x: the last sample at or below x (Mitsuba's find_interval),
// then linear interpolation.
double interpolate_samples(const std::vector<double>& w, const std::vector<double>& v, double x) {
    size_t i = size_t(std::upper_bound(w.begin(), w.end(), x) - w.begin());
    i = std::clamp<size_t>(i == 0 ? 0 : i - 1, 0, w.size() - 2);
    double w0 = w[i], w1 = w[i + 1];
    if (w1 == w0) return v[i + 1];
    return ((x - w1) * v[i] + (w0 - x) * v[i + 1]) / (w0 - w1);
}
}  // namespace

double SampledSpectrum::at(double wavelength_nm) const {
    if (wavelengths.size() < 2 || !(wavelength_nm >= wavelengths.front() && wavelength_nm <= wavelengths.back())) return 0.0;
    return interpolate_samples(wavelengths, values, wavelength_nm);
}

Spectrum spectrum_to_rgb(const SampledSpectrum& s, bool weight_by_d65, bool bounded, bool* clamped) {
    auto value = [&](double x) { return interpolate_samples(s.wavelengths, s.values, x); };
    return finish(integrate_xyz(value, weight_by_d65, s.wavelengths.front(), s.wavelengths.back()), bounded, clamped);
}

std::vector<Vec3d> spectrum_to_rgb_weights(const std::vector<double>& wavelengths, bool weight_by_d65) {
    check_spectrum(SampledSpectrum{wavelengths, std::vector<double>(wavelengths.size(), 0.0)});
    std::vector<Vec3d> weights(wavelengths.size());
    std::vector<double> basis(wavelengths.size(), 0.0);
    for (size_t j = 0; j < wavelengths.size(); ++j) {
        // The conversion is linear in the sample values: sample j's weight is the colour of the
        // spectrum that is 1 at sample j and 0 at the others, before any clamping.
        basis[j] = 1.0;
        auto value = [&](double x) { return interpolate_samples(wavelengths, basis, x); };
        weights[j] = xyz_to_linear_srgb(integrate_xyz(value, weight_by_d65, wavelengths.front(), wavelengths.back()));
        basis[j] = 0.0;
    }
    return weights;
}

Spectrum uniform_emission_rgb(double value) { return Spectrum(xyz_to_linear_srgb(Vec3d(1.0)) * value); }

double blackbody_radiance(double wavelength_nm, double temperature) {
    const double c = 2.99792458e+8, h = 6.62607004e-34, k = 1.38064852e-23;  // as in Mitsuba's blackbody
    const double c0 = 2 * h * c * c, c1 = h * c / k;
    double lambda = wavelength_nm * 1e-9;
    // W m^-2 sr^-1 per metre of wavelength, times 1e-9 for per nanometre.
    return 1e-9 * c0 / (std::pow(lambda, 5.0) * (std::exp(c1 / (lambda * temperature)) - 1.0));
}

SampledSpectrum blackbody_samples(double temperature, double lambda_min, double lambda_max, double scale) {
    SampledSpectrum s;
    int steps = std::max(1, int(std::ceil(lambda_max - lambda_min)));
    for (int i = 0; i <= steps; ++i) {
        double w = lambda_min + (lambda_max - lambda_min) * i / steps;
        s.wavelengths.push_back(w);
        s.values.push_back(scale * blackbody_radiance(w, temperature));
    }
    return s;
}

Spectrum blackbody_rgb(double temperature, double lambda_min, double lambda_max) {
    auto value = [&](double w) { return blackbody_radiance(w, temperature); };
    return finish(integrate_xyz(value, false, lambda_min, lambda_max), false, nullptr);
}

}  // namespace candela
