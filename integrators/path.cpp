// path: unidirectional path tracing with next-event estimation, combined with BSDF sampling by
// multiple importance sampling (Veach's power heuristic), and Russian roulette.
//
// Parameters (Mitsuba 3 names and semantics):
//   max_depth       integer   longest path in segments; -1 = unbounded (default), 1 = only
//                             emitters seen directly, 2 = direct illumination
//   rr_depth        integer   depth from which Russian roulette may end paths (default 5)
//   hide_emitters   boolean   emitters (and the environment) seen directly render black
//                             (default false)
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
    : max_depth_(s.max_depth < 0 ? UINT32_MAX : uint32_t(s.max_depth)), rr_depth_(uint32_t(s.rr_depth)), hide_emitters_(s.hide_emitters),
      light_strategy_(s.light_sampler) {
    if (auto problem = check_path_settings(s)) throw InputError(problem->message);
}
void PathIntegrator::prepare(const Scene& scene) { lights_ = create_light_sampler(light_strategy_, scene); }

Spectrum PathIntegrator::sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, FirstHitAovs* aovs) const {
    if (max_depth_ == 0) return Spectrum(0.0f);
    SurfaceInteraction si;
    if (!scene.intersect(ray, si)) return hide_emitters_ ? Spectrum(0.0f) : scene.eval_environment(ray.d);
    if (aovs) {
        aovs->albedo = si.shape->bsdf()->albedo(si);
        aovs->normal = si.shading.n;
        aovs->depth = si.t;
    }
    Spectrum L(0.0f);
    // Seen directly: no MIS (the camera ray is a delta "lobe").
    if (const Emitter* emitter = si.shape->emitter(); emitter && !hide_emitters_) L += emitter->eval(si);
    return L + continue_path(scene, sampler, si, *si.shape->bsdf(), 0);
}

Spectrum PathIntegrator::continue_path(const Scene& scene, Sampler& sampler, const SurfaceInteraction& start, const BSDF& start_bsdf,
                                       uint32_t depth) const {
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
    for (;;) {
        // At the last allowed bounce only a Null lobe may still carry the path on.
        bool may_scatter = depth + 1 < max_depth_;
        if (!may_scatter && !bsdf->has_null_lobe()) break;
        BSDFContext ctx;
        if (!may_scatter) ctx.lobes = Null;
        if (may_scatter && bsdf->has_smooth_lobe()) L += beta * sample_light(scene, sampler, si, *bsdf);

        float u_lobe = sampler.next_1d();
        Vec2 u_dir = sampler.next_2d();
        BSDFSample bs = bsdf->sample(ctx, si, u_lobe, u_dir);
        if (!bs.valid() || is_black(bs.weight)) break;
        beta *= bs.weight;
        bool scattered = bs.lobe != Null;
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
            if (!hidden) L += beta * environment_radiance(scene, from, ray.d, from_pdf, from_delta);
            break;
        }
        if (const Emitter* emitter = si.shape->emitter(); emitter && !hidden) {
            Spectrum Le = emitter->eval(si);
            if (!is_black(Le)) {
                float w = 1.0f;
                if (!from_delta) {
                    // Measured from the scattering vertex itself, as light sampling measures it.
                    DirectionSample ds;
                    ds.p = si.p;
                    ds.n = si.n;
                    Vec3 to = si.p - from.p;
                    ds.dist = glm::length(to);
                    ds.d = to / ds.dist;
                    w = power_heuristic(from_pdf, lights_->pmf(from, emitter) * emitter->pdf_direction(from, ds));
                }
                L += beta * Le * w;
            }
        }
        bsdf = si.shape->bsdf();

        if (scattered && depth >= rr_depth_) {
            float q = std::min(max_component(beta) * eta * eta, 0.95f);
            if (!(sampler.next_1d() < q)) break;
            beta /= q;
        }
        if (max_component(beta) <= 0.0f) break;
    }
    return L;
}

// Next-event estimation: one light sample, weighted against BSDF sampling.
Spectrum PathIntegrator::sample_light(const Scene& scene, Sampler& sampler, const SurfaceInteraction& si, const BSDF& bsdf) const {
    const BSDFContext ctx;
    float u_pick = sampler.next_1d();
    Vec2 u = sampler.next_2d();
    float pick_prob = 0.0f;
    const Emitter* emitter = lights_->sample(si, u_pick, pick_prob);
    if (!emitter || !(pick_prob > 0.0f)) return Spectrum(0.0f);
    Spectrum weight;
    DirectionSample ds = emitter->sample_direction(si, u, weight);
    if (!(ds.pdf > 0.0f) || is_black(weight)) return Spectrum(0.0f);
    Vec3 wo = si.to_local(ds.d);
    Spectrum f = bsdf.eval(ctx, si, wo);
    if (is_black(f)) return Spectrum(0.0f);
    Ray shadow = std::isinf(ds.dist) ? si.spawn_ray(ds.d) : si.spawn_ray_to(ds.p, ds.delta ? Vec3(0.0f) : ds.n, ds.p_error);
    Spectrum T = scene.transmittance(shadow);  // through null surfaces and masks
    if (is_black(T)) return Spectrum(0.0f);
    float w = ds.delta ? 1.0f : power_heuristic(ds.pdf * pick_prob, bsdf.pdf(ctx, si, wo));
    return T * f * weight * (w / pick_prob);
}

// Radiance of the infinite emitters along an escaped ray, each MIS-weighted against the light
// sampling that could have produced the same direction.
Spectrum PathIntegrator::environment_radiance(const Scene& scene, const SurfaceInteraction& prev_si, const Vec3& d, float prev_pdf,
                                              bool prev_delta) const {
    Spectrum L(0.0f);
    for (const Emitter* e : scene.infinite_emitters()) {
        Spectrum Le = e->eval_environment(d);
        if (is_black(Le)) continue;
        float w = 1.0f;
        if (!prev_delta) {
            DirectionSample ds;
            ds.d = d;
            ds.dist = Infinity;
            w = power_heuristic(prev_pdf, lights_->pmf(prev_si, e) * e->pdf_direction(prev_si, ds));
        }
        L += Le * w;
    }
    return L;
}

CANDELA_REGISTER(PathIntegrator, ObjectKind::Integrator, "path");

}  // namespace candela
