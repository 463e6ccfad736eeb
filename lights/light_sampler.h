#pragma once
// Light selection: which emitter to sample for next-event estimation at a shading point.
// Strategies: "uniform" (each emitter equally likely), "power" (proportional to emitted flux) and
// "tree" (a light BVH that weighs each light's bounded contribution at the shading point).

#include "core/emitter.h"

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace candela {

class Scene;

class LightSampler {
public:
    explicit LightSampler(const Scene& scene);
    virtual ~LightSampler() = default;
    // Picks an emitter for the shading point `ref` (null when the scene has none) and its
    // selection probability.
    virtual const Emitter* sample(const SurfaceInteraction& ref, float u, float& prob) const = 0;
    // Probability that sample() picks `emitter` at `ref`.
    virtual float pmf(const SurfaceInteraction& ref, const Emitter* emitter) const = 0;
    // False when the scene has one emitter or none: the choice is forced and sample() does not
    // read u, so a caller may skip drawing it (Sampler::skip_1d), a hash and a permutation per
    // path vertex for the grid and sequence samplers.
    bool reads_pick_sample() const { return reads_pick_sample_; }

private:
    bool reads_pick_sample_;
};

// The strategies by name (the one list of them), and the default of every integrator that picks
// lights for next-event estimation.
const std::vector<std::string>& light_sampler_names();
constexpr const char* DefaultLightSampler = "tree";
// The names for a message: "uniform, power or tree".
std::string light_sampler_choices();
// Builds the named strategy for a scene; throws InputError for an unknown name.
std::unique_ptr<LightSampler> create_light_sampler(const std::string& strategy, const Scene& scene);

}  // namespace candela
