// ptracer: particle tracing (Mitsuba 3's `ptracer`). Light paths leave the emitters
// (Emitter::sample_ray) and scatter by BSDF sampling; every vertex is connected to the sensor
// (Sensor::sample_direction) and splatted into the film where it lands. A second estimator of the
// same image as `path`: good where most scattering is seen directly, hopeless for what is seen
// only through glass or mirrors (a pinhole cannot be hit by a specular path).
//
// Parameters (Mitsuba 3 names and semantics):
//   max_depth          integer   longest path in segments, camera included; -1 = unbounded
//                                (default), 1 = only emitters seen directly, 2 = direct light
//   rr_depth           integer   segments after which Russian roulette may end a light path
//                                (default 5); it continues with probability
//                                min(throughput / emitted weight, 0.95)
//   hide_emitters      boolean   emitters seen directly render black (default false)
//   samples_per_pass   integer   accepted for compatibility (Mitsuba splits the work into passes
//                                of this many samples per pixel); Candela's passes always hold
//                                one light path per pixel, so the image never depends on it
//
// The sampler's sample count (or --spp) sets the work: spp light paths per pixel of the crop
// window, traced in passes of one path per pixel. Each path also connects its starting point on
// an area light to the sensor (emitters seen directly); an infinite emitter seen directly is
// sampled by direction from the sensor's position and connected from far away (exact for a
// pinhole, within the aperture's parallax for thinlens; an orthographic camera, which sees a
// single direction, shows environments black, as in Mitsuba). `directionalarea` lights work
// as in Mitsuba's ptracer: their beams are traced, and they are black to the eye.
//
// Motion blur: each light path is traced at one shutter time, uniform over the sensor's shutter
// (Mitsuba's ptracer draws it the same way): moving shapes, emitters and cameras take their poses
// then, and timed_sunsky its sun.
//
// In scalar_spectral_polarized a light path carries the Stokes vector of its light (emitted
// unpolarised; each BSDF's Mueller matrix with the directions swapped, Mitsuba's importance
// transport), and a connection splats the S0 of what leaves toward the sensor.
//
// Splats go through the film's reconstruction filter (of unit integral) without normalisation;
// each pass is divided by its number of paths. Only the "variance" AOV is available: the
// variance of the pixel mean, from the spread of the independent passes.

#include "core/bsdf.h"
#include "core/film.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/properties.h"
#include "core/random_2d.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/wavelengths.h"
#include "integrators/light_paths.h"
#include "integrators/path_settings.h"

#include <chrono>

namespace candela {

namespace {

struct Splat {
    Vec2 pos;  // crop pixels
    Spectrum value;
};

struct ChunkSplats {
    std::vector<Splat> splats;
    uint64_t paths = 0, nonfinite = 0;
};

constexpr uint64_t ChunkPaths = 1024;
constexpr uint64_t BatchChunks = 64;  // chunks traced before their splats are applied

}  // namespace

class ParticleTracerIntegrator final : public Integrator {
public:
    explicit ParticleTracerIntegrator(const Properties& props) {
        settings_ = read_path_settings(props, DepthSettings | HideEmittersSetting);
        int per_pass = props.get_int("samples_per_pass", -1);
        if (per_pass == 0 || per_pass < -1) props.fail("samples_per_pass", "samples_per_pass must be positive (or -1)");
    }

