#include "farm/part_file.h"

#include "core/error.h"
#include "core/mapped_file.h"
#include "core/parallel.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "core/text.h"

#include <candela/version.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

namespace candela {

namespace {

// 2: sums of every splatted value (alpha, integrator channels), taken.N, the film and integrator
// channels in the identity.
constexpr const char* PartFormat = "2";
// float32 holds every integer up to 2^24 exactly: the largest per-pixel sample count of a part.
constexpr uint32_t MaxExactCount = 1u << 24;

// A plain, stable 64-bit hash of bytes (not cryptographic; it tells renders apart). It takes
// eight bytes per step, a multiply by an odd constant (2^64 / golden ratio) and a fold of the
// high half into the low: the scene's input files are hashed before every render, and a
// byte-wise FNV-1a over a 200 MB mesh took a quarter of a second of it; files are hashed in
// parallel blocks (add_file).
struct ContentHash {
    uint64_t state = 0xcbf29ce484222325ULL;
    void add(const char* data, size_t size) {
        size_t i = 0;
        for (; i + 8 <= size; i += 8) {
            uint64_t word;
            std::memcpy(&word, data + i, 8);
            mix(word);
        }
        for (; i < size; ++i) mix(static_cast<unsigned char>(data[i]));
    }
    void mix(uint64_t word) {
        state = (state ^ word) * 0x9E3779B97F4A7C15ULL;
        state ^= state >> 32;
    }
    void add(const std::string& s) {
        add(s.data(), s.size());
        add("\0", 1);  // so that "ab"+"c" and "a"+"bc" differ
    }
    // A file's bytes: 1 MB blocks hashed in parallel, each on its own from its index, then their
    // hashes added in order (the same value whatever the thread count). Each chunk of blocks is
    // read with pread into the chunk's own buffer: for a 190 MB mesh that took 0.04 s against
    // 0.10 s through a memory map, whose page faults and unmapping cost more than the copy.
    void add_file(const std::string& path) {
        size_t size = 0;
        int fd = -1;
        try {
            fd = open_regular_file(path, size);
        } catch (const std::runtime_error& e) {
            throw InputError(path + ": cannot read it to hash the scene: " + e.what());
        }
        const size_t block = size_t(1) << 20, blocks = (size + block - 1) / block;
        std::vector<uint64_t> hashes(blocks);
        std::atomic<bool> short_read{false};
        parallel_chunks(blocks, 8, [&](size_t first, size_t last) {
            const std::unique_ptr<char[]> buffer(new char[block]);
            for (size_t b = first; b < last; ++b) {
                const size_t begin = b * block, length = std::min(block, size - begin);
                size_t done = 0;
                while (done < length) {
                    const ssize_t got = ::pread(fd, buffer.get() + done, length - done, off_t(begin + done));
                    if (got > 0) {
                        done += size_t(got);
                    } else if (got == 0 || errno != EINTR) {
                        short_read = true;
                        return;
                    }
                }
                ContentHash h;
                h.mix(b);
                h.add(buffer.get(), length);
                hashes[b] = h.state;
            }
        });
        ::close(fd);
        if (short_read) throw InputError(path + ": cannot read it to hash the scene: it changed or failed while being read");
        mix(size);
        for (uint64_t h : hashes) mix(h);
        add("\0", 1);
    }
};

std::vector<std::string> part_channels(const SampleLayout& values, const AovLayout& layout) {
    std::vector<std::string> ch = {"R", "G", "B"};
    for (const std::string& v : values.value_names()) ch.push_back("sum." + v);
    ch.push_back("sum.W");
    if (layout.pixel_stats()) ch.push_back("count.N");
    if (layout.samples()) ch.push_back("taken.N");
    auto layer = [&](const char* name, const char* components) {
        for (const char* c = components; *c; ++c) ch.push_back(std::string(name) + "." + *c);
    };
    if (layout.albedo()) layer("albedoSum", "RGB");
    if (layout.normal()) layer("normalSum", "XYZ");
    if (layout.depth()) layer("depthSum", "Z");
    if (layout.variance()) {
        layer("moment1", "RGB");
        layer("moment1lo", "RGB");
        layer("moment2", "RGB");
        layer("moment2lo", "RGB");
    }
    return ch;
}

std::string format_seconds(double s) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3f", s);
    return buf;
}

// The metadata value `key` of a part, InputError naming the file when absent.
struct HeaderReader {
    const std::string& path;
    const ImageHeader& header;

