#pragma once
// The boundary between core/image.cpp and the image module: OpenImageIO's readers, compiled apart
// (imageio/oiio_codecs.cpp) as the shared module `candela_images`, which core/image.cpp loads with
// dlopen the first time a program reads an image other than an OpenEXR or PNG file (those OpenEXR
// and libpng read, core/exr_input.h and core/png_file.h, but for rare kinds). PNG files are
// written by libpng (core/png_file.h), OpenEXR files by OpenEXR.
//
// Why a module: Debian 12's OpenImageIO links some 250 shared libraries (FFmpeg, OpenCV, GDAL,
// DCMTK, GStreamer, ...). Linked into Candela's programs, they were loaded and their symbols
// bound at every start: about 0.19 s of CPU before main, in every run of every program, whether
// it read an image or not (README "Benchmarks", start-up). Renders of scenes without textures
// other than EXR and PNG files, and most test processes, now never load them.
//
// Only plain data and strings cross the boundary, and no exception: each function catches what
// it calls and returns "" on success, else the whole error message (the file's path included).

#include "core/image.h"

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace candela {

// Changed whenever ImageCodecs or DecodedImage change, so that a module left over from another
// build is refused instead of called with the wrong layout.
constexpr int ImageCodecsAbi = 2;

struct DecodedImage {
    ImageHeader header;
    std::vector<float> values;  // width x height x channels, interleaved; empty when only the header was read
};

// The size check both readers (the module's and core/exr_input.h) make from a header before any
// pixel is allocated: "" when it passes, else the message. Both decode whole blocks and allocate
// for a block first: whole tiles (tile_width and tile_height above 0), or else 256 scan lines
// however few lines the image has (OpenImageIO 2.4's read_scanlines; OpenEXR's largest chunk,
// DWAB's). 3-line OpenEXR and BMP files 4 million pixels wide had OpenImageIO allocate 6 and
// 2.9 GB (fuzz_image). The blocks' values are limited to MaxImageValues (image.h).
inline std::string image_size_problem(const std::string& path, int64_t width, int64_t height, int64_t channels, int64_t tile_width,
                                      int64_t tile_height) {
    if (width <= 0 || height <= 0 || channels <= 0) return path + ": image has no pixels";
    uint64_t block_width = uint64_t(width), block_height = uint64_t(height);
    if (tile_width > 0 && tile_height > 0) {
        block_width = (block_width + uint64_t(tile_width) - 1) / uint64_t(tile_width) * uint64_t(tile_width);
        block_height = (block_height + uint64_t(tile_height) - 1) / uint64_t(tile_height) * uint64_t(tile_height);
    } else {
        block_height = std::max<uint64_t>(block_height, 256);
    }
    // Compared without overflow: w h c > M exactly when w h > floor(M / c), each factor first.
    if (block_width > MaxImageValues || block_height > MaxImageValues || block_width * block_height > MaxImageValues / uint64_t(channels))
        return path + ": image of " + std::to_string(width) + " x " + std::to_string(height) + " pixels (read as " +
               std::to_string(block_width) + " x " + std::to_string(block_height) + ") and " + std::to_string(channels) +
               " channels is larger than the 2^28 values Candela reads";
    return "";
}

class ImageCodecs {
public:
    // Reads `path` with the reader of `format` only (an extension OpenImageIO knows: "exr",
    // "png", "jpg", "hdr", "pnm", "bmp", "tga"), and its pixels too when `pixels`. Refuses
    // volume images and images larger than MaxImageValues (image.h) before allocating. An EXR
    // file's header must have passed exr_header_problem (core/exr_input.h) first.
    virtual std::string read(const std::string& path, const std::string& format, bool pixels, DecodedImage& out) const = 0;
    // The name of the format OpenImageIO associates with `path`'s extension ("dds", "tiff"),
    // "" if none; it opens nothing.
    virtual std::string format_by_extension(const std::string& path) const = 0;

protected:
    ~ImageCodecs() = default;
};

}  // namespace candela

// The module's one entry point: its codecs, or null when `abi` is not its ImageCodecsAbi.
#define CANDELA_IMAGE_CODECS_ENTRY "candela_image_codecs"
extern "C" const candela::ImageCodecs* candela_image_codecs(int abi);
