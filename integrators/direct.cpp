// direct: direct illumination only, by next-event estimation and BSDF sampling combined with
// multiple importance sampling (Mitsuba 3's `direct`). No indirect light.
//
// Parameters (Mitsuba 3 names and defaults):
//   shading_samples   integer   sets both counts below (default 1)
//   emitter_samples   integer   light samples per camera hit (default shading_samples)
//   bsdf_samples      integer   BSDF samples per camera hit (default shading_samples)
//   hide_emitters     boolean   as path: no emission from what the camera sees directly; the
//                               hidden light's surface is still lit (default false)
//   light_sampler     string    (Candela) how a light is picked, as path: tree (default), power,
//                               uniform
// shading_samples together with emitter_samples or bsdf_samples is an error, as is taking no
// sample at all. With m emitter and n BSDF samples, each light sample is weighted by the power
// heuristic with the two pdfs scaled by the strategies' shares m / (m + n) and n / (m + n),
// divided by m; each BSDF sample likewise, divided by n (Veach 1997, 9.2). So m = 0 is pure BSDF
// sampling and n = 0 pure light sampling (which misses lights seen through delta lobes, and
// n = 0 misses point lights: as in Mitsuba). Lights are sampled only at BSDFs with a smooth lobe.
// Null surfaces (null, the transparent part of mask, a thindielectric sheet) are crossed as path crosses them: what
// they let through shows what lies behind, weighted by their null_transmission, and their
// scattering part is lit directly; Mitsuba's direct instead sees only emitters behind them.
// A sample is valid (the film's alpha) when the camera ray reaches a surface that scatters
// (Mitsuba's direct counts any surface hit, null ones included).

#include "core/bsdf.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "integrators/direct_lighting.h"
#include "integrators/path_settings.h"

namespace candela {

class DirectIntegrator final : public SamplingIntegrator {
public:
    explicit DirectIntegrator(const Properties& props) {
        if (props.has("shading_samples") && (props.has("emitter_samples") || props.has("bsdf_samples")))
            props.fail("shading_samples", "give shading_samples or emitter_samples / bsdf_samples, not both");
        int shading = props.get_int("shading_samples", 1);
        emitter_samples_ = props.get_int("emitter_samples", shading);
        bsdf_samples_ = props.get_int("bsdf_samples", shading);
        if (shading < 0 || emitter_samples_ < 0 || bsdf_samples_ < 0)
            props.fail(props.has("shading_samples") ? "shading_samples"
                       : emitter_samples_ < 0       ? "emitter_samples"
                                                    : "bsdf_samples",
                       "sample counts must not be negative");
        if (emitter_samples_ + bsdf_samples_ == 0)
            props.fail(props.has("shading_samples") ? "shading_samples" : "emitter_samples",
                       "direct needs at least one emitter or BSDF sample");
        const PathSettings settings = read_path_settings(props, HideEmittersSetting | LightSamplerSetting);
        hide_emitters_ = settings.hide_emitters;
        light_strategy_ = settings.light_sampler;
        float total = float(emitter_samples_ + bsdf_samples_);
        shares_ = StrategyShares{float(emitter_samples_) / total, float(bsdf_samples_) / total};
    }

    void prepare(const Scene& scene) override { lights_ = create_light_sampler(light_strategy_, scene); }

    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& camera_ray, SampleRecord& record) const override {
        Spectrum L(0.0f), beta(1.0f);
        PolarizedPath camera(camera_ray.wavelengths);  // the polarized variant's null crossings
        Ray ray = camera_ray;
        for (int crossed = 0; crossed <= MaxNullCrossings; ++crossed) {
            const bool first = crossed == 0;
            SurfaceInteraction si;
            if (!scene.intersect(ray, si)) {
                if (!hide_emitters_) L += camera.contribute(beta * scene.eval_environment(ray.d, ray.wavelengths, ray.time));
                return L;
            }
            const BSDF& bsdf = *si.shape->bsdf();
            if (first) record.record_first_hit(si);
            if ((bsdf.flags() & ~uint32_t(Null)) != 0) record.valid = true;
            if (const Emitter* emitter = si.shape->emitter(); emitter && !hide_emitters_) L += camera.contribute(beta * emitter->eval(si));
            L += scattered_direct(scene, sampler, si, bsdf, beta, camera);
            // Through a null surface, as path crosses it: what lies behind, seen directly still.
            if (!bsdf.has_null_lobe()) return L;
            beta *= bsdf.null_transmission(si);
            if (is_black(beta)) return L;
            camera.scatter(bsdf, null_lobe(), si, -si.wi, Null);
            ray = si.spawn_ray(ray.d);
        }
        return L;  // more null surfaces than a ray crosses: blocked
    }