    std::string text(const std::string& key) const {
        auto p = header.metadata.find(key);
        if (p == header.metadata.end()) throw InputError(path + ": part metadata lacks " + key);
        return p->second;
    }
    // For values that may be empty: an empty string attribute does not survive the file.
    std::string text_or_empty(const std::string& key) const {
        auto p = header.metadata.find(key);
        return p == header.metadata.end() ? std::string() : p->second;
    }
    template <typename T>
    T number(const std::string& key) const {
        std::string s = text(key);
        try {
            size_t used = 0;
            T v;
            if constexpr (std::is_same_v<T, double>)
                v = std::stod(s, &used);
            else if constexpr (std::is_same_v<T, uint64_t>)
                v = std::stoull(s, &used);
            else
                v = T(std::stoi(s, &used));
            if (used == s.size()) return v;
        } catch (const std::exception&) {}
        throw InputError(path + ": part metadata " + key + " is not a number: \"" + s + "\"");
    }
};

}  // namespace

AovLayout RenderIdentity::layout() const { return AovLayout(split_list(aovs)); }

SampleLayout RenderIdentity::values() const { return SampleLayout::from_film_key(film_channels, split_list(integrator_channels)); }

std::string RenderIdentity::difference(const RenderIdentity& o) const {
    auto differs = [](const std::string& what, const std::string& a, const std::string& b) {
        return a == b ? std::string() : what + " " + a + " against " + b;
    };
    std::string d;
    auto check = [&](const std::string& what, const std::string& a, const std::string& b) {
        if (d.empty()) d = differs(what, a, b);
    };
    check("Candela version", version, o.version);
    check("scene hash", scene_hash + " (" + scene + ")", o.scene_hash + " (" + o.scene + ")");
    check("seed", std::to_string(seed), std::to_string(o.seed));
    check("sampler", sampler, o.sampler);
    check("samples per pixel", std::to_string(spp), std::to_string(o.spp));
    check("resolution", std::to_string(image.x) + "x" + std::to_string(image.y),
          std::to_string(o.image.x) + "x" + std::to_string(o.image.y));
    check("integrator", integrator, o.integrator);
    check("variant", variant, o.variant);
    check("film channels", "\"" + film_channels + "\"", "\"" + o.film_channels + "\"");
    check("integrator channels", "\"" + integrator_channels + "\"", "\"" + o.integrator_channels + "\"");
    check("AOVs", "\"" + aovs + "\"", "\"" + o.aovs + "\"");
    check("film format", float32 ? "float32" : "float16", o.float32 ? "float32" : "float16");
    return d;
}

std::string scene_hash(const Scene& scene) {
    ContentHash h;
    h.add_file(scene.source_file);
    for (const std::string& f : scene.input_files) h.add_file(f);
    for (const auto& [name, value] : scene.parameters) h.add(name + "=" + value);
    // Another sensor is another render (the first one's hash is as it was before sensors counted).
    if (scene.sensor_index() != 0) h.add("sensor=" + std::to_string(scene.sensor_index()));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h.state));
    return buf;
}

RenderIdentity render_identity(const Scene& scene, const std::string& scene_path, const RenderStats& stats, const SampleLayout& values,
                               const AovLayout& layout, const std::string& command) {
    RenderIdentity id;
    id.scene = scene_path;
    id.scene_hash = scene_hash(scene);
    id.seed = stats.seed;
    id.sampler = stats.sampler;
    id.spp = stats.spp;
    id.image = scene.sensor().film().crop_size();
    id.integrator = scene.integrator().to_string();
    id.variant = variant_name(scene.variant());
    id.film_channels = values.film_key();
    id.integrator_channels = join_list(values.integrator_channels());
    id.aovs = layout.names();
    id.version = CANDELA_VERSION;
    id.float32 = scene.sensor().film().float32();
    id.command = command;
    return id;
}

