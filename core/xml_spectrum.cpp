// The spectrum plugins of Mitsuba 3 as the loader reads them, each reduced to the colour it has in
// an RGB variant:
//   uniform    value (float, 1)                          grey
//   srgb       color (rgb, required), unbounded (false)  the colour; outside [0, 1] only if unbounded
//   d65        scale (float, 1), color (rgb), or one nested texture
//                                                        color * scale, or scale (white), or the texture
//   regular    wavelength_min, wavelength_max (nm), values (string of numbers, equally spaced)
//   irregular  wavelengths, values (strings of numbers)   converted like wavelength:value pairs
//   blackbody  temperature (K, required), lambda_min, lambda_max (nm, 360 and 830)
//                                                        Planck's law, W m^-2 sr^-1 nm^-1
// Mitsuba's RGB variants cannot evaluate regular, irregular or blackbody plugins; Candela gives
// them the colour that the pairs conversion (or Mitsuba's spectral variants) would give.

#include "core/xml_spectrum.h"

#include "core/registry.h"
#include "core/text.h"
#include "core/texture.h"
#include "core/warning.h"

#include <cstdio>

namespace candela {

SpectrumRole spectrum_role(const std::string& parent_tag, const std::string& name) {
    if (parent_tag == "emitter") return SpectrumRole::Emission;
    if (parent_tag == "film") return SpectrumRole::Response;
    // Mitsuba 3's unbounded spectra (xml.cpp, is_unbounded_spectrum), sigma_t among them.
    if (name == "eta" || name == "k" || name == "int_ior" || name == "ext_ior" || name == "sigma_t") return SpectrumRole::Unbounded;
    if (name == "srf") return SpectrumRole::Response;  // a sensor's response, as a specfilm's bands
    return SpectrumRole::Reflectance;
}

Spectrum uniform_spectrum_rgb(double value, SpectrumRole role) {
    return role == SpectrumRole::Emission ? uniform_emission_rgb(value) : Spectrum(float(value));
}

Spectrum sampled_spectrum_rgb(const SampledSpectrum& s, SpectrumRole role, const SourceLocation& where) {
    if (role == SpectrumRole::Response) return Spectrum(0.0f);
    bool clamped = false;
    Spectrum rgb = spectrum_to_rgb(s, role != SpectrumRole::Emission, role == SpectrumRole::Reflectance, &clamped);
    if (clamped) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "spectrum lies outside the sRGB gamut%s; clamped to (%g, %g, %g)",
                      role == SpectrumRole::Reflectance ? " of reflectances [0, 1]" : "", rgb.x, rgb.y, rgb.z);
        warn(where, buf);
    }
    return rgb;
}

namespace {

std::vector<double> parse_numbers(const Properties& props, const std::string& name) {
    std::vector<double> out;
    for (const std::string& item : split_list(props.get_string(name))) {
        char* end = nullptr;
        double v = std::strtod(item.c_str(), &end);
        if (end != item.c_str() + item.size() || !std::isfinite(v)) props.fail(name, "\"" + item + "\" is not a number");
        out.push_back(v);
    }
    return out;
}

SampledSpectrum regular_samples(const Properties& props) {
    float lo = props.get_float("wavelength_min"), hi = props.get_float("wavelength_max");
    std::vector<double> values = parse_numbers(props, "values");
    if (values.size() < 2) props.fail("values", "a regular spectrum needs at least two values");
    if (!(hi > lo)) props.fail("wavelength_max", "wavelength_max must exceed wavelength_min");
    SampledSpectrum s;
    for (size_t i = 0; i < values.size(); ++i) s.wavelengths.push_back(lo + (hi - lo) * double(i) / double(values.size() - 1));
    s.values = values;
    return s;
}

Spectrum checked(const Properties& props, const SampledSpectrum& s, SpectrumRole role) {
    try {
        check_spectrum(s);
    } catch (const SpectrumFormatError& e) {
        props.fail(e.what());
    }
    return sampled_spectrum_rgb(s, role, props.location());
}

}  // namespace

Spectrum spectrum_plugin_rgb(const Properties& props, SpectrumRole role, Ref<Object>* texture, SampledSpectrum* measured) {
    const std::string& type = props.plugin_type();
    if (type == "uniform") {
        const float value = props.get_float("value", 1.0f);
        // In an emitter the spectral variant emits it flat (equal energy), as Mitsuba's does; in
        // a film it is a flat response.
        if (role == SpectrumRole::Emission || role == SpectrumRole::Response) *measured = SampledSpectrum{{CieMin, CieMax}, {value, value}};
        return Spectrum(value);
    }
    if (type == "srgb") {
        Spectrum color = props.get_rgb("color");
        bool unbounded = props.get_bool("unbounded", false);
        if (!unbounded && (min_component(color) < 0.0f || max_component(color) > 1.0f))
            props.fail("color", "srgb colour outside [0, 1] (add <boolean name=\"unbounded\" value=\"true\"/> for emission or IOR values)");
        return color;
    }
    if (type == "d65") {
        // In RGB variants D65 is the white point: the spectrum is its colour (or a nested texture).
        float scale = props.get_float("scale", 1.0f);
        auto nested = props.get_objects(ObjectKind::Texture);
        if (nested.size() > 1) props.fail("d65 takes at most one nested texture");
        if (!nested.empty() && props.has("color")) props.fail("color", "give d65 either a color or a nested texture, not both");
        if (!nested.empty()) {
            if (scale != 1.0f) props.fail("scale", "d65 with a nested texture takes no scale in RGB rendering");
            *texture = nested[0];
            return Spectrum(0.0f);
        }
        return props.get_rgb("color", Spectrum(1.0f)) * scale;
    }
    if (type == "regular") {
        *measured = regular_samples(props);
        return checked(props, *measured, role);
    }
    if (type == "irregular") {
        *measured = SampledSpectrum{parse_numbers(props, "wavelengths"), parse_numbers(props, "values")};
        return checked(props, *measured, role);
    }
    if (type == "blackbody") {
        float temperature = props.get_float("temperature");
        float lo = props.get_float("lambda_min", float(CieMin)), hi = props.get_float("lambda_max", float(CieMax));
        if (!(temperature > 0.0f)) props.fail("temperature", "the temperature must be positive (in kelvin)");
        if (!(hi > lo)) props.fail("lambda_max", "lambda_max must exceed lambda_min");
        *measured = blackbody_samples(temperature, lo, hi);
        return blackbody_rgb(temperature, lo, hi);
    }
    std::vector<std::string> known = {"blackbody", "d65", "irregular", "regular", "srgb", "uniform"};
    props.fail("unknown spectrum type \"" + type + "\" (nearest supported: \"" + nearest_name(type, known) +
               "\") (known: blackbody, d65, irregular, regular, srgb, uniform)");
}

}  // namespace candela
