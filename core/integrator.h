#pragma once
// Integrators turn a scene into an image. A SamplingIntegrator estimates radiance along camera
// rays; the shared render loop (tiles, passes, film, AOVs, progress) lives in its render().

#include "core/image.h"
#include "core/object.h"
#include "core/pixel_sums.h"
#include "core/ray.h"
#include "core/spectrum.h"

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace candela {

class Scene;
class Sampler;
class Film;

struct RenderOptions {
    int spp = 0;                        // 0: the scene's sampler sample_count
    std::optional<uint64_t> seed;       // default: the sampler's seed
    int threads = 0;                    // 0: all hardware threads
    bool progress = false;              // progress bar on stderr
    const std::atomic<bool>* interrupt = nullptr;  // set (e.g. by SIGINT) to stop early
    // Extra EXR layers: "albedo", "normal", "depth", "variance".
    std::vector<std::string> aovs;
    // A part of the render (see Integrator::renders_parts): only these sample indices (default:
    // [0, spp)) of only these pixels (default: the whole image). The part's sums are the same as
    // those sample indices contribute to those pixels in the whole render.
    SampleRange samples;
    ImageRect region;
    // Called every `checkpoint_seconds` (at the end of a pass, when the sums are consistent) with
    // what the render holds so far; 0 or no callback: never.
    double checkpoint_seconds = 0.0;
    std::function<void(const PixelSums& sums, const std::vector<CoverageBox>& coverage)> checkpoint;
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
    Image image;  // R, G, B then any AOV layers (of sums.rect(): the region and its filter margin)
    RenderStats stats;
    PixelSums sums;  // what `image` was developed from; empty unless the integrator renders parts
    // Which samples of which pixels `sums` holds: the requested region and samples, less what an
    // interruption left out (whole tiles of the last pass).
    std::vector<CoverageBox> coverage;
};

class Integrator : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Integrator; }
    virtual RenderResult render(const Scene& scene, const RenderOptions& options) = 0;
    // A display image (values in [0, 1]) for --png: by default the sRGB tonemap of the render;
    // integrators that render other quantities (irradiance) draw false colour with a legend.
    virtual Image preview(const Image& rendered) const;
    // Whether render() honours RenderOptions::samples and ::region and fills RenderResult::sums,
    // so that a render can be split across machines and merged: only for integrators whose every
    // sample depends on nothing but (seed, pixel, sample index).
    virtual bool renders_parts() const { return false; }
};

class SamplingIntegrator : public Integrator {
public:
    RenderResult render(const Scene& scene, const RenderOptions& options) override;
    // True; an integrator whose samples share state across sample indices (a progressive photon
    // map, a cache built while rendering) must override this with false.
    bool renders_parts() const override { return true; }
    // Called once per render before any sample (build light samplers, caches).
    virtual void prepare(const Scene& scene) {}
    // Radiance arriving along `ray`. Fills `aovs` when not null.
    virtual Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, FirstHitAovs* aovs) const = 0;
};

// The pixels the samples of `region` splat onto: the region grown by the film filter's reach and
// clipped to the image (RenderResult::sums covers this).
ImageRect sums_rect(const Film& film, const ImageRect& region);

// Number of rays traced by the calling thread so far (the accelerator counts them).
uint64_t thread_ray_count();

}  // namespace candela
