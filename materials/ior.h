#pragma once
// Named indices of refraction (Mitsuba 3's table) and the complex indices of Mitsuba 3's named
// conductors (measured spectra in materials/data/ior, turned into RGB as Mitsuba 3 does).

#include "core/properties.h"
#include "core/texture.h"

#include <optional>
#include <string>
#include <vector>

namespace candela {

// Index of refraction of a named dielectric ("bk7", "water", "air", ...), case-insensitive.
std::optional<float> named_ior(const std::string& name);
// Reads an IOR parameter given as a number or a name; `default_name` when absent.
float read_ior(const Properties& props, const std::string& param, const std::string& default_name);
// The relative index eta = int_ior / ext_ior of a dielectric interface (ext_ior defaults to air);
// equal indices are an error (no interface).
float read_relative_ior(const Properties& props, const std::string& default_interior);

struct ComplexIOR {
    Spectrum eta, k;
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
