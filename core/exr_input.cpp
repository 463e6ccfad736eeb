#include "core/exr_input.h"

#include "core/byte_order.h"
#include "core/text.h"

#include <Imath/ImathBox.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <OpenEXR/ImfTileDescriptionAttribute.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <new>
#include <set>

namespace fs = std::filesystem;

namespace candela {

namespace {

// The bytes OpenEXR 3.1's reader of a standard attribute type of fixed length consumes, whatever
// size the header declares for it (its typed readers read their fields and ignore the size); -1
// for the other types. From the OpenEXR file layout document, "Attribute types".
int64_t fixed_attribute_size(const std::string& type) {
    static const std::map<std::string, int64_t> sizes = {{"box2i", 16},
                                                         {"box2f", 16},
                                                         {"chromaticities", 32},
                                                         {"compression", 1},
                                                         {"deepImageState", 1},
                                                         {"double", 8},
                                                         {"envmap", 1},
                                                         {"float", 4},
                                                         {"int", 4},
                                                         {"keycode", 28},
                                                         {"lineOrder", 1},
                                                         {"m33f", 36},
                                                         {"m33d", 72},
                                                         {"m44f", 64},
                                                         {"m44d", 128},
                                                         {"rational", 8},
                                                         {"tiledesc", 9},
                                                         {"timecode", 8},
                                                         {"v2i", 8},
                                                         {"v2f", 8},
                                                         {"v2d", 16},
                                                         {"v3i", 12},
                                                         {"v3f", 12},
                                                         {"v3d", 24}};
    const auto it = sizes.find(type);
    return it == sizes.end() ? -1 : it->second;
}

uint32_t little_endian_u32(const char* p) { return uint32_t(read_little_endian(reinterpret_cast<const unsigned char*>(p), 4)); }
uint32_t little_endian_u32(const std::string& bytes, size_t at) { return little_endian_u32(bytes.data() + at); }

// The bytes OpenEXR reads for an attribute of type `type` whose value the header says is
// `value.size()` bytes long: the fixed length of the fixed types; chlist, stringvector and
// preview walked as their readers walk them (-1 when a reader would run past the value); a whole
// number of floats for floatvector; all of it for string and for the types OpenEXR does not know
// (read as opaque bytes). `channels` counts a channel list's entries.
int64_t attribute_bytes_read(const std::string& type, const std::string& value, int64_t& channels) {
    if (const int64_t fixed = fixed_attribute_size(type); fixed >= 0) return fixed;
    const size_t n = value.size();
    if (type == "chlist") {  // (name, 0, 16 bytes of type, linearity and sampling)*, 0
        size_t at = 0;
        for (channels = 0;; ++channels) {
            const size_t end = value.find('\0', at);
            if (end == std::string::npos || end - at > 255) return -1;
            if (end == at) return int64_t(end + 1);
            at = end + 1 + 16;
            if (at > n) return -1;
        }
    }
    if (type == "stringvector") {  // (int32 length, that many bytes)* while fewer than size were read
        size_t at = 0;
        while (at < n) {
            if (n - at < 4) return -1;
            const uint32_t length = little_endian_u32(value, at);
            if (length > n - at - 4) return -1;
            at += 4 + length;
        }
        return int64_t(at);
    }
    if (type == "preview") {  // uint32 width, uint32 height, width * height RGBA bytes
        if (n < 8) return -1;
        return 8 + 4 * int64_t(little_endian_u32(value, 0)) * int64_t(little_endian_u32(value, 4));
    }
    if (type == "floatvector") return int64_t(n - n % 4);
    return int64_t(n);
}

}  // namespace

std::string exr_header_problem(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::error_code ec;
    const uint64_t file_size = fs::file_size(path, ec);
    unsigned char start[8];
    if (ec || !in.read(reinterpret_cast<char*>(start), 8)) return "";
    const bool multipart = (start[5] & 0x10) != 0;  // version flag bit 12
    // A zero-terminated name (at most 255 characters); false when there is none.
    auto read_name = [&](std::string& name) {
        name.clear();
        for (char c; in.get(c);) {
            if (c == '\0') return true;
            if (name.size() == 255) return false;
            name += c;
        }
        return false;
    };
    for (;;) {
        // What OpenEXR allocates for when it opens the file: a block of whole tiles or scan lines
        // of the data window, for every channel.
        int64_t width = 0, height = 0, channels = 0, tile_width = 0, tile_height = 0;
        for (;;) {
            std::string name, type;
            if (!read_name(name)) return "";
            if (name.empty()) break;  // the end of this header
            char size_bytes[4];
            if (!read_name(type) || !in.read(size_bytes, 4)) return "";
            const int64_t size = int32_t(little_endian_u32(size_bytes));
            const uint64_t at = uint64_t(in.tellg());
            const std::string attribute = path + ": cannot read image: its header's attribute \"" + name + "\" ";
            if (size < 0 || uint64_t(size) > file_size - std::min(at, file_size))
                return attribute + "declares " + std::to_string(size) + " bytes, but the file has " +
                       std::to_string(file_size - std::min(at, file_size)) + " left";
            // OpenEXR reads a typed value by its own length and goes on from where it stopped, not
            // from where the declared size ends: a size that disagrees would have it read the rest
            // of the header out of step with this check (found by fuzz_part: a channel list
            // declared 515 bytes long that ran on for 519, after whose end OpenEXR met a 1.8 GB attribute).
            std::string value(size_t(size), '\0');
            if (!in.read(value.data(), size)) return "";
            int64_t entries = 0;
            const int64_t reads = attribute_bytes_read(type, value, entries);
            if (reads != size)
                return attribute + "of type " + type + " declares " + std::to_string(size) + " bytes, but its value " +
                       (reads < 0 ? std::string("runs past them") : "holds " + std::to_string(reads));
            if (name == "channels" && type == "chlist") channels = entries;
            if (name == "dataWindow" && type == "box2i") {
                const auto corner = [&](size_t at) { return int64_t(int32_t(little_endian_u32(value, at))); };
                width = corner(8) - corner(0) + 1;
                height = corner(12) - corner(4) + 1;
            }
            if (name == "tiles" && type == "tiledesc") {
                tile_width = int64_t(little_endian_u32(value, 0));
                tile_height = int64_t(little_endian_u32(value, 4));
            }
        }
        // OpenEXR allocates its line or tile buffers when it opens the file, before any reader
        // could check the size (fuzz_part: a 1-line file 458760 pixels wide with 21 channels, whose
        // 16-line ZIP buffer is 616 MB).
        if (width != 0 && channels > 0)
            if (std::string problem = image_size_problem(path, width, height, channels, tile_width, tile_height); !problem.empty())
                return problem;
        // After a multi-part file's header, another one or an empty one (the end of them all).
        if (!multipart || in.peek() == 0 || !in) return "";
    }
}

std::vector<int> exr_channel_order(const std::vector<std::string>& names) {
    // The names known, lower case (they match case-insensitively).
    static const std::vector<std::string> usual = {"r",     "red", "g",  "green", "b",  "blue", "y",  "real", "imag",  "a",
                                                   "alpha", "ar",  "ra", "ag",    "ga", "ab",   "ba", "z",    "depth", "zback"};
    static const std::vector<std::string> positions = {"r", "red",   "g",  "green", "b",  "blue", "x",  "y",  "z",     "real", "imag",
                                                       "a", "alpha", "ar", "ra",    "ag", "ga",   "ab", "ba", "depth", "zback"};
    struct Key {
        std::string layer, suffix, lower;  // lower: the suffix in lower case
        int rank;
        int index;
    };
    std::vector<Key> keys;
    for (size_t i = 0; i < names.size(); ++i) {
        const size_t dot = names[i].rfind('.');
        const std::string layer = dot == std::string::npos ? "" : names[i].substr(0, dot + 1);
        const std::string suffix = dot == std::string::npos ? names[i] : names[i].substr(dot + 1);
        keys.push_back({layer, suffix, to_lower(suffix), 0, int(i)});
    }
    auto layer_has = [&](const std::string& layer, const char* lower) {
        for (const Key& k : keys)
            if (k.layer == layer && k.lower == lower) return true;
        return false;
    };
    for (Key& k : keys) {
        // A layer with X and Y or Z holds positions or normals: X, Y, Z in that order.
        const bool xyz = layer_has(k.layer, "x") && (layer_has(k.layer, "y") || layer_has(k.layer, "z"));
        const std::vector<std::string>& known = xyz ? positions : usual;
        k.rank = int(std::find(known.begin(), known.end(), k.lower) - known.begin());
    }
    std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
        if (a.layer != b.layer) return a.layer < b.layer;
        if (a.rank != b.rank) return a.rank < b.rank;
        return a.suffix < b.suffix;
    });
    std::vector<int> order;
    for (const Key& k : keys) order.push_back(k.index);
    return order;
}

