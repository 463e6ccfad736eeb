#include "core/png_file.h"

#include "core/byte_order.h"
#include "core/error.h"
#include "core/text.h"

#include <png.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <string>
#include <utility>
#include <vector>

namespace candela {
namespace {

// libpng reports an error by calling this, which must not return: back to the setjmp of the step
// that failed. The file is then left to the image module, whose message names the error.
void leave_on_error(png_structp png, png_const_charp) { png_longjmp(png, 1); }
// Warnings (a damaged ancillary chunk dropped, ...) are ignored, as OpenImageIO ignores them: the
// same libpng, called the same way, gives the same image.
void ignore_warning(png_structp, png_const_charp) {}

// libpng's state for one file, released however the reading ends.
struct PngFile {
    std::FILE* file = nullptr;
    png_structp png = nullptr;
    png_infop info = nullptr;
    ~PngFile() {
        if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
        if (file) std::fclose(file);
    }
};

// The two steps in which libpng may jump back. Nothing with a destructor lives in their frames, so
// that the jump skips none. The calls are OpenImageIO 2.4's, in its order: its reader expands
// (palettes, tRNS, grey below 8 bits) and swaps 16-bit samples from PNG's big-endian order to the
// machine's little-endian one (core/byte_order.h), then reads the rows.
bool read_info(PngFile& f) {
    if (setjmp(png_jmpbuf(f.png))) return false;
    png_read_info(f.png, f.info);
    png_set_expand(f.png);
    png_set_swap(f.png);
    png_read_update_info(f.png, f.info);
    return true;
}

bool read_rows(PngFile& f, png_bytepp rows, bool interlaced) {
    if (setjmp(png_jmpbuf(f.png))) return false;
    png_read_image(f.png, rows);
    // OpenImageIO reads an interlaced image whole and then to its end, a progressive one row by
    // row without the end: the same checks here.
    if (interlaced) png_read_end(f.png, nullptr);
    return true;
}

std::string printed(const char* format, double a) {
    char text[64];
    std::snprintf(text, sizeof text, format, a);
    return text;
}

// The file's attributes as OpenImageIO 2.4's PNG reader names and formats them (core/png_file.h),
// in its order. False when a chunk would have it decode more (ICC profile, Exif, XMP).
bool png_metadata(png_structp png, png_infop info, std::vector<std::pair<std::string, std::string>>& attributes) {
    if (png_get_valid(png, info, PNG_INFO_iCCP | PNG_INFO_eXIf)) return false;
    int srgb_intent = 0;
    double file_gamma = 0.0;
    if (png_get_sRGB(png, info, &srgb_intent)) {
        attributes.emplace_back("oiio:ColorSpace", "sRGB");
    } else if (png_get_gAMA(png, info, &file_gamma) && file_gamma > 0.0) {
        // The decoding exponent, rounded to hundredths (2.2, not 2.19998), in float as there.
        float g = float(1.0 / file_gamma);
        g = std::round(float(100.0 * g)) / 100.0f;
        attributes.emplace_back("oiio:Gamma", number_text(g, 6));
        attributes.emplace_back("oiio:ColorSpace", g == 1.0f ? "linear" : printed("Gamma%.2g", g));
    } else {
        attributes.emplace_back("oiio:ColorSpace", "sRGB");  // no colour information: sRGB assumed
    }
    png_timep time = nullptr;
    if (png_get_tIME(png, info, &time) && time) {
        char text[64];
        std::snprintf(text, sizeof text, "%4d:%02d:%02d %02d:%02d:%02d", time->year, time->month, time->day, time->hour, time->minute,
                      time->second);
        attributes.emplace_back("DateTime", text);
    }
    png_textp texts = nullptr;
    const int text_count = png_get_text(png, info, &texts, nullptr);
    for (int i = 0; i < text_count; ++i) {
        if (!texts[i].key || !texts[i].text) return false;
        const std::string key = to_lower(texts[i].key);
        if (key == "xml:com.adobe.xmp" || key == "raw profile type exif") return false;
        const char* name = key == "description" ? "ImageDescription"
                           : key == "author"    ? "Artist"
                           : key == "title"     ? "DocumentName"
                                                : texts[i].key;
        attributes.emplace_back(name, texts[i].text);
    }
    png_uint_32 x_resolution = 0, y_resolution = 0;
    int unit = 0;
    if (png_get_pHYs(png, info, &x_resolution, &y_resolution, &unit)) {
        float scale = 1.0f;
        if (unit == PNG_RESOLUTION_METER) {
            scale = float(2.54 / 100.0);  // per inch, as most formats give it
            attributes.emplace_back("ResolutionUnit", "inch");
        } else {
            attributes.emplace_back("ResolutionUnit", "none");
        }
        attributes.emplace_back("XResolution", number_text(float(x_resolution) * scale, 6));
        attributes.emplace_back("YResolution", number_text(float(y_resolution) * scale, 6));
    }
    const float aspect = float(png_get_pixel_aspect_ratio(png, info));
    if (aspect != 0.0f && aspect != 1.0f) attributes.emplace_back("PixelAspectRatio", number_text(aspect, 6));
    return true;
}

// Integer samples to [0, 1] floats, as OpenImageIO converts them.
template <class T>
float to_unit(T v) {
    return float(v) * (1.0f / float(std::numeric_limits<T>::max()));
}

// The rows, read into samples of the file's width (libpng writes them through byte pointers, which
// may alias any type), then converted to floats; alpha stays unassociated, as PNG stores it and
// Mitsuba's Bitmap reads it. False on a libpng error.
template <class T>
bool read_pixels(PngFile& f, size_t width, size_t height, int channels, bool interlaced, std::vector<float>& values) {
    std::vector<T> samples(width * height * size_t(channels));
    std::vector<png_bytep> rows(height);
    for (size_t y = 0; y < height; ++y) rows[y] = reinterpret_cast<png_bytep>(samples.data() + y * width * size_t(channels));
    if (!read_rows(f, rows.data(), interlaced)) return false;
    values.resize(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) values[i] = to_unit(samples[i]);
    return true;
}

}  // namespace

std::string png_chunk_problem(const std::string& path) {
    std::error_code ec;
    const uint64_t file_size = std::filesystem::file_size(path, ec);
    std::ifstream in(path, std::ios::binary);
    if (ec || !in.seekg(8)) return "";
    uint64_t at = 8;  // after the signature: chunks of length (4 bytes), name (4), data, CRC (4)
    unsigned char head[8];
    while (at + 8 <= file_size && in.read(reinterpret_cast<char*>(head), 8)) {
        const uint64_t length = uint64_t(head[0]) << 24 | uint64_t(head[1]) << 16 | uint64_t(head[2]) << 8 | uint64_t(head[3]);
        const uint64_t left = file_size - (at + 8);
        std::string name;
        for (int i = 4; i < 8; ++i) name += std::isalpha(head[i]) ? char(head[i]) : '?';
        if (length > left)
            return path + ": cannot read image: its chunk \"" + name + "\" declares " + std::to_string(length) +
                   " bytes, but the file has " + std::to_string(left) + " left";
        if (name == "IEND") return "";
        at += 8 + length + 4;
        if (!in.seekg(std::streamoff(at))) return "";
    }
    return "";
}

namespace {

// libpng's output, appended to a string; an allocation failure becomes libpng's error.
void append_to_string(png_structp png, png_bytep data, size_t length) {
    try {
        static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), length);
    } catch (const std::bad_alloc&) {
        png_error(png, "out of memory");
    }
}
void no_flush(png_structp) {}

