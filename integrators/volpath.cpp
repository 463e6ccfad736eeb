// volpath and volpathmis: volumetric path tracing with Mitsuba 3's names and semantics.
// Free flights through media are sampled by delta tracking, shadow rays find their
// transmittance by ratio tracking (exactly, in homogeneous media), surfaces scatter as in
// `path` (next-event estimation and BSDF sampling combined by the power heuristic; phase-function
// sampling takes the BSDF's place at points in a medium). Rays change medium where they cross a
// shape with an interior or exterior medium (null-BSDF and dielectric boundaries alike); shadow
// rays cross null surfaces (and masks), changing medium there, and stop at any other surface.
//
// Parameters (both; Mitsuba 3):
//   max_depth       integer   longest path in scattering events: surface bounces and real
//                             collisions in media count, null surfaces and null collisions do
//                             not; -1 = unbounded (default), 1 = only emitters seen directly
//   rr_depth        integer   depth from which Russian roulette may end paths (default 5)
//   hide_emitters   boolean   no emission seen before the first scattering event (default false)
//
// RGB and chromatic media. Each channel has its own tracking technique (free flights with its
// own majorant, real or null collisions with its own probabilities); one channel, drawn per
// path, makes the decisions and the estimate is the balance heuristic over the three
// techniques (spectral MIS; core/medium.h, TrackingWeights):
//   volpath     uses the largest channel's majorant for every channel, so free flights do not
//               depend on the channel (Mitsuba's volpath samples with one scalar majorant too);
//               only the real/null choice does.
//   volpathmis  uses each channel's own majorant (Mitsuba's volpathmis): a medium that is thin in
//               one channel and dense in another gets free flights suited to each.
// For grey media (equal channels) both are plain delta tracking with weight albedo.

#include "core/bsdf.h"
#include "core/medium.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "integrators/direct_lighting.h"
#include "integrators/path.h"

#include <cstring>

namespace candela {

namespace {

// Where the path last scattered (a surface bounce or a real collision in a medium): the point
// that MIS weights of emission found later refer to.
struct ScatterVertex {
    SurfaceInteraction at;
    float pdf = 0.0f;
    bool delta = true;  // the camera, or a delta lobe
};

// A point in a medium as a SurfaceInteraction for the light samplers: no normal (zero), no error.
SurfaceInteraction medium_vertex(const Vec3& p) {
    SurfaceInteraction it;
    it.p = p;
    it.p_error = 0.0f;
    it.n = Vec3(0.0f);
    it.shading.n = Vec3(0.0f);
    return it;
}

uint32_t float_bits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

}  // namespace

class VolPathIntegrator : public SamplingIntegrator {
public:
    VolPathIntegrator(const Properties& props, bool spectral_mis) : spectral_mis_(spectral_mis) {
        max_depth_ = props.get_int("max_depth", -1);
        rr_depth_ = props.get_int("rr_depth", 5);
        hide_emitters_ = props.get_bool("hide_emitters", false);
        if (max_depth_ < -1) props.fail("max_depth", "max_depth must be -1 (unbounded) or >= 0");
        if (rr_depth_ <= 0) props.fail("rr_depth", "rr_depth must be positive");
    }
    void prepare(const Scene& scene) override { lights_ = create_light_sampler("tree", scene); }
    bool renders_media() const override { return true; }
    std::string to_string() const override { return spectral_mis_ ? "volpathmis" : "volpath"; }

