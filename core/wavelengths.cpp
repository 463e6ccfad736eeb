#include "core/wavelengths.h"

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
    double c = std::cosh(A * (double(lambda_nm) - Center));
    return float(Norm / (c * c));
}

Wavelengths sample_visible_wavelengths(float u) {
    Wavelengths w;
    for (int j = 0; j < WavelengthSamples; ++j) {
        double uj = double(u) + double(j) / WavelengthSamples;
        if (uj >= 1.0) uj -= 1.0;
        double lambda = Center + std::atanh(TanhLow + (TanhHigh - TanhLow) * uj) / A;
        w.lambda[j] = float(std::clamp(lambda, CieMin, CieMax));
        w.pdf[j] = visible_wavelength_pdf(w.lambda[j]);
    }
    return w;
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
        if (times_d65) out[j] *= float(cie_d65(w.lambda[j]));
    }
    return out;
}

Spectrum rgb_at_wavelengths(const Spectrum& rgb, SpectrumRole role, const Wavelengths* w) {
    return w ? RGBSpectrum(rgb, role).at(*w) : rgb;
}

}  // namespace candela
