// prb_basic: Mitsuba 3's basic path replay backpropagation integrator, the simplest of the
// differentiable integrators its tutorials name. Candela renders forward only, and prb_basic's
// forward (primal) estimate is a path tracer that samples the BSDF at every vertex and adds the
// emission its rays find: emitters they hit, the environment where they escape. No next-event
// estimation, no MIS, no Russian roulette (Mitsuba's prb_basic.py). Its expectation is `path`'s
// and its noise larger; point, spot and directional lights, which no ray can hit, add nothing,
// as in Mitsuba. Its gradients are not computed.
//
// Parameters (Mitsuba 3 names and defaults):
//   max_depth       integer   longest path in segments, every surface met counting (null ones
//                             too, as Mitsuba's loop counts them); -1 = unbounded (default 6)
//   hide_emitters   boolean   emission on the camera ray's own segment renders black (default
//                             false)
//   rr_depth        integer   read by Mitsuba's base class and unused by its prb_basic (default
//                             5); here only where max_depth is -1: Russian roulette from that
//                             depth (Mitsuba's rule, survival min(max(throughput) eta^2, 0.95))
//                             ends unbounded paths, unbiased. Without it a path inside a closed
//                             mirror would never end (Mitsuba's would not).
// Not in the polarized variant, as in Mitsuba.
//
// Sample dimensions: vertex k draws its lobe and direction at SampleDimensions::bounce(k), the
// blocks of `path`.

#include "core/bsdf.h"
#include "core/integrator.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "core/wavelengths.h"
#include "integrators/direct_lighting.h"
#include "integrators/path_settings.h"

namespace candela {

class PrbBasicIntegrator final : public SamplingIntegrator {
public:
    // max_depth 6: prb_basic.py's default.
    explicit PrbBasicIntegrator(const Properties& props)
        : settings_(read_differentiable_settings(props, "prb_basic", DepthSettings | HideEmittersSetting, 6)) {}
    std::string to_string() const override { return "prb_basic"; }

    // A sample is valid (the film's alpha) when its camera ray meets a surface, whatever it sees
    // beyond: prb_basic.py's "depth != 0" (path and prb count a visible environment too).
    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& camera_ray, SampleRecord& record) const override {
        Spectrum L(0.0f), beta(1.0f);
        float eta = 1.0f;
        Ray ray = camera_ray;
        SurfaceInteraction si;
        record.valid = false;
        for (uint32_t depth = 0; settings_.max_depth != 0; ++depth) {
            const bool seen_directly = depth == 0;
            if (!scene.intersect(ray, si)) {
                if (!(seen_directly && settings_.hide_emitters)) L += beta * scene.eval_environment(ray.d, ray.wavelengths, ray.time);
                break;
            }
            if (seen_directly) {
                record.record_first_hit(si);
                record.valid = true;
            }
            if (const Emitter* emitter = si.shape->emitter(); emitter && !(seen_directly && settings_.hide_emitters))
                L += beta * emitter->eval(si);
            if (!settings_.may_extend(depth)) break;
            // The safeguard of an unbounded path: Mitsuba's roulette rule from rr_depth.
            const uint32_t dims = SampleDimensions::bounce(depth);
            if (settings_.max_depth < 0 && depth >= uint32_t(settings_.rr_depth)) {
                sampler.set_dimension(dims + SampleDimensions::Roulette);
                const float q = roulette_continue_probability(beta, eta);
                if (!(sampler.next_1d() < q)) break;
                beta /= q;
            }
            const BSDF& bsdf = *si.shape->bsdf();
            sampler.set_dimension(dims + SampleDimensions::Lobe);
            const float u_lobe = draw_lobe_number(bsdf, sampler);
            const Vec2 u_direction = sampler.next_2d();
            const BSDFSample bs = bsdf.sample(BSDFContext(), si, u_lobe, u_direction);
            if (!bs.valid() || is_black(bs.weight)) break;
            if (bs.dispersed && si.wavelengths) si.wavelengths->terminate_secondary();
            beta *= bs.weight;
            eta *= bs.eta;
            ray = si.spawn_ray(si.to_world(bs.wo));
        }
        return L;
    }

private:
    PathSettings settings_;
};

CANDELA_REGISTER_SPECTRAL(PrbBasicIntegrator, ObjectKind::Integrator, "prb_basic");

}  // namespace candela
