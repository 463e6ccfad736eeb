#include "integrators/photons.h"

#include "core/sampler.h"
#include "core/scene.h"
#include "integrators/direct_lighting.h"
#include "integrators/path_settings.h"

namespace candela {

void refuse_polarized_photons(const Properties& props, const char* name) {
    if (props.variant() == Variant::ScalarSpectralPolarized)
        props.fail(std::string(name) +
                   " does not render in variant scalar_spectral_polarized yet (its photons carry no Stokes vector); "
                   "it renders in scalar_spectral and scalar_rgb");
}

GatherPoint walk_to_gather_point(const Scene& scene, Sampler& sampler, Ray ray, Spectrum beta, uint32_t depth,
                                 const WalkSettings& settings) {
    GatherPoint end;
    const uint32_t start = depth;
    float eta = 1.0f;
    bool all_delta = true;
    SurfaceInteraction& si = end.si;
    auto within = [&](uint32_t d) { return settings.max_depth < 0 || d <= uint32_t(settings.max_depth); };
    auto add_emission = [&](const Spectrum& Le, uint32_t d) {
        if (settings.hide_first && d == start + 1) return;
        (all_delta ? end.emission_after_delta : end.emission_after_other) += beta * Le;
    };
    // A Null lobe (null, mask, a thindielectric sheet) is crossed without a segment counted, at
    // most MaxNullCrossings in a row, as path crosses it.
    int null_crossings = 0;
    for (++depth; within(depth);) {
        if (!scene.intersect(ray, si)) {
            add_emission(scene.eval_environment(ray.d, ray.wavelengths, ray.time), depth);
            break;
        }
        if (const Emitter* e = si.shape->emitter()) add_emission(e->eval(si), depth);
        const BSDF& bsdf = *si.shape->bsdf();
        if (gathers_photons(bsdf)) {
            end.bsdf = &bsdf;
            end.beta = beta;
            end.depth = depth;
            break;
        }
        // The 2D sample first, as GCC evaluated the former call's arguments (last first): the
        // order of a call's argument evaluation is unspecified, so it is written out.
        const Vec2 u_dir = sampler.next_2d();
        const float u_lobe = draw_lobe_number(bsdf, sampler);
        BSDFSample bs = bsdf.sample(BSDFContext(), si, u_lobe, u_dir);
        if (!bs.valid() || is_black(bs.weight)) break;
        if (bs.dispersed && si.wavelengths) si.wavelengths->terminate_secondary();
        beta *= bs.weight;
        ray = si.spawn_ray(si.to_world(bs.wo));
        if (bs.lobe == Null) {
            if (++null_crossings > MaxNullCrossings) break;
            continue;
        }
        null_crossings = 0;
        eta *= bs.eta;
        all_delta = all_delta && is_delta(bs.lobe);
        if (depth >= uint32_t(settings.rr_depth)) {
            float q = roulette_continue_probability(beta, eta);
            if (!(sampler.next_1d() < q)) break;
            beta /= q;
        }
        ++depth;
    }
    return end;
}

}  // namespace candela
