#pragma once
// Integrators turn a scene into an image. A SamplingIntegrator estimates radiance along camera
// rays; the shared render loop (tiles, passes, film, AOVs, progress) lives in its render().

#include "core/image.h"
#include "core/object.h"
#include "core/pixel_sums.h"
#include "core/progress.h"
#include "core/ray.h"
#include "core/sampler.h"
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

// Adaptive sampling (off unless threshold > 0): after `min_spp` samples, and then every `step`
// samples, a pixel with n samples stops once its error estimate, pooled over its 3x3
// neighbourhood, is below threshold * sqrt(n / min_spp). The estimate is Cycles' (the difference
// between the mean of all samples and the mean of half of them, |I - A|_1 / sqrt(I_r + I_g + I_b),
// Dammertz et al. 2010); the growing limit gives each pixel about sqrt(its variance) samples, the
// allocation with the least summed squared error (see stop_converged in integrator.cpp).
// Decisions are made between passes over the whole image, so the result does not depend on the
// thread count.
struct AdaptiveSampling {
    float threshold = 0.0f;  // 0: off
    int min_spp = 0;         // 0: automatic, max(16, spp / 16) rounded up to a power of two
    int step = 0;            // 0: automatic, min_spp
    bool enabled() const { return threshold > 0.0f; }
};

struct RenderOptions {
    int spp = 0;                                   // 0: the scene's sampler sample_count
    std::optional<uint64_t> seed;                  // default: the sampler's seed
    std::string sampler;                           // a sampler plugin to use instead of the scene's ("" keeps it)
    int threads = 0;                               // 0: all hardware threads
    bool progress = false;                         // progress bar on stderr
    ProgressSink* progress_sink = nullptr;         // also reports progress here (core/progress.h)
    const std::atomic<bool>* interrupt = nullptr;  // set (e.g. by SIGINT) to stop early
    // Extra EXR layers: "albedo", "normal", "depth", "variance", "samples" (samples per pixel).
    std::vector<std::string> aovs;
    AdaptiveSampling adaptive;
    // A part of the render (see Integrator::parts_refusal): only these sample indices (default:
    // [0, spp)) of only these pixels (default: the whole image). The part's sums are the same as
    // those sample indices contribute to those pixels in the whole render. Not with adaptive
    // sampling, whose pixels take samples depending on their earlier ones and their neighbours'.
    SampleRange samples;
    ImageRect region;
    // Called every `checkpoint_seconds` (at the end of a pass, when the sums are consistent) with
    // what the render holds so far; 0 or no callback: never.
    double checkpoint_seconds = 0.0;
    // The widest pass in sample indices (passes grow 1, 2, 4, ... up to it; at most 32): between
    // passes the render takes checkpoints and sees interruptions. The viewer asks for narrow
    // passes to show its progress often from one render call.
    int widest_pass = 32;
    // Whether camera samples may be taken in batches where the integrator can (a wavefront:
    // SamplingIntegrator::samples_in_batches); the image is the same either way. False: one at a
    // time, sample_radiance() for every sample (the reference a batch is tested against).
    bool wavefront = true;
    std::function<void(const PixelSums& sums, const std::vector<CoverageBox>& coverage)> checkpoint;
};

// What rendering took. The renders of a split or resumed render add theirs up (add_work): the
// one place these counters are summed.
struct RenderWork {
    double seconds = 0.0;
    uint64_t samples = 0;    // camera samples taken
    uint64_t rays = 0;       // closest-hit and shadow rays traced
    uint64_t nonfinite = 0;  // samples dropped because they were NaN, infinite or beyond 1e30 (storable_sample_value)
    void add_work(const RenderWork& other) {
        seconds += other.seconds;
        samples += other.samples;
        rays += other.rays;
        nonfinite += other.nonfinite;
    }
};

struct RenderStats : RenderWork {
    int spp = 0;  // samples per pixel requested (after the sampler's rounding)
    uint64_t seed = 0;
    std::string sampler;   // the sampler's plugin name
    bool partial = false;  // interrupted before all samples were taken
    // `seconds` timed one rasterized frame, not Monte Carlo sampling: a summary reports the
    // frame time rather than sample and ray rates.
    bool single_frame = false;
};

