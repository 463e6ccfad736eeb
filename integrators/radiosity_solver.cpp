// Form factors and progressive refinement.
//
// Form factors are computed on demand, one shot at a time, from each receiving element's centre
// to the shooting patch: F = F_analytic x V. F_analytic is the exact unoccluded point-to-triangle
// form factor (form_factor.h), which stays accurate for neighbouring patches where sampling
// 1 / r^2 would be noisy; V is the fraction of `visibility_rays` rays from the centre to points
// of the triangle that arrive (Hammersley points, rotated per pair by a hash of the seed and the
// two elements: deterministic and independent of the thread count). The irradiance that a patch
// of radiosity B sends to a point is B x F(point -> patch), so shooting needs no reciprocity.

#include "integrators/radiosity_solver.h"
#include "core/emitter.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/random_2d.h"
#include "core/scene.h"
#include "core/warning.h"
#include "core/warp.h"
#include "integrators/direct_lighting.h"
#include "integrators/form_factor.h"

#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>

namespace candela {

namespace {

// Van der Corput's radical inverse in base 2: the second coordinate of Hammersley points.
float radical_inverse_2(uint32_t k) {
    k = (k << 16u) | (k >> 16u);
    k = ((k & 0x00ff00ffu) << 8u) | ((k & 0xff00ff00u) >> 8u);
    k = ((k & 0x0f0f0f0fu) << 4u) | ((k & 0xf0f0f0f0u) >> 4u);
    k = ((k & 0x33333333u) << 2u) | ((k & 0xccccccccu) >> 2u);
    k = ((k & 0x55555555u) << 1u) | ((k & 0xaaaaaaaau) >> 1u);
    return float(k >> 8) * 0x1p-24f;
}

// A point of an element as a ray origin or target: its error bound and side normal.
SurfaceInteraction surface_point(const Vec3& p, float p_error, const Vec3& n) {
    SurfaceInteraction si;
    si.p = p;
    si.p_error = p_error;
    si.n = n;
    si.shading = Frame(n);
    return si;
}

// The form factor from the centre of `receiver` to the patch of `source` (see the file comment).
float form_factor(const RadiosityPatches& patches, const RadiositySettings& settings, size_t receiver_index, size_t source_index,
                  const Vec3 (&tri)[3]) {
    const RadiosityElement& receiver = patches.elements()[receiver_index];
    const RadiosityElement& source = patches.elements()[source_index];
    Vec3 d = receiver.centroid - source.centroid;
    // The receiver must lie in front of the source (not behind it, nor in its plane).
    if (glm::dot(source.normal, d) <= 1e-5f * glm::length(d)) return 0.0f;
    const Vec3d vertices[3] = {Vec3d(tri[0]), Vec3d(tri[1]), Vec3d(tri[2])};
    double f = point_polygon_form_factor(Vec3d(receiver.centroid), Vec3d(receiver.normal), vertices, 3);
    if (!(f > 1e-12)) return 0.0f;

    PCG32 rng(hash_combine(settings.seed, source_index), uint64_t(receiver_index));
    Vec2 rotation = next_vec2(rng);
    SurfaceInteraction from = surface_point(receiver.centroid, receiver.p_error, receiver.normal);
    int above = 0, visible = 0;
    const int n = settings.visibility_rays;
    for (int k = 0; k < n; ++k) {
        Vec2 u((float(k) + 0.5f) / float(n) + rotation.x, radical_inverse_2(uint32_t(k)) + rotation.y);
        u -= glm::floor(u);
        Vec2 b = warp::square_to_uniform_triangle(u);
        float b0 = 1.0f - b.x - b.y;
        Vec3 y = b0 * tri[0] + b.x * tri[1] + b.y * tri[2];
        if (glm::dot(receiver.normal, y - receiver.centroid) <= 0.0f) continue;  // below the horizon: clipped away
        ++above;
        float y_error = gamma_bound(7) * max_component(glm::abs(b0 * tri[0]) + glm::abs(b.x * tri[1]) + glm::abs(b.y * tri[2]));
        if (!patches.occluded(from.spawn_ray_to(y, source.normal, y_error))) ++visible;
    }
    return above > 0 ? float(f) * float(visible) / float(above) : 0.0f;
}

// Reports the solve's progress as the fraction of the way, on a log scale, from all power unshot
// to the tolerance.
class SolveProgress {
public:
    SolveProgress(bool enabled, float tolerance)
        : reporter_("Radiosity", Steps, enabled, "steps"), log_tolerance_(std::log(double(tolerance))) {}
    void update(double unshot_fraction) {
        double f = unshot_fraction > 0.0 ? std::log(unshot_fraction) / log_tolerance_ : 1.0;
        uint64_t level = uint64_t(std::clamp(f, 0.0, 1.0) * double(Steps));
        if (level > reported_) reporter_.add(level - reported_), reported_ = level;
    }
    void finish() { reporter_.finish(); }

private:
    static constexpr uint64_t Steps = 1000;
    ProgressReporter reporter_;
    double log_tolerance_;
    uint64_t reported_ = 0;
};

}  // namespace

std::vector<Spectrum> direct_irradiance(const RadiosityPatches& patches, const Scene& scene, const RadiositySettings& settings,
                                        const RenderOptions& options) {
    const auto& elements = patches.elements();
    std::vector<Spectrum> irradiance(elements.size(), Spectrum(0.0f));
    const auto& emitters = scene.emitters();
    tbb::task_arena arena = thread_arena(options.threads);
    arena.execute([&] {
        parallel_for(elements.size(), [&](size_t i) {
            const RadiosityElement& e = elements[i];
            SurfaceInteraction at = surface_point(e.centroid, e.p_error, e.normal);
            for (size_t l = 0; l < emitters.size(); ++l) {
                const Emitter& emitter = *emitters[l];
                if (emitter.type() == EmitterType::Area) continue;  // shot by the solve itself
                const int samples = emitter.is_delta() ? 1 : 64;
                PCG32 rng(hash_combine(settings.seed, i), ~uint64_t(l));
                Spectrum sum(0.0f);
                for (int s = 0; s < samples; ++s) {
                    Spectrum weight;
                    Vec2 u = next_vec2(rng);
                    DirectionSample ds = emitter.sample_direction(at, u, weight);
                    float cos_theta = glm::dot(e.normal, ds.d);
                    if (!(ds.pdf > 0.0f) || cos_theta <= 0.0f || is_black(weight)) continue;
                    if (!patches.occluded(shadow_ray(at, ds))) sum += weight * cos_theta;
                }
                irradiance[i] += sum / float(samples);
            }
        });
    });
    return irradiance;
}

std::vector<Spectrum> shoot_radiosity(const RadiosityPatches& patches, const RadiositySettings& settings,
                                      const std::vector<Spectrum>& initial, const RenderOptions& options, RadiosityStats& stats) {
    auto start = std::chrono::steady_clock::now();
    const auto& elements = patches.elements();
    const size_t n = elements.size();
    std::vector<Spectrum> irradiance = initial, unshot(n);
    double emitted_power = 0.0;
    for (size_t i = 0; i < n; ++i) {
        unshot[i] = elements[i].emitted + elements[i].reflectance * initial[i];
        emitted_power += double(luminance(unshot[i])) * elements[i].area;
    }
    std::atomic<uint64_t> rays{0};
    SolveProgress progress(options.progress, settings.tolerance);
    tbb::task_arena arena = thread_arena(options.threads);
    stats.shots = 0;
    stats.unshot_fraction = emitted_power > 0.0 ? 1.0 : 0.0;
    while (true) {
        // The shooter: the most unshot power (the first of equals, for determinism).
        double unshot_power = 0.0, best = -1.0;
        size_t shooter = 0;
        for (size_t i = 0; i < n; ++i) {
            double power = double(luminance(unshot[i])) * elements[i].area;
            unshot_power += power;
            if (power > best) best = power, shooter = i;
        }
        stats.unshot_fraction = emitted_power > 0.0 ? unshot_power / emitted_power : 0.0;
        stats.converged = stats.unshot_fraction <= settings.tolerance;
        progress.update(stats.unshot_fraction);
        if (stats.converged || stats.shots >= settings.max_iterations) break;
        if (options.interrupt && options.interrupt->load(std::memory_order_relaxed)) {
            stats.interrupted = true;
            break;
        }
        const Spectrum shot = unshot[shooter];
        unshot[shooter] = Spectrum(0.0f);
        Vec3 tri[3];
        patches.triangle(elements[shooter], tri[0], tri[1], tri[2]);
        arena.execute([&] {
            parallel_chunks(n, 64, [&](size_t begin, size_t end) {
                uint64_t rays_before = thread_ray_count();
                for (size_t j = begin; j != end; ++j) {
                    if (j == shooter) continue;
                    float f = form_factor(patches, settings, j, shooter, tri);
                    if (f <= 0.0f) continue;
                    Spectrum received = shot * f;
                    irradiance[j] += received;
                    unshot[j] += elements[j].reflectance * received;
                }
                rays += thread_ray_count() - rays_before;
            });
        });
        ++stats.shots;
    }
    progress.finish();
    stats.rays += rays;
    stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return irradiance;
}

namespace {

// The key a solution file must carry: the patches, the light before the first shot, and every
// setting that changes the solution.
uint64_t solution_key(const RadiosityPatches& patches, const RadiositySettings& s, const std::vector<Spectrum>& initial) {
    uint64_t key = patches.hash();
    const uint64_t fields[] = {uint64_t(s.subdivisions), uint64_t(s.max_iterations), uint64_t(s.visibility_rays), s.seed};
    for (uint64_t f : fields) key = hash_combine(key, f);
    for (float f : {s.max_patch_area, s.tolerance}) {
        uint32_t bits;
        std::memcpy(&bits, &f, sizeof bits);
        key = hash_combine(key, bits);
    }
    for (const Spectrum& e : initial)
        for (int c = 0; c < 3; ++c) {
            uint32_t bits;
            std::memcpy(&bits, &e[c], sizeof bits);
            key = hash_combine(key, bits);
        }
    return key;
}

}  // namespace

std::vector<Spectrum> solve_radiosity(const RadiosityPatches& patches, const Scene& scene, const RadiositySettings& settings,
                                      const RenderOptions& options, const std::string& solution_file, const SourceLocation& where,
                                      RadiosityStats& stats) {
    stats.patches = patches.patch_count();
    stats.elements = patches.elements().size();
    stats.approximated_bsdfs = patches.approximated_bsdfs();
    if (!stats.approximated_bsdfs.empty()) {
        std::string names;
        for (const auto& n : stats.approximated_bsdfs) names += (names.empty() ? "" : ", ") + n;
        warn(where, "radiosity treats non-diffuse BSDFs by their diffuse albedo: " + names);
    }
    std::vector<Spectrum> initial = direct_irradiance(patches, scene, settings, options);
    uint64_t key = solution_key(patches, settings, initial);
    if (!solution_file.empty() && std::filesystem::exists(solution_file)) {
        std::vector<Spectrum> irradiance;
        std::string reason;
        if (read_radiosity_file(solution_file, key, patches.elements().size(), irradiance, stats, reason)) {
            stats.loaded = true;
            stats.converged = stats.unshot_fraction <= settings.tolerance;
            return irradiance;
        }
        warn(where, "radiosity solution " + solution_file + " refused (" + reason + "); solving again and replacing it");
    }
    std::vector<Spectrum> irradiance = shoot_radiosity(patches, settings, initial, options, stats);
    if (!solution_file.empty() && !stats.interrupted) write_radiosity_file(solution_file, key, irradiance, stats);
    return irradiance;
}

}  // namespace candela
