#pragma once
// The path tracer (see path.cpp for its parameters). Exposed so that the irradiance integrator
// and the estimators reuse its light transport from any surface vertex.

#include "core/integrator.h"
#include "lights/light_sampler.h"

#include <optional>

namespace candela {

class BSDF;
class Properties;

struct PathSettings {
    int max_depth = -1;  // segments; -1 unbounded
    int rr_depth = 5;
    bool hide_emitters = false;
    std::string light_sampler = "tree";
};

// The settings of every integrator that continues paths (path, irradiance, the estimators) are
// read and checked here and nowhere else.
struct PathSettingProblem {
    std::string parameter;  // Mitsuba name: max_depth, rr_depth or light_sampler
    std::string message;
};
// The first invalid setting, or nothing when all are valid.
std::optional<PathSettingProblem> check_path_settings(const PathSettings& settings);
// Reads max_depth, rr_depth, light_sampler (and hide_emitters when `hide_emitters` is true) from
// an integrator's properties; an invalid value is a SceneError at its file:line.
PathSettings read_path_settings(const Properties& props, bool hide_emitters);

class PathIntegrator : public SamplingIntegrator {
public:
    explicit PathIntegrator(const Properties& props);
    // InputError naming the parameter when the settings are invalid.
    explicit PathIntegrator(const PathSettings& settings);

    void prepare(const Scene& scene) override;
    // A sample is valid (the film's alpha) when it scatters at a surface, or when the environment
    // is visible (there is one and hide_emitters is off), as in Mitsuba.
    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const override;
    // Radiance that `bsdf` at vertex `si` (si.wi set) scatters toward si.wi, by next-event
    // estimation and BSDF sampling with MIS, following the path onward; `depth` is the number of
    // segments that led to si. Emission at si itself is not included. prepare() must have run.
    // `scattered`, when given, learns whether the path scattered anywhere (not only crossed null
    // surfaces).
    Spectrum continue_path(const Scene& scene, Sampler& sampler, const SurfaceInteraction& si, const BSDF& bsdf, uint32_t depth,
                           bool* scattered = nullptr) const;

    std::string to_string() const override { return "path"; }

private:
    uint32_t max_depth_ = UINT32_MAX, rr_depth_ = 5;
    bool hide_emitters_ = false;
    std::string light_strategy_;
    std::unique_ptr<LightSampler> lights_;
};

}  // namespace candela
