#pragma once
// Float images with named channels, read by OpenEXR (core/exr_input.h), libpng (core/png_file.h)
// or else OpenImageIO (loaded on first use: see core/image_codecs.h), and written as OpenEXR (with
// metadata) or as a tonemapped sRGB PNG (libpng). Every file is written whole or not at all: to a
// temporary beside the target, then renamed.

#include "core/spectrum.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace candela {

class Image {
public:
    Image() = default;
    Image(int width, int height, std::vector<std::string> channels);
    // Takes `values` (width x height x channels, interleaved) as its pixels.
    Image(int width, int height, std::vector<std::string> channels, std::vector<float> values);
    static Image rgb(int width, int height) { return Image(width, height, {"R", "G", "B"}); }

    int width() const { return width_; }
    int height() const { return height_; }
    int channel_count() const { return int(channels_.size()); }
    const std::vector<std::string>& channels() const { return channels_; }
    int channel_index(const std::string& name) const;  // -1 when absent

    float& at(int x, int y, int c) { return data_[(size_t(y) * width_ + x) * channels_.size() + c]; }
    float at(int x, int y, int c) const { return data_[(size_t(y) * width_ + x) * channels_.size() + c]; }
    Spectrum rgb_at(int x, int y) const { return Spectrum(at(x, y, 0), at(x, y, 1), at(x, y, 2)); }
    // A pixel's colour as stored: its RGB, or a grey image's value as grey; alpha left out.
    Spectrum colour_at(int x, int y) const { return channel_count() >= 3 ? rgb_at(x, y) : Spectrum(at(x, y, 0)); }
    // colour_at as linear radiance, as Mitsuba converts a bitmap to linear float RGB for an
    // environment map: the integers of 8- and 16-bit files are sRGB-decoded (the bitmap texture's
    // rule unless raw).
    Spectrum linear_rgb_at(int x, int y) const;
    void set_rgb(int x, int y, const Spectrum& s) {
        at(x, y, 0) = s.x;
        at(x, y, 1) = s.y;
        at(x, y, 2) = s.z;
    }
    std::vector<float>& data() { return data_; }
    const std::vector<float>& data() const { return data_; }
    // A copy with only the named channels (e.g. {"R","G","B"} or {"variance.R",...}).
    Image select_channels(const std::vector<std::string>& names) const;

    std::map<std::string, std::string> metadata;
    // For an image read from a file: 8 or 16 when the file stores integers (display-referred,
    // usually sRGB-encoded values), 0 when it stores floating point.
    int integer_bits = 0;

private:
    int width_ = 0, height_ = 0;
    std::vector<std::string> channels_;
    std::vector<float> data_;
};

// What an image file says about its image, without the pixels.
struct ImageHeader {
    int width = 0, height = 0;
    std::vector<std::string> channels;            // as the file names them; "C0", "C1", ... where it does not
    std::map<std::string, std::string> metadata;  // the file's other attributes, as text
    int integer_bits = 0;                         // 8 or 16 for integer formats, 0 for floating point
};

// Reads a 2D image in one of the formats Mitsuba 3 reads (OpenEXR, PNG, JPEG, RGBE, PFM, PPM, TGA,
// BMP; told apart by content, TGA by extension). Channels come back as the file names them; 8- and
// 16-bit integer images are returned in [0, 1] without colour conversion. Throws InputError, also
// for other formats, volume images and images of more than MaxImageValues values (an 8192 x 8192
// RGBA image has exactly that many; a corrupt header must not make us allocate without bound).
constexpr uint64_t MaxImageValues = uint64_t(1) << 28;
Image read_image(const std::string& path);
// The header of such an image, checked as read_image checks it; the pixels are not read.
ImageHeader read_image_header(const std::string& path);
// Loads the image module (core/image_codecs.h) now instead of at the first read of an image it
// reads. The fuzzers do, in their set-up: under AddressSanitizer, loading OpenImageIO's ~250
// libraries took longer than the 15 s an input is given, and it is no input's cost.
void load_image_module();

// Fails with InputError if `path` cannot be created or replaced (missing or read-only directory,
// a read-only file, a directory, device, pipe or symbolic link in the way). Creates nothing.
// A full disk shows only when writing: write_atomically then keeps the earlier file.
void check_output_path(const std::string& path);

void write_exr(const Image& image, const std::string& path, bool float32);
// The linear sRGB colour of a render, whatever the film's pixel format: its R, G, B channels;
// X, Y, Z converted (Rec. 709, D65); or Y alone as grey. InputError when it has none of these.
Image linear_rgb(const Image& rendered);
// Linear RGB (times 2^exposure) clamped to [0, 1] and encoded with the sRGB curve, for display.
Image tonemap_srgb(const Image& linear, float exposure = 0.0f);
// The bytes of an 8-bit PNG of a display-referred image (for embedding in HTML reports).
std::string encode_png(const Image& display);
// Writes an 8-bit PNG of an image whose values are already display-referred in [0, 1].
void write_png_display(const Image& image, const std::string& path);

}  // namespace candela
