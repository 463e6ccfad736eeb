#include "integrators/estimators.h"

#include "core/wavelengths.h"

#include "core/bsdf.h"
#include "core/mueller.h"
#include "core/parallel.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"

#include <tbb/task_arena.h>

#include <limits>

namespace candela {

namespace {

struct Sums {
    double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0}, y = 0, y2 = 0, y3 = 0, y4 = 0;
    uint64_t n = 0, nonfinite = 0;
    void add(const Spectrum& v) {
        if (!all_finite(v)) {
            ++nonfinite;
            return;
        }
        for (int c = 0; c < 3; ++c) {
            s[c] += v[c];
            s2[c] += double(v[c]) * v[c];
        }
        double l = luminance(v);
        y += l;
        y2 += l * l;
        y3 += l * l * l;
        y4 += l * l * l * l;
        ++n;
    }
    void merge(const Sums& o) {
        for (int c = 0; c < 3; ++c) {
            s[c] += o.s[c];
            s2[c] += o.s2[c];
        }
        y += o.y;
        y2 += o.y2;
        y3 += o.y3;
        y4 += o.y4;
        n += o.n;
        nonfinite += o.nonfinite;
    }
};

// The estimators draw from the independent sampler as if their work items (samples, or points)
// were the pixels of a film RowLength wide, each taking `samples_per_item` samples.
constexpr uint64_t RowLength = 65536;
Vec2i item_pixel(uint64_t item) { return Vec2i(int(item % RowLength), int(item / RowLength)); }

Ref<Sampler> estimator_sampler(uint64_t seed, uint64_t items, uint64_t samples_per_item) {
    const uint64_t rows = (std::max<uint64_t>(items, 1) + RowLength - 1) / RowLength;
    if (rows > uint64_t(std::numeric_limits<int>::max())) throw InputError("too many estimator work items (" + std::to_string(items) + ")");
    if (std::string problem = sample_count_problem(int64_t(std::min<uint64_t>(samples_per_item, uint64_t(INT64_MAX)))); !problem.empty())
        throw InputError("estimator samples per point: " + problem);
    Ref<Sampler> sampler = create_plugin_as<Sampler>(ObjectKind::Sampler, Properties("independent", SourceLocation{"<estimator>", 0}));
    sampler->set_seed(seed);
    sampler->set_sample_count(int(samples_per_item));
    sampler->set_film(Vec2i(int(RowLength), int(rows)), 0);
    return sampler;
}

// Runs `one(sampler)` for every sample in fixed chunks and combines the chunks in order, so the
// result does not depend on the thread count.
template <typename F>
Estimate run(const EstimatorOptions& options, F one) {
    const uint64_t chunk = 4096, chunks = (options.samples + chunk - 1) / chunk;
    std::vector<Sums> partial(chunks);
    tbb::task_arena arena = thread_arena(options.threads);
    arena.execute([&] {
        // Random numbers for sample i: the independent sampler, positioned as "pixel" i.
        Ref<Sampler> prototype = estimator_sampler(options.seed, options.samples, 1);
        parallel_for(size_t(chunks), [&](uint64_t c) {
            Ref<Sampler> sampler = prototype->clone();
            for (uint64_t i = c * chunk; i < std::min(options.samples, (c + 1) * chunk); ++i) {
                sampler->start(item_pixel(i), 0);
                partial[c].add(one(*sampler));
            }
        });
    });
    Sums total;
    for (const Sums& s : partial) total.merge(s);
    Estimate e;
    e.samples = total.n;
    e.nonfinite = total.nonfinite;
    double n = double(total.n);
    if (total.n == 0) return e;
    for (int c = 0; c < 3; ++c) {
        double mean = total.s[c] / n;
        double var = total.n > 1 ? std::max(0.0, (total.s2[c] - n * mean * mean) / (n - 1)) : 0.0;
        e.mean[c] = float(mean);
        e.std_error[c] = float(std::sqrt(var / n));
    }
    double ym = total.y / n;
    e.luminance = ym;
    e.luminance_std_error = total.n > 1 ? std::sqrt(std::max(0.0, (total.y2 - n * ym * ym) / (n - 1)) / n) : 0.0;
    // Central moments from raw sums: m2 = E[Y^2] - m^2, m4 = E[Y^4] - 4 m E[Y^3] + 6 m^2 E[Y^2] - 3 m^4.
    double e2 = total.y2 / n, e3 = total.y3 / n, e4 = total.y4 / n;
    double m2 = e2 - ym * ym, m4 = e4 - 4 * ym * e3 + 6 * ym * ym * e2 - 3 * ym * ym * ym * ym;
    e.luminance_kurtosis = m2 > 0.0 ? m4 / (m2 * m2) : 0.0;
    return e;
}

}  // namespace

