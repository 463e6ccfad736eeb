#pragma once
// Spectral data turned into linear sRGB (Rec. 709) as Mitsuba 3's RGB variants turn it: spectra
// given as wavelength samples (nm, linearly interpolated), read from .spd files or written as
// "wavelength:value" pairs, and Planck's black body. The CIE 1931 2-degree colour matching
// functions and the CIE D65 illuminant are tabulated in spectral.cpp (5 nm, 360-830 nm).

#include "core/spectrum.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace candela {

// Mitsuba's integration range and its normalisations (include/mitsuba/core/spectrum.h): a flat
// spectrum of value 1 has luminance Y = 1 after CIE_Y_NORMALIZATION, and D65 scaled by
// CIE_D65_NORMALIZATION has the luminance of that flat spectrum.
constexpr double CieMin = 360.0, CieMax = 830.0;
constexpr double CieYNormalization = 1.0 / 106.7502593994140625;
constexpr double CieD65Normalization = 1.0 / 98.99741751876255;

struct SampledSpectrum {
    std::vector<double> wavelengths;  // nm, non-decreasing
    std::vector<double> values;
    // Linearly interpolated between samples, zero outside the sampled range (Mitsuba's
    // irregular and regular spectra).
    double at(double wavelength_nm) const;
};

// What a spectrum or colour stands for where the scene uses it: the same spectrum means a
// different colour as a reflectance, as an index of refraction and as an emission, and an RGB
// colour becomes a different spectrum in the spectral variant (core/wavelengths.h).
enum class SpectrumRole {
    Reflectance,  // weighted by D65, clamped to [0, 1]: a flat spectrum is grey
    Unbounded,    // eta, k, int_ior, ext_ior, sigma_t: weighted by D65, only negatives clamped
    Emission,     // directly inside an <emitter>: not weighted, negatives clamped
    Response,     // a sensor's `srf` and a specfilm's bands (directly inside a <film>): a sensor's
                  // response, used only as its samples (spectral variants); it has no colour
};

// A malformed spectrum (the loader adds the file and line of the element).
struct SpectrumFormatError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// "400:0.1, 500:0.2 ..." (commas and/or spaces between pairs).
SampledSpectrum parse_spectrum_pairs(const std::string& text);
// An .spd file's text: one "wavelength value" pair per line, '#' starts a comment.
SampledSpectrum parse_spd(const std::string& text);
// Checks the sample lists (equal sizes, at least two samples, finite, wavelengths non-decreasing).
void check_spectrum(const SampledSpectrum& s);

// The colour of a sampled spectrum: XYZ = CIE_Y_NORMALIZATION * integral of cmf(l) * s(l)
// (* D65(l) normalised, when `weight_by_d65`), as a 1000-point sum over [360, 830] nm
// (Mitsuba's spectrum_list_to_srgb), then linear sRGB. Bounded colours are clamped to [0, 1],
// others only to >= 0; `clamped` reports whether clamping changed anything.
//   reflectance:                       weight_by_d65 = true,  bounded = true  (a flat spectrum is grey)
//   eta, k, int_ior, ext_ior, sigma_t spectra:  weight_by_d65 = true,  bounded = false
//   emission, and named-conductor data: weight_by_d65 = false, bounded = false
Spectrum spectrum_to_rgb(const SampledSpectrum& s, bool weight_by_d65, bool bounded, bool* clamped = nullptr);

// The same conversion as a linear map, before clamping: the linear sRGB of sample values v_j at
// `wavelengths` is sum_j weights[j] * v_j. For tabulated spectra converted many times (the
// measured BSDF's). Throws SpectrumFormatError for wavelengths check_spectrum refuses.
std::vector<Vec3d> spectrum_to_rgb_weights(const std::vector<double>& wavelengths, bool weight_by_d65);

// A single-valued spectrum in an emitter: the equal-energy white, v * xyz_to_srgb(1, 1, 1),
// slightly pink against sRGB's D65 white point (Mitsuba does this so that RGB and spectral
// variants agree). A single value anywhere else is simply grey.
Spectrum uniform_emission_rgb(double value);

// Planck's law in W m^-2 sr^-1 nm^-1 (wavelength in nm, temperature in K), with the constants of
// Mitsuba's blackbody plugin.
double blackbody_radiance(double wavelength_nm, double temperature);
// The emitted colour of a black body restricted to [lambda_min, lambda_max] nm: the emission
// conversion above applied to Planck's law, i.e. what Mitsuba's spectral variants render.
Spectrum blackbody_rgb(double temperature, double lambda_min = CieMin, double lambda_max = CieMax);

// Planck's law times `scale` sampled every nanometre over [lambda_min, lambda_max]: what the
// spectral variant interpolates per wavelength.
SampledSpectrum blackbody_samples(double temperature, double lambda_min, double lambda_max, double scale = 1.0);

// The tabulated functions, linearly interpolated as Mitsuba does (zero outside 360-830 nm).
Vec3d cie1931_xyz(double wavelength_nm);
double cie_d65(double wavelength_nm);  // times CIE_D65_NORMALIZATION
Vec3d xyz_to_linear_srgb(const Vec3d& xyz);
// Its inverse, Mitsuba's srgb_to_xyz (Rec. 709 primaries, D65 white): the film's xyz and
// luminance pixel formats and the moment integrator use it.
Vec3d linear_srgb_to_xyz(const Vec3d& rgb);

}  // namespace candela
