#pragma once
// Named indices of refraction (Mitsuba 3's table) and the complex indices of Mitsuba 3's named
// conductors (measured spectra in materials/data/ior, turned into RGB as Mitsuba 3 does).

#include "core/properties.h"
#include "core/spectral.h"
#include "core/texture.h"

#include <optional>
#include <string>
#include <vector>

namespace candela {

// Index of refraction of a named dielectric ("bk7", "water", "air", ...), case-insensitive; a
// named glass (below) gives its index at 589.3 nm, the wavelength of Mitsuba's table.
std::optional<float> named_ior(const std::string& name);

// A glass whose index follows Sellmeier's equation, n^2(l) = 1 + sum_i B_i l^2 / (l^2 - C_i) with
// l in micrometres: the catalogue coefficients of Schott N-BK7, N-BAF10, F2 and SF11 and of fused
// silica (Malitson 1965), the set pbrt-v4 names. Not in Mitsuba 3, whose named indices are
// constants: these names start with "glass-" (glass-BK7, glass-BAF10, glass-F2, glass-SF11,
// glass-fused-silica) so that Mitsuba's "bk7" keeps its constant 1.5046.
struct SellmeierGlass {
    const char* name;
    double B[3], C[3];  // C in square micrometres
    double ior(double lambda_nm) const;
};
const SellmeierGlass* named_glass(const std::string& name);

// A dielectric's index of refraction in either variant: a number or a name (constant), a named
// glass, or, in the spectral variant, a <spectrum> of indices per wavelength. Dispersive ones
// vary with the wavelength; `value` is the index at 589.3 nm (what the RGB variant uses).
struct SpectralIOR {
    float value = 1.0f;
    const SellmeierGlass* glass = nullptr;
    std::shared_ptr<const SpectrumTexture> samples;
    bool dispersive() const { return glass || samples; }
    float at(float lambda_nm) const;
};
SpectralIOR read_spectral_ior(const Properties& props, const std::string& param, const std::string& default_name);
// Reads an IOR parameter given as a number or a name; `default_name` when absent.
float read_ior(const Properties& props, const std::string& param, const std::string& default_name);
// The relative index eta = int_ior / ext_ior of a dielectric interface (ext_ior defaults to air);
// equal indices are an error (no interface).
float read_relative_ior(const Properties& props, const std::string& default_interior);

struct ComplexIOR {
    Spectrum eta, k;
    // The measured spectra the colours came from (empty for "none"), for the spectral variant.
    SampledSpectrum eta_spectrum, k_spectrum;
};
// Reads a conductor's eta and k (rgb or textures) or its `material` name (default "none", a
// perfect mirror); giving both is an error.
void read_conductor_ior(const Properties& props, Ref<Texture>& eta, Ref<Texture>& k);

// Complex index of refraction of a named conductor (every material of Mitsuba 3's conductor
// table: Au, Ag, Cu, Al, Cr, Cu_palik, TiN, ..., matched ignoring case), or "none" (a perfect
// mirror: eta 0, k 1). As Mitsuba 3's complex_ior_from_file: the measured eta and k spectra are
// integrated against the CIE 1931 curves without an illuminant (spectrum_to_rgb with
// weight_by_d65 = false, unbounded).
std::optional<ComplexIOR> named_conductor(const std::string& name);
// The names named_conductor knows, "none" included, sorted.
std::vector<std::string> named_conductors();

}  // namespace candela
