#include "integrators/direct_lighting.h"

#include "core/sampler.h"
#include "core/scene.h"
#include "core/wavelengths.h"

namespace candela {

void PolarizedPath::begin_product() { product = identity_spectrum(); }

Spectrum PolarizedPath::contribute_polarized(const Spectrum& c, const StokesSpectrum* arriving) const {
    Spectrum s0;
    for (int k = 0; k < 3; ++k) {
        const Mueller& P = product->w[k];
        // Unpolarised light is the first column's direction: P (1, 0, 0, 0).
        const Stokes s = arriving ? P * arriving->w[k] : first_column(P);
        stokes->w[k] += c[k] * s;
        s0[k] = c[k] * s[0];
    }
    return s0;
}

void PolarizedPath::scatter_polarized(const BSDF& bsdf, const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo,
                                      uint32_t lobe) {
    multiply_by_bsdf(*product, bsdf, ctx, si, wo, lobe);
}

Spectrum shadow_transmittance(const Scene& scene, const Ray& shadow, const Medium* medium, PCG32* rng, const BSDF* bsdf,
                              const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, StokesSpectrum* arriving) {
    auto transmittance = [&](MuellerSpectrum* crossed) {
        return rng ? scene.transmittance(shadow, medium, *rng, crossed) : scene.transmittance(shadow, crossed);
    };
    if (!arriving) return transmittance(nullptr);
    MuellerSpectrum crossed;  // only here: zeroing it per shadow ray cost the other variants (1105a23)
    const Spectrum T = transmittance(&crossed);
    if (is_black(T)) return T;
    for (int k = 0; k < 3; ++k) arriving->w[k] = first_column(crossed.w[k]);
    if (bsdf) scatter_stokes(*bsdf, ctx, si, wo, BSDFNone, *arriving);
    return T;
}

LightSampleNumbers draw_light_numbers(const LightSampler& lights, Sampler& sampler) {
    LightSampleNumbers u;
    if (lights.reads_pick_sample())
        u.pick = sampler.next_1d();
    else
        sampler.skip_1d();
    u.point = sampler.next_2d();
    return u;
}

float draw_lobe_number(const BSDF& bsdf, Sampler& sampler) {
    if (bsdf.reads_lobe_sample()) return sampler.next_1d();
    sampler.skip_1d();
    return 0.5f;
}

LightSample draw_light_sample(const LightSampler& lights, const LightSampleNumbers& u, const SurfaceInteraction& at) {
    float pick_prob = 0.0f;
    const Emitter* emitter = lights.sample(at, u.pick, pick_prob);
    if (!emitter || !(pick_prob > 0.0f)) return LightSample{};
    Spectrum weight(0.0f);
    // Braced initialisers run in order: sample_direction sets `weight` before it is copied.
    return LightSample{emitter, pick_prob, emitter->sample_direction(at, u.point, weight), weight};
}

Ray shadow_ray(const SurfaceInteraction& at, const DirectionSample& ds) {
    return std::isinf(ds.dist) ? at.spawn_ray(ds.d) : at.spawn_ray_to(ds.p, ds.delta ? Vec3(0.0f) : ds.n, ds.p_error);
}

void unshadowed_emitter_mis(const LightSampler& lights, const LightSampleNumbers& u, const SurfaceInteraction& si, const BSDF& bsdf,
                            const BSDFContext& ctx, UnshadowedLight& out, StrategyShares shares) {
    out.valid = false;
    const LightSample light = draw_light_sample(lights, u, si);
    if (!light.valid()) return;
    const DirectionSample& ds = light.ds;
    out.wo = si.to_local(ds.d);
    // eval and pdf together (the pdf weighs this sample against BSDF sampling below).
    const BSDFEvalPdf f_pdf = bsdf.eval_pdf(ctx, si, out.wo);
    if (is_black(f_pdf.value)) return;
    out.f = f_pdf.value;
    out.light_weight = light.weight;
    const float w = ds.delta ? 1.0f : power_heuristic(ds.pdf * light.pick_prob * shares.emitter, f_pdf.pdf * shares.bsdf);
    out.scale = w / light.pick_prob;
    out.shadow = shadow_ray(si, ds);
    out.towards = ds.d;
    out.valid = true;
}

Spectrum sample_emitter_mis(const Scene& scene, const LightSampler& lights, const LightSampleNumbers& u, const SurfaceInteraction& si,
                            const BSDF& bsdf, const BSDFContext& ctx, StrategyShares shares, const PathMedium& medium,
                            StokesSpectrum* arriving) {
    UnshadowedLight light;
    unshadowed_emitter_mis(lights, u, si, bsdf, ctx, light, shares);
    if (!light.valid) return Spectrum(0.0f);
    // Through null surfaces and masks, and media when there is an rng (from the medium on the light's side).
    const Medium* start = medium.rng && si.shape->is_medium_transition() ? si.shape->target_medium(si, light.towards) : medium.medium;
    const Spectrum T = shadow_transmittance(scene, light.shadow, start, medium.rng, &bsdf, ctx, si, light.wo, arriving);
    if (is_black(T)) return Spectrum(0.0f);
    return light.contribution(T);
}

float emitter_hit_weight(const LightSampler& lights, const SurfaceInteraction& from, float bsdf_pdf, const Emitter& emitter,
                         const SurfaceInteraction& hit, StrategyShares shares) {
    // Measured from the scattering vertex itself, as light sampling measures it.
    DirectionSample ds;
    ds.p = hit.p;
    ds.n = hit.shading.n;  // the normal the light's own sampling uses (Mesh::sample_position)
    Vec3 to = hit.p - from.p;
    ds.dist = glm::length(to);
    ds.d = to / ds.dist;
    return power_heuristic(bsdf_pdf * shares.bsdf, lights.pmf(from, &emitter) * emitter.pdf_direction(from, ds) * shares.emitter);
}

Spectrum environment_mis(const Scene& scene, const LightSampler& lights, const SurfaceInteraction& from, const Vec3& d, float bsdf_pdf,
                         bool from_delta, StrategyShares shares) {
    Spectrum L(0.0f);
    for (const Emitter* e : scene.infinite_emitters()) {
        if (from_delta) {
            L += e->eval_environment(d, from.wavelengths, from.time);
            continue;
        }
        float pdf = 0.0f;
        const Spectrum Le = e->eval_environment_pdf(from, d, pdf);
        if (is_black(Le)) continue;
        L += Le * power_heuristic(bsdf_pdf * shares.bsdf, lights.pmf(from, e) * pdf * shares.emitter);
    }
    return L;
}

}  // namespace candela
