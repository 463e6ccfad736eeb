// The image module (the shared module `candela_images`, see core/image_codecs.h): reading images
// through OpenImageIO. Only core/image.cpp calls it, after choosing the reader by
// the file's first bytes (image_format_of there); nothing here throws past the boundary.

#include "core/image_codecs.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>

namespace fs = std::filesystem;

namespace candela {
namespace {

#if defined(__has_feature)
#if __has_feature(thread_sanitizer)
// The ThreadSanitizer build does its EXR work on the calling thread (see core/sanitizer_options.cpp):
// OpenImageIO's own EXR pool (exr_threads) is off as well as OpenEXR's.
struct SingleThreadedExrReads {
    SingleThreadedExrReads() { OIIO::attribute("exr_threads", -1); }
} single_threaded_exr_reads;
#endif
#endif

// The fewest bytes a PFM or PNM file of this size can hold its pixels in, after the header: its
// pixels are stored uncompressed (P1 and P4 one bit per pixel, P2 and P3 at least one digit per
// value, P5, P6 and PFM as binary samples). Other formats compress, and are not bounded here.
uint64_t least_pnm_pixel_bytes(const std::string& path, const OIIO::ImageSpec& spec) {
    char head[2] = {0, 0};
    std::ifstream(path, std::ios::binary).read(head, 2);
    const uint64_t pixels = uint64_t(spec.width) * uint64_t(spec.height);
    switch (head[1]) {
        case '4': return (uint64_t(spec.width) + 7) / 8 * uint64_t(spec.height);
        case '1': return pixels / 8;
        case '2':
        case '3': return pixels * uint64_t(spec.nchannels);
        default: return uint64_t(spec.image_bytes(true));
    }
}

int integer_bits(const OIIO::TypeDesc& f) {
    if (f.basetype == OIIO::TypeDesc::UINT8 || f.basetype == OIIO::TypeDesc::INT8) return 8;
    if (f.basetype == OIIO::TypeDesc::UINT16 || f.basetype == OIIO::TypeDesc::INT16) return 16;
    return 0;
}

// The size checks a header must pass before any pixel is allocated; "" when it passes.
std::string check_size(const std::string& path, const OIIO::ImageInput& in) {
    const OIIO::ImageSpec& spec = in.spec();
    // A volume image (DDS volume textures, ...) would fill depth times the buffer of a 2D one.
    if (spec.depth != 1) return path + ": is a volume image (depth " + std::to_string(spec.depth) + "); only 2D images are read";
    if (std::string problem = image_size_problem(path, spec.width, spec.height, spec.nchannels, spec.tile_width, spec.tile_height);
        !problem.empty())
        return problem;
    // A header promising more pixels than the file holds would have us allocate for them first.
    if (in.format_name() == std::string("pnm")) {
        const uint64_t least = least_pnm_pixel_bytes(path, spec), size = fs::file_size(path);
        if (size < least)
            return path + ": header promises " + std::to_string(spec.width) + " x " + std::to_string(spec.height) + " pixels (at least " +
                   std::to_string(least) + " bytes), but the file has " + std::to_string(size) + " bytes";
    }
    return "";
}

std::string read_with(const std::string& path, const std::string& format, bool pixels, DecodedImage& out) {
    // Only the reader of `format` sees the file: ImageInput::open(path) would try every reader
    // OpenImageIO has when the first fails (core/image.cpp, image_format_of).
    auto in = OIIO::ImageInput::create(format, false);
    if (!in) return path + ": cannot read image: no " + format + " reader: " + OIIO::geterror();
    // An EXR file's header was checked before (core/exr_input.h, exr_header_problem).
    OIIO::ImageSpec opened, config;
    // Alpha as the file stores it, never premultiplied into the colour (Mitsuba's Bitmap reads
    // files so; a texture's colour must not darken where it is transparent).
    config.attribute("oiio:UnassociatedAlpha", 1);
    if (!in->open(path, opened, config)) return path + ": cannot read image: " + in->geterror();
    if (std::string error = check_size(path, *in); !error.empty()) return error;
    const OIIO::ImageSpec& spec = in->spec();
    ImageHeader& h = out.header;
    h.width = spec.width;
    h.height = spec.height;
    for (int c = 0; c < spec.nchannels; ++c) {
        std::string n = c < int(spec.channelnames.size()) ? spec.channelnames[c] : "";
        h.channels.push_back(n.empty() ? "C" + std::to_string(c) : n);
    }
    for (const auto& p : spec.extra_attribs) h.metadata[p.name().string()] = p.get_string();
    h.integer_bits = integer_bits(spec.format);
    if (pixels) {
        out.values.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
        if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out.values.data()))
            return path + ": cannot read image: " + in->geterror();
    }
    in->close();
    return "";
}

class OiioCodecs final : public ImageCodecs {
public:
    std::string read(const std::string& path, const std::string& format, bool pixels, DecodedImage& out) const override {
        try {
            return read_with(path, format, pixels, out);
        } catch (const std::bad_alloc&) {
            return path + ": cannot read image: out of memory";
        } catch (const std::exception& e) {
            return path + ": cannot read image: " + e.what();
        }
    }

    std::string format_by_extension(const std::string& path) const override {
        try {
            auto by_name = OIIO::ImageInput::create(path, false);  // creating a reader opens nothing
            return by_name ? by_name->format_name() : "";
        } catch (const std::exception&) {
            return "";
        }
    }
};

}  // namespace
}  // namespace candela

extern "C" __attribute__((visibility("default"))) const candela::ImageCodecs* candela_image_codecs(int abi) {
    static const candela::OiioCodecs codecs;
    return abi == candela::ImageCodecsAbi ? &codecs : nullptr;
}