void write_part(const std::string& path, const PixelSums& sums, const PartHeader& header) {
    const AovLayout& layout = sums.layout();
    const Vec2i size = sums.size();
    const int stride = sums.stride();
    Image img(size.x, size.y, part_channels(sums.values(), layout));
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
            int c = 0;
            auto put = [&](double v) { img.at(x, y, c++) = float(v); };
            // Three values as float32 (momentK), then what float32 rounded off (momentKlo).
            auto put_hi_lo = [&](const double* v) {
                for (int k = 0; k < 3; ++k) {
                    img.at(x, y, c + k) = float(v[k]);
                    img.at(x, y, c + 3 + k) = float(v[k] - double(float(v[k])));
                }
                c += 6;
            };
            const double* f = sums.filtered_at(x, y);
            const double w = f[stride - 1];
            for (int k = 0; k < 3; ++k) put(w > 0.0 ? f[k] / w : 0.0);
            for (int k = 0; k < stride; ++k) put(f[k]);
            if (!layout.pixel_stats()) continue;
            const PixelStats& ps = sums.stats_at(x, y);
            if (ps.taken > MaxExactCount)
                throw InputError(path + ": a pixel holds " + std::to_string(ps.taken) +
                                 " samples, more than a part can count exactly (2^24)");
            put(ps.n);
            if (layout.samples()) put(ps.taken);
            if (layout.albedo())
                for (double v : ps.albedo) put(v);
            if (layout.normal())
                for (double v : ps.normal) put(v);
            if (layout.depth()) put(ps.depth);
            if (layout.variance()) {
                put_hi_lo(ps.sum);
                put_hi_lo(ps.sum_sq);
            }
        }
    const RenderIdentity& id = header.identity;
    auto& m = img.metadata;
    m["software"] = "Candela " + id.version;
    m["candela.partFormat"] = PartFormat;
    m["candela.scene"] = id.scene;
    m["candela.sceneHash"] = id.scene_hash;
    m["candela.seed"] = std::to_string(id.seed);
    m["candela.sampler"] = id.sampler;
    m["candela.spp"] = std::to_string(id.spp);
    m["candela.imageSize"] = std::to_string(id.image.x) + "x" + std::to_string(id.image.y);
    m["candela.integrator"] = id.integrator;
    m["candela.variant"] = id.variant;
    m["candela.filmChannels"] = id.film_channels;
    m["candela.integratorChannels"] = id.integrator_channels;
    m["candela.aovs"] = id.aovs;
    m["candela.version"] = id.version;
    m["candela.float32"] = id.float32 ? "true" : "false";
    m["candela.command"] = id.command;
    m["candela.coverage"] = format_coverage(header.coverage);
    m["candela.partial"] = header.partial ? "true" : "false";
    m["candela.origin"] = std::to_string(sums.rect().offset.x) + "," + std::to_string(sums.rect().offset.y);
    m["candela.renderTime"] = format_seconds(header.work.seconds);
    m["candela.started"] = format_seconds(header.started);
    m["candela.finished"] = format_seconds(header.finished);
    m["candela.host"] = header.host;
    m["candela.renderedParts"] = std::to_string(header.rendered_parts);
    m["candela.samples"] = std::to_string(header.work.samples);
    m["candela.rays"] = std::to_string(header.work.rays);
    m["candela.nonfiniteSamples"] = std::to_string(header.work.nonfinite);
    write_exr(img, path, true);
}

PartHeader read_part_header(const std::string& path) {
    // Parts are OpenEXR files; a file of another format has no part metadata.
    const ImageHeader file = read_image_header(path);
    if (!file.metadata.count("candela.partFormat"))
        throw InputError(path +
                         ": not a part of a split render (no candela.partFormat metadata; parts come from "
                         "`candela render --samples START:END` or `--crop`)");
    HeaderReader r{path, file};
    if (r.text("candela.partFormat") != PartFormat)
        throw InputError(path + ": part format " + r.text("candela.partFormat") + ", this Candela reads format " + PartFormat);
    PartHeader h;
    h.path = path;
    RenderIdentity& id = h.identity;
    id.scene = r.text("candela.scene");
    id.scene_hash = r.text("candela.sceneHash");
    id.seed = r.number<uint64_t>("candela.seed");
    id.sampler = r.text("candela.sampler");
    id.spp = r.number<int>("candela.spp");
    if (std::sscanf(r.text("candela.imageSize").c_str(), "%dx%d", &id.image.x, &id.image.y) != 2)
        throw InputError(path + ": part metadata candela.imageSize is not WIDTHxHEIGHT");
    id.integrator = r.text("candela.integrator");
    if (!r.text_or_empty("candela.variant").empty()) id.variant = r.text_or_empty("candela.variant");
    id.film_channels = r.text("candela.filmChannels");
    id.integrator_channels = r.text_or_empty("candela.integratorChannels");
    id.aovs = r.text_or_empty("candela.aovs");
    id.version = r.text("candela.version");
    id.float32 = r.text("candela.float32") == "true";
    id.command = r.text("candela.command");
    h.partial = r.text("candela.partial") == "true";
    try {
        h.coverage = r.text_or_empty("candela.coverage").empty() ? std::vector<CoverageBox>{} : parse_coverage(r.text("candela.coverage"));
    } catch (const InputError& e) {
        throw InputError(path + ": " + e.what());
    }
    if (std::sscanf(r.text("candela.origin").c_str(), "%d,%d", &h.rect.offset.x, &h.rect.offset.y) != 2)
        throw InputError(path + ": part metadata candela.origin is not X,Y");
    h.rect.size = Vec2i(file.width, file.height);
    h.work.seconds = r.number<double>("candela.renderTime");
    h.started = r.number<double>("candela.started");
    h.finished = r.number<double>("candela.finished");
    h.host = r.text_or_empty("candela.host");
    h.rendered_parts = r.number<int>("candela.renderedParts");
    h.work.samples = r.number<uint64_t>("candela.samples");
    h.work.rays = r.number<uint64_t>("candela.rays");
    h.work.nonfinite = r.number<uint64_t>("candela.nonfiniteSamples");
    // What each sample splats and which AOV layers there are, both named by the metadata.
    SampleLayout values;
    AovLayout layout;
    try {
        values = id.values();
        layout = id.layout();
    } catch (const InputError& e) {
        throw InputError(path + ": part metadata: " + e.what());
    }
    std::vector<std::string> expected = part_channels(values, layout), found = file.channels;
    std::sort(expected.begin(), expected.end());
    std::sort(found.begin(), found.end());
    if (found != expected)
        throw InputError(path + ": its channels are not those of a part with film channels \"" + id.film_channels +
                         "\", integrator channels \"" + id.integrator_channels + "\" and AOVs \"" + id.aovs + "\"");
    if (id.image.x <= 0 || id.image.y <= 0) throw InputError(path + ": part metadata candela.imageSize is not a positive size");
    if (!sample_count_problem(id.spp).empty()) throw InputError(path + ": part metadata candela.spp: " + sample_count_problem(id.spp));
    bool inside = rect_inside_image(h.rect, id.image);
    for (const CoverageBox& b : h.coverage) inside = inside && rect_inside(b.rect, h.rect) && b.samples.end <= id.spp;
    if (!inside) throw InputError(path + ": its coverage " + format_coverage(h.coverage) + " lies outside its image or samples");
    return h;
}