    // A sample is valid (alpha) when the path scatters somewhere (a surface or a medium), or when
    // the environment is visible (there is one and hide_emitters is off).
    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& camera_ray, SampleRecord& record) const override {
        // Tracking draws an unbounded count of numbers: a PCG32 of its own per camera sample,
        // seeded from where the sample lies on the film and the aperture (deterministic per sample).
        PCG32 rng(hash_combine(float_bits(record.film_pos.x), float_bits(record.film_pos.y)),
                  hash_combine(float_bits(record.aperture.x), float_bits(record.aperture.y)));
        TrackingWeights w;
        w.shared_majorant = !spectral_mis_;
        w.channel = int(rng.next_bounded(3));
        record.valid = !hide_emitters_ && !scene.infinite_emitters().empty();
        if (max_depth_ == 0) return Spectrum(0.0f);
        return trace(scene, sampler, camera_ray, scene.sensor().medium(), rng, w, record);
    }

private:
    Spectrum trace(const Scene& scene, Sampler& sampler, Ray ray, const Medium* medium, PCG32& rng, TrackingWeights& w,
                   SampleRecord& record) const;
    Spectrum sample_light(const Scene& scene, Sampler& sampler, const SurfaceInteraction& at, const Medium* medium, const BSDF* bsdf,
                          const PhaseFunction* phase, const Vec3& wi, PCG32& rng) const;
    bool roulette(Sampler& sampler, uint32_t dims, uint32_t depth, float eta, TrackingWeights& w) const {
        if (depth < uint32_t(rr_depth_)) return true;
        sampler.set_dimension(dims + SampleDimensions::Roulette);
        float q = std::min(max_component(w.estimate_weight()) * eta * eta, 0.95f);
        if (!(sampler.next_1d() < q)) return false;
        w.beta /= q;
        return true;
    }
    bool may_scatter(uint32_t depth) const { return max_depth_ < 0 || depth + 1 < uint32_t(max_depth_); }

    bool spectral_mis_;
    int max_depth_ = -1, rr_depth_ = 5;
    bool hide_emitters_ = false;
    std::unique_ptr<LightSampler> lights_;
};

Spectrum VolPathIntegrator::trace(const Scene& scene, Sampler& sampler, Ray ray, const Medium* medium, PCG32& rng, TrackingWeights& w,
                                  SampleRecord& record) const {
    Spectrum L(0.0f);
    float eta = 1.0f;
    ScatterVertex from;
    uint32_t depth = 0;      // scattering events so far
    int null_crossings = 0;  // since the last scattering event, at most MaxNullCrossings
    // Sample dimensions: every vertex (surface, null surface or real collision) claims a block.
    for (uint32_t vertex = 0;; ++vertex) {
        const uint32_t dims = SampleDimensions::bounce(vertex);
        SurfaceInteraction si;
        bool found = scene.intersect(ray, si);
        if (medium) {
            float t;
            MediumPoint mp;
            bool collided = sample_free_flight(*medium, ray, found ? si.t : Infinity, rng, w, t, mp);
            if (is_black(w.beta)) break;
            if (collided) {
                record.valid = true;
                if (!may_scatter(depth)) break;
                SurfaceInteraction at = medium_vertex(ray(t));
                at.time = ray.time;
                const PhaseFunction& phase = medium->phase();
                if (medium->sample_emitters()) {
                    sampler.set_dimension(dims + SampleDimensions::LightPick);
                    L += w.estimate_weight() * sample_light(scene, sampler, at, medium, nullptr, &phase, -ray.d, rng);
                }
                sampler.set_dimension(dims + SampleDimensions::Direction);
                PhaseSample ps = phase.sample(MediumInteraction{at.p, -ray.d}, sampler.next_2d());
                if (!ps.valid()) break;
                w.beta *= ps.weight;
                from = ScatterVertex{at, ps.pdf, !medium->sample_emitters()};
                ++depth;
                null_crossings = 0;
                ray = Ray(at.p, ps.wo);
                ray.time = at.time;
                if (!roulette(sampler, dims, depth, eta, w)) break;
                continue;
            }
        }
        bool hidden = hide_emitters_ && depth == 0;
        if (!found) {
            if (!hidden) L += w.estimate_weight() * environment_mis(scene, *lights_, from.at, ray.d, from.pdf, from.delta);
            break;
        }
        if (vertex == 0) record.record_first_hit(si);
        if (const Emitter* emitter = si.shape->emitter(); emitter && !hidden) {
            Spectrum Le = emitter->eval(si);
            if (!is_black(Le))
                L += w.estimate_weight() * Le * (from.delta ? 1.0f : emitter_hit_weight(*lights_, from.at, from.pdf, *emitter, si));
        }
        const BSDF& bsdf = *si.shape->bsdf();
        bool scatter_allowed = may_scatter(depth);
        if (!scatter_allowed && !bsdf.has_null_lobe()) break;
        BSDFContext ctx;
        if (!scatter_allowed) ctx.lobes = Null;
        if (scatter_allowed && bsdf.has_smooth_lobe()) {
            sampler.set_dimension(dims + SampleDimensions::LightPick);
            L += w.estimate_weight() * sample_light(scene, sampler, si, medium, &bsdf, nullptr, Vec3(0.0f), rng);
        }
        sampler.set_dimension(dims + SampleDimensions::Lobe);
        float u_lobe = sampler.next_1d();
        BSDFSample bs = bsdf.sample(ctx, si, u_lobe, sampler.next_2d());
        if (!bs.valid() || is_black(bs.weight)) {
            record.valid = true;
            break;
        }
        w.beta *= bs.weight;
        bool scattered = bs.lobe != Null;
        null_crossings = scattered ? 0 : null_crossings + 1;
        if (null_crossings > MaxNullCrossings) break;
        if (scattered) {
            record.valid = true;
            eta *= bs.eta;
            from = ScatterVertex{si, bs.pdf, is_delta(bs.lobe)};
            ++depth;
        }
        Vec3 d = si.to_world(bs.wo);
        if (si.shape->is_medium_transition()) medium = si.shape->target_medium(si, d);
        ray = si.spawn_ray(d);
        if (scattered && !roulette(sampler, dims, depth, eta, w)) break;
        if (max_component(w.beta) <= 0.0f) break;
    }
    return L;
}

