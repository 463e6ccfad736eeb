#include "core/integrator.h"

#include "core/progress.h"
#include "core/scene.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>

// The pixel loop, in the order a render runs it:
//   AovLayout      which extra layers were asked for, and their channels after R, G, B
//   make_tiles     the film cut into tiles, each with its own ImageBlock (and pixel statistics)
//   sample_passes  the sample indices [begin, end) cut into passes of growing width
//   TileSampler    takes the samples of one pass for every pixel of one tile
//   develop        merges the tiles in a fixed order and writes RGB and the AOV layers
// A pixel's samples depend only on (seed, pixel, sample index), so the schedule (threads, tile
// order) never changes the image. Rendering a sub-range of sample indices, or another sampler,
// only changes what sample_passes and the sampler hand out.

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

    void add(const Spectrum& L, const FirstHitAovs& aov) {
        n++;
        for (int c = 0; c < 3; ++c) {
            sum[c] += L[c];
            sum_sq[c] += double(L[c]) * L[c];
        }
        albedo += aov.albedo;
        normal += aov.normal;
        depth += aov.depth;
    }
    // Unbiased sample variance divided by n: the variance of the pixel mean.
    double variance_of_mean(int c) const {
        double count = n;
        double var = count > 1 ? (sum_sq[c] - sum[c] * sum[c] / count) / (count - 1) / count : 0.0;
        return std::max(var, 0.0);
    }
};

struct Tile {
    Vec2i offset, size;  // in crop pixels
    ImageBlock block;
    std::vector<PixelStats> stats;  // empty unless an AOV needs them
};

// A half-open range of sample indices [begin, end).
struct SampleRange {
    int begin = 0, end = 0;
};

// The extra layers of a render and their channel layout: R, G, B, then albedo.RGB, normal.XYZ,
// depth.Z and variance.RGB, each only when asked for.
class AovLayout {
public:
    explicit AovLayout(const std::vector<std::string>& names) {
        for (const auto& a : names) {
            if (a == "albedo") albedo_ = true;
            else if (a == "normal") normal_ = true;
            else if (a == "depth") depth_ = true;
            else if (a == "variance") variance_ = true;
            else throw InputError("unknown AOV \"" + a + "\" (known: albedo, normal, depth, variance)");
        }
    }
    // Whether samples must report their first hit, and whether pixels keep running sums.
    bool first_hit() const { return albedo_ || normal_ || depth_; }
    bool pixel_stats() const { return first_hit() || variance_; }

    std::vector<std::string> channels() const {
        std::vector<std::string> channels = {"R", "G", "B"};
        const char* rgb[3] = {"R", "G", "B"};
        if (albedo_)
            for (auto c : rgb) channels.push_back(std::string("albedo.") + c);
        if (normal_)
            for (auto c : {"X", "Y", "Z"}) channels.push_back(std::string("normal.") + c);
        if (depth_) channels.push_back("depth.Z");
        if (variance_)
            for (auto c : rgb) channels.push_back(std::string("variance.") + c);
        return channels;
    }

    // Writes the AOV channels of pixel (x, y) from its statistics.
    void write(const PixelStats& ps, Image& img, int x, int y) const {
        int c = 3;
        float inv_n = ps.n ? 1.0f / float(ps.n) : 0.0f;
        if (albedo_)
            for (int k = 0; k < 3; ++k) img.at(x, y, c++) = ps.albedo[k] * inv_n;
        if (normal_)
            for (int k = 0; k < 3; ++k) img.at(x, y, c++) = ps.normal[k] * inv_n;
        if (depth_) img.at(x, y, c++) = float(ps.depth * inv_n);
        if (variance_)
            for (int k = 0; k < 3; ++k) img.at(x, y, c++) = float(ps.variance_of_mean(k));
    }

private:
    bool albedo_ = false, normal_ = false, depth_ = false, variance_ = false;
};

// Tiles covering the film's crop window in row-major order (the order develop() merges them).
std::vector<Tile> make_tiles(const Film& film, bool with_stats) {
    const Vec2i crop = film.crop_size();
    std::vector<Tile> tiles;
    for (int y = 0; y < crop.y; y += TileSize)
        for (int x = 0; x < crop.x; x += TileSize) {
            Tile t;
            t.offset = Vec2i(x, y);
            t.size = glm::min(Vec2i(TileSize), crop - t.offset);
            t.block = ImageBlock(t.offset, t.size, &film.filter());
            if (with_stats) t.stats.resize(size_t(t.size.x) * t.size.y);
            tiles.push_back(std::move(t));
        }
    return tiles;
}

// Passes over the whole image with growing sample counts (1, 2, 4, ... 32 samples per pixel):
// an interrupted render still has every pixel sampled about equally often.
std::vector<SampleRange> sample_passes(const SampleRange& samples) {
    std::vector<SampleRange> passes;
    for (int s0 = samples.begin, step = 1; s0 < samples.end; s0 += step, step = std::min(step * 2, 32))
        passes.push_back({s0, std::min(samples.end, s0 + step)});
    return passes;
}

// A stop request (SIGINT) seen by every worker; once one worker has seen it, the render stops.
class Interruption {
public:
    explicit Interruption(const std::atomic<bool>* request) : request_(request) {}
    bool requested() const { return request_ && request_->load(std::memory_order_relaxed); }
    // Checked between pixels: records the stop so that no further pass starts.
    bool check() {
        if (requested()) stopped_ = true;
        return stopped_;
    }
    bool stopped() const { return stopped_ || requested(); }

private:
    const std::atomic<bool>* request_;
    std::atomic<bool> stopped_{false};
};

struct RenderCounters {
    std::atomic<uint64_t> rays{0}, samples{0}, nonfinite{0};
};

