#include "core/wavelengths.h"

#include "core/sampler.h"

#include "core/variant.h"

#include <algorithm>
#include <cmath>

namespace candela {

std::optional<Variant> parse_variant(const std::string& name) {
    if (name == "scalar_rgb") return Variant::ScalarRGB;
    if (name == "scalar_spectral") return Variant::ScalarSpectral;
    if (name == "scalar_spectral_polarized") return Variant::ScalarSpectralPolarized;
    return std::nullopt;
}

const char* variant_name(Variant v) {
    switch (v) {
        case Variant::ScalarRGB: return "scalar_rgb";
        case Variant::ScalarSpectral: return "scalar_spectral";
        case Variant::ScalarSpectralPolarized: return "scalar_spectral_polarized";
    }
    return "scalar_rgb";
}

const char* variant_names() { return "scalar_rgb, scalar_spectral, scalar_spectral_polarized"; }

void Wavelengths::terminate_secondary() {
    if (secondary_terminated()) return;
    pdf = Vec3(pdf.x / float(WavelengthSamples), 0.0f, 0.0f);
}

namespace {
// The density's constants for [360, 830] nm: p(l) = Norm / cosh^2(A (l - Center)); its
// cumulative distribution is (tanh(A (l - Center)) - TanhLow) / (TanhHigh - TanhLow).
constexpr double A = 0.0072, Center = 538.0, Norm = 0.003939804229326285;
const double TanhLow = std::tanh(A * (CieMin - Center)), TanhHigh = std::tanh(A * (CieMax - Center));
}  // namespace

float visible_wavelength_pdf(float lambda_nm) {
    if (!(lambda_nm >= float(CieMin) && lambda_nm <= float(CieMax))) return 0.0f;
    const float c = std::cosh(float(A) * (lambda_nm - float(Center)));
    return float(Norm) / (c * c);
}

Wavelengths Wavelengths::at(const Vec3& lambda_nm) {
    Wavelengths w;
    w.lambda = lambda_nm;
    for (int j = 0; j < WavelengthSamples; ++j) {
        w.pdf[j] = visible_wavelength_pdf(w.lambda[j]);
        w.d65[j] = float(cie_d65(w.lambda[j]));
    }
    return w;
}

Wavelengths sample_visible_wavelengths(float u) {
    // Float arithmetic suffices: a wavelength rounded to float (about 3e-5 nm) is far finer than
    // the 5 nm steps of the tables it is looked up in.
    Vec3 lambda;
    for (int j = 0; j < WavelengthSamples; ++j) {
        float uj = u + float(j) / WavelengthSamples;
        if (uj >= 1.0f) uj -= 1.0f;
        const float l = float(Center) + std::atanh(float(TanhLow) + float(TanhHigh - TanhLow) * uj) / float(A);
        lambda[j] = std::clamp(l, float(CieMin), float(CieMax));
    }
    return Wavelengths::at(lambda);
}

Wavelengths draw_wavelengths(Sampler& sampler, const SensorResponse* response) {
    sampler.set_dimension(SampleDimensions::Wavelength);
    const float u = sampler.next_1d();
    sampler.set_dimension(SampleDimensions::FirstBounce);
    return response ? response->sample(u) : sample_visible_wavelengths(u);
}

SensorResponse::SensorResponse(SampledSpectrum srf) : srf_(std::move(srf)) {
    check_spectrum(srf_);
    lo_ = std::max(CieMin, srf_.wavelengths.front());
    hi_ = std::min(CieMax, srf_.wavelengths.back());
    if (!(hi_ > lo_)) throw SpectrumFormatError("the sensor response lies outside 360-830 nm");
    const int bins = std::max(1, int(std::ceil(hi_ - lo_)));
    std::vector<float> weights(size_t(bins), 0.0f);
    for (int i = 0; i < bins; ++i) {
        // The bin's mean response (from its ends and middle, Simpson's rule).
        const double a = lo_ + (hi_ - lo_) * i / bins, b = lo_ + (hi_ - lo_) * (i + 1) / bins;
        const double mean = (srf_.at(a) + 4.0 * srf_.at(0.5 * (a + b)) + srf_.at(b)) / 6.0;
        if (mean < 0.0) throw SpectrumFormatError("the sensor response must not be negative");
        weights[size_t(i)] = float(mean);
    }
    bins_ = Distribution1D(std::move(weights));
    if (!(bins_.total() > 0.0f)) throw SpectrumFormatError("the sensor response is zero over 360-830 nm");
}

Wavelengths SensorResponse::sample(float u) const {
    Vec3 lambda, pdf;
    for (int j = 0; j < WavelengthSamples; ++j) {
        float uj = u + float(j) / WavelengthSamples;
        if (uj >= 1.0f) uj -= 1.0f;
        float pdf_unit = 0.0f;
        const float x = bins_.sample_continuous(uj, &pdf_unit);
        lambda[j] = float(lo_ + (hi_ - lo_) * double(x));
        pdf[j] = float(double(pdf_unit) / (hi_ - lo_));
    }
    Wavelengths w = Wavelengths::at(lambda);
    w.pdf = pdf;
    return w;
}

Spectrum SensorResponse::at(const Wavelengths& w) const {
    Spectrum out;
    for (int j = 0; j < WavelengthSamples; ++j) out[j] = float(srf_.at(w.lambda[j]));
    return out;
}

Spectrum spectral_to_linear_srgb(const Spectrum& values, const Wavelengths& w) {
    Vec3d xyz(0.0);
    for (int j = 0; j < WavelengthSamples; ++j)
        if (w.pdf[j] > 0.0f) xyz += cie1931_xyz(w.lambda[j]) * (double(values[j]) / double(w.pdf[j]));
    xyz *= CieYNormalization / WavelengthSamples;
    return Spectrum(xyz_to_linear_srgb(xyz));
}

RGBSpectrum::RGBSpectrum(const Spectrum& rgb, SpectrumRole role) {
    if (role == SpectrumRole::Reflectance) {
        shape = rgb_to_reflectance_spectrum(glm::clamp(rgb, Spectrum(0.0f), Spectrum(1.0f)));
        return;
    }
    times_d65 = role == SpectrumRole::Emission;
    const float m = std::max(max_component(rgb), 0.0f);
    if (!(m > 0.0f)) {
        scale = 0.0f;
        return;
    }
    scale = 2.0f * m;
    shape = rgb_to_reflectance_spectrum(glm::max(rgb, Spectrum(0.0f)) / scale);
}

Spectrum RGBSpectrum::at(const Wavelengths& w) const {
    Spectrum out;
    for (int j = 0; j < WavelengthSamples; ++j) {
        out[j] = scale * shape(w.lambda[j]);
        if (times_d65) out[j] *= w.d65[j];
    }
    return out;
}

Spectrum rgb_at_wavelengths(const Spectrum& rgb, SpectrumRole role, const Wavelengths* w) {
    return w ? RGBSpectrum(rgb, role).at(*w) : rgb;
}

}  // namespace candela
