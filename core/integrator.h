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

// Adaptive sampling (off unless threshold > 0): after `min_spp` samples, and then every `step`
// samples, a pixel stops once its error estimate and those of its 8 neighbours are below
// `threshold` (Cycles' noise threshold: the difference between the mean of all samples and the
// mean of half of them, |I - A|_1 / sqrt(I_r + I_g + I_b), Dammertz et al. 2010). Decisions are
// made between passes over the whole image, from each pixel's own samples, so the result does
// not depend on the thread count.
struct AdaptiveSampling {
    float threshold = 0.0f;  // 0: off
    int min_spp = 0;         // 0: automatic, max(16, spp / 16) rounded up to a power of two
    int step = 0;            // 0: automatic, min_spp
    bool enabled() const { return threshold > 0.0f; }
};

struct RenderOptions {
    int spp = 0;                        // 0: the scene's sampler sample_count
    std::optional<uint64_t> seed;       // default: the sampler's seed
    std::string sampler;                // a sampler plugin to use instead of the scene's ("" keeps it)
    int threads = 0;                    // 0: all hardware threads
    bool progress = false;              // progress bar on stderr
    const std::atomic<bool>* interrupt = nullptr;  // set (e.g. by SIGINT) to stop early
    // Extra EXR layers: "albedo", "normal", "depth", "variance", "samples" (samples per pixel).
    std::vector<std::string> aovs;
    AdaptiveSampling adaptive;
};

struct RenderStats {
    double seconds = 0.0;
    uint64_t samples = 0;      // camera samples taken
    uint64_t rays = 0;         // closest-hit and shadow rays traced
    uint64_t nonfinite = 0;    // samples dropped because they were NaN or infinite
    int spp = 0;               // samples per pixel requested (after the sampler's rounding)
    uint64_t seed = 0;
    std::string sampler;       // the sampler's plugin name
    bool partial = false;      // interrupted before all samples were taken
    // `seconds` timed one rasterized frame, not Monte Carlo sampling: a summary reports the
    // frame time rather than sample and ray rates.
    bool single_frame = false;
};

struct RenderResult {
    // The film's channels (R, G, B, or as its pixel_format says), the integrator's channels, then
    // the --aov layers.
    Image image;
    RenderStats stats;
};

// What a sample reports about its first hit, for the --aov layers.
struct FirstHitAovs {
    Spectrum albedo{0.0f};
    Vec3 normal{0.0f};
    float depth = 0.0f;
};

// The most extra values one sample may report (SamplingIntegrator::channel_names()).
constexpr int MaxSampleChannels = 64;

// One camera sample besides its radiance: where it lies on the film (in), what the integrator
// reports about it (out). Lives on the stack of the pixel loop: nothing is allocated per sample.
struct SampleRecord {
    // In: the film position (pixels of the full film) and aperture sample the camera ray came
    // from, and the scale of ray differentials (Mitsuba's: one pixel times 1 / sqrt(spp)).
    Vec2 film_pos{0.0f}, aperture{0.5f};
    float differential_scale = 1.0f;
    // In: the --aov first-hit layers to fill, or null.
    FirstHitAovs* first_hit = nullptr;
    // Out: the sample saw something (Mitsuba's `valid`: the film's alpha). Each integrator
    // documents its rule; by default a sample sees nothing.
    bool valid = false;
    // Out: the values of the integrator's channel_names(), in order.
    float channels[MaxSampleChannels];

    // Fills the --aov first-hit layers, when asked for, from the camera ray's first surface.
    void record_first_hit(const SurfaceInteraction& si);
};

class Integrator : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Integrator; }
    virtual RenderResult render(const Scene& scene, const RenderOptions& options) = 0;
    // A display image (values in [0, 1]) for --png: by default the sRGB tonemap of the render;
    // integrators that render other quantities (irradiance) draw false colour with a legend.
    virtual Image preview(const Image& rendered) const;
    // Whether this integrator renders participating media (volpath, volpathmis, raster's fog).
    virtual bool renders_media() const { return false; }
    // Stops with a SceneError naming volpath when the scene has media this integrator would
    // ignore (Mitsuba's path ignores them silently; a silently wrong picture is worse).
    void refuse_unrendered_media(const Scene& scene) const;
};

class SamplingIntegrator : public Integrator {
public:
    RenderResult render(const Scene& scene, const RenderOptions& options) override;
    // Called once per render before any sample (build light samplers, caches).
    virtual void prepare(const Scene& scene) {}
    // Radiance arriving along `ray`; fills `record` (valid, channels, first_hit when asked).
    virtual Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const = 0;
    // The extra channels every sample fills, written after the film's own (Mitsuba's
    // aov_names(): "dd.T", "nn.X", ...); at most MaxSampleChannels.
    virtual std::vector<std::string> channel_names() const { return {}; }
};

// Number of rays traced by the calling thread so far (the accelerator counts them).
uint64_t thread_ray_count();

}  // namespace candela
