// sppm: stochastic progressive photon mapping (Hachisuka and Jensen 2009), with direct light by
// next-event estimation at the visible points (as pbrt-v3's SPPM does). Consistent: every pass
// shrinks each pixel's gather radius, and the image converges to the one `path` renders,
// including caustics seen on diffuse surfaces (light through glass) that path tracing renders as
// fireflies.
//
// Parameters (Mitsuba 0.6 names, snake_case as Mitsuba 3 upgrades them):
//   photon_count     integer   light paths emitted per pass (default 250000); Mitsuba counts
//                              stored photons instead, which varies with the scene
//   initial_radius   float     first gather radius in scene units (default 0: five pixels' worth,
//                              5 r / max(width, height) with r the scene's bounding radius, as
//                              Mitsuba guesses it)
//   alpha            float     the fraction of new photons kept each pass, in (0, 1): the radius
//                              shrinks by sqrt((N + alpha M) / (N + M)) (default 0.7)
//   granularity      integer   light paths per parallel work unit (default 0: 4096); the image
//                              does not depend on it
//   max_passes       integer   passes to render (default -1: the sampler's sample count; --spp
//                              overrides both); each pass takes one camera sample per pixel
//   max_depth        integer   longest path in segments (camera ray included), -1 = unbounded
//                              (default); 1 = emitters seen directly, 2 = direct light
//   rr_depth         integer   segments after which Russian roulette may end light paths and
//                              camera paths through specular surfaces (default 5)
//   hide_emitters    boolean   emitters seen directly render black (default false)
//
// Each pass: (1) a camera ray per pixel (its position drawn from the film's reconstruction filter,
// so the pixel estimates the filtered image) follows delta and glossy-only surfaces, adding the
// emission it meets, to the first surface with a diffuse lobe and no delta lobe (plastic's
// coating is a delta lobe: such surfaces are passed through by sampling): the visible point, where direct light is estimated by next-event estimation with MIS (the `path`
// integrator's, one bounce); (2) photon_count light paths deposit photons on such surfaces from
// their second hit on (the first is direct light); (3) every visible point gathers the photons
// within its radius from a hash grid and updates its statistics. Pixel value: the mean direct
// term plus tau / (N_emitted pi R^2).
//
// In scalar_spectral each pass draws one set of wavelengths (its own stream), shared by the pass's
// camera and light paths (pbrt-v4's SPPM); each pixel and light path works on its own copy (a
// dispersive interface ends only that path's secondaries; a photon whose path dispersed carries
// its hero wavelength alone), and the pass's direct term and gathered flux are converted to RGB
// before they join the statistics. Not in scalar_spectral_polarized (its photons carry no Stokes
// vector).
//
// Motion blur the same way: each pass draws one shutter time (its own stream), at which its
// camera rays and light paths both meet moving shapes, emitters and cameras; the passes average
// over the shutter as they average over each pixel's area (consistent, as the rest).
//
// Deterministic: camera samples depend on (seed, pixel, pass), light paths on (seed, index); each
// visible point sums its photons in a fixed order (integrators/photon_grid.h). Not available:
// AOVs (passes are correlated, so there is no per-pixel variance).

#include "core/bsdf.h"
#include "core/distribution.h"
#include "core/film.h"
#include "core/memory_budget.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/wavelengths.h"
#include "integrators/light_paths.h"
#include "integrators/path.h"
#include "integrators/photons.h"

#include <tbb/enumerable_thread_specific.h>

#include <chrono>
#include <cstdio>

