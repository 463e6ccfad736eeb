#include "integrators/surface_step.h"

#include "core/sampler.h"
#include "core/scene.h"
#include "core/wavelengths.h"

namespace candela {

namespace {

// Russian roulette's decision with the number `u` (survive_roulette's rule).
bool survive_with(float u, CameraPath& path) {
    const float q = roulette_continue_probability(path.weights.estimate_weight(), path.eta);
    if (!(u < q)) return false;
    path.weights.beta /= q;
    return true;
}

// The numbers of the vertex at `dims`, drawn from the sampler as the vertex asks for them, in
// the sampler's order: the light pick and position (LightPick, LightPosition), the lobe and
// direction, the roulette.
struct DrawnFromSampler {
    const LightSampler& lights;
    Sampler& sampler;
    uint32_t dims;

    LightSampleNumbers light(bool estimate_next_event) {
        sampler.set_dimension(dims + SampleDimensions::LightPick);
        return estimate_next_event ? draw_light_numbers(lights, sampler) : LightSampleNumbers{};
    }
    float lobe(const BSDF& bsdf) {
        sampler.set_dimension(dims + SampleDimensions::Lobe);
        return draw_lobe_number(bsdf, sampler);
    }
    Vec2 direction() { return sampler.next_2d(); }
    float roulette() {
        sampler.set_dimension(dims + SampleDimensions::Roulette);
        return sampler.next_1d();
    }
};

// The numbers drawn before (draw_vertex_numbers); the roulette's, when it was not, drawn now
// from the lane's place in the sampler.
struct DrawnBefore {
    const VertexNumbers& u;
    LaterDraws later;
    LightSampleNumbers light(bool) const { return u.light; }
    float lobe(const BSDF&) const { return u.lobe; }
    Vec2 direction() const { return u.direction; }
    float roulette() {
        if (u.roulette_drawn) return u.roulette;
        later.sampler.restore(later.state);
        later.sampler.set_dimension(later.dims + SampleDimensions::Roulette);
        const float number = later.sampler.next_1d();
        later.sampler.save(later.state);
        return number;
    }
};

// The vertex of surface_step, its numbers from `numbers`.
template <class Numbers>
bool scatter_at_surface(const Scene& scene, const LightSampler& lights, const PathSettings& settings, Numbers& numbers,
                        const SurfaceInteraction& si, const BSDF& bsdf, const PathMedium& medium, CameraPath& path, Spectrum& L,
                        Vec3& direction, PendingShadow* deferred) {
    if (!bsdf.has_null_lobe()) path.scattered = true;
    // At the last allowed bounce only a Null lobe may still carry the path on.
    const bool may_scatter = settings.may_extend(path.depth);
    if (!may_scatter && !bsdf.has_null_lobe()) return false;
    BSDFContext ctx;
    if (!may_scatter) ctx.lobes = Null;
    const bool estimate_next_event = may_scatter && bsdf.has_smooth_lobe();
    const LightSampleNumbers u_light = numbers.light(estimate_next_event);
    const float u_lobe = numbers.lobe(bsdf);
    const Vec2 u_direction = numbers.direction();
    // The BSDF sample before next-event estimation, which does not change it: the warp's
    // dependent chain (a division, a polynomial, a square root) then runs alongside the light
    // sample's instead of between the shadow ray and the extension ray, where nothing overlaps it.
    const BSDFSample bs = bsdf.sample(ctx, si, u_lobe, u_direction);
    if (estimate_next_event && deferred) {
        unshadowed_emitter_mis(lights, u_light, si, bsdf, BSDFContext(), deferred->light);
        deferred->pending = deferred->light.valid;
        if (deferred->pending) deferred->path_weight = path.weights.estimate_weight();
    } else if (estimate_next_event) {
        StokesSpectrum arriving;
        const Spectrum nee = sample_emitter_mis(scene, lights, u_light, si, bsdf, BSDFContext(), {}, medium,
                                                path.polarization.active() ? &arriving : nullptr);
        L += path.polarization.contribute(path.weights.estimate_weight() * nee, &arriving);
    }
    if (!bs.valid() || bs.lobe != Null) path.scattered = true;
    if (!bs.valid() || is_black(bs.weight)) return false;
    if (bs.dispersed && si.wavelengths) si.wavelengths->terminate_secondary();
    path.weights.beta *= bs.weight;
    path.polarization.scatter(bsdf, ctx, si, bs.wo, bs.lobe);
    if (bs.lobe == Null) {
        // No scattering event: neither the depth nor the vertex MIS weights refer to changes.
        if (++path.null_crossings > MaxNullCrossings) return false;
    } else {
        path.eta *= bs.eta;
        path.scatter(si, bs.pdf, is_delta(bs.lobe));
        // Russian roulette before the extension ray is traced, as Mitsuba decides it: a path it
        // ends costs no ray (nor the emission that ray would have found, which the survivors'
        // 1 / q makes up for).
        if (path.depth >= uint32_t(settings.rr_depth) && !survive_with(numbers.roulette(), path)) return false;
    }
    direction = si.to_world(bs.wo);
    return max_component(path.weights.beta) > 0.0f;
}

}  // namespace

bool survive_roulette(const PathSettings& settings, Sampler& sampler, uint32_t dims, CameraPath& path) {
    if (path.depth < uint32_t(settings.rr_depth)) return true;
    sampler.set_dimension(dims + SampleDimensions::Roulette);
    return survive_with(sampler.next_1d(), path);
}

bool surface_step(const Scene& scene, const LightSampler& lights, const PathSettings& settings, Sampler& sampler, uint32_t dims,
                  const SurfaceInteraction& si, const BSDF& bsdf, const PathMedium& medium, CameraPath& path, Spectrum& L,
                  Vec3& direction) {
    DrawnFromSampler numbers{lights, sampler, dims};
    return scatter_at_surface(scene, lights, settings, numbers, si, bsdf, medium, path, L, direction, nullptr);
}

void draw_vertex_numbers(const LightSampler& lights, const PathSettings& settings, Sampler& sampler, uint32_t dims, const BSDF& bsdf,
                         const CameraPath& path, VertexNumbers& u) {
    const bool may_scatter = settings.may_extend(path.depth);
    u.roulette_drawn = false;
    if (!may_scatter && !bsdf.has_null_lobe()) return;  // the vertex ends the path before drawing
    DrawnFromSampler numbers{lights, sampler, dims};
    u.light = numbers.light(may_scatter && bsdf.has_smooth_lobe());
    u.lobe = numbers.lobe(bsdf);
    u.direction = numbers.direction();
    // The scattering event takes the path to depth + 1; the roulette's number is drawn only
    // where it will be read (a stream sampler's later numbers stay in place): behind a Null lobe
    // only once the lobe is known (DrawnBefore::roulette).
    if (may_scatter && !bsdf.has_null_lobe() && path.depth + 1 >= uint32_t(settings.rr_depth)) {
        u.roulette = numbers.roulette();
        u.roulette_drawn = true;
    }
}

bool surface_step_drawn(const Scene& scene, const LightSampler& lights, const PathSettings& settings, const VertexNumbers& u,
                        LaterDraws later, const SurfaceInteraction& si, const BSDF& bsdf, CameraPath& path, Spectrum& L, Vec3& direction,
                        PendingShadow& deferred) {
    DrawnBefore numbers{u, later};
    return scatter_at_surface(scene, lights, settings, numbers, si, bsdf, PathMedium{}, path, L, direction, &deferred);
}

Spectrum emission_found(const LightSampler& lights, const PathSettings& settings, const CameraPath& path, const SurfaceInteraction& hit) {
    const Emitter* emitter = hit.shape->emitter();
    // Hidden: seen directly, through null surfaces at most.
    if (!emitter || (settings.hide_emitters && path.depth == 0)) return Spectrum(0.0f);
    const Spectrum Le = emitter->eval(hit);
    if (is_black(Le)) return Spectrum(0.0f);
    return path.polarization.contribute(path.weights.estimate_weight() * Le *
                                        (path.from.delta ? 1.0f : emitter_hit_weight(lights, path.from.at, path.from.pdf, *emitter, hit)));
}

Spectrum environment_found(const Scene& scene, const LightSampler& lights, const PathSettings& settings, const CameraPath& path,
                           const Vec3& direction) {
    if (settings.hide_emitters && path.depth == 0) return Spectrum(0.0f);
    return path.polarization.contribute(path.weights.estimate_weight() *
                                        environment_mis(scene, lights, path.from.at, direction, path.from.pdf, path.from.delta));
}

}  // namespace candela
