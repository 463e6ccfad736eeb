// The path tracer as a wavefront (PathIntegrator::sample_batch): a batch of camera samples
// advances bounce by bounce, each bounce's extension rays traced together as Embree's 16-ray
// packets (Scene::intersect_batch), then every path's vertex numbers drawn, then every path
// shaded, then the bounce's shadow rays traced together (Scene::occluded_batch). Each path runs
// the scalar path's vertex (surface_step's, as draw_vertex_numbers and surface_step_drawn;
// emission_found, environment_found) with its shadow ray held back (PendingShadow), and keeps
// where its sample stands in the one sampler the batch shares (Sampler::save/restore), so that
// every sample's numbers and radiance are bit for bit those of sample_radiance;
// tests/integrators/test_path_wave.cpp holds the two to that.
//
// Used for what it reproduces exactly: the RGB and spectral variants (each sample's wavelengths
// are its own, drawn by the pixel loop; no Stokes vectors) without media (path refuses them
// anyway). In a scene with Null surfaces (thindielectric, mask, null) a shadow ray's
// transmittance is Scene::transmittance's, one ray at a time; without them the bounce's shadow
// rays go to Embree as packets (clear means a transmittance of exactly 1). The polarized variant
// takes the scalar path.
//
// What it gains and what it does not yet is measured in docs/benchmarks.md ("The wavefront
// path"): the shading is still the scalar plugins', lane by lane.

#include "core/bsdf.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "integrators/path.h"
#include "integrators/surface_step.h"

#include <memory>
#include <vector>

namespace candela {

namespace {

// One path of the batch.
struct WaveLane {
    SurfaceInteraction si;  // where the path's last ray arrived
    CameraPath path;
    Ray ray;  // the ray it traces next
    SamplerState sampler_state;
    VertexNumbers numbers;  // its vertex's numbers, drawn before it is shaded
    PendingShadow shadow;
    // What sample_radiance adds up: the emission the camera ray finds, and what the path finds
    // after (continue_path's sum), added last in that order.
    Spectrum seen{0.0f}, gathered{0.0f};
    uint32_t dims = 0;      // the next vertex's first dimension
    bool at_camera = true;  // its ray is the camera ray
    bool goes_on = false;   // after this bounce's vertex: the path traces another ray
};

// A thread's lanes and the arrays the batch queries take, reused from batch to batch (the pixel
// loop's threads render many batches each).
struct WaveWorkspace {
    std::vector<WaveLane> lanes;
    std::vector<uint32_t> live, pending;  // lanes still tracing; lanes with a shadow ray this bounce
    std::vector<const Ray*> rays;
    std::vector<SurfaceInteraction*> hits;
    // The batch queries' answers (std::vector<bool> has no data()).
    std::unique_ptr<bool[]> found, blocked;
    size_t capacity = 0;

