#include "core/integrator.h"

#include "core/memory_budget.h"
#include "core/progress.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "core/bsdf.h"
#include "core/shape.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>

// The pixel loop, in the order a render runs it:
//   SampleLayout   the values each sample splats: R, G, B, the alpha when the film has one, and
//                  the integrator's own channels (aov, moment, ...)
//   AovLayout      which --aov layers were asked for, and their channels after all of those
//   make_tiles     the film cut into tiles, each with its own ImageBlock (and pixel statistics);
//                  with sample_border the tiles on the crop's edges also sample the ring of
//                  pixels outside it that the filter reaches
//   sample_passes  the sample indices [begin, end) cut into passes of growing width (and, with
//                  adaptive sampling, ending at every convergence check)
//   TileSampler    takes the samples of one pass for every active pixel of one tile
//   stop_converged adaptive sampling: between passes, stops the pixels whose noise is low enough
//   develop        merges the tiles in a fixed order, writes the film's pixel format, the
//                  integrator's channels and the --aov layers
// A pixel's samples depend only on (seed, pixel, sample index), so the schedule (threads, tile
// order) never changes the image. Rendering a sub-range of sample indices, or another sampler,
// only changes what sample_passes and the sampler hand out.

namespace candela {

namespace {

constexpr int TileSize = 32;

// Per-pixel running sums of the samples that landed in the pixel (not filtered): these give the
// variance of the pixel mean, the first-hit AOVs and the adaptive error estimate.
struct PixelStats {
    uint32_t n = 0;
    uint32_t taken = 0;   // sample indices taken (n plus the non-finite samples dropped)
    bool active = true;   // adaptive sampling has not stopped the pixel
    double sum[3] = {0, 0, 0}, sum_sq[3] = {0, 0, 0};
    // Adaptive sampling's half buffer: the samples of class A (see in_class_a).
    uint32_t n_a = 0;
    double sum_a[3] = {0, 0, 0};
    Spectrum albedo{0.0f};
    Vec3 normal{0.0f};
    double depth = 0.0;

    void add(const Spectrum& L, const FirstHitAovs& aov, uint32_t index) {
        n++;
        bool a = in_class_a(index);
        n_a += a;
        for (int c = 0; c < 3; ++c) {
            sum[c] += L[c];
            sum_sq[c] += double(L[c]) * L[c];
            if (a) sum_a[c] += L[c];
        }
        albedo += aov.albedo;
        normal += aov.normal;
        depth += aov.depth;
    }
    // Half of the sample indices, chosen so that both halves of a stratified or (0, 2) pattern stay
    // well stratified: those with an odd number of ones at the odd bit positions (Christensen,
    // Kensler and Kilpatrick 2018, "Progressive Multi-Jittered Sample Sequences", section 10.2.1).
    static bool in_class_a(uint32_t index) {
        uint32_t v = index & 0xaaaaaaaau;
        int ones = 0;
        for (; v; v &= v - 1) ++ones;
        return ones & 1;
    }
    // Cycles' per-pixel error (Dammertz et al. 2010, section 2.1): the L1 difference of the mean of
    // all samples and the mean of class A, over the square root of the mean's channel sum.
    double adaptive_error() const {
        if (n == 0 || n_a == 0) return Infinity;
        double difference = 0, total = 0;
        for (int c = 0; c < 3; ++c) {
            double mean = sum[c] / n;
            difference += std::abs(mean - sum_a[c] / n_a);
            total += mean;
        }
        return difference / (1e-4 + std::sqrt(std::max(total, 0.0)));
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
    // The pixels this tile samples, relative to `offset`: its own, and with sample_border the
    // ring outside the crop next to it. The block receives them all; only its own are developed.
    Vec2i sample_min{0}, sample_max{0};
    ImageBlock block;
    std::vector<PixelStats> stats;  // own pixels only; empty unless an --aov layer needs them
    int sampled_pixels() const { return (sample_max.x - sample_min.x) * (sample_max.y - sample_min.y); }
};

// A half-open range of sample indices [begin, end).
struct SampleRange {
    int begin = 0, end = 0;
};

// What each sample splats into the image blocks, filtered like the radiance (as Mitsuba films
// its alpha and AOVs): R, G, B, then alpha (1 for a valid sample, 0 otherwise) when the film's
// pixel format has one, then the integrator's channels.
class SampleLayout {
public:
    SampleLayout(const Film& film, const SamplingIntegrator& integrator)
        : format_(film.pixel_format()), alpha_(pixel_format_has_alpha(film.pixel_format())), extra_names_(integrator.channel_names()) {
        if (extra_names_.size() > size_t(MaxSampleChannels))
            throw InputError("the integrator reports " + std::to_string(extra_names_.size()) + " channels per sample, more than the " +
                             std::to_string(MaxSampleChannels) + " Candela supports");
    }
    int values() const { return 3 + (alpha_ ? 1 : 0) + extras(); }
    int extras() const { return int(extra_names_.size()); }