struct RenderResult {
    // The film's channels (R, G, B, or as its pixel_format says), the integrator's channels, then
    // the --aov layers; for a part, of sums.rect() (the region and its filter margin).
    Image image;
    RenderStats stats;
    PixelSums sums;  // what `image` was developed from; empty unless the integrator renders parts
    // Which samples of which pixels `sums` holds: the requested region and samples, less what an
    // interruption left out (whole tiles of the last pass).
    std::vector<CoverageBox> coverage;
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
    void record_first_hit(const SurfaceInteraction& si) {
        if (first_hit) fill_first_hit(si, *first_hit);
    }
    // What record_first_hit records: the BSDF's albedo (a colour in every variant), the shading
    // normal and the distance.
    static void fill_first_hit(const SurfaceInteraction& si, FirstHitAovs& aovs);
};

// One camera sample of a batch (SamplingIntegrator::sample_batch). In: its camera ray, where
// the sample stands in the sampler after the camera's numbers, and the --aov first-hit layers to
// fill or null (as SampleRecord's). Out: its radiance and whether it is valid
// (SampleRecord::valid).
struct BatchSample {
    Ray ray;
    SamplerState sampler_state;
    FirstHitAovs* first_hit = nullptr;
    Spectrum L{0.0f};
    bool valid = false;
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
    // Whether this integrator renders motion blur: every ray it traces carries the camera ray's
    // time (the sampling integrators that follow camera paths). The others stop with a SceneError
    // on a scene with an animated to_world rather than render one pose silently.
    virtual bool renders_motion() const { return false; }
    void refuse_unrendered_motion(const Scene& scene) const;
    // Stops with a SceneError at the film's line when the film is a specfilm: for the integrators
    // that develop their own image (ptracer, sppm, raster) rather than the pixel loop's bands.
    void refuse_film_bands(const Scene& scene) const;
    // Why render() cannot honour RenderOptions::samples and ::region and fill RenderResult::sums
    // (so that a render is split across machines and merged, resumed or checkpointed); "" when it
    // can: only integrators whose every sample depends on nothing but (seed, pixel, sample index)
    // and on state that every part computes alike.
    virtual std::string parts_refusal() const { return "it renders one frame, not independent pixel samples"; }
    bool renders_parts() const { return parts_refusal().empty(); }
};

class SamplingIntegrator : public Integrator {
public:
    // Camera paths: the camera ray's time reaches every ray spawned from its interactions.
    bool renders_motion() const override { return true; }
    RenderResult render(const Scene& scene, const RenderOptions& options) override;
    // "": every sample is a pixel sample; an integrator whose samples share state across sample
    // indices (a cache built while rendering) must say why it cannot render parts.
    std::string parts_refusal() const override { return ""; }
    // Called once per render before any sample (build light samplers, caches).
    virtual void prepare(const Scene& scene) {}
    // Radiance arriving along `ray`; fills `record` (valid, channels, first_hit when asked).
    virtual Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const = 0;
    // Whether this render's camera samples may go to sample_batch() many at a time instead of one
    // at a time to sample_radiance(), which gives every sample the same radiance and validity bit
    // for bit (a wavefront path tracer). Asked only for renders without integrator channels or
    // a specfilm's bands. No by default.
    virtual bool samples_in_batches(const Scene& scene) const { return false; }
    // Fills L and valid of samples[0, n), serving them all with one sampler (Sampler::restore).
    virtual void sample_batch(const Scene& scene, Sampler& sampler, BatchSample samples[], size_t n) const {}
    // The extra channels every sample fills, written after the film's own (Mitsuba's
    // aov_names(): "dd.T", "nn.X", ...); at most MaxSampleChannels.
    virtual std::vector<std::string> channel_names() const { return {}; }
};

// The scene's sampler, or the one the options name with the scene's sample count and seed, with
// the render's sample count and seed, told the film's size and border: how every integrator gets
// its sampler (render()'s pixel loop, sppm's camera passes with one sample per pass).
Ref<Sampler> configured_sampler(const Scene& scene, const RenderOptions& options);

// The pixels the samples of `region` splat onto: the region grown by the film filter's reach and
// clipped to the image (RenderResult::sums covers this).
ImageRect sums_rect(const Film& film, const ImageRect& region);

// Writes what a render records about itself into `image`'s metadata (candela.*): the Candela
// version, the scene file, the integrator, spp, seed, sampler, render time, samples, rays,
// dropped non-finite samples and whether it is partial.
void annotate_image(Image& image, const RenderStats& stats, const std::string& integrator, const std::string& scene_path);

// Number of rays traced by the calling thread so far (the accelerator counts them).
uint64_t thread_ray_count();

}  // namespace candela
