#pragma once
// How the scene loader turns <spectrum> elements into colours, as Mitsuba 3's RGB variants do
// (src/core/properties.cpp, get_texture_impl): the same spectrum means a different colour as a
// reflectance, as an index of refraction and as an emission. Used by core/xml.cpp only.

#include "core/properties.h"
#include "core/spectral.h"

#include <string>

namespace candela {

// The role of a spectrum property called `name` directly inside an element `parent_tag`: an
// emitter's own properties are emissions, a film's (specfilm's bands) responses.
SpectrumRole spectrum_role(const std::string& parent_tag, const std::string& name);

// A single value: grey, except in an emitter (uniform_emission_rgb).
Spectrum uniform_spectrum_rgb(double value, SpectrumRole role);
// Sampled data; a colour clamped into gamut is reported as a warning at `where`, as Mitsuba does.
Spectrum sampled_spectrum_rgb(const SampledSpectrum& s, SpectrumRole role, const SourceLocation& where);

// <spectrum type="..."> (uniform, srgb, d65, regular, irregular, blackbody) with its children
// read into `props`: the colour it stands for. A d65 spectrum around a nested texture stands for
// that texture: `texture` is set and the colour is meaningless. Unknown types and bad parameters
// are SceneErrors at the element.
// `measured` receives the spectrum itself for regular, irregular and blackbody spectra.
Spectrum spectrum_plugin_rgb(const Properties& props, SpectrumRole role, Ref<Object>* texture, SampledSpectrum* measured);

}  // namespace candela
