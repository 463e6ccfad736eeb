#pragma once
// Named indices of refraction (Mitsuba 3's table) and complex indices of common metals.

#include "core/properties.h"
#include "core/texture.h"

#include <optional>
#include <string>

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

// Complex index of refraction of a named conductor: Au, Ag, Cu, Al, Cr, or "none" (a perfect
// mirror: eta 0, k 1).
std::optional<ComplexIOR> named_conductor(const std::string& name);

}  // namespace candela
