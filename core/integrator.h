#pragma once
// Integrators turn a scene into an image. A SamplingIntegrator estimates radiance along camera
// rays; the shared render loop (tiles, passes, film, AOVs, progress) lives in its render().

#include "core/image.h"
#include "core/object.h"
#include "core/ray.h"
#include "core/spectrum.h"

#include <atomic>
#include <optional>
#include <string>
#include <vector>

namespace candela {

class Scene;
class Sampler;

struct RenderOptions {
    int spp = 0;                        // 0: the scene's sampler sample_count
    std::optional<uint64_t> seed;       // default: the sampler's seed
    int threads = 0;                    // 0: all hardware threads
    bool progress = false;              // progress bar on stderr
    const std::atomic<bool>* interrupt = nullptr;  // set (e.g. by SIGINT) to stop early
    // Extra EXR layers: "albedo", "normal", "depth", "variance".
    std::vector<std::string> aovs;
};

struct RenderStats {
    double seconds = 0.0;
    uint64_t samples = 0;      // camera samples taken
    uint64_t rays = 0;         // closest-hit and shadow rays traced
    uint64_t nonfinite = 0;    // samples dropped because they were NaN or infinite
    int spp = 0;               // samples per pixel requested
    uint64_t seed = 0;
    bool partial = false;      // interrupted before all samples were taken
    // `seconds` timed one rasterized frame, not Monte Carlo sampling: a summary reports the
    // frame time rather than sample and ray rates.
    bool single_frame = false;
};

struct RenderResult {
    Image image;  // R, G, B then any AOV layers
    RenderStats stats;
};

// What a sample reports about its first hit, for AOVs.
struct FirstHitAovs {
    Spectrum albedo{0.0f};
    Vec3 normal{0.0f};
    float depth = 0.0f;
};

class Integrator : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Integrator; }
    virtual RenderResult render(const Scene& scene, const RenderOptions& options) = 0;
    // A display image (values in [0, 1]) for --png: by default the sRGB tonemap of the render;
    // integrators that render other quantities (irradiance) draw false colour with a legend.
    virtual Image preview(const Image& rendered) const;
};

class SamplingIntegrator : public Integrator {
public:
    RenderResult render(const Scene& scene, const RenderOptions& options) override;
    // Called once per render before any sample (build light samplers, caches).
    virtual void prepare(const Scene& scene) {}
    // Radiance arriving along `ray`. Fills `aovs` when not null.
    virtual Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, FirstHitAovs* aovs) const = 0;
};

// Number of rays traced by the calling thread so far (the accelerator counts them).
uint64_t thread_ray_count();

}  // namespace candela
