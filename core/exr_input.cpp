#include "core/exr_input.h"

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
#include <cctype>
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
    static const std::vector<const char*> usual = {"R",     "Red", "G",  "Green", "B",  "Blue", "Y",  "real", "imag",  "A",
                                                   "Alpha", "AR",  "RA", "AG",    "GA", "AB",   "BA", "Z",    "Depth", "Zback"};
    static const std::vector<const char*> positions = {"R", "Red",   "G",  "Green", "B",  "Blue", "X",  "Y",  "Z",     "real", "imag",
                                                       "A", "Alpha", "AR", "RA",    "AG", "GA",   "AB", "BA", "Depth", "Zback"};
    auto same = [](const std::string& a, const char* b) {
        size_t i = 0;
        for (; i < a.size() && b[i]; ++i)
            if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
        return i == a.size() && !b[i];
    };
    struct Key {
        std::string layer, suffix;
        int rank;
        int index;
    };
    std::vector<Key> keys;
    for (size_t i = 0; i < names.size(); ++i) {
        const size_t dot = names[i].rfind('.');
        if (dot == std::string::npos)
            keys.push_back({"", names[i], 0, int(i)});
        else
            keys.push_back({names[i].substr(0, dot + 1), names[i].substr(dot + 1), 0, int(i)});
    }
    auto layer_has = [&](const std::string& layer, const char* suffix) {
        for (const Key& k : keys)
            if (k.layer == layer && same(k.suffix, suffix)) return true;
        return false;
    };
    for (Key& k : keys) {
        // A layer with X and Y or Z holds positions or normals: X, Y, Z in that order.
        const bool xyz = layer_has(k.layer, "X") && (layer_has(k.layer, "Y") || layer_has(k.layer, "Z"));
        const std::vector<const char*>& known = xyz ? positions : usual;
        k.rank = int(known.size());
        for (int r = 0; r < int(known.size()); ++r)
            if (same(k.suffix, known[size_t(r)])) {
                k.rank = r;
                break;
            }
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

// A number with `digits` significant digits, enough to read it back exactly (9 for float, 17 for
// double): "1" for 1.
std::string text_of(double v, int digits) {
    char text[40];
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    return text;
}

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
            metadata[name] = text_of(double(f->value()), 9);
        else if (auto* d = dynamic_cast<const Imf::DoubleAttribute*>(&a))
            metadata[name] = text_of(d->value(), 17);
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
    const uint64_t channels = file_names.size();
    if (width <= 0 || height <= 0 || channels == 0) {
        error = path + ": image has no pixels";
        return true;
    }
    // OpenEXR decodes whole chunks: tiles, or up to 256 scan lines (DWAB's chunk) however few lines
    // the image has. Bounded as the module's reader bounded them (OpenImageIO reads 256 lines at
    // a time), so that what it refused stays refused: a 3-line file 4 million pixels wide.
    uint64_t block_width = uint64_t(width), block_height = std::max<uint64_t>(uint64_t(height), 256);
    if (tiled && header.hasTileDescription()) {
        block_height = uint64_t(height);
        const uint64_t tw = std::max(1u, header.tileDescription().xSize), th = std::max(1u, header.tileDescription().ySize);
        block_width = (block_width + tw - 1) / tw * tw;
        block_height = (block_height + th - 1) / th * th;
    }
    if (block_width > MaxImageValues || block_height > MaxImageValues || block_width * block_height * channels > MaxImageValues) {
        error = path + ": image of " + std::to_string(width) + " x " + std::to_string(height) + " pixels (read as " +
                std::to_string(block_width) + " x " + std::to_string(block_height) + ") and " + std::to_string(channels) +
                " channels is larger than the 2^28 values Candela reads";
        return true;
    }
    ImageHeader& h = out.header;
    h.width = int(width);
    h.height = int(height);
    h.integer_bits = 0;
    const std::vector<int> order = exr_channel_order(file_names);
    h.channels.clear();
    for (int i : order) h.channels.push_back(file_names[size_t(i)]);
    h.metadata = exr_metadata(header);
    if (pixels) {
        out.values.assign(uint64_t(width) * uint64_t(height) * channels, 0.0f);
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