namespace {

// The header's attributes a caller may want, as text (core/exr_input.h).
std::map<std::string, std::string> exr_metadata(const Imf::Header& header) {
    static const std::set<std::string> required = {"channels",  "compression",      "dataWindow",         "displayWindow",
                                                   "lineOrder", "pixelAspectRatio", "screenWindowCenter", "screenWindowWidth"};
    std::map<std::string, std::string> metadata;
    for (auto it = header.begin(); it != header.end(); ++it) {
        const std::string name = it.name();
        if (required.count(name)) continue;
        const Imf::Attribute& a = it.attribute();
        if (auto* s = dynamic_cast<const Imf::StringAttribute*>(&a))
            metadata[name] = s->value();
        else if (auto* i = dynamic_cast<const Imf::IntAttribute*>(&a))
            metadata[name] = std::to_string(i->value());
        else if (auto* f = dynamic_cast<const Imf::FloatAttribute*>(&a))
            metadata[name] = number_text(double(f->value()), 9);
        else if (auto* d = dynamic_cast<const Imf::DoubleAttribute*>(&a))
            metadata[name] = number_text(d->value(), 17);
    }
    return metadata;
}

bool read_exr_file(const std::string& path, bool pixels, int threads, DecodedImage& out, std::string& error) {
    bool tiled = false, deep = false, multipart = false;
    if (!Imf::isOpenExrFile(path.c_str(), tiled, deep, multipart) || deep || multipart) return false;
    Imf::InputFile file(path.c_str(), threads);
    const Imf::Header& header = file.header();
    std::vector<std::string> file_names;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
        // OpenImageIO scaled 32-bit unsigned values to [0, 1]: such files (object ids, rare as
        // textures) stay with it, read as they always were.
        if (it.channel().xSampling != 1 || it.channel().ySampling != 1 || it.channel().type == Imf::UINT) return false;
        file_names.push_back(it.name());
    }
    const Imath::Box2i window = header.dataWindow();
    const int64_t width = int64_t(window.max.x) - window.min.x + 1, height = int64_t(window.max.y) - window.min.y + 1;
    const size_t channels = file_names.size();
    const bool tiles = tiled && header.hasTileDescription();
    error = image_size_problem(path, width, height, int64_t(channels), tiles ? int64_t(header.tileDescription().xSize) : 0,
                               tiles ? int64_t(header.tileDescription().ySize) : 0);
    if (!error.empty()) return true;
    ImageHeader& h = out.header;
    h.width = int(width);
    h.height = int(height);
    for (int i : exr_channel_order(file_names)) h.channels.push_back(file_names[size_t(i)]);
    h.metadata = exr_metadata(header);
    if (pixels) {
        out.values.assign(size_t(width) * size_t(height) * channels, 0.0f);
        Imf::FrameBuffer frame;
        const size_t x_stride = sizeof(float) * channels, y_stride = x_stride * size_t(width);
        for (size_t c = 0; c < channels; ++c)
            frame.insert(h.channels[c], Imf::Slice::Make(Imf::FLOAT, out.values.data() + c, window, x_stride, y_stride));
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
    }
    return true;
}

}  // namespace

bool read_exr(const std::string& path, bool pixels, int threads, DecodedImage& out, std::string& error) {
    DecodedImage decoded;
    error.clear();
    try {
        if (!read_exr_file(path, pixels, threads, decoded, error)) return false;
    } catch (const std::bad_alloc&) {
        error = path + ": cannot read image: out of memory";
    } catch (const std::exception& e) {
        error = path + ": cannot read image: " + e.what();
    }
    if (error.empty()) out = std::move(decoded);
    return true;
}

}  // namespace candela