void add_part(const PartHeader& h, PixelSums& image_sums) {
    // OpenEXR stores channels sorted by name: find each where it is.
    Image part = read_image(h.path);
    std::vector<int> index;
    for (const std::string& name : part_channels(image_sums.values(), image_sums.layout()))
        if (name.find('.') != std::string::npos) index.push_back(part.channel_index(name));  // not R, G, B: the image
    if (part.width() != h.rect.size.x || part.height() != h.rect.size.y || std::count(index.begin(), index.end(), -1) > 0)
        throw InputError(h.path + ": changed while merging");
    if (!rect_inside(h.rect, image_sums.rect())) throw InputError(h.path + ": lies outside the merged area");
    const Vec2i at = h.rect.offset - image_sums.rect().offset;
    const AovLayout& layout = image_sums.layout();
    auto pixel_name = [&](int x, int y) { return std::to_string(h.rect.offset.x + x) + "," + std::to_string(h.rect.offset.y + y); };
    for (int y = 0; y < part.height(); ++y)
        for (int x = 0; x < part.width(); ++x) {
            const int ix = at.x + x, iy = at.y + y;
            int c = 0;
            // A part holds finite sums and whole sample counts; anything else is a damaged or
            // crafted file, refused before it reaches the image.
            auto value = [&](int channel) {
                const double v = part.at(x, y, index[channel]);
                if (!std::isfinite(v)) throw InputError(h.path + ": holds a non-finite sum at pixel " + pixel_name(x, y));
                return v;
            };
            // A count is written only up to 2^24, which float32 holds exactly (write_part refuses
            // more): anything above is not a part's.
            auto count = [&]() {
                const double v = part.at(x, y, index[c++]);
                if (!(v >= 0.0 && v <= double(MaxExactCount) && v == std::floor(v)))
                    throw InputError(h.path + ": holds a sample count that is not a whole number in [0, 2^24] at pixel " +
                                     pixel_name(x, y));
                return uint32_t(v);
            };
            auto next = [&]() { return value(c++); };
            auto add_hi_lo = [&](double* sum) {
                for (int k = 0; k < 3; ++k) sum[k] += value(c + k) + value(c + 3 + k);
                c += 6;
            };
            double* f = image_sums.filtered_at(ix, iy);
            for (int k = 0; k < image_sums.stride(); ++k) f[k] += next();
            if (!layout.pixel_stats()) continue;
            PixelStats& ps = image_sums.stats_at(ix, iy);
            ps.n += count();
            ps.taken += layout.samples() ? count() : 0;
            if (layout.albedo())
                for (double& v : ps.albedo) v += next();
            if (layout.normal())
                for (double& v : ps.normal) v += next();
            if (layout.depth()) ps.depth += next();
            if (layout.variance()) {
                add_hi_lo(ps.sum);
                add_hi_lo(ps.sum_sq);
            }
        }
}

}  // namespace candela
