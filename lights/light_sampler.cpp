#include "lights/light_sampler.h"

#include "core/distribution.h"
#include "core/error.h"
#include "core/scene.h"
#include "lights/light_tree.h"

namespace candela {

LightSampler::LightSampler(const Scene& scene) : reads_pick_sample_(scene.emitters().size() > 1) {}

namespace {

// Picks emitters with fixed probabilities, independent of the shading point.
class FixedLightSampler final : public LightSampler {
public:
    FixedLightSampler(const Scene& scene, bool by_power) : LightSampler(scene) {
        std::vector<float> weights;
        for (const auto& e : scene.emitters()) {
            index_[e.get()] = emitters_.size();
            emitters_.push_back(e.get());
            weights.push_back(by_power ? std::max(luminance(e->power()), 0.0f) : 1.0f);
        }
        // Lights with zero power (or a scene where all have zero) keep a fair share, so that
        // sampling never misses an emitter that does contribute.
        if (by_power) {
            float total = 0.0f;
            for (float w : weights) total += w;
            for (float& w : weights)
                if (!(w > 0.0f)) w = total > 0.0f ? total * 1e-3f : 1.0f;
        }
        if (!weights.empty()) distribution_ = Distribution1D(std::move(weights));
    }

    const Emitter* sample(const SurfaceInteraction&, float u, float& prob) const override {
        if (emitters_.empty()) {
            prob = 0.0f;
            return nullptr;
        }
        size_t i = distribution_.sample_discrete(u);
        prob = distribution_.pmf(i);
        return emitters_[i];
    }

    float pmf(const SurfaceInteraction&, const Emitter* emitter) const override {
        auto it = index_.find(emitter);
        return it == index_.end() ? 0.0f : distribution_.pmf(it->second);
    }

private:
    std::vector<const Emitter*> emitters_;
    std::unordered_map<const Emitter*, size_t> index_;
    Distribution1D distribution_;
};

}  // namespace

const std::vector<std::string>& light_sampler_names() {
    static const std::vector<std::string> names = {"uniform", "power", "tree"};
    return names;
}

std::unique_ptr<LightSampler> create_light_sampler(const std::string& strategy, const Scene& scene) {
    if (strategy == "uniform") return std::make_unique<FixedLightSampler>(scene, false);
    if (strategy == "power") return std::make_unique<FixedLightSampler>(scene, true);
    if (strategy == "tree") return std::make_unique<LightTree>(scene);
    throw InputError("unknown light sampler \"" + strategy + "\" (known: " + light_sampler_choices() + ")");
}

std::string light_sampler_choices() {
    const std::vector<std::string>& names = light_sampler_names();
    std::string out;
    for (size_t i = 0; i < names.size(); ++i) out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return out;
}

}  // namespace candela
