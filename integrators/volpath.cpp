// volpath and volpathmis: volumetric path tracing with Mitsuba 3's names and semantics; and
// prbvolpath, Mitsuba 3's differentiable volumetric path tracer, whose forward (primal) estimate
// is volpath's (Candela renders forward only: its gradients are not computed).
// Free flights through media are sampled by delta tracking, shadow rays find their
// transmittance by ratio tracking (exactly, in homogeneous media), surfaces scatter as in
// `path` (next-event estimation and BSDF sampling combined by the power heuristic; phase-function
// sampling takes the BSDF's place at points in a medium; the surface vertex is `path`'s,
// integrators/surface_step.h). Rays change medium where they cross a
// shape with an interior or exterior medium (null-BSDF and dielectric boundaries alike); shadow
// rays cross null surfaces (and masks), changing medium there, and stop at any other surface.
//
// Parameters (all three; Mitsuba 3):
//   max_depth       integer   longest path in scattering events: surface bounces and real
//                             collisions in media count, null surfaces and null collisions do
//                             not; -1 = unbounded (default; prbvolpath: 6, Mitsuba's), 1 = only
//                             emitters seen directly
//   rr_depth        integer   depth from which Russian roulette may end paths (default 5)
//   hide_emitters   boolean   no emission seen before the first scattering event (default false)
//   light_sampler   string    how next-event estimation picks a light, as `path`: tree (default),
//                             power, uniform
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
//   prbvolpath  as volpath; not in the polarized variant (as in Mitsuba).
// For grey media (equal channels) both are plain delta tracking with weight albedo.
//
// In scalar_spectral the three channels are the path's three wavelengths (core/wavelengths.h):
// every medium query takes them (sigma_t unbounded, the albedo a reflectance, as Mitsuba 3's
// spectral variants upsample them), and the same spectral MIS spans the wavelengths.

#include "core/bsdf.h"
#include "core/medium.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "integrators/surface_step.h"

#include <cstring>

namespace candela {

namespace {

// A point in a medium as a SurfaceInteraction for the light samplers: no normal (zero), no error;
// it keeps the ray's time and wavelengths.
SurfaceInteraction medium_vertex(const Ray& ray, float t) {
    SurfaceInteraction it;
    it.p = ray(t);
    it.time = ray.time;
    it.wavelengths = ray.wavelengths;
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
    // `name`: the plugin's.
    VolPathIntegrator(const PathSettings& settings, bool spectral_mis, const char* name)
        : settings_(settings), spectral_mis_(spectral_mis), name_(name) {}
    void prepare(const Scene& scene) override { lights_ = create_light_sampler(settings_.light_sampler, scene); }
    bool renders_media() const override { return true; }
    std::string to_string() const override { return name_; }

    // A sample is valid (alpha) when the path meets a surface that is not purely null or scatters
    // in a medium, or when the environment is visible (there is one and hide_emitters is off).
    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& camera_ray, SampleRecord& record) const override {
        // Tracking draws an unbounded count of numbers: a PCG32 of its own per camera sample,
        // seeded from where the sample lies on the film and the aperture (deterministic per sample).
        PCG32 rng(hash_combine(float_bits(record.film_pos.x), float_bits(record.film_pos.y)),
                  hash_combine(float_bits(record.aperture.x), float_bits(record.aperture.y)));
        CameraPath path;
        path.polarization.begin(camera_ray.wavelengths);
        path.weights.shared_majorant = !spectral_mis_;
        path.weights.channel = int(rng.next_bounded(3));
        // The camera is the first vertex: what the path finds before scattering (the sky seen
        // directly or through null surfaces and media) is looked up at its wavelengths.
        path.from.at.wavelengths = camera_ray.wavelengths;
        record.valid = !settings_.hide_emitters && !scene.infinite_emitters().empty();
        if (settings_.max_depth == 0) return Spectrum(0.0f);
        const Spectrum L = trace(scene, sampler, camera_ray, scene.sensor().medium(), rng, path, record);
        record.valid = record.valid || path.scattered;
        return L;
    }

private:
    Spectrum trace(const Scene& scene, Sampler& sampler, Ray ray, const Medium* medium, PCG32& rng, CameraPath& path,
                   SampleRecord& record) const;
    // Next-event estimation at a medium point; `arriving` as sample_emitter_mis gives it.
    Spectrum sample_phase_light(const Scene& scene, Sampler& sampler, const SurfaceInteraction& at, const Medium& medium, const Vec3& wi,
                                PCG32& rng, StokesSpectrum* arriving) const;

