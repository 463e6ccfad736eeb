#pragma once
// Colour: linear Rec.709 RGB in float, as Mitsuba 3's rgb variants use it.

#include "core/math.h"

namespace candela {

using Spectrum = glm::vec3;

// Rec.709 / sRGB luminance weights.
inline float luminance(const Spectrum& s) { return 0.212671f * s.x + 0.715160f * s.y + 0.072169f * s.z; }
inline float average(const Spectrum& s) { return (s.x + s.y + s.z) * (1.0f / 3.0f); }
inline bool is_black(const Spectrum& s) { return s.x == 0.0f && s.y == 0.0f && s.z == 0.0f; }

// The sRGB transfer function (IEC 61966-2-1) and its inverse, per channel.
inline float srgb_to_linear(float v) { return v <= 0.04045f ? v * (1.0f / 12.92f) : std::pow((v + 0.055f) * (1.0f / 1.055f), 2.4f); }
inline float linear_to_srgb(float v) { return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f; }

}  // namespace candela
