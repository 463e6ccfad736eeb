#include "core/integrator.h"

#include "core/bsdf.h"
#include "core/memory_budget.h"
#include "core/mueller.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "core/shape.h"
#include "core/warning.h"
#include "core/wavelengths.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/task_arena.h>

#include <candela/version.h>

#include <chrono>
#include <cmath>
#include <cstdio>

// The pixel loop, in the order a render runs it:
//   SampleLayout   the values each sample splats: R, G, B, the alpha when the film has one, and
//                  the integrator's own channels (aov, moment, ...) (core/pixel_sums.h)
//   AovLayout      which --aov layers were asked for, and their channels after all of those
//   render_window  the region whose samples it takes, and the rectangle its sums cover (the region
//                  plus the filter's reach): the whole image unless the render is a part
//   make_tiles     the region cut into tiles, each with its own ImageBlock (and pixel statistics);
//                  with sample_border the tiles on the crop's edges also sample the ring of
//                  pixels outside it that the filter reaches
//   sample_passes  the sample indices [begin, end) cut into passes of growing width (and, with
//                  adaptive sampling, ending at every convergence check)
//   TileSampler    takes the samples of one pass for every active pixel of one tile
//   stop_converged adaptive sampling: between passes, stops the pixels whose noise is low enough
//   gather_sums    adds the tiles in a fixed order into PixelSums, which develop into the film's
//                  pixel format, the integrator's channels and the --aov layers; tile_coverage
//                  says which samples of which pixels they hold
// A pixel's samples depend only on (seed, pixel, sample index), so the schedule (threads, tile
// order) never changes the image. Rendering a sub-range of sample indices or a region (a part of
// a farm render, farm/; the rest of an interrupted render), or another sampler, only changes what
// render_window, sample_passes and the sampler hand out.

