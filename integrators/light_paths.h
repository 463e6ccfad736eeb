#pragma once
// Light paths: particles that leave the emitters (Emitter::sample_ray) and scatter by BSDF
// sampling in importance transport. What ptracer, sppm and photonmapper share: the path itself,
// the shading-normal correction of the adjoint BSDF, and a deterministic parallel loop.
//
// Determinism: light path i draws its random numbers from its own PCG32 stream, seeded by
// (seed, i); paths are traced in chunks of consecutive indices, each chunk writes only its own
// output, and outputs are consumed in chunk order. So the result never depends on the number of
// threads or on which thread traced which chunk.

#include "core/bsdf.h"
#include "core/parallel.h"
#include "core/rng.h"
#include "core/scene.h"
#include "lights/light_sampler.h"

#include <tbb/task_arena.h>

#include <atomic>
#include <memory>
#include <vector>

namespace candela {

// A surface hit of a light path.
struct LightVertex {
    const SurfaceInteraction* si;  // si->wi points back along the path, toward the light
    const BSDF* bsdf;
    Spectrum beta;   // flux weight arriving at si (W): the emitted weight times the scattering weights
    uint32_t depth;  // segments from the emitter to si (1: the first hit)
    bool caustic;    // every scattering before si was by a delta lobe, and there was at least one
    // The polarized variant: the Stokes vectors of the light arriving at si, per unit of its
    // intensity as it left the emitter (world bases along its travel); null in the other variants.
    const StokesSpectrum* stokes = nullptr;
};

// Where a light path starts: an emitter picked by power and a ray it emits.
struct LightPathStart {
    const Emitter* emitter = nullptr;
    float pick_prob = 0.0f;
    EmitterRay ray;
    // The path's shutter time, its first ray's: the emitter's pose, and every ray of the path,
    // take it.
    float time() const { return ray.ray.time; }
    Spectrum beta{0.0f};  // ray.weight / pick_prob
    // The path's wavelengths in the spectral variant (set before start(); null in RGB): the
    // emitted weight and every value along the path are at them.
    Wavelengths* wavelengths = nullptr;
    bool polarized = false;  // the polarized variant: the path carries a Stokes vector
};

// The sample count and seed of a render: the sensor's sampler, unless the options override them.
// Light-path integrators read "samples per pixel" as light paths per pixel (ptracer) or passes
// (sppm): the count and seed of configured_sampler(), so --spp, --seed and --sampler (its
// rounding) mean what they mean for the pixel loop.
struct SampleSettings {
    int spp = 1;
    uint64_t seed = 0;
};
SampleSettings sample_settings(const Scene& scene, const RenderOptions& options);

// The random numbers of light path `index` of a render with `seed` (`stream` tells apart the
// path families of one render, such as global and caustic photons).
PCG32 light_path_rng(uint64_t seed, uint64_t stream, uint64_t index);

// The adjoint BSDF's correction for shading normals (Veach 1997, section 5.3.2): light paths
// multiply f |cos_s wo| by |cos_s wi| |cos_g wo| / (|cos_s wo| |cos_g wi|). Zero when wi or wo
// lies on different sides of the geometric and the shading surface (a light leak).
float shading_normal_correction(const SurfaceInteraction& si, const Vec3& wo_local);

// The polarized variant: the Stokes vectors `s` of light arriving at si (along -si.wi) after it
// leaves through `lobe` of `bsdf` toward wo_local: the BSDF's Mueller matrix with the directions
// swapped (the light's travel, Mitsuba's importance transport), divided by its (0, 0) element
// (the intensity is the path's beta).
void scatter_stokes_forward(const SurfaceInteraction& si, const BSDF& bsdf, const Vec3& wo_local, uint32_t lobe, StokesSpectrum& s);

class LightPathTracer {
public:
    // `max_hits`: the surface hits a path may make (-1: unbounded); Russian roulette from
    // `rr_depth` segments on, with probability min(throughput / emitted weight, 0.95).
    LightPathTracer(const Scene& scene, int max_hits, int rr_depth);

    // A light path's own shutter time: uniform over the sensor's shutter, as a camera sample's;
    // its opening when the shutter is closed, drawing nothing.
    float sample_time(PCG32& rng) const;
    // Picks an emitter (by power) and one of its rays at shutter time `time` (start.time() gives
    // it back); false when the sample carries nothing.
    bool start(PCG32& rng, float time, LightPathStart& start) const;
    // Follows a path from its start: visit(const LightVertex&) runs at each surface hit; the
    // path ends where visit returns false, after max_hits hits, or by absorption or roulette.
    template <typename Visit>
    void follow(PCG32& rng, const LightPathStart& start, Visit&& visit) const;

