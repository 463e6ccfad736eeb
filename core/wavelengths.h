#pragma once
// The spectral variant's wavelengths and the conversions at both ends of a path (Mitsuba 3's
// scalar_spectral; pbrt-v4's SampledWavelengths): each camera sample draws WavelengthSamples
// wavelengths, one per component of a Spectrum, and every value along its path is the value at
// those wavelengths; the pixel loop turns the result into linear sRGB through the CIE 1931
// matching functions before the film sees it, so films, AOVs, farm parts and files stay RGB.
// The one exception is a specfilm (core/film.h, FilmBands): its channels are spectral bands,
// each the integral of its response times the radiance, and its wavelengths follow the responses.

#include "core/distribution.h"
#include "core/rgb2spec.h"
#include "core/spectral.h"
#include "core/spectrum.h"

namespace candela {

constexpr int WavelengthSamples = 3;  // one per Spectrum component

struct StokesSpectrum;

struct Wavelengths {
    Vec3 lambda{550.0f};  // nm
    Vec3 pdf{1.0f};       // per nm, of each wavelength as drawn; 0 for a terminated one
    Vec3 d65{1.0f};       // CIE D65 at each wavelength (normalised as cie_d65): what emission multiplies
    // The polarized variant: where the sample's Stokes vector sums (core/mueller.h), in the
    // implicit basis of light arriving along -ray.d; null in the other variants.
    StokesSpectrum* stokes = nullptr;

    // These wavelengths with the visible density's pdf and D65 filled in.
    static Wavelengths at(const Vec3& lambda_nm);

    // At a dispersive interface only the first (hero) wavelength goes on: the others' pdf becomes
    // 0 and the hero's is divided by WavelengthSamples, so that the pixel's average over the
    // samples still estimates the colour (pbrt-v4, SampledWavelengths::TerminateSecondary).
    void terminate_secondary();
    bool secondary_terminated() const { return pdf.y == 0.0f && pdf.z == 0.0f; }
};

// Mitsuba's and pbrt-v4's visible-wavelength density over [360, 830] nm,
// p(l) = 0.003939804229326285 / cosh^2(0.0072 (l - 538)), which follows the sum of the CIE
// matching functions closely and so spreads colour noise evenly; zero outside the range.
float visible_wavelength_pdf(float lambda_nm);
// WavelengthSamples wavelengths from one uniform number: u + j / WavelengthSamples (mod 1), each
// by inverting p's distribution (a stratified set, as Mitsuba's sample_shifted).
Wavelengths sample_visible_wavelengths(float u);

// A sensor's spectral response (Mitsuba's `srf` on a sensor, spectral variant): wavelengths are
// drawn in proportion to it (piecewise constant over 1 nm bins of its samples within 360-830 nm,
// with the same 1/3 shifts as the visible density), and each sample's values are weighted by it,
// so that the image is CIE_Y_NORMALIZATION * integral of srf(l) L(l) cmf(l) dl in XYZ.
class SensorResponse {
public:
    // Throws SpectrumFormatError for a response that is not positive somewhere in 360-830 nm.
    explicit SensorResponse(SampledSpectrum srf);
    Wavelengths sample(float u) const;
    // The response at the wavelengths: what a sample's values are multiplied by.
    Spectrum at(const Wavelengths& w) const;

private:
    SampledSpectrum srf_;
    double lo_ = CieMin, hi_ = CieMax;
    Distribution1D bins_;
};

// A camera sample's wavelengths, from the sampler's own dimension for them
// (SampleDimensions::Wavelength): from the visible density, or from the sensor's response when
// it has one. The sampler is left at the first bounce's dimensions, where a path continues.
class Sampler;
Wavelengths draw_wavelengths(Sampler& sampler, const SensorResponse* response = nullptr);

// A path's values at the wavelengths as linear sRGB: the Monte Carlo estimate of
// CIE_Y_NORMALIZATION * integral of cmf(l) L(l) dl, averaged over the wavelengths (each divided
// by its pdf), through Mitsuba's XYZ to sRGB matrix.
Spectrum spectral_to_linear_srgb(const Spectrum& values, const Wavelengths& w);

// The spectrum an RGB input stands for, as Mitsuba's spectral variants make it (Jakob and Hanika
// 2019, core/rgb2spec.h):
//   Reflectance  the smooth spectrum in [0, 1] whose colour under D65 is rgb (clamped to [0, 1])
//   Unbounded    2 max(rgb) times the reflectance spectrum of rgb / (2 max(rgb))
//   Emission     the unbounded spectrum times D65 (normalised to luminance 1): white rgb
//                emits D65, sRGB's white
struct RGBSpectrum {
    SigmoidPolynomial shape;
    float scale = 1.0f;
    bool times_d65 = false;
    RGBSpectrum() = default;
    RGBSpectrum(const Spectrum& rgb, SpectrumRole role);
    Spectrum at(const Wavelengths& w) const;
};
// The same at the wavelengths `w`; with none (the RGB variant) rgb itself.
Spectrum rgb_at_wavelengths(const Spectrum& rgb, SpectrumRole role, const Wavelengths* w);

}  // namespace candela