namespace candela {

namespace {

constexpr int TileSize = 32;

struct Tile {
    Vec2i offset, size;  // in pixels of the region
    // The pixels this tile samples, relative to `offset`: its own, and with sample_border the
    // ring outside the crop next to it. The block receives them all; only its own are developed.
    Vec2i sample_min{0}, sample_max{0};
    ImageBlock block;
    std::vector<PixelStats> stats;  // own pixels only; empty unless an --aov layer needs them
    int done = 0;                   // every pixel holds the sample indices [first, done)
    int sampled_pixels() const { return (sample_max.x - sample_min.x) * (sample_max.y - sample_min.y); }
};

// The pixels of a render: `region` is the rectangle whose samples it takes (image pixels),
// `stored` the one its sums cover: the region grown by the filter's reach and clipped to the
// image, so that every splat of the region's samples is kept. Sums of disjoint regions (and
// sample ranges) then add up to those of the whole render (core/pixel_sums.h).
struct RenderWindow {
    ImageRect region, stored;
    bool whole(const Vec2i& image) const { return region.offset == Vec2i(0) && region.size == image; }
};

RenderWindow render_window(const Film& film, const ImageRect& requested) {
    const Vec2i image = film.crop_size();
    RenderWindow w;
    w.region = requested.empty() ? ImageRect{Vec2i(0), image} : requested;
    if (!rect_inside_image(w.region, image))
        throw InputError("region " + std::to_string(w.region.offset.x) + "," + std::to_string(w.region.offset.y) + "," +
                         std::to_string(w.region.size.x) + "," + std::to_string(w.region.size.y) + " is not inside the " +
                         std::to_string(image.x) + " x " + std::to_string(image.y) + " image");
    w.stored = sums_rect(film, w.region);
    return w;
}

// What each sample splats with this film and integrator.
SampleLayout sample_layout(const Film& film, const SamplingIntegrator& integrator) {
    std::vector<std::string> extras = integrator.channel_names();
    if (extras.size() > size_t(MaxSampleChannels))
        throw InputError("the integrator reports " + std::to_string(extras.size()) + " channels per sample, more than the " +
                         std::to_string(MaxSampleChannels) + " Candela supports");
    return SampleLayout::of_film(film, std::move(extras));
}

// Tiles covering the region in row-major order (the order gather_sums() adds them), each with a
// block of `values` channels placed in the stored rectangle's pixels. With sample_border, the
// tiles on the crop's edges also sample the pixels outside it within the filter's reach (Mitsuba
// samples a crop grown by the filter's border size): a pixel of that ring is sampled by the tile
// of the nearest crop pixel, so disjoint regions sample it once. Pixels inside the crop receive the
// same samples in the same order as without it, so only those within that reach of an edge change.
std::vector<Tile> make_tiles(const Film& film, const RenderWindow& window, int values, bool with_stats, int first_sample) {
    const Vec2i image = film.crop_size();
    const Vec2i area = window.region.size;
    const Vec2i block_origin = window.region.offset - window.stored.offset;
    const int border = film_sampled_border(film);
    std::vector<Tile> tiles;
    for (int y = 0; y < area.y; y += TileSize)
        for (int x = 0; x < area.x; x += TileSize) {
            Tile t;
            t.offset = Vec2i(x, y);
            t.size = glm::min(Vec2i(TileSize), area - t.offset);
            t.sample_max = t.size;
            for (int axis = 0; axis < 2; ++axis) {
                const int first = window.region.offset[axis] + t.offset[axis];
                if (first == 0) t.sample_min[axis] = -border;
                if (first + t.size[axis] == image[axis]) t.sample_max[axis] += border;
            }
            t.block = ImageBlock(block_origin + t.offset, t.size, &film.filter(), values);
            if (with_stats) t.stats.resize(size_t(t.size.x) * t.size.y);
            t.done = first_sample;
            tiles.push_back(std::move(t));
        }
    return tiles;
}

// Stops the render before any allocation when its buffers cannot fit in memory: the tiles'
// blocks (with their filter borders) and pixel statistics, then the double-precision sums and
// the image, or at the end the image and write_exr's buffers for one band of rows.
void check_film_memory(const Film& film, const RenderWindow& window, const SampleLayout& values, const AovLayout& layout) {
    const uint64_t w = uint64_t(window.region.size.x), h = uint64_t(window.region.size.y), pixels = w * h;
    const uint64_t stored = uint64_t(window.stored.size.x) * uint64_t(window.stored.size.y);
    const uint64_t border = uint64_t(ImageBlock::reach(film.filter()));
    const uint64_t tiles_x = (w + TileSize - 1) / TileSize, tiles_y = (h + TileSize - 1) / TileSize;
    // A block holds each splatted value and the filter weight per pixel.
    uint64_t blocks =
        saturating_mul(saturating_mul(w + 2 * border * tiles_x, h + 2 * border * tiles_y), uint64_t(values.values() + 1) * sizeof(float));
    blocks = saturating_add(blocks, saturating_mul(tiles_x * tiles_y, sizeof(Tile)));
    uint64_t stats = layout.pixel_stats() ? saturating_mul(pixels, sizeof(PixelStats)) : 0;
    uint64_t image = saturating_mul(stored, (values.channels().size() + layout.channels().size()) * sizeof(float));
    uint64_t sums = saturating_mul(stored, uint64_t(values.values() + 1) * sizeof(double));
    if (layout.pixel_stats()) sums = saturating_add(sums, saturating_mul(stored, sizeof(PixelStats)));
    uint64_t develop = saturating_add(saturating_add(blocks, stats), saturating_add(sums, image));
    // The image, and write_exr's buffer for one band of rows: 16 MB, or 16 rows when those are
    // more, or the whole image when it is less.
    const uint64_t row =
        saturating_mul(uint64_t(window.stored.size.x), (values.channels().size() + layout.channels().size()) * sizeof(float));
    uint64_t write = saturating_add(image, std::min(image, std::max(uint64_t(16) << 20, saturating_mul(row, 16))));
    std::string what = film_description(film);
    if (int n = layout.layer_count()) what += " with " + std::to_string(n) + (n == 1 ? " AOV" : " AOVs");
    check_memory(std::max(develop, write), what, film.location());
}

// Adaptive sampling's schedule: the sample counts at which pixels are checked.
struct AdaptiveSchedule {
    bool enabled = false;
    float threshold = 0.0f;
    int min_spp = 0, step = 0;

