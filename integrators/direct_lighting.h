#pragma once
// The two strategies of direct lighting at a surface vertex and their multiple importance
// sampling (Veach's power heuristic), shared by the path and direct integrators: next-event
// estimation (a light picked by a LightSampler, a point on it, a shadow ray), and the weight of
// emission that a BSDF sample finds. Each strategy's pdf is scaled by the share of samples it
// takes (Veach's n_i): path takes one sample of each (shares 1 and 1, the plain heuristic),
// direct emitter_samples and bsdf_samples.

#include "core/bsdf.h"
#include "core/rng.h"
#include "core/wavelengths.h"
#include "lights/light_sampler.h"

#include <optional>

namespace candela {

class Medium;
class Scene;
class Sampler;

// The polarized variant's part of a camera path (core/mueller.h): the product of the Mueller
// matrices it has met since the camera, in world bases and each divided by its (0, 0) element
// (the intensity stays in the path's throughput, as in the other variants), and the sample's
// Stokes sum it adds to. Inactive (stokes null, every call a no-op) in the other variants.
struct PolarizedPath {
    StokesSpectrum* stokes = nullptr;
    // Only in the polarized variant (an empty optional costs the other variants nothing per path).
    std::optional<MuellerSpectrum> product;

    PolarizedPath() = default;
    explicit PolarizedPath(const Wavelengths* wavelengths) { begin(wavelengths); }
    // (Re)starts the path in place: active, with the identity product, when the wavelengths carry
    // a Stokes sum (the polarized variant). Inline, and no temporary to copy: the other variants
    // pay a test (a temporary's fields read back as one block stalled store forwarding).
    void begin(const Wavelengths* wavelengths) {
        stokes = wavelengths ? wavelengths->stokes : nullptr;
        if (stokes) begin_product();
    }
    bool active() const { return stokes != nullptr; }
    // A contribution `c` to the sample (its intensity, as the other variants add it) of light
    // reaching the path's current vertex with normalised Stokes vectors `arriving` (null:
    // unpolarised, as every emitter emits): adds the Stokes vector the camera sees to the sum and
    // returns its S0, what the film adds.
    Spectrum contribute(const Spectrum& c, const StokesSpectrum* arriving = nullptr) const {
        return stokes ? contribute_polarized(c, arriving) : c;  // inline: the other variants pay a test
    }
    // The path goes on from `si` through `lobe` of `bsdf` toward `wo` (local).
    void scatter(const BSDF& bsdf, const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe) {
        if (stokes) scatter_polarized(bsdf, ctx, si, wo, lobe);
    }

private:
    void begin_product();
    Spectrum contribute_polarized(const Spectrum& c, const StokesSpectrum* arriving) const;
    void scatter_polarized(const BSDF& bsdf, const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe);
};

struct StrategyShares {
    float emitter = 1.0f, bsdf = 1.0f;
};

// The medium a path is in at a vertex, and the random numbers of its tracking (volpath). Without
// an rng (path, direct) shadow rays see only surfaces, through one any-hit query when they can.
struct PathMedium {
    const Medium* medium = nullptr;
    PCG32* rng = nullptr;
};

// The first half of next-event estimation, before any BSDF or phase function: a light picked by
// the light sampler (one 1D number) and a point on it seen from `at` (one 2D number), with the
// light's weight (radiance over its pdf) and the pick probability.
struct LightSample {
    const Emitter* emitter = nullptr;
    float pick_prob = 0.0f;
    DirectionSample ds;
    Spectrum weight{0.0f};
    // False when nothing could be sampled (no light, zero probability, pdf or weight).
    bool valid() const { return emitter && ds.pdf > 0.0f && !is_black(weight); }
};
// Its numbers: the pick, then the point, drawn in that order from the sampler's current
// dimension (the pick skipped when the light sampler does not read it). Drawn apart from their
// use so that a caller can draw in the sampler's order and compute in another (surface_step).
struct LightSampleNumbers {
    float pick = 0.5f;
    Vec2 point{0.5f};
};
LightSampleNumbers draw_light_numbers(const LightSampler& lights, Sampler& sampler);
// The 1D number that picks a lobe of `bsdf` (u_lobe of BSDF::sample): drawn, or skipped
// (Sampler::skip_1d, the later numbers unchanged) for a BSDF that does not read it.
float draw_lobe_number(const BSDF& bsdf, Sampler& sampler);
// Returned by value and built in place: the emitter writes its DirectionSample straight into
// the result (assigning it to an existing LightSample copied it through memory, and the reloads
// stalled store forwarding).
LightSample draw_light_sample(const LightSampler& lights, const LightSampleNumbers& u, const SurfaceInteraction& at);
inline LightSample draw_light_sample(const LightSampler& lights, Sampler& sampler, const SurfaceInteraction& at) {
    return draw_light_sample(lights, draw_light_numbers(lights, sampler), at);
}

// The shadow ray from `at` to a sampled light point: a direction for an infinitely distant
// light, else a segment that stops short of the point's surface (its normal and error bound).
Ray shadow_ray(const SurfaceInteraction& at, const DirectionSample& ds);

// A next-event-estimation sample before its shadow ray is traced: that ray, and what
// sample_emitter_mis returns once its transmittance T is known, contribution(T). A wavefront
// traces the shadow rays of many paths together (Scene::occluded_batch) and adds the
// contributions of those that are clear. Written into the caller's `out` (a wavefront's lane
// keeps it; returned by value it was built and then copied there, 1% of a Cornell box render).
struct UnshadowedLight {
    Spectrum f{0.0f};             // the BSDF toward the light (eval)
    Spectrum light_weight{0.0f};  // the light's radiance over its pdf
    float scale = 0.0f;           // the MIS weight over the light's pick probability
    Ray shadow;
    Vec3 wo{0.0f};       // toward the light, local
    Vec3 towards{0.0f};  // toward the light, world
    bool valid = false;  // false: no contribution, and no shadow ray to trace
    // Its estimate once the shadow ray's transmittance T is known.
    Spectrum contribution(const Spectrum& T) const { return T * f * light_weight * scale; }
};
void unshadowed_emitter_mis(const LightSampler& lights, const LightSampleNumbers& u, const SurfaceInteraction& si, const BSDF& bsdf,
                            const BSDFContext& ctx, UnshadowedLight& out, StrategyShares shares = {});

// One next-event-estimation sample at `si` (si.wi set) for `bsdf` restricted to `ctx`: the light's
// radiance times the BSDF and the shadow ray's transmittance (through null surfaces, and media
// when `medium` has an rng: the ray starts in the medium on its side of si), over the light's
// pdf, weighted against BSDF sampling (weight 1 for delta lights). Draws one 1D and one 2D
// number. With `arriving` (the polarized variant) also the normalised Stokes vectors of that
// light as it leaves si toward si.wi (what PolarizedPath::contribute takes).
Spectrum sample_emitter_mis(const Scene& scene, const LightSampler& lights, const LightSampleNumbers& u, const SurfaceInteraction& si,
                            const BSDF& bsdf, const BSDFContext& ctx, StrategyShares shares = {}, const PathMedium& medium = {},
                            StokesSpectrum* arriving = nullptr);
inline Spectrum sample_emitter_mis(const Scene& scene, const LightSampler& lights, Sampler& sampler, const SurfaceInteraction& si,
                                   const BSDF& bsdf, const BSDFContext& ctx, StrategyShares shares = {}, const PathMedium& medium = {},
                                   StokesSpectrum* arriving = nullptr) {
    return sample_emitter_mis(scene, lights, draw_light_numbers(lights, sampler), si, bsdf, ctx, shares, medium, arriving);
}
// The transmittance of a shadow ray from `si` (Scene::transmittance: through null surfaces, and
// through media from `medium` when `rng` is given) and, with `arriving` (the polarized variant),
// the light it brings as it leaves si toward si.wi: its Stokes vectors after the polarising null
// surfaces it crossed and the scattering there by `bsdf` (toward `wo`, local; skipped for a null
// `bsdf`: a medium's phase function keeps the polarisation, as in Mitsuba). The other variants
// do not build the crossed surfaces' Mueller product (192 bytes).
Spectrum shadow_transmittance(const Scene& scene, const Ray& shadow, const Medium* medium, PCG32* rng, const BSDF* bsdf,
                              const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, StokesSpectrum* arriving);

// The MIS weight of the emission of `emitter` at `hit`, found by a BSDF sample of solid-angle pdf
// `bsdf_pdf` from `from` (not a delta lobe), against next-event estimation from `from`.
float emitter_hit_weight(const LightSampler& lights, const SurfaceInteraction& from, float bsdf_pdf, const Emitter& emitter,
                         const SurfaceInteraction& hit, StrategyShares shares = {});

// The radiance of the infinite emitters along direction `d` escaping from `from`, each weighted
// against next-event estimation (weight 1 after a delta lobe).
Spectrum environment_mis(const Scene& scene, const LightSampler& lights, const SurfaceInteraction& from, const Vec3& d, float bsdf_pdf,
                         bool from_delta, StrategyShares shares = {});

}  // namespace candela
