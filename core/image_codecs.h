#pragma once
// The boundary between core/image.cpp and the image module: OpenImageIO's readers and its PNG
// writer, compiled apart (imageio/oiio_codecs.cpp) as the shared module `candela_images`, which
// core/image.cpp loads with dlopen the first time a program reads an image other than an
// OpenEXR file (those OpenEXR reads, core/exr_input.h, but for rare kinds) or writes a PNG.
//
// Why a module: Debian 12's OpenImageIO links some 250 shared libraries (FFmpeg, OpenCV, GDAL,
// DCMTK, GStreamer, ...). Linked into Candela's programs, they were loaded and their symbols
// bound at every start: about 0.19 s of CPU before main, in every run of every program, whether
// it read an image or not (README "Benchmarks", start-up). Renders of scenes without textures
// other than EXR files, and most test processes, now never load them.
//
// Only plain data and strings cross the boundary, and no exception: each function catches what
// it calls and returns "" on success, else the whole error message (the file's path included).

#include "core/image.h"

#include <string>
#include <vector>

namespace candela {

// Changed whenever ImageCodecs or DecodedImage change, so that a module left over from another
// build is refused instead of called with the wrong layout.
constexpr int ImageCodecsAbi = 1;

struct DecodedImage {
    ImageHeader header;
    std::vector<float> values;  // width x height x channels, interleaved; empty when only the header was read
};

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
    // Writes `bytes` (width x height x channels, interleaved, 1 to 4 channels) as an 8-bit PNG.
    virtual std::string write_png(const std::string& path, int width, int height, int channels, const unsigned char* bytes) const = 0;

protected:
    ~ImageCodecs() = default;
};

}  // namespace candela

// The module's one entry point: its codecs, or null when `abi` is not its ImageCodecsAbi.
#define CANDELA_IMAGE_CODECS_ENTRY "candela_image_codecs"
extern "C" const candela::ImageCodecs* candela_image_codecs(int abi);