    // The splatted values of one sample; false when any is NaN or infinite.
    bool fill(const Spectrum& L, const SampleRecord& record, float* out) const {
        int c = 0;
        for (int k = 0; k < 3; ++k) out[c++] = L[k];
        if (alpha_) out[c++] = record.valid ? 1.0f : 0.0f;
        for (int k = 0; k < extras(); ++k) out[c++] = record.channels[k];
        for (int k = 0; k < c; ++k)
            if (!std::isfinite(out[k])) return false;
        return true;
    }

    // The image's first channels: the film's pixel format, then the integrator's channels.
    std::vector<std::string> channels() const {
        std::vector<std::string> names = pixel_format_channels(format_);
        names.insert(names.end(), extra_names_.begin(), extra_names_.end());
        return names;
    }
    // Writes those channels of one pixel from its normalised values.
    void write(const double* v, float* out) const {
        const Spectrum rgb{float(v[0]), float(v[1]), float(v[2])};
        write_pixel_format(format_, rgb, alpha_ ? float(v[3]) : 1.0f, out);
        out += pixel_format_channels(format_).size();
        for (int k = 0, first = alpha_ ? 4 : 3; k < extras(); ++k) out[k] = float(v[first + k]);
    }

private:
    PixelFormat format_;
    bool alpha_;
    std::vector<std::string> extra_names_;
};

// The --aov layers of a render and their channel layout: albedo.RGB, normal.XYZ, depth.Z,
// variance.RGB and samples.N, each only when asked for, after the film's and the integrator's
// channels.
class AovLayout {
public:
    explicit AovLayout(const std::vector<std::string>& names) {
        for (const auto& a : names) {
            if (a == "albedo") albedo_ = true;
            else if (a == "normal") normal_ = true;
            else if (a == "depth") depth_ = true;
            else if (a == "variance") variance_ = true;
            else if (a == "samples") samples_ = true;
            else throw InputError("unknown AOV \"" + a + "\" (known: albedo, normal, depth, variance, samples)");
        }
    }
    // Whether samples must report their first hit, and whether pixels keep running sums.
    bool first_hit() const { return albedo_ || normal_ || depth_; }
    bool pixel_stats() const { return first_hit() || variance_ || samples_; }
    int layer_count() const { return int(albedo_) + int(normal_) + int(depth_) + int(variance_) + int(samples_); }

    std::vector<std::string> channels() const {
        std::vector<std::string> channels;
        const char* rgb[3] = {"R", "G", "B"};
        if (albedo_)
            for (auto c : rgb) channels.push_back(std::string("albedo.") + c);
        if (normal_)
            for (auto c : {"X", "Y", "Z"}) channels.push_back(std::string("normal.") + c);
        if (depth_) channels.push_back("depth.Z");
        if (variance_)
            for (auto c : rgb) channels.push_back(std::string("variance.") + c);
        if (samples_) channels.push_back("samples.N");
        return channels;
    }