namespace candela {

namespace {

// Film positions drawn from the reconstruction filter around a pixel centre, with the weight
// h / pdf (1 for the box filter): the pixel estimates the filtered image, as `path` does.
class FilterSampler {
public:
    explicit FilterSampler(const ReconstructionFilter& filter) : filter_(filter), radius_(filter.radius()) {
        std::vector<float> w(Bins);
        for (int i = 0; i < Bins; ++i) w[i] = std::max(filter.eval(radius_ * (2.0f * (i + 0.5f) / Bins - 1.0f)), 0.0f) + 1e-6f;
        distribution_ = Distribution1D(std::move(w));
    }
    // An offset from the pixel centre and its weight.
    Vec2 sample(const Vec2& u, float& weight) const {
        float pdf_x, pdf_y;
        float x = radius_ * (2.0f * distribution_.sample_continuous(u.x, &pdf_x) - 1.0f);
        float y = radius_ * (2.0f * distribution_.sample_continuous(u.y, &pdf_y) - 1.0f);
        weight = filter_.eval(x) * filter_.eval(y) * (4.0f * radius_ * radius_) / (pdf_x * pdf_y);
        return Vec2(x, y);
    }

private:
    static constexpr int Bins = 256;
    const ReconstructionFilter& filter_;
    float radius_;
    Distribution1D distribution_;
};

// A pixel's progressive statistics (Hachisuka and Jensen 2009, section 4).
struct PixelState {
    float radius = 0.0f;
    double n = 0.0;
    double tau[3] = {0, 0, 0};
    double direct[3] = {0, 0, 0};  // sum over passes of the camera pass's own estimate
};

struct PassPhotons {
    std::vector<Photon> photons;
    uint64_t paths = 0;
};

}  // namespace

class SPPMIntegrator final : public Integrator {
public:
    explicit SPPMIntegrator(const Properties& props) : direct_(direct_settings()) {
        photon_count_ = props.get_int("photon_count", 250000);
        if (photon_count_ <= 0) props.fail("photon_count", "photon_count must be positive");
        initial_radius_ = props.get_float("initial_radius", 0.0f);
        if (!(initial_radius_ >= 0.0f) || !std::isfinite(initial_radius_)) props.fail("initial_radius", "initial_radius must be >= 0");
        alpha_ = props.get_float("alpha", 0.7f);
        if (!(alpha_ > 0.0f && alpha_ < 1.0f)) props.fail("alpha", "alpha must lie in (0, 1)");
        granularity_ = props.get_int("granularity", 0);
        if (granularity_ < 0) props.fail("granularity", "granularity must be >= 0");
        max_passes_ = props.get_int("max_passes", -1);
        if (max_passes_ == 0 || max_passes_ < -1) props.fail("max_passes", "max_passes must be positive (or -1)");
        settings_ = read_path_settings(props, DepthSettings | HideEmittersSetting);
        photon_count_location_ = props.location_of("photon_count");
        refuse_polarized_photons(props, "sppm");
    }

    RenderResult render(const Scene& scene, const RenderOptions& options) override;
    std::string to_string() const override { return "sppm"; }
    // Each pass is traced at one shutter time (camera rays and photons alike).
    bool renders_motion() const override { return true; }
    std::string parts_refusal() const override {
        return "each pass shrinks the photon radius of every visible point from the photons of all earlier passes, so a range "
               "of passes depends on those before it and its pixels have no independent samples";
    }

private:
    static PathSettings direct_settings() {
        PathSettings s;
        s.max_depth = 2;  // one bounce from the visible point: next-event estimation with MIS
        return s;
    }
    // The camera pass for one pixel: the emission and direct light found (returned) and the
    // visible point (vp.bsdf null when there is none).
    // `wavelengths`: the pixel's copy of the pass's wavelengths (spectral variant; null in RGB);
    // `time`: the pass's shutter time.
    Spectrum trace_camera(const Scene& scene, Sampler& sampler, const FilterSampler& filter, const Vec2i& pixel, Wavelengths* wavelengths,
                          float time, GatherPoint& vp) const;
    // The photons of light paths [begin, end) of pass `pass`, each path at its own copy of the
    // pass's wavelengths (spectral variant; null in RGB), at the pass's shutter time.
    void trace_photons(const LightPathTracer& tracer, uint64_t seed, uint64_t first, uint64_t count, const Wavelengths* wavelengths,
                       float time, PassPhotons& out) const;
    // Radiance from the photons near a visible point (sum of f beta, and their number). A photon
    // whose path dispersed carries only its hero wavelength: unless the visible point's own path
    // did too (its conversion then weighs the hero alone), its flux is the hero's, tripled, as
    // terminate_secondary weighs it.
    Spectrum gather(const PhotonGrid& grid, const GatherPoint& vp, float radius, uint64_t& found) const;
    // Stops the render (a SceneError at photon_count, exit code 2) before anything is allocated
    // when its buffers cannot fit in memory (core/memory_budget.h).
    void check_render_memory(const LightPathTracer& tracer, uint64_t seed, uint64_t chunk, size_t pixels) const;

