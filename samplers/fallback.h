#pragma once
// FALLBACK: Mitsuba 3's stratified, multijitter, orthogonal and ldsampler plugins are read with
// all their parameters, but render with the independent sampler until the performance work
// implements them. The expected image is the same (every sampler is unbiased); only the noise
// differs. Each prints one warning. The sample count is rounded as Mitsuba rounds it, so a scene
// takes as many samples per pixel as it would in Mitsuba.

#include "samplers/independent.h"

#include <string>

namespace candela {

class FallbackSampler : public IndependentSampler {
protected:
    // Reads sample_count and seed, rounds the count with `round`, and warns once.
    FallbackSampler(const Properties& props, int (*round)(int requested));
};

}  // namespace candela