    const Scene& scene() const { return scene_; }

private:
    // One scattering: samples the BSDF in importance transport and updates beta; false when the
    // path ends there. `lobe` receives the lobe chosen.
    bool scatter(PCG32& rng, const SurfaceInteraction& si, const BSDF& bsdf, Spectrum& beta, Vec3& wo_world, uint32_t& lobe) const;

    const Scene& scene_;
    std::unique_ptr<LightSampler> lights_;
    uint32_t max_hits_, rr_depth_;
};

template <typename Visit>
void LightPathTracer::follow(PCG32& rng, const LightPathStart& start, Visit&& visit) const {
    // The origin as a surface point, so that the first ray leaves an area emitter offset.
    SurfaceInteraction origin;
    origin.p = start.ray.ray.o;
    origin.p_error = start.ray.p_error;
    origin.n = start.ray.n;
    origin.wavelengths = start.wavelengths;
    origin.time = start.time();
    Ray ray = start.ray.n == Vec3(0.0f) ? start.ray.ray : origin.spawn_ray(start.ray.ray.d);
    ray.wavelengths = start.wavelengths;
    Spectrum beta = start.beta;
    const float beta_start = max_component(beta);
    bool all_delta = true;
    StokesSpectrum stokes;
    if (start.polarized)
        for (Stokes& s : stokes.w) s = Stokes(1, 0, 0, 0);  // emitters emit unpolarised light
    SurfaceInteraction si;
    // A Null lobe (null, mask, a thindielectric sheet) passes the path on as the camera side
    // does (integrators/surface_step.h): no hit counted, at most MaxNullCrossings in a row; the
    // emitter's distance attenuation measures the whole first leg.
    uint32_t depth = 1;
    int null_crossings = 0;
    float first_leg = 0.0f, attenuation = 1.0f;
    for (;;) {
        if (!scene_.intersect(ray, si)) return;
        if (depth == 1) {
            first_leg += si.t;
            const float a = start.emitter->ray_attenuation(first_leg);
            beta *= a / attenuation;
            attenuation = a;
        }
        const BSDF& bsdf = *si.shape->bsdf();
        if (!visit(LightVertex{&si, &bsdf, beta, depth, depth > 1 && all_delta, start.polarized ? &stokes : nullptr})) return;
        if (depth >= max_hits_) return;
        Vec3 wo;
        uint32_t lobe = 0;
        if (!scatter(rng, si, bsdf, beta, wo, lobe)) return;
        if (start.polarized) scatter_stokes_forward(si, bsdf, si.to_local(wo), lobe, stokes);
        if (lobe == Null) {
            if (++null_crossings > MaxNullCrossings) return;
        } else {
            null_crossings = 0;
            all_delta = all_delta && is_delta(lobe);
            if (depth >= rr_depth_) {
                float q = std::min(max_component(beta) / beta_start, 0.95f);
                if (!(rng.next_float() < q)) return;
                beta /= q;
            }
            ++depth;
        }
        ray = si.spawn_ray(wo);
    }
}

// Runs trace(begin, end, output) over the index range [0, count) cut into chunks of `chunk`
// consecutive indices, in parallel inside `arena`, one output per chunk (in index order).
// Returns false when `interrupt` was set before every chunk ran; outputs of chunks that did not
// run are left empty. `rays` accumulates the rays traced.
template <typename Output, typename Trace>
bool trace_in_chunks(tbb::task_arena& arena, uint64_t count, uint64_t chunk, std::vector<Output>& outputs,
                     const std::atomic<bool>* interrupt, std::atomic<uint64_t>& rays, Trace&& trace) {
    const size_t chunks = size_t((count + chunk - 1) / chunk);
    outputs.resize(chunks);
    std::atomic<bool> skipped{false};
    arena.execute([&] {
        parallel_chunks(chunks, 1, [&](size_t begin, size_t end) {
            for (size_t c = begin; c != end; ++c) {
                if (interrupt && interrupt->load(std::memory_order_relaxed)) {
                    skipped = true;
                    continue;
                }
                uint64_t rays_before = thread_ray_count();
                trace(uint64_t(c) * chunk, std::min(count, uint64_t(c + 1) * chunk), outputs[c]);
                rays += thread_ray_count() - rays_before;
            }
        });
    });
    return !skipped;
}

}  // namespace candela
