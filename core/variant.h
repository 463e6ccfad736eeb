#pragma once
// Rendering variants, by Mitsuba 3's names: what one radiance value carries along a path.
//   scalar_rgb                 linear Rec. 709 RGB (the default)
//   scalar_spectral            values at WavelengthSamples wavelengths per path (core/wavelengths.h)
//   scalar_spectral_polarized  Stokes vectors per wavelength: not implemented yet; asking for it
//                              is an input error that says so

#include <optional>
#include <string>

namespace candela {

enum class Variant { ScalarRGB, ScalarSpectral, ScalarSpectralPolarized };

// The variant of a Mitsuba name, or nullopt for a name that is none.
std::optional<Variant> parse_variant(const std::string& name);
const char* variant_name(Variant v);
// The names parse_variant knows, for messages and --help.
const char* variant_names();

}  // namespace candela
