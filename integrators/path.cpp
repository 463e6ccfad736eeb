// path: unidirectional path tracing with next-event estimation, combined with BSDF sampling by
// multiple importance sampling (Veach's power heuristic), and Russian roulette.
//
// Parameters (Mitsuba 3 names and semantics):
//   max_depth       integer   longest path in segments; -1 = unbounded (default), 1 = only
//                             emitters seen directly, 2 = direct illumination
//   rr_depth        integer   depth from which Russian roulette may end paths (default 5)
//   hide_emitters   boolean   no emission from what the camera sees directly, through null
//                             surfaces at most (default false): the environment renders black
//                             and an area light shows only what its surface reflects; the path
//                             goes on from the light's surface, which still lights the scene
//                             (Mitsuba 3's semantics, as its volpath and, since 3.6, path)
//   light_sampler   string    how next-event estimation picks a light: tree (default; a light
//                             BVH, best with many lights), power, uniform
// Roulette continues with probability min(max(throughput) * eta^2, 0.95) (Mitsuba's rule),
// decided at the vertex, before the scattered ray is traced (as Mitsuba). Surfaces with a Null
// lobe (null, mask, polarizer, thindielectric) are crossed without a bounce, at most 256 in a
// row: a sampled Null lobe neither counts toward max_depth nor moves the vertex that MIS
// weights refer to, and shadow rays take their null_transmission (Scene::transmittance). Scenes
// without them pay nothing. The surface vertex is integrators/surface_step.h, which volpath
// shares.

#include "integrators/path.h"

#include "core/bsdf.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "integrators/surface_step.h"

namespace candela {

PathIntegrator::PathIntegrator(const Properties& props)
    : PathIntegrator(read_path_settings(props, DepthSettings | HideEmittersSetting | LightSamplerSetting)) {}

PathIntegrator::PathIntegrator(const PathSettings& s) : settings_(s) {
    if (auto problem = check_path_settings(s)) throw InputError(problem->message);
}

void PathIntegrator::prepare(const Scene& scene) { lights_ = create_light_sampler(settings_.light_sampler, scene); }

Spectrum PathIntegrator::sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const {
    if (settings_.max_depth == 0) return Spectrum(0.0f);
    const bool environment_seen = !settings_.hide_emitters && !scene.infinite_emitters().empty();
    // Emission seen directly reaches the camera unpolarised (what the polarized variant sums).
    const PolarizedPath camera(ray.wavelengths);
    SurfaceInteraction si;
    if (!scene.intersect(ray, si)) {
        record.valid = environment_seen;
        return settings_.hide_emitters ? Spectrum(0.0f) : camera.contribute(scene.eval_environment(ray.d, ray.wavelengths, ray.time));
    }
    record.record_first_hit(si);
    Spectrum L(0.0f);
    // Seen directly: no MIS (the camera ray is a delta "lobe"). A hidden emitter still scatters
    // what reaches it, as in Mitsuba 3: only its emission on the first segment is left out.
    if (const Emitter* emitter = si.shape->emitter(); emitter && !settings_.hide_emitters) L += camera.contribute(emitter->eval(si));
    bool scattered = false;
    L += continue_path(scene, sampler, si, *si.shape->bsdf(), 0, &scattered);
    record.valid = scattered || environment_seen;
    return L;
}

Spectrum PathIntegrator::continue_path(const Scene& scene, Sampler& sampler, const SurfaceInteraction& start, const BSDF& start_bsdf,
                                       uint32_t depth, bool* scattered_somewhere, uint32_t first_dimension) const {
    Spectrum L(0.0f);
    CameraPath path(start);
    path.polarization.begin(start.wavelengths);
    path.depth = depth;
    SurfaceInteraction si = start;
    const BSDF* bsdf = &start_bsdf;
    // Each vertex met (a Null crossing included) claims its block of dimensions.
    for (uint32_t dims = first_dimension;; dims += SampleDimensions::PerBounce) {
        Vec3 direction;
        if (!surface_step(scene, *lights_, settings_, sampler, dims, si, *bsdf, PathMedium{}, path, L, direction)) break;
        const Ray ray = si.spawn_ray(direction);
        if (!scene.intersect(ray, si)) {
            L += environment_found(scene, *lights_, settings_, path, ray.d);
            break;
        }
        L += emission_found(*lights_, settings_, path, si);
        bsdf = si.shape->bsdf();
    }
    if (scattered_somewhere) *scattered_somewhere = path.scattered;
    return L;
}

CANDELA_REGISTER_SPECTRAL(PathIntegrator, ObjectKind::Integrator, "path");

}  // namespace candela
