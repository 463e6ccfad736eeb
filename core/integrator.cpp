#include "core/integrator.h"

#include "core/progress.h"
#include "core/scene.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>

// The pixel loop, in the order a render runs it:
//   AovLayout      which extra layers were asked for (core/pixel_sums.h)
//   render_window  the region whose samples it takes, and the rectangle its sums cover (the region
//                  plus the filter's reach): the whole image unless the render is a part
//   make_tiles     the region cut into tiles, each with its own ImageBlock (and pixel statistics)
//   sample_passes  the sample indices [begin, end) cut into passes of growing width
//   TileSampler    takes the samples of one pass for every pixel of one tile
//   gather_sums    adds the tiles in a fixed order into PixelSums, which develop into RGB and the
//                  AOV layers; tile_coverage says which samples of which pixels they hold
// A pixel's samples depend only on (seed, pixel, sample index), so the schedule (threads, tile
// order) never changes the image. Rendering a sub-range of sample indices or a region (a part of
// a farm render, farm/; the rest of an interrupted render) only changes what render_window and
// sample_passes hand out.

namespace candela {

namespace {

constexpr int TileSize = 32;

struct Tile {
    Vec2i offset, size;  // in pixels of the region
    ImageBlock block;
    std::vector<PixelStats> stats;  // empty unless an AOV needs them
    int done = 0;                   // every pixel holds the sample indices [first, done)
};

// The pixels of a render: `region` is the rectangle whose samples it takes (image pixels),
// `stored` the one its sums cover: the region grown by the filter's reach and clipped to the
// image, so that every splat of the region's samples is kept. Sums of disjoint regions (and
// sample ranges) then add up to those of the whole render (core/pixel_sums.h).
struct RenderWindow {
    ImageRect region, stored;
};

RenderWindow render_window(const Film& film, const ImageRect& requested) {
    const Vec2i image = film.crop_size();
    RenderWindow w;
    w.region = requested.empty() ? ImageRect{Vec2i(0), image} : requested;
    const Vec2i end = w.region.offset + w.region.size;
    if (glm::any(glm::lessThan(w.region.offset, Vec2i(0))) || glm::any(glm::greaterThan(end, image)))
        throw InputError("region " + std::to_string(w.region.offset.x) + "," + std::to_string(w.region.offset.y) + "," +
                         std::to_string(w.region.size.x) + "," + std::to_string(w.region.size.y) + " is not inside the " +
                         std::to_string(image.x) + " x " + std::to_string(image.y) + " image");
    w.stored = sums_rect(film, w.region);
    return w;
}

// Tiles covering the region in row-major order (the order gather_sums() adds them); their
// blocks are placed in the stored rectangle's pixels.
std::vector<Tile> make_tiles(const RenderWindow& window, const ReconstructionFilter& filter, bool with_stats, int first_sample) {
    const Vec2i area = window.region.size;
    const Vec2i block_origin = window.region.offset - window.stored.offset;
    std::vector<Tile> tiles;
    for (int y = 0; y < area.y; y += TileSize)
        for (int x = 0; x < area.x; x += TileSize) {
            Tile t;
            t.offset = Vec2i(x, y);
            t.size = glm::min(Vec2i(TileSize), area - t.offset);
            t.block = ImageBlock(block_origin + t.offset, t.size, &filter);
            if (with_stats) t.stats.resize(size_t(t.size.x) * t.size.y);
            t.done = first_sample;
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

// A stop request (SIGINT, SIGTERM) seen by every worker; once one worker has seen it, the render
// stops. Checked between tiles, so that a tile holds a whole pass or none of it and what an
// interrupted render holds can be stated exactly (RenderResult::coverage) and resumed.
class Interruption {
public:
    explicit Interruption(const std::atomic<bool>* request) : request_(request) {}
    bool requested() const { return request_ && request_->load(std::memory_order_relaxed); }
    // Records the stop so that no further tile or pass starts.
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
    TileSampler(const SamplingIntegrator& integrator, const Scene& scene, const AovLayout& layout, const RenderWindow& window)
        : integrator_(integrator), scene_(scene), sensor_(scene.sensor()),
          region_origin_(scene.sensor().film().crop_offset() + window.region.offset),
          block_origin_(scene.sensor().film().crop_offset() + window.stored.offset), first_hit_(layout.first_hit()) {}

    // Samples `samples` of every pixel of `tile`, unless the render was interrupted before.
    void sample_tile(Tile& tile, const SampleRange& samples, Sampler& sampler, Interruption& interruption, RenderCounters& counters,
                     ProgressReporter& progress) const {
        if (interruption.check()) return;
        uint64_t rays_before = thread_ray_count();
        uint64_t taken = 0, nonfinite = 0;
        for (int y = 0; y < tile.size.y; ++y)
            for (int x = 0; x < tile.size.x; ++x) sample_pixel(tile, Vec2i(x, y), samples, sampler, taken, nonfinite);
        tile.done = samples.end;
        counters.rays += thread_ray_count() - rays_before;
        counters.samples += taken;
        counters.nonfinite += nonfinite;
        progress.add(taken);
    }

private:
    // The samples of one pixel (tile coordinates): each positions the sampler at (pixel, index),
    // so its random numbers depend on nothing else. Non-finite radiance is counted and dropped.
    void sample_pixel(Tile& tile, const Vec2i& local, const SampleRange& samples, Sampler& sampler, uint64_t& taken, uint64_t& nonfinite) const {
        const Vec2i pixel = region_origin_ + tile.offset + local;
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
            tile.block.put(pos - Vec2(block_origin_), L);
            if (ps) ps->add(L, aov);
        }
    }

    const SamplingIntegrator& integrator_;
    const Scene& scene_;
    const Sensor& sensor_;
    const Vec2i region_origin_;  // film pixel of the region's first pixel
    const Vec2i block_origin_;   // film pixel of the stored rectangle's first pixel
    const bool first_hit_;
};

// Adds the tiles into the stored rectangle's sums in a fixed order, with the pixel statistics of
// the region's pixels.
PixelSums gather_sums(const std::vector<Tile>& tiles, const RenderWindow& window, const AovLayout& layout) {
    PixelSums sums(window.stored, layout);
    for (const Tile& t : tiles) t.block.accumulate_into(sums.filtered(), window.stored.size);
    const Vec2i to_stored = window.region.offset - window.stored.offset;
    for (const Tile& t : tiles) {
        if (t.stats.empty()) continue;
        for (int y = 0; y < t.size.y; ++y)
            for (int x = 0; x < t.size.x; ++x) {
                const Vec2i p = to_stored + t.offset + Vec2i(x, y);
                sums.stats_at(p.x, p.y) = t.stats[size_t(y) * t.size.x + x];
            }
    }
    return sums;
}

// What the tiles hold: the region for the samples every tile took, then the tiles that took
// more (an interruption stops between tiles), joined into runs along each row of tiles.
std::vector<CoverageBox> tile_coverage(const std::vector<Tile>& tiles, const RenderWindow& window, int first_sample) {
    int common = tiles.empty() ? first_sample : tiles[0].done;
    for (const Tile& t : tiles) common = std::min(common, t.done);
    std::vector<CoverageBox> boxes;
    if (common > first_sample) boxes.push_back({window.region, SampleRange{first_sample, common}});
    for (const Tile& t : tiles) {
        if (t.done == common) continue;
        const ImageRect rect{window.region.offset + t.offset, t.size};
        CoverageBox* last = boxes.empty() ? nullptr : &boxes.back();
        if (last && last->samples.begin == common && last->samples.end == t.done && last->rect.offset.y == rect.offset.y &&
            last->rect.size.y == rect.size.y && last->rect.offset.x + last->rect.size.x == rect.offset.x)
            last->rect.size.x += rect.size.x;
        else
            boxes.push_back({rect, SampleRange{common, t.done}});
    }
    return boxes;
}

// The scene's sampler with the render's sample count and seed.
Ref<Sampler> configured_sampler(const Scene& scene, const RenderOptions& options) {
    Ref<Sampler> sampler = scene.sensor().sampler().clone();
    if (options.spp > 0) sampler->set_sample_count(options.spp);
    if (options.seed) sampler->set_seed(*options.seed);
    return sampler;
}

// The sample indices a render takes: `requested`, or all of [0, spp) when none were given.
SampleRange sample_indices(const SampleRange& requested, int spp) {
    if (requested.begin == 0 && requested.end == 0) return SampleRange{0, spp};
    if (requested.begin < 0 || requested.empty() || requested.end > spp)
        throw InputError("sample range " + std::to_string(requested.begin) + ":" + std::to_string(requested.end) +
                         " is not a non-empty part of [0, " + std::to_string(spp) + ")");
    return requested;
}

}  // namespace

ImageRect sums_rect(const Film& film, const ImageRect& region) {
    const int reach = ImageBlock::reach(film.filter());
    const Vec2i lo = glm::max(region.offset - Vec2i(reach), Vec2i(0));
    const Vec2i hi = glm::min(region.offset + region.size + Vec2i(reach), film.crop_size());
    return ImageRect{lo, hi - lo};
}

Image Integrator::preview(const Image& rendered) const { return tonemap_srgb(rendered); }

RenderResult SamplingIntegrator::render(const Scene& scene, const RenderOptions& options) {
    auto t_start = std::chrono::steady_clock::now();
    const AovLayout layout(options.aovs);
    Ref<Sampler> prototype = configured_sampler(scene, options);
    const SampleRange samples = sample_indices(options.samples, prototype->sample_count());
    const Film& film = scene.sensor().film();
    const RenderWindow window = render_window(film, options.region);
    prepare(scene);

    std::vector<Tile> tiles = make_tiles(window, film.filter(), layout.pixel_stats(), samples.begin);
    const uint64_t pixels = uint64_t(window.region.size.x) * uint64_t(window.region.size.y);
    ProgressReporter progress("Rendering", uint64_t(samples.end - samples.begin) * pixels, options.progress);
    RenderCounters counters;
    Interruption interruption(options.interrupt);
    const TileSampler tile_sampler(*this, scene, layout, window);
    tbb::enumerable_thread_specific<Ref<Sampler>> samplers([&] { return prototype->clone(); });
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    auto last_checkpoint = std::chrono::steady_clock::now();
    for (const SampleRange& pass : sample_passes(samples)) {
        if (interruption.stopped()) break;
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
                for (size_t i = r.begin(); i != r.end(); ++i) tile_sampler.sample_tile(tiles[i], pass, *samplers.local(), interruption, counters, progress);
            });
        });
        // A checkpoint after a whole pass, and only when more passes follow.
        const auto now = std::chrono::steady_clock::now();
        if (options.checkpoint && options.checkpoint_seconds > 0.0 && !interruption.stopped() && pass.end < samples.end &&
            std::chrono::duration<double>(now - last_checkpoint).count() >= options.checkpoint_seconds) {
            options.checkpoint(gather_sums(tiles, window, layout), tile_coverage(tiles, window, samples.begin));
            last_checkpoint = now;
        }
    }
    progress.finish();

    RenderResult result;
    result.sums = gather_sums(tiles, window, layout);
    result.coverage = tile_coverage(tiles, window, samples.begin);
    result.image = result.sums.develop();
    RenderStats& st = result.stats;
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    st.samples = counters.samples;
    st.rays = counters.rays;
    st.nonfinite = counters.nonfinite;
    st.spp = prototype->sample_count();
    st.seed = prototype->seed();
    st.partial = !(result.coverage.size() == 1 && result.coverage[0].samples.begin == samples.begin &&
                   result.coverage[0].samples.end == samples.end && result.coverage[0].rect.size == window.region.size);
    return result;
}

}  // namespace candela