    // Writes the AOV channels of pixel (x, y), from channel c on, from its statistics.
    void write(const PixelStats& ps, Image& img, int x, int y, int c) const {
        float inv_n = ps.n ? 1.0f / float(ps.n) : 0.0f;
        if (albedo_)
            for (int k = 0; k < 3; ++k) img.at(x, y, c++) = ps.albedo[k] * inv_n;
        if (normal_)
            for (int k = 0; k < 3; ++k) img.at(x, y, c++) = ps.normal[k] * inv_n;
        if (depth_) img.at(x, y, c++) = float(ps.depth * inv_n);
        if (variance_)
            for (int k = 0; k < 3; ++k) img.at(x, y, c++) = float(ps.variance_of_mean(k));
        if (samples_) img.at(x, y, c++) = float(ps.taken);
    }

private:
    bool albedo_ = false, normal_ = false, depth_ = false, variance_ = false, samples_ = false;
};

// Tiles covering the film's crop window in row-major order (the order develop() merges them),
// each with a block of `values` channels. With sample_border, the tiles on the crop's edges also
// sample the pixels outside it within the filter's reach (Mitsuba samples a crop grown by the
// filter's border size); pixels inside the crop receive the same samples in the same order as
// without it, so only those within that reach of an edge change.
std::vector<Tile> make_tiles(const Film& film, int values, bool with_stats) {
    const Vec2i crop = film.crop_size();
    const int border = film.sample_border() ? std::max(0, int(std::ceil(film.filter().radius() - 0.5f))) : 0;
    std::vector<Tile> tiles;
    for (int y = 0; y < crop.y; y += TileSize)
        for (int x = 0; x < crop.x; x += TileSize) {
            Tile t;
            t.offset = Vec2i(x, y);
            t.size = glm::min(Vec2i(TileSize), crop - t.offset);
            t.sample_max = t.size;
            for (int axis = 0; axis < 2; ++axis) {
                if (t.offset[axis] == 0) t.sample_min[axis] = -border;
                if (t.offset[axis] + t.size[axis] == crop[axis]) t.sample_max[axis] += border;
            }
            t.block = ImageBlock(t.offset, t.size, &film.filter(), values);
            if (with_stats) t.stats.resize(size_t(t.size.x) * t.size.y);
            tiles.push_back(std::move(t));
        }
    return tiles;
}

// Stops the render before any allocation when the film's buffers cannot fit in memory: the
// tiles' blocks (with their filter borders) and pixel statistics, then develop's
// double-precision sum and the image, or at the end the image and write_exr's copies.
void check_film_memory(const Film& film, const SampleLayout& values, const AovLayout& layout) {
    const Vec2i crop = film.crop_size();
    const uint64_t w = uint64_t(crop.x), h = uint64_t(crop.y), pixels = w * h;
    const uint64_t border = uint64_t(std::max(0, int(std::ceil(film.filter().radius() - 0.5f))));
    const uint64_t tiles_x = (w + TileSize - 1) / TileSize, tiles_y = (h + TileSize - 1) / TileSize;
    // A block holds each splatted value and the filter weight per pixel.
    uint64_t blocks = saturating_mul(saturating_mul(w + 2 * border * tiles_x, h + 2 * border * tiles_y), uint64_t(values.values() + 1) * sizeof(float));
    blocks = saturating_add(blocks, saturating_mul(tiles_x * tiles_y, sizeof(Tile)));
    uint64_t stats = layout.pixel_stats() ? saturating_mul(pixels, sizeof(PixelStats)) : 0;
    uint64_t image = saturating_mul(pixels, (values.channels().size() + layout.channels().size()) * sizeof(float));
    uint64_t develop = saturating_add(saturating_add(blocks, stats), saturating_add(saturating_mul(pixels, 4 * sizeof(double)), image));
    uint64_t write = saturating_add(saturating_mul(image, 2), image / 2);  // the image, a sanitised copy, half floats
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
std::vector<SampleRange> sample_passes(const SampleRange& samples, const AdaptiveSchedule& adaptive) {
    std::vector<SampleRange> passes;
    for (int s0 = samples.begin, step = 1; s0 < samples.end; step = std::min(step * 2, 32)) {
        int end = std::min(samples.end, s0 + step);
        for (int c = s0 + 1; c < end; ++c)
            if (adaptive.checks_at(c)) end = c;
        passes.push_back({s0, end});
        s0 = end;
    }
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
    TileSampler(const SamplingIntegrator& integrator, const Scene& scene, const SampleLayout& values, const AovLayout& layers, int spp)
        : integrator_(integrator), scene_(scene), sensor_(scene.sensor()), crop_offset_(scene.sensor().film().crop_offset()), values_(values),
          first_hit_(layers.first_hit()), differential_scale_(1.0f / std::sqrt(float(std::max(spp, 1)))) {}

    // Samples `samples` of every pixel the tile samples, pixel by pixel, until done or interrupted.
    void sample_tile(Tile& tile, const SampleRange& samples, Sampler& sampler, Interruption& interruption, RenderCounters& counters,
                     ProgressReporter& progress) const {
        uint64_t rays_before = thread_ray_count();
        uint64_t taken = 0, nonfinite = 0;
        for (int y = tile.sample_min.y; y < tile.sample_max.y && !interruption.check(); ++y)
            for (int x = tile.sample_min.x; x < tile.sample_max.x && !interruption.check(); ++x)
                sample_pixel(tile, Vec2i(x, y), samples, sampler, taken, nonfinite);
        counters.rays += thread_ray_count() - rays_before;
        counters.samples += taken;
        counters.nonfinite += nonfinite;
        progress.add(taken);
    }

private:
    // The samples of one pixel (tile coordinates): each positions the sampler at (pixel, index),
    // so its random numbers depend on nothing else. Samples with a non-finite value are counted
    // and dropped.
    void sample_pixel(Tile& tile, const Vec2i& local, const SampleRange& samples, Sampler& sampler, uint64_t& taken, uint64_t& nonfinite) const {
        const Vec2i pixel = crop_offset_ + tile.offset + local;
        const bool own = local.x >= 0 && local.y >= 0 && local.x < tile.size.x && local.y < tile.size.y;
        PixelStats* ps = tile.stats.empty() || !own ? nullptr : &tile.stats[size_t(local.y) * tile.size.x + local.x];
        if (ps && !ps->active) return;
        if (ps) ps->taken += uint32_t(samples.end - samples.begin);
        float values[3 + 1 + MaxSampleChannels];
        for (int s = samples.begin; s < samples.end; ++s) {
            sampler.start(pixel, uint32_t(s));
            SampleRecord record;
            record.film_pos = Vec2(pixel) + sensor_.pixel_offset(sampler.next_2d());
            record.aperture = sampler.next_2d();
            record.differential_scale = differential_scale_;
            FirstHitAovs aov;
            record.first_hit = first_hit_ ? &aov : nullptr;
            Ray ray = sensor_.sample_ray(record.film_pos, record.aperture);
            Spectrum L = integrator_.sample_radiance(scene_, sampler, ray, record);
            ++taken;
            if (!values_.fill(L, record, values)) {
                ++nonfinite;
                continue;
            }
            tile.block.put(record.film_pos - Vec2(crop_offset_), values);
            if (ps) ps->add(L, aov, uint32_t(s));
        }
    }

    const SamplingIntegrator& integrator_;
    const Scene& scene_;
    const Sensor& sensor_;
    const Vec2i crop_offset_;
    const SampleLayout& values_;
    const bool first_hit_;
    const float differential_scale_;
};

// Adaptive sampling's check, between passes: a pixel is quiet when it has stopped or its error
// is below the threshold; an active pixel stops when it and its 8 neighbours are quiet (Cycles
// dilates the unconverged pixels by one the same way), and never starts again, so all active
// pixels take the same sample indices. Single-threaded over the whole image: deterministic.
void stop_converged(std::vector<Tile>& tiles, const Vec2i& crop, float threshold) {
    std::vector<uint8_t> quiet(size_t(crop.x) * crop.y, 0);
    for (const Tile& t : tiles)
        for (int y = 0; y < t.size.y; ++y)
            for (int x = 0; x < t.size.x; ++x) {
                const PixelStats& ps = t.stats[size_t(y) * t.size.x + x];
                quiet[size_t(t.offset.y + y) * crop.x + t.offset.x + x] = !ps.active || ps.adaptive_error() < threshold;
            }
    auto neighbourhood_quiet = [&](int px, int py) {
        for (int y = std::max(0, py - 1); y <= std::min(crop.y - 1, py + 1); ++y)
            for (int x = std::max(0, px - 1); x <= std::min(crop.x - 1, px + 1); ++x)
                if (!quiet[size_t(y) * crop.x + x]) return false;
        return true;
    };
    for (Tile& t : tiles)
        for (int y = 0; y < t.size.y; ++y)
            for (int x = 0; x < t.size.x; ++x) {
                PixelStats& ps = t.stats[size_t(y) * t.size.x + x];
                if (ps.active && neighbourhood_quiet(t.offset.x + x, t.offset.y + y)) ps.active = false;
            }
}

// Merges the tiles in a fixed order, normalises by the filter weights, and writes the film's
// pixel format, the integrator's channels and the --aov layers.
Image develop(const std::vector<Tile>& tiles, const Vec2i& crop, const SampleLayout& values, const AovLayout& layers) {
    const int stride = values.values() + 1;
    std::vector<double> accum(size_t(crop.x) * crop.y * size_t(stride), 0.0);
    for (const Tile& t : tiles) t.block.accumulate_into(accum, crop);
    std::vector<std::string> channels = values.channels();
    const int first_layer = int(channels.size());
    std::vector<std::string> layer_channels = layers.channels();
    channels.insert(channels.end(), layer_channels.begin(), layer_channels.end());
    Image img(crop.x, crop.y, channels);
    std::vector<double> normalised(size_t(stride - 1));
    for (int y = 0; y < crop.y; ++y)
        for (int x = 0; x < crop.x; ++x) {
            const double* a = &accum[(size_t(y) * crop.x + x) * stride];
            const double w = a[stride - 1];
            for (int c = 0; c + 1 < stride; ++c) normalised[c] = w > 0.0 ? a[c] / w : 0.0;
            values.write(normalised.data(), &img.at(x, y, 0));
        }
    for (const Tile& t : tiles) {
        if (t.stats.empty()) continue;
        for (int y = 0; y < t.size.y; ++y)
            for (int x = 0; x < t.size.x; ++x)
                layers.write(t.stats[size_t(y) * t.size.x + x], img, t.offset.x + x, t.offset.y + y, first_layer);
    }
    return img;
}

// An image's channel names must be distinct (an EXR cannot hold two channels of one name).
void check_distinct_channels(const std::vector<std::string>& channels) {
    for (size_t i = 0; i < channels.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (channels[i] == channels[j]) throw InputError("two image channels are named \"" + channels[i] + "\" (rename an AOV)");
}

// The scene's sampler, or the one the options name with the scene's sample count and seed, with
// the render's sample count and seed.
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
    sampler->set_film_size(scene.sensor().film().full_size());
    if (options.spp > 0) sampler->set_sample_count(options.spp);
    if (options.seed) sampler->set_seed(*options.seed);
    return sampler;
}

}  // namespace

void SampleRecord::record_first_hit(const SurfaceInteraction& si) {
    if (!first_hit) return;
    first_hit->albedo = si.shape->bsdf()->albedo(si);
    first_hit->normal = si.shading.n;
    first_hit->depth = si.t;
}

Image Integrator::preview(const Image& rendered) const { return tonemap_srgb(linear_rgb(rendered)); }

void Integrator::refuse_unrendered_media(const Scene& scene) const {
    if (!scene.has_media() || renders_media()) return;
    throw SceneError(SourceLocation{scene.source_file, 0}, "the scene has participating media, which the " + to_string() +
                                                               " integrator would ignore: render it with volpath (or volpathmis)");
}

RenderResult SamplingIntegrator::render(const Scene& scene, const RenderOptions& options) {
    refuse_unrendered_media(scene);
    auto t_start = std::chrono::steady_clock::now();
    const Film& film = scene.sensor().film();
    const SampleLayout values(film, *this);
    const AovLayout layers(options.aovs);
    std::vector<std::string> channels = values.channels(), layer_channels = layers.channels();
    channels.insert(channels.end(), layer_channels.begin(), layer_channels.end());
    check_distinct_channels(channels);
    check_film_memory(film, values, layers);
    Ref<Sampler> prototype = configured_sampler(scene, options);
    const SampleRange samples{0, prototype->sample_count()};
    const AdaptiveSchedule adaptive(options.adaptive, samples.end);
    prepare(scene);

    std::vector<Tile> tiles = make_tiles(film, values.values(), layers.pixel_stats() || adaptive.enabled);
    uint64_t sampled_pixels = 0;
    for (const Tile& t : tiles) sampled_pixels += uint64_t(t.sampled_pixels());
    ProgressReporter progress("Rendering", uint64_t(samples.end - samples.begin) * sampled_pixels, options.progress);
    RenderCounters counters;
    Interruption interruption(options.interrupt);
    const TileSampler tile_sampler(*this, scene, values, layers, prototype->sample_count());
    tbb::enumerable_thread_specific<Ref<Sampler>> samplers([&] { return prototype->clone(); });
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    for (const SampleRange& pass : sample_passes(samples, adaptive)) {
        if (interruption.stopped()) break;
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
                for (size_t i = r.begin(); i != r.end(); ++i) tile_sampler.sample_tile(tiles[i], pass, *samplers.local(), interruption, counters, progress);
            });
        });
        if (adaptive.checks_at(pass.end) && !interruption.stopped()) stop_converged(tiles, film.crop_size(), adaptive.threshold);
    }
    progress.finish();

    RenderResult result;
    result.image = develop(tiles, film.crop_size(), values, layers);
    RenderStats& st = result.stats;
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    st.samples = counters.samples;
    st.rays = counters.rays;
    st.nonfinite = counters.nonfinite;
    st.spp = prototype->sample_count();
    st.seed = prototype->seed();
    st.sampler = prototype->to_string();
    st.partial = interruption.stopped();
    return result;
}

}  // namespace candela