// Copies libpng's message (which may live in the frame the jump leaves) for the exception, then
// jumps back to write_rows' setjmp.
struct PngMessage {
    char text[200] = "";
};
void keep_message_and_leave(png_structp png, png_const_charp message) {
    PngMessage* kept = static_cast<PngMessage*>(png_get_error_ptr(png));
    std::snprintf(kept->text, sizeof kept->text, "%s", message ? message : "libpng failed");
    png_longjmp(png, 1);
}

// The step in which libpng may jump back; nothing with a destructor lives in its frame.
bool write_rows(png_structp png, png_infop info, int width, int height, int channels, png_bytepp rows) {
    if (setjmp(png_jmpbuf(png))) return false;
    static const int color_types[4] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, color_types[channels - 1], PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, info);
    return true;
}

}  // namespace

std::string png_file_bytes(int width, int height, int channels, const unsigned char* samples) {
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4)
        throw InputError("cannot write PNG: " + std::to_string(width) + " x " + std::to_string(height) + " pixels of " +
                         std::to_string(channels) + " channels (a PNG has 1 to 4 channels and at least one pixel)");
    PngMessage message;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &message, keep_message_and_leave, ignore_warning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        throw std::bad_alloc();
    }
    std::string bytes;
    png_set_write_fn(png, &bytes, append_to_string, no_flush);
    std::vector<png_bytep> rows(static_cast<size_t>(height));
    for (size_t y = 0; y < rows.size(); ++y) rows[y] = const_cast<png_bytep>(samples + y * size_t(width) * size_t(channels));
    const bool written = write_rows(png, info, width, height, channels, rows.data());
    png_destroy_write_struct(&png, &info);
    if (!written) throw InputError(std::string("cannot write PNG: ") + message.text);
    return bytes;
}