    RenderResult render(const Scene& scene, const RenderOptions& options) override;
    // Each light path takes its own shutter time (LightPathTracer::sample_time), and its emitter, its
    // rays and its connections to the sensor their poses then.
    bool renders_motion() const override { return true; }
    std::string to_string() const override { return "ptracer"; }
    std::string parts_refusal() const override {
        return "its samples are light paths that splat onto whichever pixels they reach, not sample indices of pixels";
    }

private:
    // One light path: its connections to the sensor as splats.
    void trace_path(const LightPathTracer& tracer, PCG32& rng, ChunkSplats& out) const;
    void connect_area_emitter(const Scene& scene, const LightPathStart& start, PCG32& rng, ChunkSplats& out) const;
    void connect_environment(const Scene& scene, const LightPathStart& start, PCG32& rng, ChunkSplats& out) const;
    void connect_vertex(const Scene& scene, const LightVertex& v, PCG32& rng, ChunkSplats& out) const;
    void splat(const Scene& scene, const Vec2& film_pos, const Spectrum& value, const Wavelengths* wavelengths, ChunkSplats& out) const;
    // max_depth counts segments, camera included (settings_.within_depth).
    PathSettings settings_;
};

void ParticleTracerIntegrator::trace_path(const LightPathTracer& tracer, PCG32& rng, ChunkSplats& out) const {
    const Scene& scene = tracer.scene();
    LightPathStart start;
    // The spectral variant: the path's own wavelengths, from its own stream (RGB draws nothing).
    Wavelengths wavelengths;
    if (scene.spectral()) {
        const float u = rng.next_float();
        const SensorResponse* response = scene.sensor().response();
        wavelengths = response ? response->sample(u) : sample_visible_wavelengths(u);
        start.wavelengths = &wavelengths;
        start.polarized = scene.polarized();
    }
    const float time = tracer.sample_time(rng);
    if (!tracer.start(rng, time, start)) return;
    if (!settings_.hide_emitters && settings_.within_depth(1)) {
        if (start.emitter->is_infinite())
            connect_environment(scene, start, rng, out);
        else if (!start.emitter->is_delta() && !start.ray.delta_direction)
            connect_area_emitter(scene, start, rng, out);
    }
    tracer.follow(rng, start, [&](const LightVertex& v) {
        if (!settings_.within_depth(v.depth + 1)) return false;
        if (v.bsdf->has_smooth_lobe()) connect_vertex(scene, v, rng, out);
        return true;
    });
}

// The emitter's own point seen by the sensor: Le |cos| / (pdf_position pick_prob) times the
// sensor's weight.
void ParticleTracerIntegrator::connect_area_emitter(const Scene& scene, const LightPathStart& start, PCG32& rng, ChunkSplats& out) const {
    Vec2 u = next_vec2(rng);
    SensorSample ss = scene.sensor().sample_direction(start.ray.ray.o, u, start.time());
    if (!(ss.pdf > 0.0f)) return;
    SurfaceInteraction si;
    si.time = start.time();
    si.p = start.ray.ray.o;
    si.p_error = start.ray.p_error;
    si.n = start.ray.n;
    si.shading = Frame(start.ray.n);
    si.uv = start.ray.uv;
    si.shape = start.emitter->shape();
    si.wavelengths = start.wavelengths;
    si.wi = si.to_local(ss.d);
    Spectrum Le = start.emitter->eval(si);
    if (is_black(Le)) return;
    float cos_theta = std::abs(glm::dot(si.n, ss.d));
    if (scene.occluded(si.spawn_ray_to(ss.p))) return;
    splat(scene, ss.film_pos, Le * (cos_theta * ss.weight / (start.ray.pdf_position * start.pick_prob)), start.wavelengths, out);
}

// An infinite emitter seen directly: a direction toward it drawn from the sensor's position
// (pdf per solid angle there), placed at a distance D so large that the connection back to the
// sensor lands where that direction is seen; the sensor weight falls as 1 / D^2 and the solid
// angle of the emitter "surface" grows as D^2, so D cancels.
void ParticleTracerIntegrator::connect_environment(const Scene& scene, const LightPathStart& start, PCG32& rng, ChunkSplats& out) const {
    const Vec2 u_dir = next_vec2(rng), u_lens = next_vec2(rng);
    SurfaceInteraction eye;
    eye.p = scene.sensor().pose_at(start.time()).apply_point(Vec3(0.0f));
    eye.wavelengths = start.wavelengths;
    eye.time = start.time();
    Spectrum radiance_over_pdf;
    DirectionSample ds = start.emitter->sample_direction(eye, u_dir, radiance_over_pdf);
    if (!(ds.pdf > 0.0f) || is_black(radiance_over_pdf)) return;
    float far = 1e3f * (glm::length(eye.p - scene.bbox().center()) + scene.bbox().bounding_radius() + 1.0f);
    SensorSample ss = scene.sensor().sample_direction(eye.p + ds.d * far, u_lens, start.time());
    if (!(ss.pdf > 0.0f)) return;
    Ray camera_ray(ss.p, -ss.d);
    camera_ray.time = start.time();
    if (scene.occluded(camera_ray)) return;  // the camera ray must escape
    splat(scene, ss.film_pos, radiance_over_pdf * (far * far * ss.weight / start.pick_prob), start.wavelengths, out);
}

// A light path vertex seen by the sensor: beta f |cos| (adjoint, shading-corrected) times the
// sensor's weight.
void ParticleTracerIntegrator::connect_vertex(const Scene& scene, const LightVertex& v, PCG32& rng, ChunkSplats& out) const {
    Vec2 u = next_vec2(rng);
    SensorSample ss = scene.sensor().sample_direction(v.si->p, u, v.si->time);
    if (!(ss.pdf > 0.0f)) return;
    Vec3 wo = v.si->to_local(ss.d);
    float correction = shading_normal_correction(*v.si, wo);
    if (!(correction > 0.0f)) return;
    BSDFContext ctx;
    ctx.mode = TransportMode::Importance;
    Spectrum f = v.bsdf->eval(ctx, *v.si, wo);
    if (is_black(f)) return;
    if (scene.occluded(v.si->spawn_ray_to(ss.p))) return;
    Spectrum value = v.beta * f * (correction * ss.weight);
    if (v.stokes) {
        // Polarized: the sensor measures S0 of the light that leaves toward it.
        StokesSpectrum toward_sensor = *v.stokes;
        scatter_stokes_forward(*v.si, *v.bsdf, wo, BSDFNone, toward_sensor);
        for (int k = 0; k < 3; ++k) value[k] *= toward_sensor.w[k][0];
    }
    splat(scene, ss.film_pos, value, v.si->wavelengths, out);
}

void ParticleTracerIntegrator::splat(const Scene& scene, const Vec2& film_pos, const Spectrum& path_value, const Wavelengths* wavelengths,
                                     ChunkSplats& out) const {
    // The film takes colours: in the spectral variant the path's values, weighted by the sensor's
    // response when it has one, through CIE 1931.
    Spectrum value = path_value;
    if (wavelengths) {
        if (const SensorResponse* response = scene.sensor().response()) value *= response->at(*wavelengths);
        value = spectral_to_linear_srgb(value, *wavelengths);
    }
    if (!storable_sample_value(value)) {
        ++out.nonfinite;
        return;
    }
    out.splats.push_back({film_pos - Vec2(scene.sensor().film().crop_offset()), value});
}

RenderResult ParticleTracerIntegrator::render(const Scene& scene, const RenderOptions& options) {
    refuse_unrendered_media(scene);
    refuse_film_bands(scene);
    if (!scene.sensor().reached_by_light_paths())
        throw InputError("ptracer cannot render through the " + scene.sensor().to_string() +
                         " sensor: light paths cannot reach it (render it with path or another camera-path integrator)");
    auto t_start = std::chrono::steady_clock::now();
    bool variance = false;
    for (const std::string& a : options.aovs) {
        if (a != "variance")
            throw InputError("ptracer renders no \"" + a + "\" AOV (only variance: its light paths have no first hit per pixel)");
        variance = true;
    }
    const SampleSettings samples = sample_settings(scene, options);
    const Film& film = scene.sensor().film();
    const Vec2i crop = film.crop_size();
    const uint64_t pixels = uint64_t(crop.x) * uint64_t(crop.y);
    const LightPathTracer tracer(scene, settings_.max_depth < 0 ? -1 : settings_.max_depth - 1, settings_.rr_depth);
    ProgressReporter progress("Rendering", uint64_t(samples.spp) * pixels, options.progress, "samples", options.progress_sink);
    tbb::task_arena arena = thread_arena(options.threads);
    std::atomic<uint64_t> rays{0};
    uint64_t paths = 0, nonfinite = 0;
    int passes = 0;
    bool interrupted = false;

    ImageBlock block(Vec2i(0), crop, &film.filter());
    std::vector<double> pass_sum(pixels * 4), sum(pixels * 3, 0.0), sum_sq(variance ? pixels * 3 : 0, 0.0);
    std::vector<ChunkSplats> chunks;
    for (int pass = 0; pass < samples.spp && !interrupted; ++pass) {
        block.clear();
        // A pass's paths in batches: trace a batch in parallel, then apply its splats in order.
        for (uint64_t first = 0; first < pixels && !interrupted; first += ChunkPaths * BatchChunks) {
            uint64_t count = std::min(pixels - first, ChunkPaths * BatchChunks), base = uint64_t(pass) * pixels + first;
            interrupted =
                !trace_in_chunks(arena, count, ChunkPaths, chunks, options.interrupt, rays, [&](uint64_t b, uint64_t e, ChunkSplats& out) {
                    out.splats.clear();
                    out.paths = e - b;
                    out.nonfinite = 0;
                    for (uint64_t i = b; i < e; ++i) {
                        PCG32 rng = light_path_rng(samples.seed, 0, base + i);
                        trace_path(tracer, rng, out);
                    }
                    progress.add(e - b);
                });
            for (const ChunkSplats& c : chunks)
                for (const Splat& s : c.splats) block.put(s.pos, s.value);
            for (const ChunkSplats& c : chunks) paths += c.paths, nonfinite += c.nonfinite;
        }
        if (interrupted) break;  // a pass cut short would bias its pixels; it is dropped
        // The pass's image: splat sums over its paths.
        std::fill(pass_sum.begin(), pass_sum.end(), 0.0);
        block.accumulate_into(pass_sum, crop);
        for (uint64_t i = 0; i < pixels; ++i)
            for (int c = 0; c < 3; ++c) {
                double x = pass_sum[i * 4 + c] / double(pixels);
                sum[i * 3 + c] += x;
                if (variance) sum_sq[i * 3 + c] += x * x;
            }
        ++passes;
    }
    progress.finish();

    std::vector<std::string> channels = {"R", "G", "B"};
    if (variance) channels.insert(channels.end(), {"variance.R", "variance.G", "variance.B"});
    RenderResult result;
    result.image = Image(crop.x, crop.y, channels);
    for (uint64_t i = 0; i < pixels; ++i) {
        int x = int(i % uint64_t(crop.x)), y = int(i / uint64_t(crop.x));
        for (int c = 0; c < 3; ++c) {
            double s = sum[i * 3 + c], k = passes;
            result.image.at(x, y, c) = passes > 0 ? float(s / k) : 0.0f;
            if (variance)
                result.image.at(x, y, 3 + c) = passes > 1 ? float(std::max(0.0, (sum_sq[i * 3 + c] - s * s / k) / (k - 1) / k)) : 0.0f;
        }
    }
    RenderStats& st = result.stats;
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    st.samples = paths;
    st.rays = rays;
    st.nonfinite = nonfinite;
    st.spp = samples.spp;
    st.seed = samples.seed;
    st.partial = interrupted;
    return result;
}

CANDELA_REGISTER_SPECTRAL(ParticleTracerIntegrator, ObjectKind::Integrator, "ptracer");

}  // namespace candela
