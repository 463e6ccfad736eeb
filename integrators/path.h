#pragma once
// The path tracer (see path.cpp for its parameters). Exposed so that the irradiance integrator,
// the estimators and the light-path integrators' direct light reuse its light transport from any
// surface vertex.

#include "core/integrator.h"
#include "core/sampler.h"
#include "integrators/path_settings.h"
#include "lights/light_sampler.h"

#include <memory>

namespace candela {

class BSDF;
class Properties;

class PathIntegrator : public SamplingIntegrator {
public:
    explicit PathIntegrator(const Properties& props);
    // InputError naming the parameter when the settings are invalid.
    explicit PathIntegrator(const PathSettings& settings);

    void prepare(const Scene& scene) override;
    // A sample is valid (the film's alpha) when it scatters at a surface, or when the environment
    // is visible (there is one and hide_emitters is off), as in Mitsuba.
    // Final: sample_batch() gives what it gives, so a subclass (prb, ...) changes neither.
    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const final;
    // The same as a wavefront, bit for bit (path_wave.cpp): RGB and spectral scenes.
    bool samples_in_batches(const Scene& scene) const final;
    void sample_batch(const Scene& scene, Sampler& sampler, BatchSample samples[], size_t n) const final;
    // Radiance that `bsdf` at vertex `si` (si.wi set) scatters toward si.wi, by next-event
    // estimation and BSDF sampling with MIS, following the path onward; `depth` is the number of
    // segments that led to si. Emission at si itself is not included. prepare() must have run.
    // `scattered`, when given, learns whether the path scattered anywhere (not only crossed null
    // surfaces). The numbers of si's vertex start at dimension `first_dimension`, and each later
    // vertex claims the next block of SampleDimensions::PerBounce: a caller that has drawn numbers
    // of its own before (the walk to a gather point) or estimates several times from one sample
    // passes dimensions beyond the ones drawn, else the estimates reuse them (and, for the
    // dimension-addressed samplers, repeat each other). On return every dimension the path drew is
    // below sampler.dimension().
    Spectrum continue_path(const Scene& scene, Sampler& sampler, const SurfaceInteraction& si, const BSDF& bsdf, uint32_t depth,
                           bool* scattered = nullptr, uint32_t first_dimension = SampleDimensions::FirstBounce) const;

    std::string to_string() const override { return "path"; }

private:
    PathSettings settings_;
    std::unique_ptr<LightSampler> lights_;
};

}  // namespace candela