    void reserve(size_t n) {
        if (lanes.size() < n) lanes.resize(n);
        if (capacity >= n) return;
        found.reset(new bool[n]);
        blocked.reset(new bool[n]);
        capacity = n;
    }
};

}  // namespace

bool PathIntegrator::samples_in_batches(const Scene& scene) const { return !scene.polarized() && !scene.has_media(); }

void PathIntegrator::sample_batch(const Scene& scene, Sampler& sampler, BatchSample samples[], size_t n) const {
    const bool environment_seen = !settings_.hide_emitters && !scene.infinite_emitters().empty();
    if (settings_.max_depth == 0) {
        for (size_t i = 0; i < n; ++i) samples[i].L = Spectrum(0.0f), samples[i].valid = false;
        return;
    }
    thread_local WaveWorkspace w;
    w.reserve(n);
    w.live.resize(n);
    // A path's sample, once it has ended and its last shadow ray (if any) is traced: the sums in
    // sample_radiance's order, and its validity by the same rule.
    auto finish = [&](uint32_t index) {
        const WaveLane& lane = w.lanes[index];
        samples[index].L = lane.seen + lane.gathered;
        samples[index].valid = lane.path.scattered || environment_seen;
    };
    for (size_t i = 0; i < n; ++i) {
        WaveLane& lane = w.lanes[i];
        lane.ray = samples[i].ray;
        lane.sampler_state = samples[i].sampler_state;
        lane.seen = lane.gathered = Spectrum(0.0f);
        lane.at_camera = true;
        w.live[i] = uint32_t(i);
    }
    size_t live = n;
    // The first round traces camera rays only: a packet holds one pixel's samples (or a row's
    // neighbouring pixels), which Embree traces faster as a frustum when the sensor's rays run
    // together (3-5% of a Cornell-box render, bench/results/coherent_camera_rays_2026-12-07.txt).
    // Later rounds' rays scatter: the coherent traversal was slower for them (the first bounce's
    // by 1%, the shadow rays' by 6%).
    bool coherent = scene.sensor().rays_coherent();
    while (live > 0) {
        // Trace: every live path's ray, in packets.
        w.rays.resize(live);
        w.hits.resize(live);
        bool* found = w.found.get();
        for (size_t k = 0; k < live; ++k) {
            WaveLane& lane = w.lanes[w.live[k]];
            w.rays[k] = &lane.ray;
            w.hits[k] = &lane.si;
        }
        scene.intersect_batch(w.rays.data(), w.hits.data(), found, live, coherent);
        coherent = false;
        // What each path found, as sample_radiance and continue_path take it, and the numbers of
        // the vertex it found, drawn for all paths before any is shaded: the place for a batch
        // draw (by itself no faster than drawing in the vertex, measured 2026-12-07).
        size_t still = 0;
        for (size_t k = 0; k < live; ++k) {
            const uint32_t index = w.live[k];
            WaveLane& lane = w.lanes[index];
            if (lane.at_camera) {
                if (!found[k]) {
                    samples[index].L =
                        settings_.hide_emitters ? Spectrum(0.0f) : scene.eval_environment(lane.ray.d, lane.ray.wavelengths, lane.ray.time);
                    samples[index].valid = environment_seen;
                    continue;
                }
                if (samples[index].first_hit) SampleRecord::fill_first_hit(lane.si, *samples[index].first_hit);
                // Seen directly: no MIS (the camera ray is a delta "lobe").
                if (const Emitter* emitter = lane.si.shape->emitter(); emitter && !settings_.hide_emitters)
                    lane.seen += emitter->eval(lane.si);
                lane.path.restart(lane.si);
                lane.path.polarization.begin(lane.ray.wavelengths);  // inactive: no Stokes vectors
                lane.dims = SampleDimensions::FirstBounce;
                lane.at_camera = false;
            } else if (!found[k]) {
                lane.gathered += environment_found(scene, *lights_, settings_, lane.path, lane.ray.d);
                finish(index);
                continue;
            } else {
                lane.gathered += emission_found(*lights_, settings_, lane.path, lane.si);
            }
            sampler.restore(lane.sampler_state);
            draw_vertex_numbers(*lights_, settings_, sampler, lane.dims, *lane.si.shape->bsdf(), lane.path, lane.numbers);
            sampler.save(lane.sampler_state);
            w.live[still++] = index;
        }
        live = still;
        // Each vertex (surface_step's), its shadow ray held back.
        w.pending.clear();
        still = 0;
        for (size_t k = 0; k < live; ++k) {
            const uint32_t index = w.live[k];
            WaveLane& lane = w.lanes[index];
            lane.shadow.pending = false;
            Vec3 direction;
            lane.goes_on = surface_step_drawn(scene, *lights_, settings_, lane.numbers, LaterDraws{sampler, lane.sampler_state, lane.dims},
                                              lane.si, *lane.si.shape->bsdf(), lane.path, lane.gathered, direction, lane.shadow);
            if (lane.goes_on) {
                lane.ray = lane.si.spawn_ray(direction);
                lane.dims += SampleDimensions::PerBounce;
                w.live[still++] = index;
            }
            if (lane.shadow.pending)
                w.pending.push_back(index);
            else if (!lane.goes_on)
                finish(index);
        }
        // The bounce's shadow rays, in packets; a clear one adds its estimate. Through Null
        // surfaces, each its transmittance.
        const size_t shadows = w.pending.size();
        if (scene.has_null_surfaces()) {
            for (size_t k = 0; k < shadows; ++k) {
                WaveLane& lane = w.lanes[w.pending[k]];
                const Spectrum T = scene.transmittance(lane.shadow.light.shadow);
                if (!is_black(T)) lane.gathered += lane.shadow.value(T);
            }
        } else {
            w.rays.resize(shadows);
            bool* blocked = w.blocked.get();
            for (size_t k = 0; k < shadows; ++k) w.rays[k] = &w.lanes[w.pending[k]].shadow.light.shadow;
            scene.occluded_batch(w.rays.data(), blocked, shadows);
            for (size_t k = 0; k < shadows; ++k)
                if (!blocked[k]) w.lanes[w.pending[k]].gathered += w.lanes[w.pending[k]].shadow.value(Spectrum(1.0f));
        }
        for (size_t k = 0; k < shadows; ++k)
            if (!w.lanes[w.pending[k]].goes_on) finish(w.pending[k]);
        live = still;
    }
}

}  // namespace candela