// Takes samples for the pixels of tiles with the calling thread's sampler.
class TileSampler {
public:
    TileSampler(const SamplingIntegrator& integrator, const Scene& scene, const AovLayout& layout)
        : integrator_(integrator), scene_(scene), sensor_(scene.sensor()), crop_offset_(scene.sensor().film().crop_offset()),
          first_hit_(layout.first_hit()) {}

    // Samples `samples` of every pixel of `tile`, pixel by pixel, until done or interrupted.
    void sample_tile(Tile& tile, const SampleRange& samples, Sampler& sampler, Interruption& interruption, RenderCounters& counters,
                     ProgressReporter& progress) const {
        uint64_t rays_before = thread_ray_count();
        uint64_t taken = 0, nonfinite = 0;
        for (int y = 0; y < tile.size.y && !interruption.check(); ++y)
            for (int x = 0; x < tile.size.x && !interruption.check(); ++x)
                sample_pixel(tile, Vec2i(x, y), samples, sampler, taken, nonfinite);
        counters.rays += thread_ray_count() - rays_before;
        counters.samples += taken;
        counters.nonfinite += nonfinite;
        progress.add(taken);
    }

private:
    // The samples of one pixel (tile coordinates): each positions the sampler at (pixel, index),
    // so its random numbers depend on nothing else. Non-finite radiance is counted and dropped.
    void sample_pixel(Tile& tile, const Vec2i& local, const SampleRange& samples, Sampler& sampler, uint64_t& taken, uint64_t& nonfinite) const {
        const Vec2i pixel = crop_offset_ + tile.offset + local;
        PixelStats* ps = tile.stats.empty() ? nullptr : &tile.stats[size_t(local.y) * tile.size.x + local.x];
        for (int s = samples.begin; s < samples.end; ++s) {
            sampler.start(pixel, uint32_t(s));
            Vec2 pos = Vec2(pixel) + sampler.next_2d();
            Vec2 aperture = sampler.next_2d();
            Ray ray = sensor_.sample_ray(pos, aperture);
            FirstHitAovs aov;
            Spectrum L = integrator_.sample_radiance(scene_, sampler, ray, first_hit_ ? &aov : nullptr);
            ++taken;
            if (!all_finite(L)) {
                ++nonfinite;
                continue;
            }
            tile.block.put(pos - Vec2(crop_offset_), L);
            if (ps) ps->add(L, aov);
        }
    }

    const SamplingIntegrator& integrator_;
    const Scene& scene_;
    const Sensor& sensor_;
    const Vec2i crop_offset_;
    const bool first_hit_;
};

// Merges the tiles in a fixed order, normalises by the filter weights, and writes the AOVs.
Image develop(const std::vector<Tile>& tiles, const Vec2i& crop, const AovLayout& layout) {
    std::vector<double> accum(size_t(crop.x) * crop.y * 4, 0.0);
    for (const Tile& t : tiles) t.block.accumulate_into(accum, crop);
    Image img(crop.x, crop.y, layout.channels());
    for (int y = 0; y < crop.y; ++y)
        for (int x = 0; x < crop.x; ++x) {
            const double* a = &accum[(size_t(y) * crop.x + x) * 4];
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = a[3] > 0.0 ? float(a[c] / a[3]) : 0.0f;
        }
    for (const Tile& t : tiles) {
        if (t.stats.empty()) continue;
        for (int y = 0; y < t.size.y; ++y)
            for (int x = 0; x < t.size.x; ++x) layout.write(t.stats[size_t(y) * t.size.x + x], img, t.offset.x + x, t.offset.y + y);
    }
    return img;
}

// The scene's sampler with the render's sample count and seed.
Ref<Sampler> configured_sampler(const Scene& scene, const RenderOptions& options) {
    Ref<Sampler> sampler = scene.sensor().sampler().clone();
    if (options.spp > 0) sampler->set_sample_count(options.spp);
    if (options.seed) sampler->set_seed(*options.seed);
    return sampler;
}

}  // namespace

Image Integrator::preview(const Image& rendered) const { return tonemap_srgb(rendered); }

RenderResult SamplingIntegrator::render(const Scene& scene, const RenderOptions& options) {
    auto t_start = std::chrono::steady_clock::now();
    const AovLayout layout(options.aovs);
    Ref<Sampler> prototype = configured_sampler(scene, options);
    const SampleRange samples{0, prototype->sample_count()};
    prepare(scene);

    const Vec2i crop = scene.sensor().film().crop_size();
    std::vector<Tile> tiles = make_tiles(scene.sensor().film(), layout.pixel_stats());
    ProgressReporter progress("Rendering", uint64_t(samples.end - samples.begin) * uint64_t(crop.x) * uint64_t(crop.y), options.progress);
    RenderCounters counters;
    Interruption interruption(options.interrupt);
    const TileSampler tile_sampler(*this, scene, layout);
    tbb::enumerable_thread_specific<Ref<Sampler>> samplers([&] { return prototype->clone(); });
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    for (const SampleRange& pass : sample_passes(samples)) {
        if (interruption.stopped()) break;
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
                for (size_t i = r.begin(); i != r.end(); ++i) tile_sampler.sample_tile(tiles[i], pass, *samplers.local(), interruption, counters, progress);
            });
        });
    }
    progress.finish();

    RenderResult result;
    result.image = develop(tiles, crop, layout);
    RenderStats& st = result.stats;
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    st.samples = counters.samples;
    st.rays = counters.rays;
    st.nonfinite = counters.nonfinite;
    st.spp = prototype->sample_count();
    st.seed = prototype->seed();
    st.partial = interruption.stopped();
    return result;
}

}  // namespace candela