    AdaptiveSchedule(const AdaptiveSampling& a, int spp) : enabled(a.enabled()), threshold(a.threshold) {
        if (!enabled) return;
        if (a.min_spp < 0 || a.step < 0) throw InputError("adaptive sampling: the minimum sample count and the step must not be negative");
        int automatic = 16;
        while (automatic < spp / 16) automatic *= 2;
        min_spp = a.min_spp > 0 ? a.min_spp : automatic;
        step = a.step > 0 ? a.step : min_spp;
    }
    // Whether pixels are checked once `count` samples are taken.
    bool checks_at(int count) const { return enabled && count >= min_spp && (count - min_spp) % step == 0; }
};

// Passes over the whole image with growing sample counts (1, 2, 4, ... 32 samples per pixel):
// an interrupted render still has every pixel sampled about equally often. With adaptive
// sampling a pass also ends at every count where pixels are checked.
std::vector<SampleRange> sample_passes(const SampleRange& samples, const AdaptiveSchedule& adaptive, int widest) {
    std::vector<SampleRange> passes;
    widest = std::clamp(widest, 1, 32);
    for (int s0 = samples.begin, step = 1; s0 < samples.end; step = std::min(step * 2, widest)) {
        int end = std::min(samples.end, s0 + step);
        for (int c = s0 + 1; c < end; ++c)
            if (adaptive.checks_at(c)) end = c;
        passes.push_back({s0, end});
        s0 = end;
    }
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

// Takes samples for the pixels of tiles with the calling thread's sampler: one at a time
// (SamplingIntegrator::sample_radiance), or, when `batched`, a tile's samples in batches of
// BatchLength (sample_batch), splatted in the same order.
class TileSampler {
public:
    TileSampler(const SamplingIntegrator& integrator, const Scene& scene, const SampleLayout& values, const AovLayout& layers,
                const RenderWindow& window, int spp, bool batched)
        : integrator_(integrator),
          scene_(scene),
          sensor_(scene.sensor()),
          region_origin_(scene.sensor().film().crop_offset() + window.region.offset),
          block_origin_(scene.sensor().film().crop_offset() + window.stored.offset),
          values_(values),
          first_hit_(layers.first_hit()),
          differential_scale_(1.0f / std::sqrt(float(std::max(spp, 1)))),
          spectral_(scene.spectral()),
          polarized_(scene.polarized()),
          bands_(scene.sensor().film().bands()),
          batched_(batched) {}

    // Samples `samples` of every pixel the tile samples, unless the render was interrupted before.
    void sample_tile(Tile& tile, const SampleRange& samples, Sampler& sampler, Interruption& interruption, RenderCounters& counters,
                     ProgressReporter& progress) const {
        if (interruption.check()) return;
        uint64_t rays_before = thread_ray_count();
        uint64_t taken = 0, nonfinite = 0;
        if (batched_)
            sample_tile_batched(tile, samples, sampler, taken, nonfinite);
        else
            for (int y = tile.sample_min.y; y < tile.sample_max.y; ++y)
                for (int x = tile.sample_min.x; x < tile.sample_max.x; ++x)
                    sample_pixel(tile, Vec2i(x, y), samples, sampler, taken, nonfinite);
        tile.done = samples.end;
        counters.rays += thread_ray_count() - rays_before;
        counters.samples += taken;
        counters.nonfinite += nonfinite;
        progress.add(taken);
    }

private:
    // The samples of a batch: enough paths for Embree's packets to stay full through the bounces
    // as paths end, few enough that their state stays in the core's caches.
    static constexpr size_t BatchLength = 1024;

    // Where a pixel's samples go (tile coordinates): its statistics (null when none are kept or
    // the pixel is outside the tile's own), and whether it takes samples at all (adaptive
    // sampling may have stopped it); counts the samples it is about to take.
    PixelStats* begin_pixel(Tile& tile, const Vec2i& local, const SampleRange& samples, bool& active) const {
        const bool own = local.x >= 0 && local.y >= 0 && local.x < tile.size.x && local.y < tile.size.y;
        PixelStats* ps = tile.stats.empty() || !own ? nullptr : &tile.stats[size_t(local.y) * tile.size.x + local.x];
        active = !ps || ps->active;
        if (ps && active) ps->taken += uint32_t(samples.end - samples.begin);
        return ps;
    }

    // Positions the sampler at sample `index` of `pixel`, so that its random numbers depend on
    // nothing else, and draws the camera's numbers: the film position and aperture into
    // `record`, and the camera ray.
    Ray camera_sample(const Vec2i& pixel, uint32_t index, Sampler& sampler, SampleRecord& record) const {
        sampler.start(pixel, index);
        record.film_pos = Vec2(pixel) + sensor_.pixel_offset(sampler.next_2d());
        record.aperture = sampler.next_2d();
        record.differential_scale = differential_scale_;
        return sensor_.sample_ray(record.film_pos, record.aperture, sample_time(sampler));
    }

    // Splats a sample's RGB value `L` (radiance times the sensor's sample_weight) at `film_pos`; a
    // sample with a non-finite value is counted and dropped.
    void splat_rgb(Tile& tile, PixelStats* ps, uint32_t index, const Vec2& film_pos, const Spectrum& L, bool valid, const float* channels,
                   const FirstHitAovs& aov, uint64_t& nonfinite) const {
        float values[MaxFilmBands + MaxSampleChannels];
        if (!values_.fill(L, valid, channels, values)) {
            ++nonfinite;
            return;
        }
        tile.block.put(film_pos - Vec2(block_origin_), values);
        if (ps) ps->add(L, aov, index);
    }

    // The spectral variants' wavelengths of a sample, drawn after the camera's numbers: a
    // specfilm's follow its bands' responses (a sensor's srf is then refused), else the sensor's.
    Wavelengths sample_wavelengths(Sampler& sampler) const {
        return draw_wavelengths(sampler, bands_ ? bands_->sampling.get() : sensor_.response());
    }

    // The spectral variants' sample values `L` at `wavelengths` (times the sensor's sample_weight)
    // as the film's linear sRGB, through the sensor's spectral response when it has one.
    Spectrum film_rgb(Spectrum L, const Wavelengths& wavelengths) const {
        if (const SensorResponse* response = sensor_.response()) L *= response->at(wavelengths);
        return spectral_to_linear_srgb(L, wavelengths);
    }

    // The samples of one pixel (tile coordinates), one at a time.
    void sample_pixel(Tile& tile, const Vec2i& local, const SampleRange& samples, Sampler& sampler, uint64_t& taken,
                      uint64_t& nonfinite) const {
        const Vec2i pixel = region_origin_ + tile.offset + local;
        bool active;
        PixelStats* ps = begin_pixel(tile, local, samples, active);
        if (!active) return;
        float values[MaxFilmBands + MaxSampleChannels], band_values[MaxFilmBands];
        for (int s = samples.begin; s < samples.end; ++s) {
            SampleRecord record;
            FirstHitAovs aov;
            record.first_hit = first_hit_ ? &aov : nullptr;
            Ray ray = camera_sample(pixel, uint32_t(s), sampler, record);
            Wavelengths wavelengths;
            StokesSpectrum stokes;  // what a polarized path sums besides its S0
            if (spectral_) {
                wavelengths = sample_wavelengths(sampler);
                if (polarized_) wavelengths.stokes = &stokes;
                ray.wavelengths = &wavelengths;
            }
            Spectrum L = integrator_.sample_radiance(scene_, sampler, ray, record) * sensor_.sample_weight(record.film_pos);
            ++taken;
            if (bands_) {
                bands_->values(L, wavelengths, band_values);
                if (!values_.fill_bands(band_values, record.channels, values)) {
                    ++nonfinite;
                    continue;
                }
                // No colour: the pixel statistics (variance, adaptive) are refused with bands.
                tile.block.put(record.film_pos - Vec2(block_origin_), values);
                if (ps) ps->add(Spectrum(0.0f), aov, uint32_t(s));
                continue;
            }
            if (spectral_) L = film_rgb(L, wavelengths);
            splat_rgb(tile, ps, uint32_t(s), record.film_pos, L, record.valid, record.channels, aov, nonfinite);
        }
    }

    // The tile's samples in batches (no channels, no bands, not polarized: render() and the
    // integrator check), pixel by pixel and sample by sample as sample_pixel takes them, and
    // splatted in that order.
    void sample_tile_batched(Tile& tile, const SampleRange& samples, Sampler& sampler, uint64_t& taken, uint64_t& nonfinite) const {
        struct Pending {
            Vec2 film_pos;
            PixelStats* ps;
            uint32_t index;
        };
        thread_local std::vector<BatchSample> batch;
        thread_local std::vector<Pending> where;
        thread_local std::vector<FirstHitAovs> aovs;
        thread_local std::vector<Wavelengths> wavelengths;  // the spectral variant's, each sample's own
        batch.resize(BatchLength);
        where.resize(BatchLength);
        aovs.resize(BatchLength);
        wavelengths.resize(BatchLength);
        size_t n = 0;
        auto flush = [&] {
            integrator_.sample_batch(scene_, sampler, batch.data(), n);
            taken += n;
            for (size_t i = 0; i < n; ++i) {
                Spectrum L = batch[i].L * sensor_.sample_weight(where[i].film_pos);
                if (spectral_) L = film_rgb(L, wavelengths[i]);
                splat_rgb(tile, where[i].ps, where[i].index, where[i].film_pos, L, batch[i].valid, nullptr, aovs[i], nonfinite);
            }
            n = 0;
        };
        for (int y = tile.sample_min.y; y < tile.sample_max.y; ++y)
            for (int x = tile.sample_min.x; x < tile.sample_max.x; ++x) {
                bool active;
                PixelStats* ps = begin_pixel(tile, Vec2i(x, y), samples, active);
                if (!active) continue;
                const Vec2i pixel = region_origin_ + tile.offset + Vec2i(x, y);
                for (int s = samples.begin; s < samples.end; ++s) {
                    SampleRecord record;
                    batch[n].ray = camera_sample(pixel, uint32_t(s), sampler, record);
                    if (spectral_) {
                        wavelengths[n] = sample_wavelengths(sampler);
                        batch[n].ray.wavelengths = &wavelengths[n];
                    }
                    sampler.save(batch[n].sampler_state);
                    aovs[n] = FirstHitAovs();
                    batch[n].first_hit = first_hit_ ? &aovs[n] : nullptr;
                    where[n] = Pending{record.film_pos, ps, uint32_t(s)};
                    if (++n == BatchLength) flush();
                }
            }
        if (n) flush();
    }

    // The camera sample's shutter time: from its own dimension when the shutter is open for a
    // while (then the path continues at the first bounce's dimensions), else the opening time,
    // drawing nothing.
    float sample_time(Sampler& sampler) const {
        if (!(sensor_.shutter_open_time() > 0.0f)) return sensor_.shutter_open();
        sampler.set_dimension(SampleDimensions::Time);
        float u = sampler.next_1d();
        sampler.set_dimension(SampleDimensions::FirstBounce);
        return sensor_.sample_time(u);
    }

    const SamplingIntegrator& integrator_;
    const Scene& scene_;
    const Sensor& sensor_;
    const Vec2i region_origin_;  // film pixel of the region's first pixel
    const Vec2i block_origin_;   // film pixel of the stored rectangle's first pixel
    const SampleLayout& values_;
    const bool first_hit_;
    const float differential_scale_;
    const bool spectral_, polarized_;
    const FilmBands* bands_;  // a specfilm's, or null
    const bool batched_;
};

// Adaptive sampling's check, between passes. A pixel's error is Cycles' estimate
// (PixelStats::adaptive_error) pooled over its 3x3 neighbourhood as a root mean square: one
// pixel's |I - A| is a single noisy draw (its relative spread is about 0.75), nine of them
// estimate the noise level about three times better, and a pixel then stops on evidence that is
// mostly its neighbours', not on its own samples happening to agree. An active pixel with n
// samples stops once that error is below threshold * sqrt(n / min_spp): the error of its mean
// falls as e^2 ~ v / n, so one more sample buys about e^2 / n, and stopping every pixel where
// e^2 / n drops below the same threshold^2 / min_spp gives n ~ sqrt(v), the allocation with the
// least summed squared error for its total sample count (a Lagrange multiplier). Stopping at a
// fixed error instead (Cycles: n ~ v) equalises the pixels' errors, which for the same total
// sample count gives the same summed squared error as uniform sampling, except where the
// minimum or maximum sample count binds. At the first check (n = min_spp) the limit is the
// threshold itself.
// Stopped pixels never start again, so all active pixels take the same sample indices.
// Single-threaded over the whole image: deterministic.
void stop_converged(std::vector<Tile>& tiles, const Vec2i& crop, float threshold, int min_spp) {
    std::vector<double> error(size_t(crop.x) * crop.y, 0.0);
    for (const Tile& t : tiles)
        for (int y = 0; y < t.size.y; ++y)
            for (int x = 0; x < t.size.x; ++x)
                error[size_t(t.offset.y + y) * crop.x + t.offset.x + x] = t.stats[size_t(y) * t.size.x + x].adaptive_error();
    auto pooled_error = [&](int px, int py) {
        double sum = 0.0;
        int count = 0;
        for (int y = std::max(0, py - 1); y <= std::min(crop.y - 1, py + 1); ++y)
            for (int x = std::max(0, px - 1); x <= std::min(crop.x - 1, px + 1); ++x, ++count) {
                const double e = error[size_t(y) * crop.x + x];
                sum += e * e;
            }
        return std::sqrt(sum / count);
    };
    for (Tile& t : tiles)
        for (int y = 0; y < t.size.y; ++y)
            for (int x = 0; x < t.size.x; ++x) {
                PixelStats& ps = t.stats[size_t(y) * t.size.x + x];
                if (ps.active && pooled_error(t.offset.x + x, t.offset.y + y) < threshold * std::sqrt(double(ps.n) / min_spp))
                    ps.active = false;
            }
}

// Adds the tiles into the stored rectangle's sums in a fixed order, with the pixel statistics of
// the region's pixels.
PixelSums gather_sums(const std::vector<Tile>& tiles, const RenderWindow& window, const SampleLayout& values, const AovLayout& layers) {
    PixelSums sums(window.stored, values, layers);
    for (const Tile& t : tiles) t.block.accumulate_into(sums.filtered(), window.stored.size);
    const Vec2i to_stored = window.region.offset - window.stored.offset;
    for (const Tile& t : tiles) {
        if (t.stats.empty() || !sums.has_stats()) continue;
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

// An image's channel names must be distinct (an EXR cannot hold two channels of one name).
void check_distinct_channels(const std::vector<std::string>& channels) {
    for (size_t i = 0; i < channels.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (channels[i] == channels[j]) throw InputError("two image channels are named \"" + channels[i] + "\" (rename an AOV)");
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

Ref<Sampler> configured_sampler(const Scene& scene, const RenderOptions& options) {
    const Sampler& own = scene.sensor().sampler();
    Ref<Sampler> sampler;
    if (options.sampler.empty()) {
        sampler = own.clone();
    } else {
        sampler = create_plugin_as<Sampler>(ObjectKind::Sampler, Properties(options.sampler, SourceLocation{}));
        sampler->set_sample_count(own.sample_count());
        sampler->set_seed(own.seed());
    }
    sampler->set_film(scene.sensor().film().full_size(), film_sampled_border(scene.sensor().film()));
    if (options.spp != 0) {
        if (std::string problem = sample_count_problem(options.spp); !problem.empty()) throw InputError("--spp: " + problem);
        sampler->set_sample_count(options.spp);
    }
    if (options.seed) sampler->set_seed(*options.seed);
    return sampler;
}

ImageRect sums_rect(const Film& film, const ImageRect& region) {
    const int reach = ImageBlock::reach(film.filter());
    const Vec2i lo = glm::max(region.offset - Vec2i(reach), Vec2i(0));
    const Vec2i hi = glm::min(region.offset + region.size + Vec2i(reach), film.crop_size());
    return ImageRect{lo, hi - lo};
}

void SampleRecord::fill_first_hit(const SurfaceInteraction& si, FirstHitAovs& aovs) {
    if (si.wavelengths) {
        // The albedo layer is a colour in every variant: the BSDF's albedo in RGB.
        SurfaceInteraction rgb = si;
        rgb.wavelengths = nullptr;
        aovs.albedo = si.shape->bsdf()->albedo(rgb);
    } else {
        aovs.albedo = si.shape->bsdf()->albedo(si);
    }
    aovs.normal = si.shading.n;
    aovs.depth = si.t;
}

void annotate_image(Image& image, const RenderStats& s, const std::string& integrator, const std::string& scene_path) {
    auto& m = image.metadata;
    m["software"] = std::string("Candela ") + CANDELA_VERSION;
    m["candela.version"] = CANDELA_VERSION;
    m["candela.scene"] = scene_path;
    m["candela.integrator"] = integrator;
    m["candela.spp"] = std::to_string(s.spp);
    m["candela.seed"] = std::to_string(s.seed);
    if (!s.sampler.empty()) m["candela.sampler"] = s.sampler;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3f", s.seconds);
    m["candela.renderTime"] = buf;
    m["candela.samples"] = std::to_string(s.samples);
    m["candela.rays"] = std::to_string(s.rays);
    m["candela.nonfiniteSamples"] = std::to_string(s.nonfinite);
    m["candela.partial"] = s.partial ? "true" : "false";
}

Image Integrator::preview(const Image& rendered) const { return tonemap_srgb(linear_rgb(rendered)); }

void Integrator::refuse_unrendered_media(const Scene& scene) const {
    if (!scene.has_media() || renders_media()) return;
    throw SceneError(SourceLocation{scene.source_file, 0}, "the scene has participating media, which the " + to_string() +
                                                               " integrator would ignore: render it with volpath (or volpathmis)");
}

void Integrator::refuse_unrendered_motion(const Scene& scene) const {
    if (!scene.is_animated() || renders_motion()) return;
    throw SceneError(scene.motion_location(), "this animated to_world (motion blur) is not rendered by the " + to_string() +
                                                  " integrator: render the scene with path, volpath, direct or ptracer");
}

void Integrator::refuse_film_bands(const Scene& scene) const {
    const Film& film = scene.sensor().film();
    if (!film.bands()) return;
    throw SceneError(film.location(), "the " + to_string() +
                                          " integrator renders an RGB image, not a specfilm's spectral bands: "
                                          "render them with path, volpath, direct or another integrator of camera samples, or use hdrfilm");
}

RenderResult SamplingIntegrator::render(const Scene& scene, const RenderOptions& options) {
    refuse_unrendered_media(scene);
    refuse_unrendered_motion(scene);
    auto t_start = std::chrono::steady_clock::now();
    const Film& film = scene.sensor().film();
    const SampleLayout values = sample_layout(film, *this);
    const AovLayout layers(options.aovs);
    std::vector<std::string> channels = values.channels(), layer_channels = layers.channels();
    channels.insert(channels.end(), layer_channels.begin(), layer_channels.end());
    check_distinct_channels(channels);
    const RenderWindow window = render_window(film, options.region);
    check_film_memory(film, window, values, layers);
    Ref<Sampler> prototype = configured_sampler(scene, options);
    const SampleRange samples = sample_indices(options.samples, prototype->sample_count());
    const AdaptiveSchedule adaptive(options.adaptive, prototype->sample_count());
    if (layers.variance()) require_colour_film(film, "--aov variance measures the noise of each pixel's RGB colour");
    if (adaptive.enabled) require_colour_film(film, "adaptive sampling measures the noise of each pixel's RGB colour");
    // Whether a pixel takes a sample depends on its earlier samples and on its neighbours': a part
    // could not know, so adaptive renders are whole (see farm/resumable_render.h).
    if (adaptive.enabled && (samples.begin != 0 || samples.end != prototype->sample_count() || !window.whole(film.crop_size())))
        throw InputError(
            "adaptive sampling renders every sample index of the whole image: whether a pixel takes a sample depends on "
            "its earlier samples and its neighbours', so it cannot render a part (--samples, --crop) or resume");
    // Measured on the validation Cornell box (bench/bench_adaptive): with `stratified`, adaptive
    // sampling needed more samples than uniform sampling for the same error.
    if (adaptive.enabled && prototype->stratified_only_as_a_whole())
        warn(SourceLocation{scene.source_file, 0},
             "adaptive sampling with a sampler whose pixel samples are stratified only as a whole "
             "(stratified, multijitter, orthogonal, ldsampler): pixels that stop early lose the "
             "stratification; --sampler independent or sobol suits adaptive sampling");
    prepare(scene);

    std::vector<Tile> tiles = make_tiles(film, window, values.values(), layers.pixel_stats() || adaptive.enabled, samples.begin);
    uint64_t sampled_pixels = 0;
    for (const Tile& t : tiles) sampled_pixels += uint64_t(t.sampled_pixels());
    ProgressReporter progress("Rendering", uint64_t(samples.end - samples.begin) * sampled_pixels, options.progress, "samples",
                              options.progress_sink);
    RenderCounters counters;
    Interruption interruption(options.interrupt);
    // Batches only where they give the same image: per sample its radiance, validity and first-hit
    // layers, no integrator channels or band values (the integrator says what else it needs).
    const bool batched = options.wavefront && !film.bands() && channel_names().empty() && samples_in_batches(scene);
    const TileSampler tile_sampler(*this, scene, values, layers, window, prototype->sample_count(), batched);
    tbb::enumerable_thread_specific<Ref<Sampler>> samplers([&] { return prototype->clone(); });
    tbb::task_arena arena = thread_arena(options.threads);
    auto last_checkpoint = std::chrono::steady_clock::now();
    for (const SampleRange& pass : sample_passes(samples, adaptive, options.widest_pass)) {
        if (interruption.stopped()) break;
        arena.execute([&] {
            parallel_chunks(tiles.size(), 1, [&](size_t begin, size_t end) {
                for (size_t i = begin; i != end; ++i)
                    tile_sampler.sample_tile(tiles[i], pass, *samplers.local(), interruption, counters, progress);
            });
        });
        if (adaptive.checks_at(pass.end) && !interruption.stopped())
            stop_converged(tiles, window.region.size, adaptive.threshold, adaptive.min_spp);
        // A checkpoint after a whole pass, and only when more passes follow.
        const auto now = std::chrono::steady_clock::now();
        if (options.checkpoint && options.checkpoint_seconds > 0.0 && !interruption.stopped() && pass.end < samples.end &&
            std::chrono::duration<double>(now - last_checkpoint).count() >= options.checkpoint_seconds) {
            options.checkpoint(gather_sums(tiles, window, values, layers), tile_coverage(tiles, window, samples.begin));
            last_checkpoint = now;
        }
    }
    progress.finish();

    RenderResult result;
    result.sums = gather_sums(tiles, window, values, layers);
    result.coverage = tile_coverage(tiles, window, samples.begin);
    result.image = result.sums.develop();
    RenderStats& st = result.stats;
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    st.samples = counters.samples;
    st.rays = counters.rays;
    st.nonfinite = counters.nonfinite;
    st.spp = prototype->sample_count();
    st.seed = prototype->seed();
    st.sampler = prototype->to_string();
    st.partial = !(result.coverage.size() == 1 && result.coverage[0].samples.begin == samples.begin &&
                   result.coverage[0].samples.end == samples.end && result.coverage[0].rect.size == window.region.size);
    return result;
}

}  // namespace candela