    PathSettings settings_;
    bool spectral_mis_;
    const char* name_;
    std::unique_ptr<LightSampler> lights_;
};

Spectrum VolPathIntegrator::trace(const Scene& scene, Sampler& sampler, Ray ray, const Medium* medium, PCG32& rng, CameraPath& path,
                                  SampleRecord& record) const {
    Spectrum L(0.0f);
    // Sample dimensions: every vertex (surface, null surface or real collision) claims a block.
    for (uint32_t vertex = 0;; ++vertex) {
        const uint32_t dims = SampleDimensions::bounce(vertex);
        SurfaceInteraction si;
        bool found = scene.intersect(ray, si);
        if (medium) {
            float t;
            MediumPoint mp;
            bool collided = sample_free_flight(*medium, ray, found ? si.t : Infinity, rng, path.weights, t, mp);
            if (is_black(path.weights.beta)) break;
            if (collided) {
                path.scattered = true;
                if (!settings_.may_extend(path.depth)) break;
                SurfaceInteraction at = medium_vertex(ray, t);
                const PhaseFunction& phase = medium->phase();
                if (medium->sample_emitters()) {
                    sampler.set_dimension(dims + SampleDimensions::LightPick);
                    StokesSpectrum arriving;
                    const Spectrum nee =
                        sample_phase_light(scene, sampler, at, *medium, -ray.d, rng, path.polarization.active() ? &arriving : nullptr);
                    L += path.polarization.contribute(path.weights.estimate_weight() * nee, &arriving);
                }
                sampler.set_dimension(dims + SampleDimensions::Direction);
                PhaseSample ps = phase.sample(MediumInteraction{at.p, -ray.d}, sampler.next_2d());
                if (!ps.valid()) break;
                path.weights.beta *= ps.weight;
                path.scatter(at, ps.pdf, !medium->sample_emitters());
                ray = Ray(at.p, ps.wo);
                ray.time = at.time;
                ray.wavelengths = at.wavelengths;
                if (!survive_roulette(settings_, sampler, dims, path)) break;
                continue;
            }
        }
        if (!found) {
            L += environment_found(scene, *lights_, settings_, path, ray.d);
            break;
        }
        if (vertex == 0) record.record_first_hit(si);
        L += emission_found(*lights_, settings_, path, si);
        Vec3 d;
        if (!surface_step(scene, *lights_, settings_, sampler, dims, si, *si.shape->bsdf(), PathMedium{medium, &rng}, path, L, d)) break;
        if (si.shape->is_medium_transition()) medium = si.shape->target_medium(si, d);
        ray = si.spawn_ray(d);
    }
    return L;
}

// Next-event estimation from a real collision at `at` in `medium` (wi: the world direction back
// along the path): a light picked by the light sampler, a point on it, the transmittance of the
// shadow ray through media and null surfaces, weighted against phase sampling by the power
// heuristic.
Spectrum VolPathIntegrator::sample_phase_light(const Scene& scene, Sampler& sampler, const SurfaceInteraction& at, const Medium& medium,
                                               const Vec3& wi, PCG32& rng, StokesSpectrum* arriving) const {
    const LightSample light = draw_light_sample(*lights_, sampler, at);
    if (!light.valid()) return Spectrum(0.0f);
    const DirectionSample& ds = light.ds;
    const MediumInteraction mi{at.p, wi};
    const Spectrum f = Spectrum(medium.phase().eval(mi, ds.d));
    if (is_black(f)) return Spectrum(0.0f);
    const Spectrum T = shadow_transmittance(scene, shadow_ray(at, ds), &medium, &rng, nullptr, BSDFContext(), at, ds.d, arriving);
    if (is_black(T)) return Spectrum(0.0f);
    const float mis = ds.delta ? 1.0f : power_heuristic(ds.pdf * light.pick_prob, medium.phase().pdf(mi, ds.d));
    return T * f * light.weight * (mis / light.pick_prob);
}

constexpr uint32_t VolPathSettings = DepthSettings | HideEmittersSetting | LightSamplerSetting;

struct VolPath : VolPathIntegrator {
    explicit VolPath(const Properties& props) : VolPathIntegrator(read_path_settings(props, VolPathSettings), false, "volpath") {}
};
struct VolPathMis : VolPathIntegrator {
    explicit VolPathMis(const Properties& props) : VolPathIntegrator(read_path_settings(props, VolPathSettings), true, "volpathmis") {}
};
// prbvolpath: Mitsuba's differentiable volumetric path tracer; its forward estimate is volpath's
// (delta tracking, next-event estimation, roulette) with max_depth 6 by default.
struct PrbVolPath : VolPathIntegrator {
    explicit PrbVolPath(const Properties& props)
        : VolPathIntegrator(read_differentiable_settings(props, "prbvolpath", VolPathSettings, 6), false, "prbvolpath") {}
};

CANDELA_REGISTER_SPECTRAL(VolPath, ObjectKind::Integrator, "volpath");
CANDELA_REGISTER_SPECTRAL(VolPathMis, ObjectKind::Integrator, "volpathmis");
CANDELA_REGISTER_SPECTRAL(PrbVolPath, ObjectKind::Integrator, "prbvolpath");

}  // namespace candela
