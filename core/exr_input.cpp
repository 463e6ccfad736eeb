#include "core/exr_input.h"

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
#include <new>
#include <set>

namespace fs = std::filesystem;

namespace candela {

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
        for (;;) {
            std::string name, type;
            if (!read_name(name)) return "";
            if (name.empty()) break;  // the end of this header
            unsigned char size_bytes[4];
            if (!read_name(type) || !in.read(reinterpret_cast<char*>(size_bytes), 4)) return "";
            const int64_t size = int32_t(uint32_t(size_bytes[0]) | uint32_t(size_bytes[1]) << 8 | uint32_t(size_bytes[2]) << 16 |
                                         uint32_t(size_bytes[3]) << 24);
            const uint64_t at = uint64_t(in.tellg());
            if (size < 0 || uint64_t(size) > file_size - std::min(at, file_size))
                return path + ": cannot read image: its header's attribute \"" + name + "\" declares " + std::to_string(size) +
                       " bytes, but the file has " + std::to_string(file_size - std::min(at, file_size)) + " left";
            in.seekg(std::streamoff(size), std::ios::cur);
        }
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
