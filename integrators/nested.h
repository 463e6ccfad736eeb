#pragma once
// Sampling integrators nested in another (aov, moment, as Mitsuba nests them): each sample of
// the outer integrator samples every nested one along the same camera ray, with the same
// sampler, one after the other.

#include "core/integrator.h"

#include <string>
#include <vector>

namespace candela {

class Properties;

struct NestedIntegrator {
    std::string name;  // its name attribute (the prefix of its channels), or the loader's _argN
    Ref<SamplingIntegrator> integrator;
    std::vector<std::string> channels;  // its own channel_names()
};

// The integrators nested in `props`, in document order; an integrator that is not a sampling
// integrator (raster) is an error at the outer integrator's line.
std::vector<NestedIntegrator> read_nested_integrators(const Properties& props);

// Samples `nested` along `ray` with the camera data of `outer` (film position, aperture,
// differential scale, and its --aov first-hit layers when `with_first_hit`); `record` receives
// its valid flag and channels.
Spectrum sample_nested(const NestedIntegrator& nested, const Scene& scene, Sampler& sampler, const Ray& ray, const SampleRecord& outer,
                       SampleRecord& record, bool with_first_hit = false);

}  // namespace candela