bool read_png(const std::string& path, bool pixels, DecodedImage& out) {
    PngFile f;
    f.file = std::fopen(path.c_str(), "rb");
    if (!f.file) return false;
    f.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, leave_on_error, ignore_warning);
    if (!f.png) return false;
    f.info = png_create_info_struct(f.png);
    if (!f.info) return false;
    png_init_io(f.png, f.file);
    if (!read_info(f)) return false;

    png_uint_32 width = 0, height = 0;
    int bit_depth = 0, color_type = 0, interlace = 0;
    png_get_IHDR(f.png, f.info, &width, &height, &bit_depth, &color_type, &interlace, nullptr, nullptr);
    const int channels = png_get_channels(f.png, f.info);
    // OpenImageIO's reader refuses more than 65536 pixels a side; its size check follows.
    if (width > 65536 || height > 65536 || channels < 1 || channels > 4 || (bit_depth != 8 && bit_depth != 16)) return false;
    if (!image_size_problem(path, int64_t(width), int64_t(height), channels, 0, 0).empty()) return false;
    std::vector<std::pair<std::string, std::string>> attributes;
    if (!png_metadata(f.png, f.info, attributes)) return false;
    // An attribute named twice (a text chunk named like another attribute): which one OpenImageIO
    // keeps is its business.
    for (size_t i = 0; i < attributes.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (to_lower(attributes[i].first) == to_lower(attributes[j].first)) return false;

    DecodedImage decoded;
    ImageHeader& h = decoded.header;
    h.width = int(width);
    h.height = int(height);
    static const std::vector<std::string> names[4] = {{"Y"}, {"Y", "A"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
    h.channels = names[channels - 1];
    for (auto& [name, value] : attributes) h.metadata[name] = value;
    h.metadata["oiio:UnassociatedAlpha"] = "1";  // as the module's reader says it, asked for it
    h.integer_bits = bit_depth;
    if (pixels) {
        if (png_get_rowbytes(f.png, f.info) != size_t(width) * size_t(channels) * size_t(bit_depth / 8)) return false;
        const bool interlaced = interlace != PNG_INTERLACE_NONE;
        const bool read = bit_depth == 16 ? read_pixels<uint16_t>(f, width, height, channels, interlaced, decoded.values)
                                          : read_pixels<uint8_t>(f, width, height, channels, interlaced, decoded.values);
        if (!read) return false;
    }
    out = std::move(decoded);
    return true;
}

}  // namespace candela