// Next-event estimation from a surface (bsdf) or a point in a medium (phase, with wi the world
// direction back along the path): a light picked by the light sampler, a point on it, the
// transmittance of the shadow ray through media and null surfaces, weighted against BSDF or
// phase sampling by the power heuristic. `medium` is the medium the path is in.
Spectrum VolPathIntegrator::sample_light(const Scene& scene, Sampler& sampler, const SurfaceInteraction& at, const Medium* medium,
                                         const BSDF* bsdf, const PhaseFunction* phase, const Vec3& wi, PCG32& rng) const {
    const LightSample light = draw_light_sample(*lights_, sampler, at);
    if (!light.valid()) return Spectrum(0.0f);
    const DirectionSample& ds = light.ds;
    Spectrum f;
    float scatter_pdf;
    if (bsdf) {
        Vec3 wo = at.to_local(ds.d);
        f = bsdf->eval(BSDFContext(), at, wo);
        scatter_pdf = bsdf->pdf(BSDFContext(), at, wo);
        if (at.shape->is_medium_transition()) medium = at.shape->target_medium(at, ds.d);
    } else {
        MediumInteraction mi{at.p, wi};
        f = Spectrum(phase->eval(mi, ds.d));
        scatter_pdf = phase->pdf(mi, ds.d);
    }
    if (is_black(f)) return Spectrum(0.0f);
    Spectrum T = scene.transmittance(shadow_ray(at, ds), medium, rng);  // through media and null surfaces
    if (is_black(T)) return Spectrum(0.0f);
    float mis = ds.delta ? 1.0f : power_heuristic(ds.pdf * light.pick_prob, scatter_pdf);
    return T * f * light.weight * (mis / light.pick_prob);
}

struct VolPath : VolPathIntegrator {
    explicit VolPath(const Properties& props) : VolPathIntegrator(props, false) {}
};
struct VolPathMis : VolPathIntegrator {
    explicit VolPathMis(const Properties& props) : VolPathIntegrator(props, true) {}
};

CANDELA_REGISTER(VolPath, ObjectKind::Integrator, "volpath");
CANDELA_REGISTER(VolPathMis, ObjectKind::Integrator, "volpathmis");

}  // namespace candela