    SourceLocation photon_count_location_;
    int photon_count_ = 250000, granularity_ = 0, max_passes_ = -1;
    PathSettings settings_;  // max_depth counts segments, camera ray included
    float initial_radius_ = 0.0f, alpha_ = 0.7f;
    PathIntegrator direct_;
};

Spectrum SPPMIntegrator::trace_camera(const Scene& scene, Sampler& sampler, const FilterSampler& filter, const Vec2i& pixel,
                                      Wavelengths* wavelengths, float time, GatherPoint& vp) const {
    float filter_weight;
    Vec2 offset = filter.sample(sampler.next_2d(), filter_weight);
    if (!scene.sensor().jitter()) offset = Vec2(0.0f), filter_weight = 1.0f;  // the pixel's centre
    Vec2 pos = Vec2(pixel) + Vec2(0.5f) + offset;
    Ray ray = scene.sensor().sample_ray(pos, sampler.next_2d(), time);
    ray.wavelengths = wavelengths;
    WalkSettings walk;
    walk.max_depth = settings_.max_depth;
    walk.rr_depth = settings_.rr_depth;
    walk.hide_first = settings_.hide_emitters;
    // The sensor's ray weight (pi for an irradiance meter) scales everything the path gathers.
    vp = walk_to_gather_point(scene, sampler, ray, Spectrum(filter_weight * scene.sensor().sample_weight(pos)), 0, walk);
    Spectrum L = vp.emission_after_delta + vp.emission_after_other;
    // The direct estimate draws after the walk's numbers (integrators/path.h, continue_path).
    if (vp.bsdf && settings_.within_depth(vp.depth + 1))
        L += vp.beta * direct_.continue_path(scene, sampler, vp.si, *vp.bsdf, 0, nullptr, sampler.dimension());
    return L;
}

void SPPMIntegrator::trace_photons(const LightPathTracer& tracer, uint64_t seed, uint64_t first, uint64_t count,
                                   const Wavelengths* wavelengths, float time, PassPhotons& out) const {
    out.photons.clear();
    out.paths = count;
    for (uint64_t i = 0; i < count; ++i) {
        PCG32 rng = light_path_rng(seed, 1, first + i);
        LightPathStart start;
        Wavelengths own;  // a dispersive interface ends this path's secondaries, not the pass's
        if (wavelengths) {
            own = *wavelengths;
            start.wavelengths = &own;
        }
        if (!tracer.start(rng, time, start)) continue;
        tracer.follow(rng, start, [&](const LightVertex& v) {
            // Direct light (depth 1) is next-event estimation's; the shortest camera path is one segment.
            if (!settings_.within_depth(v.depth + 1)) return false;
            if (v.depth >= 2 && gathers_photons(*v.bsdf) && all_finite(v.beta)) out.photons.push_back(make_photon(*v.si, v.beta, v.depth));
            return true;
        });
    }
}

Spectrum SPPMIntegrator::gather(const PhotonGrid& grid, const GatherPoint& vp, float radius, uint64_t& found) const {
    Spectrum phi(0.0f);
    found = 0;
    const BSDFContext ctx;
    const bool hero_only_here = vp.si.wavelengths && vp.si.wavelengths->secondary_terminated();
    grid.for_each_within(vp.si.p, radius, [&](const Photon& ph, float) {
        if (!settings_.within_depth(vp.depth + ph.depth)) return;
        Vec3 wi = vp.si.to_local(ph.wi);
        float cos_theta = std::abs(Frame::cos_theta(wi));
        ++found;
        if (cos_theta < 1e-6f) return;
        const Spectrum beta = ph.hero_only && !hero_only_here ? Spectrum(float(WavelengthSamples) * ph.beta.x, 0.0f, 0.0f) : ph.beta;
        phi += beta * vp.bsdf->eval(ctx, vp.si, wi) / cos_theta;  // f, without the cosine
    });
    return phi;
}

// The pixels' statistics, visible points and direct terms, and a pass's photons three times over
// (the work units' outputs, their concatenation, the grid's sorted copy) with the grid's bucket
// starts and bucket indices. How many photons a light path stores depends on the scene: it is
// measured on the first work unit of the first pass (the same paths the render traces first).
void SPPMIntegrator::check_render_memory(const LightPathTracer& tracer, uint64_t seed, uint64_t chunk, size_t pixels) const {
    PassPhotons pilot;
    trace_photons(tracer, seed, 0, std::min<uint64_t>(chunk, uint64_t(photon_count_)), nullptr, tracer.scene().sensor().shutter_open(),
                  pilot);
    const double per_path = double(pilot.photons.size()) / double(std::max<uint64_t>(pilot.paths, 1));
    const uint64_t photons = uint64_t(std::ceil(per_path * double(photon_count_)));
    const uint64_t per_pixel = sizeof(PixelState) + sizeof(GatherPoint) + sizeof(Spectrum) + sizeof(Wavelengths);
    const uint64_t per_photon = 3 * sizeof(Photon) + 5 * sizeof(uint32_t);
    const uint64_t bytes = saturating_add(saturating_mul(pixels, per_pixel), saturating_mul(photons, per_photon));
    char rate[32];
    std::snprintf(rate, sizeof(rate), "%.2f", per_path);
    check_memory(bytes,
                 "sppm with " + std::to_string(photon_count_) + " light paths per pass (" + rate + " photons stored per path) on " +
                     std::to_string(pixels) + " pixels",
                 photon_count_location_);
}

RenderResult SPPMIntegrator::render(const Scene& scene, const RenderOptions& options) {
    refuse_unrendered_media(scene);
    refuse_film_bands(scene);
    auto t_start = std::chrono::steady_clock::now();
    if (!options.aovs.empty()) throw InputError("sppm renders no AOVs (its passes are correlated: there is no per-pixel variance)");
    const SampleSettings samples = sample_settings(scene, options);
    const int passes = options.spp > 0 ? options.spp : (max_passes_ > 0 ? max_passes_ : samples.spp);
    const Film& film = scene.sensor().film();
    const Vec2i crop = film.crop_size(), offset = film.crop_offset(), full = film.full_size();
    const size_t pixels = size_t(crop.x) * size_t(crop.y);
    const float scene_radius = std::max(scene.bbox().bounding_radius(), 1e-3f);
    const uint64_t chunk = granularity_ > 0 ? uint64_t(granularity_) : 4096;
    direct_.prepare(scene);
    const LightPathTracer tracer(scene, settings_.max_depth < 0 ? -1 : settings_.max_depth - 1, settings_.rr_depth);
    check_render_memory(tracer, samples.seed, chunk, pixels);
    std::vector<PixelState> state(pixels);
    for (PixelState& s : state) s.radius = initial_radius_ > 0.0f ? initial_radius_ : 5.0f * scene_radius / float(std::max(full.x, full.y));
    const FilterSampler filter(film.filter());
    // Pass k takes sample k of every pixel: the sampler counts the passes.
    RenderOptions camera_options = options;
    camera_options.spp = passes;
    const Ref<Sampler> prototype = configured_sampler(scene, camera_options);
    tbb::enumerable_thread_specific<Ref<Sampler>> samplers([&] { return prototype->clone(); });
    tbb::task_arena arena = thread_arena(options.threads);
    ProgressReporter progress("Rendering", uint64_t(passes), options.progress, "passes", options.progress_sink);
    const std::atomic<bool>* interrupt = options.interrupt;
    auto interrupted = [&] { return interrupt && interrupt->load(std::memory_order_relaxed); };
    std::atomic<uint64_t> rays{0};
    std::vector<GatherPoint> vps(pixels);
    std::vector<Spectrum> direct(pixels);
    // The spectral variant: every pass draws one set of wavelengths from its own stream, shared by
    // its camera and light paths (pbrt-v4's SPPM), each pixel and light path at its own copy; each
    // pass's estimates are converted to RGB before they join the statistics (the conversion is
    // linear, so the statistics stay unbiased over the passes' wavelengths).
    const bool spectral = scene.spectral();
    const SensorResponse* response = scene.sensor().response();
    std::vector<Wavelengths> pixel_wavelengths(spectral ? pixels : 0);
    auto to_rgb = [&](Spectrum value, size_t i) {
        if (!spectral) return value;
        if (response) value *= response->at(pixel_wavelengths[i]);
        return spectral_to_linear_srgb(value, pixel_wavelengths[i]);
    };
    std::vector<PassPhotons> chunks;
    std::vector<Photon> photons;
    PhotonGrid grid;
    int done = 0;
    for (int pass = 0; pass < passes && !interrupted(); ++pass) {
        Wavelengths pass_wavelengths;
        if (spectral) {
            PCG32 rng = light_path_rng(samples.seed, 3, uint64_t(pass));
            const float u = rng.next_float();
            pass_wavelengths = response ? response->sample(u) : sample_visible_wavelengths(u);
        }
        // Motion blur: every pass draws one shutter time from its own stream, shared by its camera
        // rays and light paths, so that its photons and visible points meet the scene in one pose.
        float pass_time = scene.sensor().shutter_open();
        if (scene.sensor().shutter_open_time() > 0.0f) {
            PCG32 rng = light_path_rng(samples.seed, 4, uint64_t(pass));
            pass_time = tracer.sample_time(rng);
        }
        // (1) Camera pass.
        arena.execute([&] {
            parallel_chunks(pixels, 256, [&](size_t begin, size_t end) {
                uint64_t before = thread_ray_count();
                Sampler& sampler = *samplers.local();
                for (size_t i = begin; i != end; ++i) {
                    Vec2i pixel = offset + Vec2i(int(i % size_t(crop.x)), int(i / size_t(crop.x)));
                    sampler.start(pixel, uint32_t(pass));
                    Wavelengths* w = nullptr;
                    if (spectral) {
                        pixel_wavelengths[i] = pass_wavelengths;
                        w = &pixel_wavelengths[i];
                    }
                    direct[i] = to_rgb(trace_camera(scene, sampler, filter, pixel, w, pass_time, vps[i]), i);
                }
                rays += thread_ray_count() - before;
            });
        });
        // (2) Photon pass, concatenated in path order.
        uint64_t first = uint64_t(pass) * uint64_t(photon_count_);
        if (!trace_in_chunks(arena, uint64_t(photon_count_), chunk, chunks, interrupt, rays, [&](uint64_t b, uint64_t e, PassPhotons& out) {
                trace_photons(tracer, samples.seed, first + b, e - b, spectral ? &pass_wavelengths : nullptr, pass_time, out);
            }))
            break;
        photons.clear();
        for (const PassPhotons& c : chunks) photons.insert(photons.end(), c.photons.begin(), c.photons.end());
        float max_radius = 0.0f;
        for (size_t i = 0; i < pixels; ++i)
            if (vps[i].bsdf) max_radius = std::max(max_radius, state[i].radius);
        grid.build(photons, std::max(max_radius, 1e-6f * scene_radius));
        // (3) Gather and update (Hachisuka and Jensen 2009, equations 6 and 10).
        arena.execute([&] {
            parallel_chunks(pixels, 256, [&](size_t begin, size_t end) {
                for (size_t i = begin; i != end; ++i) {
                    PixelState& s = state[i];
                    for (int c = 0; c < 3; ++c) s.direct[c] += all_finite(direct[i]) ? direct[i][c] : 0.0f;
                    if (!vps[i].bsdf) continue;
                    uint64_t m = 0;
                    Spectrum phi = to_rgb(gather(grid, vps[i], s.radius, m) * vps[i].beta, i);
                    if (m == 0 || !all_finite(phi)) continue;
                    double n_new = s.n + alpha_ * double(m), shrink = n_new / (s.n + double(m));
                    for (int c = 0; c < 3; ++c) s.tau[c] = (s.tau[c] + phi[c]) * shrink;
                    s.n = n_new;
                    s.radius *= float(std::sqrt(shrink));
                }
            });
        });
        ++done;
        progress.add(1);
    }
    progress.finish();

    RenderResult result;
    result.image = Image(crop.x, crop.y, {"R", "G", "B"});
    const double emitted = double(done) * double(photon_count_);
    for (size_t i = 0; i < pixels; ++i) {
        const PixelState& s = state[i];
        double area = 3.14159265358979323846 * double(s.radius) * double(s.radius);
        for (int c = 0; c < 3; ++c) {
            double v = done > 0 ? s.direct[c] / done + (s.n > 0.0 ? s.tau[c] / (emitted * area) : 0.0) : 0.0;
            result.image.at(int(i % size_t(crop.x)), int(i / size_t(crop.x)), c) = float(v);
        }
    }
    RenderStats& st = result.stats;
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    st.samples = uint64_t(done) * pixels;
    st.rays = rays;
    st.spp = passes;
    st.seed = samples.seed;
    st.sampler = prototype->to_string();
    st.partial = done < passes;
    return result;
}

CANDELA_REGISTER_SPECTRAL(SPPMIntegrator, ObjectKind::Integrator, "sppm");

}  // namespace candela
