// path: unidirectional path tracing with next-event estimation, combined with BSDF sampling by
// multiple importance sampling (Veach's power heuristic), and Russian roulette.
//
// Parameters (Mitsuba 3 names and semantics):
//   max_depth       integer   longest path in segments; -1 = unbounded (default), 1 = only
//                             emitters seen directly, 2 = direct illumination
//   rr_depth        integer   depth from which Russian roulette may end paths (default 5)
//   hide_emitters   boolean   emitters (and the environment) seen directly render black
//                             (default false)
//   light_sampler   string    how NEE picks a light: uniform (default), power
// Roulette continues with probability min(max(throughput) * eta^2, 0.95) (Mitsuba's rule).

#include "core/bsdf.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "lights/light_sampler.h"

namespace candela {

class PathIntegrator final : public SamplingIntegrator {
public:
    explicit PathIntegrator(const Properties& props) {
        int max_depth = props.get_int("max_depth", -1);
        if (max_depth < -1) props.fail("max_depth", "max_depth must be -1 (unbounded) or >= 0");
        max_depth_ = max_depth < 0 ? UINT32_MAX : uint32_t(max_depth);
        int rr = props.get_int("rr_depth", 5);
        if (rr <= 0) props.fail("rr_depth", "rr_depth must be positive");
        rr_depth_ = uint32_t(rr);
        hide_emitters_ = props.get_bool("hide_emitters", false);
        light_strategy_ = props.get_string("light_sampler", "uniform");
        const auto& names = light_sampler_names();
        if (std::find(names.begin(), names.end(), light_strategy_) == names.end())
            props.fail("light_sampler", "unknown light_sampler \"" + light_strategy_ + "\"");
    }

    void prepare(const Scene& scene) override { lights_ = create_light_sampler(light_strategy_, scene); }

    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& camera_ray, FirstHitAovs* aovs) const override {
        const BSDFContext ctx;
        Spectrum L(0.0f), beta(1.0f);
        if (max_depth_ == 0) return L;
        float eta = 1.0f;
        Ray ray = camera_ray;
        SurfaceInteraction si, prev_si;
        bool found = scene.intersect(ray, si);
        float prev_pdf = 1.0f;
        bool prev_delta = true;  // the camera ray counts as a delta "lobe": emitters get full weight

        for (uint32_t depth = 0;; ) {
            bool visible_emission = !(depth == 0 && hide_emitters_);
            if (!found) {
                if (visible_emission) L += beta * environment_radiance(scene, prev_si, ray.d, prev_pdf, prev_delta);
                break;
            }
            if (depth == 0 && aovs) {
                aovs->albedo = si.shape->bsdf()->albedo(si);
                aovs->normal = si.shading.n;
                aovs->depth = si.t;
            }
            if (const Emitter* emitter = si.shape->emitter(); emitter && visible_emission) {
                Spectrum Le = emitter->eval(si);
                if (!is_black(Le)) {
                    float w = 1.0f;
                    if (!prev_delta) {
                        // Measured from the previous vertex itself (not the offset ray origin),
                        // exactly as light sampling measures it, so the MIS weights sum to one.
                        DirectionSample ds;
                        ds.p = si.p;
                        ds.n = si.n;
                        Vec3 to = si.p - prev_si.p;
                        ds.dist = glm::length(to);
                        ds.d = to / ds.dist;
                        float light_pdf = lights_->pmf(prev_si, emitter) * emitter->pdf_direction(prev_si, ds);
                        w = power_heuristic(prev_pdf, light_pdf);
                    }
                    L += beta * Le * w;
                }
            }
            if (depth + 1 >= max_depth_) break;

            const BSDF* bsdf = si.shape->bsdf();
            if (bsdf->has_smooth_lobe()) L += beta * sample_light(scene, sampler, si, *bsdf, ctx);

            float u_lobe = sampler.next_1d();
            Vec2 u_dir = sampler.next_2d();
            BSDFSample bs = bsdf->sample(ctx, si, u_lobe, u_dir);
            if (!bs.valid() || is_black(bs.weight)) break;
            beta *= bs.weight;
            eta *= bs.eta;
            prev_si = si;
            prev_pdf = bs.pdf;
            prev_delta = is_delta(bs.lobe);
            ray = si.spawn_ray(si.to_world(bs.wo));
            found = scene.intersect(ray, si);
            ++depth;

            if (depth >= rr_depth_) {
                float q = std::min(max_component(beta) * eta * eta, 0.95f);
                if (!(sampler.next_1d() < q)) break;
                beta /= q;
            }
            if (max_component(beta) <= 0.0f) break;
        }
        return L;
    }

    std::string to_string() const override { return "path"; }

private:
    // Next-event estimation: one light sample, weighted against BSDF sampling.
    Spectrum sample_light(const Scene& scene, Sampler& sampler, const SurfaceInteraction& si, const BSDF& bsdf,
                          const BSDFContext& ctx) const {
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
        if (scene.occluded(shadow)) return Spectrum(0.0f);
        float w = ds.delta ? 1.0f : power_heuristic(ds.pdf * pick_prob, bsdf.pdf(ctx, si, wo));
        return f * weight * (w / pick_prob);
    }

    // Radiance of the infinite emitters along an escaped ray, each MIS-weighted against the
    // light sampling that could have produced the same direction.
    Spectrum environment_radiance(const Scene& scene, const SurfaceInteraction& prev_si, const Vec3& d, float prev_pdf,
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

    uint32_t max_depth_ = UINT32_MAX, rr_depth_ = 5;
    bool hide_emitters_ = false;
    std::string light_strategy_;
    std::unique_ptr<LightSampler> lights_;
};

CANDELA_REGISTER(PathIntegrator, ObjectKind::Integrator, "path");

}  // namespace candela
