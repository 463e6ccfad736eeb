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
// Roulette continues with probability min(max(throughput) * eta^2, 0.95) (Mitsuba's rule).
// Surfaces with a Null lobe (null, mask, polarizer) are crossed without a bounce: a sampled Null
// lobe neither counts toward max_depth nor moves the vertex that MIS weights refer to, and shadow
// rays take their null_transmission (Scene::transmittance). Scenes without them pay nothing.

#include "integrators/path.h"

#include "core/bsdf.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "integrators/direct_lighting.h"

namespace candela {

std::optional<PathSettingProblem> check_path_settings(const PathSettings& s) {
    if (s.max_depth < -1) return PathSettingProblem{"max_depth", "max_depth must be -1 (unbounded) or >= 0"};
    if (s.rr_depth <= 0) return PathSettingProblem{"rr_depth", "rr_depth must be positive"};
    const auto& names = light_sampler_names();
    if (std::find(names.begin(), names.end(), s.light_sampler) == names.end())
        return PathSettingProblem{"light_sampler", "unknown light_sampler \"" + s.light_sampler + "\" (uniform, power or tree)"};
    return std::nullopt;
}

PathSettings read_path_settings(const Properties& props, bool hide_emitters) {
    PathSettings s;
    s.max_depth = props.get_int("max_depth", -1);
    s.rr_depth = props.get_int("rr_depth", 5);
    if (hide_emitters) s.hide_emitters = props.get_bool("hide_emitters", false);
    s.light_sampler = props.get_string("light_sampler", "tree");
    if (auto problem = check_path_settings(s)) props.fail(problem->parameter, problem->message);
    return s;
}

PathIntegrator::PathIntegrator(const Properties& props) : PathIntegrator(read_path_settings(props, true)) {}

PathIntegrator::PathIntegrator(const PathSettings& s)
    : max_depth_(s.max_depth < 0 ? UINT32_MAX : uint32_t(s.max_depth)),
      rr_depth_(uint32_t(s.rr_depth)),
      hide_emitters_(s.hide_emitters),
      light_strategy_(s.light_sampler) {
    if (auto problem = check_path_settings(s)) throw InputError(problem->message);
}
void PathIntegrator::prepare(const Scene& scene) { lights_ = create_light_sampler(light_strategy_, scene); }

Spectrum PathIntegrator::sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const {
    if (max_depth_ == 0) return Spectrum(0.0f);
    SurfaceInteraction si;
    if (!scene.intersect(ray, si)) {
        record.valid = !hide_emitters_ && !scene.infinite_emitters().empty();
        return hide_emitters_ ? Spectrum(0.0f) : scene.eval_environment(ray.d);
    }
    record.record_first_hit(si);
    Spectrum L(0.0f);
    // Seen directly: no MIS (the camera ray is a delta "lobe"). A hidden emitter still scatters
    // what reaches it, as in Mitsuba 3: only its emission on the first segment is left out.
    if (const Emitter* emitter = si.shape->emitter(); emitter && !hide_emitters_) L += emitter->eval(si);
    bool scattered = false;
    L += continue_path(scene, sampler, si, *si.shape->bsdf(), 0, &scattered);
    record.valid = scattered || (!hide_emitters_ && !scene.infinite_emitters().empty());
    return L;
}

Spectrum PathIntegrator::continue_path(const Scene& scene, Sampler& sampler, const SurfaceInteraction& start, const BSDF& start_bsdf,
                                       uint32_t depth, bool* scattered_somewhere) const {
    Spectrum L(0.0f), beta(1.0f);
    float eta = 1.0f;
    SurfaceInteraction si = start;
    const BSDF* bsdf = &start_bsdf;
    // The last vertex that scattered, to which MIS weights refer. A Null lobe (null, a mask's
    // transparent part) passes the ray on unchanged: no bounce, so neither it nor depth change.
    // Before the first bounce it is the camera, a delta.
    SurfaceInteraction from = start;
    float from_pdf = 0.0f;
    bool from_delta = true;
    int null_crossings = 0;  // since the last scattering vertex, at most MaxNullCrossings
    // Sample dimensions: every vertex the path meets (a Null crossing included) claims its own
    // block of SampleDimensions, used or not, so that vertex k always draws the same dimensions.
    for (uint32_t vertex = depth;; ++vertex) {
        const uint32_t dims = SampleDimensions::bounce(vertex);
        if (scattered_somewhere && !bsdf->has_null_lobe()) *scattered_somewhere = true;
        // At the last allowed bounce only a Null lobe may still carry the path on.
        bool may_scatter = depth + 1 < max_depth_;
        if (!may_scatter && !bsdf->has_null_lobe()) break;
        BSDFContext ctx;
        if (!may_scatter) ctx.lobes = Null;
        // sample_emitter_mis draws the light pick, then the light position (LightPick, LightPosition).
        sampler.set_dimension(dims + SampleDimensions::LightPick);
        if (may_scatter && bsdf->has_smooth_lobe()) L += beta * sample_emitter_mis(scene, *lights_, sampler, si, *bsdf, BSDFContext());

        sampler.set_dimension(dims + SampleDimensions::Lobe);
        float u_lobe = sampler.next_1d();
        Vec2 u_dir = sampler.next_2d();
        BSDFSample bs = bsdf->sample(ctx, si, u_lobe, u_dir);
        if (scattered_somewhere && (!bs.valid() || bs.lobe != Null)) *scattered_somewhere = true;
        if (!bs.valid() || is_black(bs.weight)) break;
        beta *= bs.weight;
        bool scattered = bs.lobe != Null;
        null_crossings = scattered ? 0 : null_crossings + 1;
        if (null_crossings > MaxNullCrossings) break;
        if (scattered) {
            eta *= bs.eta;
            from = si;
            from_pdf = bs.pdf;
            from_delta = is_delta(bs.lobe);
            ++depth;
        }
        Ray ray = si.spawn_ray(si.to_world(bs.wo));
        bool found = scene.intersect(ray, si);
        bool hidden = hide_emitters_ && depth == 0;  // seen directly, through null surfaces only

        // Emission found by the BSDF sample, weighted against light sampling (same pdfs as
        // next-event estimation, so the two weights sum to one).
        if (!found) {
            if (!hidden) L += beta * environment_mis(scene, *lights_, from, ray.d, from_pdf, from_delta);
            break;
        }
        if (const Emitter* emitter = si.shape->emitter(); emitter && !hidden) {
            Spectrum Le = emitter->eval(si);
            if (!is_black(Le)) L += beta * Le * (from_delta ? 1.0f : emitter_hit_weight(*lights_, from, from_pdf, *emitter, si));
        }
        bsdf = si.shape->bsdf();

        if (scattered && depth >= rr_depth_) {
            sampler.set_dimension(dims + SampleDimensions::Roulette);
            float q = std::min(max_component(beta) * eta * eta, 0.95f);
            if (!(sampler.next_1d() < q)) break;
            beta /= q;
        }
        if (max_component(beta) <= 0.0f) break;
    }
    return L;
}

CANDELA_REGISTER(PathIntegrator, ObjectKind::Integrator, "path");

}  // namespace candela
