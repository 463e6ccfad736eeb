#pragma once
// The surface vertex of a camera path, written once for `path` and `volpath` (and, through
// `path`, for irradiance, the estimators and the direct light of sppm and photonmapper):
// Russian roulette for the scattering event that led here, next-event estimation, the BSDF
// sample, and the throughput; and the emission a path finds where it arrives. A Null lobe (null,
// a mask's transparent part) passes the path on without a scattering event, at most
// MaxNullCrossings times in a row. What only media need (free flights, phase functions, the
// medium a ray is in) stays in volpath.cpp.
//
// Sample dimensions: every vertex the path meets (a Null crossing included) claims its own block
// of SampleDimensions, used or not, so that vertex k always draws the same dimensions.

#include "core/medium.h"
#include "integrators/direct_lighting.h"
#include "integrators/path_settings.h"

namespace candela {

class Scene;
class Sampler;
struct SamplerState;

// Where the path last scattered (a surface bounce or a real collision in a medium): the point
// that MIS weights of emission found later refer to. Before the first event it is the camera,
// a delta.
struct ScatterVertex {
    SurfaceInteraction at;
    float pdf = 0.0f;
    bool delta = true;
};

// A camera path between vertices.
struct CameraPath {
    CameraPath() = default;
    // A path that leaves `start` first, `from` built in place: assigned after default
    // construction, a whole SurfaceInteraction was zeroed (rep stos, about 1% of a Cornell box
    // render) only to be overwritten.
    explicit CameraPath(const SurfaceInteraction& start) : from{start, 0.0f, true} {}
    // The same path, started again in place (a wavefront lane reuses its path): assigning a new
    // CameraPath copied all of it, the polarized variant's empty Mueller product included (408
    // bytes by rep movs on every camera sample: 1% of perf's samples, at most 0.5% of the time).
    void restart(const SurfaceInteraction& start) {
        weights = TrackingWeights();
        from.at = start;
        from.pdf = 0.0f;
        from.delta = true;
        depth = 0;
        eta = 1.0f;
        null_crossings = 0;
        scattered = false;
        // Inactive until begin(), field by field: `= PolarizedPath()` value-initialises a
        // temporary, which zeroes all of it (rep stos over 200 bytes) since its default
        // constructor is not user-provided.
        polarization.stokes = nullptr;
        polarization.product.reset();
    }

    // The throughput (beta) and, in chromatic media, volpath's spectral MIS ratio; without media
    // estimate_weight() is beta itself.
    TrackingWeights weights;
    ScatterVertex from;
    uint32_t depth = 0;          // scattering events so far (max_depth counts them)
    float eta = 1.0f;            // relative indices crossed: roulette keeps paths inside glass alive
    int null_crossings = 0;      // Null lobes crossed since the last scattering event
    bool scattered = false;      // met a surface that is not purely null, or scattered (the film's alpha)
    PolarizedPath polarization;  // the polarized variant's Mueller product (inactive otherwise)

    // Records a scattering event at `at` sampled with solid-angle density `pdf`.
    void scatter(const SurfaceInteraction& at, float pdf, bool delta) {
        from = ScatterVertex{at, pdf, delta};
        ++depth;
        null_crossings = 0;
    }
};

// Russian roulette by roulette_continue_probability (path_settings.h) of the estimate weight,
// once the path's depth reaches rr_depth; a survivor's throughput is divided by it. Draws
// dimension dims + Roulette. False when the path ends.
bool survive_roulette(const PathSettings& settings, Sampler& sampler, uint32_t dims, CameraPath& path);

// A next-event estimate held back until its shadow ray is traced (a wavefront traces many
// paths' shadow rays together): `light` (its shadow ray, BSDF value, weight and MIS scale) and
// the path's estimate weight at the vertex; value(T) is what joins the path's radiance once the
// shadow ray's transmittance T is known (1 when clear and the scene has no Null surfaces), the
// same product sample_emitter_mis forms. Only in no medium and without Stokes vectors (not
// polarized).
struct PendingShadow {
    UnshadowedLight light;
    Spectrum path_weight{0.0f};
    bool pending = false;
    Spectrum value(const Spectrum& T) const { return path_weight * light.contribution(T); }
};

// The surface vertex whose numbers start at dimension `dims` (SampleDimensions::bounce(k) for
// vertex k of a camera path; si.wi set, `bsdf` its BSDF): next-event estimation added to `L`
// (times the path's estimate weight; `medium` is where the path is, for the shadow rays), the
// BSDF sample, and after a scattering event the Russian roulette (before the next ray is
// traced). Returns false when the path ends here; else `direction` (world) is where it goes on,
// through a Null lobe or after a scattering event, and the throughput includes the sample's
// weight (and 1 / q of a roulette it survived).
bool surface_step(const Scene& scene, const LightSampler& lights, const PathSettings& settings, Sampler& sampler, uint32_t dims,
                  const SurfaceInteraction& si, const BSDF& bsdf, const PathMedium& medium, CameraPath& path, Spectrum& L, Vec3& direction);

// The same vertex for a wavefront, in two halves, where the path is in no medium:
// draw_vertex_numbers draws the numbers surface_step would draw, in its order, from the lane's
// place in the sampler (the roulette's whenever the scattering event reaches rr_depth: should
// the BSDF sample end the path instead, its sample draws nothing after it anyway); then
// surface_step_drawn does what surface_step does with them, next-event estimation's shadow ray
// held back in `deferred` (pending when there is one; not added to L). Behind a BSDF with a Null
// lobe the roulette's number is drawn only if the sampled lobe scatters, as surface_step draws
// it: surface_step_drawn draws it then from `later`, the lane's place after the other numbers.
struct VertexNumbers {
    LightSampleNumbers light;
    float lobe = 0.5f;
    Vec2 direction{0.5f};
    float roulette = 0.5f;
    bool roulette_drawn = false;
};
struct LaterDraws {
    Sampler& sampler;
    SamplerState& state;
    uint32_t dims;
};
void draw_vertex_numbers(const LightSampler& lights, const PathSettings& settings, Sampler& sampler, uint32_t dims, const BSDF& bsdf,
                         const CameraPath& path, VertexNumbers& u);
bool surface_step_drawn(const Scene& scene, const LightSampler& lights, const PathSettings& settings, const VertexNumbers& u,
                        LaterDraws later, const SurfaceInteraction& si, const BSDF& bsdf, CameraPath& path, Spectrum& L, Vec3& direction,
                        PendingShadow& deferred);

// The emission the path finds at surface `hit` (0 when hide_emitters hides it: nothing has
// scattered yet), weighted against next-event estimation from the last scattering vertex, times
// the path's estimate weight.
Spectrum emission_found(const LightSampler& lights, const PathSettings& settings, const CameraPath& path, const SurfaceInteraction& hit);
// The same for a path that leaves the scene along `direction`: the environment.
Spectrum environment_found(const Scene& scene, const LightSampler& lights, const PathSettings& settings, const CameraPath& path,
                           const Vec3& direction);

}  // namespace candela