    std::string to_string() const override { return "direct"; }

private:
    static BSDFContext null_lobe() {
        BSDFContext ctx;
        ctx.lobes = Null;
        return ctx;
    }

    // The direct light that the non-null lobes of `bsdf` scatter toward si.wi, times `beta`, what
    // the camera ray lost on its way to si (`camera`: its polarisation).
    Spectrum scattered_direct(const Scene& scene, Sampler& sampler, const SurfaceInteraction& si, const BSDF& bsdf, const Spectrum& beta,
                              const PolarizedPath& camera) const {
        BSDFContext ctx;
        ctx.lobes = AllLobes & ~uint32_t(Null);
        if ((bsdf.flags() & ctx.lobes) == 0) return Spectrum(0.0f);
        Spectrum L(0.0f);
        if (bsdf.has_smooth_lobe())
            for (int i = 0; i < emitter_samples_; ++i) {
                StokesSpectrum arriving;
                const Spectrum nee =
                    sample_emitter_mis(scene, *lights_, sampler, si, bsdf, ctx, shares_, {}, camera.active() ? &arriving : nullptr);
                L += camera.contribute(beta * nee / float(emitter_samples_), &arriving);
            }
        for (int i = 0; i < bsdf_samples_; ++i) {
            float u_lobe = draw_lobe_number(bsdf, sampler);
            Vec2 u_dir = sampler.next_2d();
            BSDFSample bs = bsdf.sample(ctx, si, u_lobe, u_dir);
            if (!bs.valid() || is_black(bs.weight)) continue;
            PolarizedPath branch = camera;
            branch.scatter(bsdf, ctx, si, bs.wo, bs.lobe);
            Ray ray = si.spawn_ray(si.to_world(bs.wo));
            L += emission_along(scene, ray, si, bs.pdf, is_delta(bs.lobe), beta * bs.weight / float(bsdf_samples_), branch);
        }
        return L;
    }

    // The emission a BSDF sample from `from` (pdf `pdf`, weight `T`, polarisation `path`) finds
    // along `ray`: the emitters it hits, through null surfaces (their null_transmission, as
    // shadow rays see them), or the environment, each weighted against light sampling.
    Spectrum emission_along(const Scene& scene, Ray ray, const SurfaceInteraction& from, float pdf, bool delta, Spectrum T,
                            PolarizedPath path) const {
        Spectrum L(0.0f);
        for (int crossed = 0; crossed <= MaxNullCrossings; ++crossed) {
            SurfaceInteraction si;
            if (!scene.intersect(ray, si))
                return L + path.contribute(T * environment_mis(scene, *lights_, from, ray.d, pdf, delta, shares_));
            if (const Emitter* emitter = si.shape->emitter()) {
                Spectrum Le = emitter->eval(si);
                if (!is_black(Le))
                    L += path.contribute(T * Le * (delta ? 1.0f : emitter_hit_weight(*lights_, from, pdf, *emitter, si, shares_)));
            }
            const BSDF& bsdf = *si.shape->bsdf();
            if (!bsdf.has_null_lobe()) return L;
            T *= bsdf.null_transmission(si);
            if (is_black(T)) return L;
            path.scatter(bsdf, null_lobe(), si, -si.wi, Null);
            ray = si.spawn_ray(ray.d);
        }
        return L;
    }

    int emitter_samples_ = 1, bsdf_samples_ = 1;
    bool hide_emitters_ = false;
    std::string light_strategy_;
    StrategyShares shares_;
    std::unique_ptr<LightSampler> lights_;
};

CANDELA_REGISTER_SPECTRAL(DirectIntegrator, ObjectKind::Integrator, "direct");

}  // namespace candela