namespace {
// One sample's value as a colour: in the spectral variants `value` is evaluated at wavelengths
// drawn for the sample (in the polarized one with a Stokes sum, so paths carry their Mueller
// product and the value is the sensor's S0) and converted through CIE 1931, in RGB it is
// evaluated as it is.
template <typename F>
Spectrum coloured(const Scene& scene, Sampler& sampler, F&& value) {
    if (!scene.spectral()) return value(nullptr);
    Wavelengths w = draw_wavelengths(sampler);
    StokesSpectrum stokes;
    if (scene.polarized()) w.stokes = &stokes;
    return spectral_to_linear_srgb(value(&w), w);
}
}  // namespace

SurfaceInteraction virtual_vertex(const Scene& scene, const Vec3& p, const Vec3& n_in) {
    SurfaceInteraction si;
    si.p = p;
    Vec3 n = glm::normalize(n_in);
    si.n = n;
    si.shading = Frame(n);
    si.wi = Vec3(0.0f, 0.0f, 1.0f);
    float scale = max_abs_component(p);
    if (scene.bbox().valid()) scale = std::max(scale, std::max(max_abs_component(scene.bbox().min), max_abs_component(scene.bbox().max)));
    si.p_error = gamma_bound(16) * scale;
    return si;
}

const BSDF& white_lambertian() {
    static Ref<BSDF> white = [] {
        Properties props("diffuse", SourceLocation{"<estimator>", 0});
        props.set_rgb("reflectance", Spectrum(1.0f));
        return create_plugin_as<BSDF>(ObjectKind::BSDF, props);
    }();
    return *white;
}

Estimate estimate_irradiance(const Scene& scene, const Vec3& p, const Vec3& n, const EstimatorOptions& options) {
    PathIntegrator path(options.path);
    path.prepare(scene);
    SurfaceInteraction vertex = virtual_vertex(scene, p, n);
    const BSDF& white = white_lambertian();
    // E = pi * L_o for a white Lambertian surface; its path has made no segment yet.
    return run(options, [&](Sampler& sampler) {
        return coloured(scene, sampler, [&](Wavelengths* w) {
            SurfaceInteraction at = vertex;
            at.wavelengths = w;
            return Pi * path.continue_path(scene, sampler, at, white, 0);
        });
    });
}

std::vector<Spectrum> estimate_irradiance_at(const Scene& scene, const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                             const EstimatorOptions& options) {
    PathIntegrator path(options.path);
    path.prepare(scene);
    const BSDF& white = white_lambertian();
    std::vector<Spectrum> out(points.size(), Spectrum(0.0f));
    tbb::task_arena arena = thread_arena(options.threads);
    arena.execute([&] {
        Ref<Sampler> prototype = estimator_sampler(options.seed, points.size(), std::max<uint64_t>(options.samples, 1));
        parallel_chunks(points.size(), 16, [&](size_t begin, size_t end) {
            Ref<Sampler> sampler = prototype->clone();
            for (size_t i = begin; i != end; ++i) {
                SurfaceInteraction vertex = virtual_vertex(scene, points[i], normals[i]);
                Spectrum sum(0.0f);
                uint64_t n = 0;
                for (uint64_t s = 0; s < options.samples; ++s) {
                    sampler->start(item_pixel(i), uint32_t(s));
                    Spectrum v = Pi * path.continue_path(scene, *sampler, vertex, white, 0);
                    if (!all_finite(v)) continue;
                    sum += v;
                    ++n;
                }
                out[i] = n > 0 ? sum / float(n) : Spectrum(0.0f);
            }
        });
    });
    return out;
}

Estimate estimate_radiance(const Scene& scene, const Vec3& origin, const Vec3& direction, const EstimatorOptions& options) {
    PathIntegrator path(options.path);
    path.prepare(scene);
    Ray ray(origin, glm::normalize(direction));
    return run(options, [&](Sampler& sampler) {
        return coloured(scene, sampler, [&](Wavelengths* w) {
            SampleRecord record;
            Ray along = ray;
            along.wavelengths = w;
            return path.sample_radiance(scene, sampler, along, record);
        });
    });
}

}  // namespace candela
