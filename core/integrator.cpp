#include "core/integrator.h"

#include "core/progress.h"
#include "core/scene.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>

namespace candela {

namespace {

constexpr int TileSize = 32;

// Per-pixel running sums of the samples that landed in the pixel (not filtered): these give the
// variance of the pixel mean and the first-hit AOVs.
struct PixelStats {
    uint32_t n = 0;
    double sum[3] = {0, 0, 0}, sum_sq[3] = {0, 0, 0};
    Spectrum albedo{0.0f};
    Vec3 normal{0.0f};
    double depth = 0.0;
};

struct Tile {
    Vec2i offset, size;  // in crop pixels
    ImageBlock block;
    std::vector<PixelStats> stats;
};

bool wants(const std::vector<std::string>& aovs, const char* name) {
    return std::find(aovs.begin(), aovs.end(), name) != aovs.end();
}

}  // namespace

Image Integrator::preview(const Image& rendered) const { return tonemap_srgb(rendered); }

RenderResult SamplingIntegrator::render(const Scene& scene, const RenderOptions& options) {
    auto t_start = std::chrono::steady_clock::now();
    const Sensor& sensor = scene.sensor();
    const Film& film = sensor.film();
    Ref<Sampler> prototype = sensor.sampler().clone();
    if (options.spp > 0) prototype->set_sample_count(options.spp);
    if (options.seed) prototype->set_seed(*options.seed);
    const int spp = prototype->sample_count();
    for (auto& a : options.aovs)
        if (a != "albedo" && a != "normal" && a != "depth" && a != "variance")
            throw InputError("unknown AOV \"" + a + "\" (known: albedo, normal, depth, variance)");
    const bool want_first_hit = wants(options.aovs, "albedo") || wants(options.aovs, "normal") || wants(options.aovs, "depth");
    const bool want_stats = want_first_hit || wants(options.aovs, "variance");

    prepare(scene);

    const Vec2i crop = film.crop_size(), crop_offset = film.crop_offset();
    std::vector<Tile> tiles;
    for (int y = 0; y < crop.y; y += TileSize)
        for (int x = 0; x < crop.x; x += TileSize) {
            Tile t;
            t.offset = Vec2i(x, y);
            t.size = glm::min(Vec2i(TileSize), crop - t.offset);
            t.block = ImageBlock(t.offset, t.size, &film.filter());
            if (want_stats) t.stats.resize(size_t(t.size.x) * t.size.y);
            tiles.push_back(std::move(t));
        }

    // Passes over the whole image with growing sample counts: an interrupted render still has
    // every pixel sampled about equally often.
    std::vector<std::pair<int, int>> passes;
    for (int s0 = 0, step = 1; s0 < spp; s0 += step, step = std::min(step * 2, 32))
        passes.emplace_back(s0, std::min(spp, s0 + step));

    ProgressReporter progress("Rendering", uint64_t(spp) * uint64_t(crop.x) * uint64_t(crop.y), options.progress);
    std::atomic<uint64_t> rays{0}, samples{0}, nonfinite{0};
    std::atomic<bool> stopped{false};
    auto interrupted = [&] { return options.interrupt && options.interrupt->load(std::memory_order_relaxed); };

    tbb::enumerable_thread_specific<Ref<Sampler>> samplers([&] { return prototype->clone(); });
    auto render_tile = [&](Tile& tile, int s0, int s1) {
        Sampler& sampler = *samplers.local();
        uint64_t rays_before = thread_ray_count(), tile_samples = 0, tile_nonfinite = 0;
        for (int y = 0; y < tile.size.y; ++y) {
            for (int x = 0; x < tile.size.x; ++x) {
                if (interrupted()) {
                    stopped = true;
                    goto done;
                }
                Vec2i crop_pixel = tile.offset + Vec2i(x, y);
                Vec2i pixel = crop_offset + crop_pixel;
                PixelStats* ps = want_stats ? &tile.stats[size_t(y) * tile.size.x + x] : nullptr;
                for (int s = s0; s < s1; ++s) {
                    sampler.start(pixel, uint32_t(s));
                    Vec2 pos = Vec2(pixel) + sampler.next_2d();
                    Vec2 aperture = sampler.next_2d();
                    Ray ray = sensor.sample_ray(pos, aperture);
                    FirstHitAovs aov;
                    Spectrum L = sample_radiance(scene, sampler, ray, want_first_hit ? &aov : nullptr);
                    ++tile_samples;
                    if (!all_finite(L)) {
                        ++tile_nonfinite;
                        continue;
                    }
                    tile.block.put(pos - Vec2(crop_offset), L);
                    if (ps) {
                        ps->n++;
                        for (int c = 0; c < 3; ++c) {
                            ps->sum[c] += L[c];
                            ps->sum_sq[c] += double(L[c]) * L[c];
                        }
                        ps->albedo += aov.albedo;
                        ps->normal += aov.normal;
                        ps->depth += aov.depth;
                    }
                }
            }
        }
    done:
        rays += thread_ray_count() - rays_before;
        samples += tile_samples;
        nonfinite += tile_nonfinite;
        progress.add(tile_samples);
    };

    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    for (const auto& pass : passes) {
        if (stopped || interrupted()) break;
        // Named copies: C++17 lambdas cannot capture structured bindings (clang rejects it).
        int s0 = pass.first, s1 = pass.second;
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
                for (size_t i = r.begin(); i != r.end(); ++i) render_tile(tiles[i], s0, s1);
            });
        });
    }
    progress.finish();

    // Develop: merge the tiles in a fixed order, then normalise by the filter weights.
    std::vector<double> accum(size_t(crop.x) * crop.y * 4, 0.0);
    for (const Tile& t : tiles) t.block.accumulate_into(accum, crop);
    std::vector<std::string> channels = {"R", "G", "B"};
    const char* rgb[3] = {"R", "G", "B"};
    if (wants(options.aovs, "albedo"))
        for (auto c : rgb) channels.push_back(std::string("albedo.") + c);
    if (wants(options.aovs, "normal"))
        for (auto c : {"X", "Y", "Z"}) channels.push_back(std::string("normal.") + c);
    if (wants(options.aovs, "depth")) channels.push_back("depth.Z");
    if (wants(options.aovs, "variance"))
        for (auto c : rgb) channels.push_back(std::string("variance.") + c);
    RenderResult result;
    result.image = Image(crop.x, crop.y, channels);
    Image& img = result.image;
    for (int y = 0; y < crop.y; ++y)
        for (int x = 0; x < crop.x; ++x) {
            const double* a = &accum[(size_t(y) * crop.x + x) * 4];
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = a[3] > 0.0 ? float(a[c] / a[3]) : 0.0f;
        }
    if (want_stats) {
        for (const Tile& t : tiles)
            for (int y = 0; y < t.size.y; ++y)
                for (int x = 0; x < t.size.x; ++x) {
                    const PixelStats& ps = t.stats[size_t(y) * t.size.x + x];
                    int px = t.offset.x + x, py = t.offset.y + y, c = 3;
                    float inv_n = ps.n ? 1.0f / float(ps.n) : 0.0f;
                    if (wants(options.aovs, "albedo"))
                        for (int k = 0; k < 3; ++k) img.at(px, py, c++) = ps.albedo[k] * inv_n;
                    if (wants(options.aovs, "normal"))
                        for (int k = 0; k < 3; ++k) img.at(px, py, c++) = ps.normal[k] * inv_n;
                    if (wants(options.aovs, "depth")) img.at(px, py, c++) = float(ps.depth * inv_n);
                    if (wants(options.aovs, "variance"))
                        for (int k = 0; k < 3; ++k) {
                            // Unbiased sample variance divided by n: the variance of the pixel mean.
                            double n = ps.n;
                            double var = n > 1 ? (ps.sum_sq[k] - ps.sum[k] * ps.sum[k] / n) / (n - 1) / n : 0.0;
                            img.at(px, py, c++) = float(std::max(var, 0.0));
                        }
                }
    }

    RenderStats& st = result.stats;
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    st.samples = samples;
    st.rays = rays;
    st.nonfinite = nonfinite;
    st.spp = spp;
    st.seed = prototype->seed();
    st.partial = stopped || interrupted();
    return result;
}

}  // namespace candela
