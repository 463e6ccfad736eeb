#include "core/image.h"

#include "core/error.h"
#include "core/exr_input.h"
#include "core/file_output.h"
#include "core/image_codecs.h"
#include "core/png_file.h"
#include "core/spectral.h"

#include <candela/image_module.h>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <dlfcn.h>
#include <unistd.h>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <memory>
#include <thread>

namespace fs = std::filesystem;

namespace candela {

Image::Image(int width, int height, std::vector<std::string> channels)
    : width_(width), height_(height), channels_(std::move(channels)), data_(size_t(width) * size_t(height) * channels_.size(), 0.0f) {}

Image::Image(int width, int height, std::vector<std::string> channels, std::vector<float> values)
    : width_(width), height_(height), channels_(std::move(channels)), data_(std::move(values)) {
    if (data_.size() != size_t(width) * size_t(height) * channels_.size()) throw std::logic_error("Image: values do not match the size");
}

Spectrum Image::linear_rgb_at(int x, int y) const {
    Spectrum s = colour_at(x, y);
    if (integer_bits > 0)
        for (int c = 0; c < 3; ++c) s[c] = srgb_to_linear(s[c]);
    return s;
}

int Image::channel_index(const std::string& name) const {
    for (size_t i = 0; i < channels_.size(); ++i)
        if (channels_[i] == name) return int(i);
    return -1;
}

Image Image::select_channels(const std::vector<std::string>& names) const {
    std::vector<int> src;
    for (auto& n : names) {
        int i = channel_index(n);
        if (i < 0) throw InputError("image has no channel \"" + n + "\"");
        src.push_back(i);
    }
    Image out(width_, height_, names);
    out.metadata = metadata;
    out.integer_bits = integer_bits;
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x)
            for (size_t c = 0; c < src.size(); ++c) out.at(x, y, int(c)) = at(x, y, src[c]);
    return out;
}

namespace {
// The formats Mitsuba 3's Bitmap reads, told apart as it does: by the file's first bytes, and TGA
// (which has no signature) by its extension. The value names the OpenImageIO reader (by an
// extension it reads).
//
// Only that one reader ever sees the file. OpenImageIO's ImageInput::open(path) tries every reader
// it has (DDS, TIFF, IFF, SGI, RLA, raw camera files, ...) when the first one fails, and some of
// those act on malformed headers before anything can be checked (OpenImageIO 2.4's DDS reader
// spins for minutes on a 293-byte cube map, found by fuzz_image).
std::string image_format_of(const std::string& path) {
    unsigned char head[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    std::ifstream in(path, std::ios::binary);
    in.read(reinterpret_cast<char*>(head), sizeof head);
    auto starts_with = [&](std::initializer_list<unsigned char> bytes) {
        size_t i = 0;
        for (unsigned char b : bytes)
            if (head[i++] != b) return false;
        return true;
    };
    if (starts_with({0x76, 0x2f, 0x31, 0x01})) return "exr";
    if (starts_with({0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a})) return "png";
    if (starts_with({0xff, 0xd8, 0xff})) return "jpg";
    if (starts_with({'#', '?'})) return "hdr";
    if (head[0] == 'P' && (head[1] == 'F' || head[1] == 'f' || (head[1] >= '1' && head[1] <= '6'))) return "pnm";
    if (starts_with({'B', 'M'})) return "bmp";
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".tga" || ext == ".targa" || ext == ".vda" || ext == ".icb" || ext == ".vst") return "tga";
    return "";
}

#if defined(__has_feature)
#if __has_feature(thread_sanitizer) || __has_feature(address_sanitizer)
#define CANDELA_EXR_SINGLE_THREADED 1
#endif
#endif
#if defined(__SANITIZE_THREAD__) || defined(__SANITIZE_ADDRESS__)
#define CANDELA_EXR_SINGLE_THREADED 1
#endif
// Threads for OpenEXR's compression: one per core, except in sanitizer builds, which keep
// OpenEXR on the calling thread: ThreadSanitizer for the reason core/sanitizer_options.cpp
// gives, AddressSanitizer because LeakSanitizer's exit-time scan crashes on the dynamic TLS that
// OpenEXR's pool threads leave behind once the image module is loaded (seen in CI).
int exr_threads() {
#ifdef CANDELA_EXR_SINGLE_THREADED
    return 0;
#else
    return int(std::max(1u, std::thread::hardware_concurrency()));
#endif
}

// The module is where the build put it (CANDELA_IMAGE_MODULE); a program copied elsewhere looks
// for it beside itself.
const ImageCodecs* load_image_codecs() {
    std::vector<fs::path> candidates = {fs::path(CANDELA_IMAGE_MODULE)};
    std::error_code ec;
    const fs::path program = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) candidates.push_back(program.parent_path() / candidates[0].filename());
    std::string failures;
    for (const fs::path& candidate : candidates) {
        void* module = ::dlopen(candidate.c_str(), RTLD_LAZY | RTLD_LOCAL);
        const char* why = module ? nullptr : ::dlerror();
        auto entry = module ? reinterpret_cast<decltype(&candela_image_codecs)>(::dlsym(module, CANDELA_IMAGE_CODECS_ENTRY)) : nullptr;
        if (const ImageCodecs* codecs = entry ? entry(ImageCodecsAbi) : nullptr) return codecs;
        if (module) ::dlclose(module);  // another build's module (or another library): not kept
        failures += "; " + (why ? std::string(why) : candidate.string() + ": not the image module of this build");
    }
    throw InputError("cannot load Candela's image module (OpenImageIO's readers)" + failures);
}

// Loaded once, by the first caller; the module stays loaded.
const ImageCodecs& image_codecs() {
    static const ImageCodecs* codecs = load_image_codecs();
    return *codecs;
}

// The file read by the reader of its format (the pixels too when `pixels`), or InputError.
DecodedImage decode_image(const std::string& path, bool pixels) {
    if (!fs::exists(path)) throw InputError(path + ": file not found");
    const std::string format = image_format_of(path);
    if (format.empty()) {
        std::string what = "is not an image Candela reads";
        // Name the format when OpenImageIO knows the extension.
        if (std::string known = image_codecs().format_by_extension(path); !known.empty()) what = "is a " + known + " image";
        throw InputError(path + ": " + what +
                         "; Candela reads the formats Mitsuba 3 does: OpenEXR, PNG, JPEG, RGBE (.hdr), PFM, PPM, TGA, BMP");
    }
    DecodedImage decoded;
    // EXR files are read by OpenEXR, which every program links, without the module's load
    // (core/exr_input.h); the few kinds it leaves (multi-part, deep, subsampled, 32-bit
    // unsigned) go to the module.
    if (format == "exr") {
        if (std::string problem = exr_header_problem(path); !problem.empty()) throw InputError(problem);
        std::string error;
        if (read_exr(path, pixels, exr_threads(), decoded, error)) {
            if (!error.empty()) throw InputError(error);
            return decoded;
        }
    }
    // PNG files too are read without the module (core/png_file.h), but for the kinds it leaves.
    if (format == "png") {
        if (std::string problem = png_chunk_problem(path); !problem.empty()) throw InputError(problem);
        if (read_png(path, pixels, decoded)) return decoded;
    }
    if (std::string error = image_codecs().read(path, format, pixels, decoded); !error.empty()) throw InputError(error);
    return decoded;
}
}  // namespace

Image read_image(const std::string& path) {
    DecodedImage decoded = decode_image(path, true);
    ImageHeader& h = decoded.header;
    Image image(h.width, h.height, std::move(h.channels), std::move(decoded.values));
    image.metadata = std::move(h.metadata);
    image.integer_bits = h.integer_bits;
    return image;
}

ImageHeader read_image_header(const std::string& path) { return decode_image(path, false).header; }

void load_image_module() { image_codecs(); }

namespace {
// No write permission for anyone. Checked on the mode bits as well as with access(), which
// always grants root write access: a read-only file or folder says "keep this" also to root.
bool read_only(const fs::path& p) {
    std::error_code ec;
    fs::perms perms = fs::status(p, ec).permissions();
    if (ec) return false;
    const fs::perms writable = fs::perms::owner_write | fs::perms::group_write | fs::perms::others_write;
    return (perms & writable) == fs::perms::none || ::access(p.c_str(), W_OK) != 0;
}
}  // namespace

void check_output_path(const std::string& path) {
    if (path.empty()) throw InputError("no output file given");
    fs::path p(path);
    fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw InputError(path + ": cannot write: directory " + dir.string() + " does not exist");
    if (read_only(dir)) throw InputError(path + ": cannot write: directory " + dir.string() + " is not writable");
    if (!fs::exists(fs::symlink_status(p, ec)) && !fs::exists(p, ec)) return;
    if (fs::is_directory(p, ec)) throw InputError(path + ": cannot write: it is a directory");
    // Outputs are written beside the target and renamed over it: that would replace a device
    // (/dev/full, /dev/null), a pipe or a symbolic link by a plain file.
    if (fs::is_symlink(fs::symlink_status(p, ec)) || !fs::is_regular_file(p, ec))
        throw InputError(path + ": cannot write: it is not a regular file");
    if (read_only(p)) throw InputError(path + ": cannot write: the file is read-only");
}

void write_exr(const Image& image, const std::string& path, bool float32) {
    // Written in bands of rows: each band is sanitised (never NaN or infinity; half floats
    // saturate at their largest value) into a buffer of its own and handed to OpenEXR, whose
    // thread pool compresses the band's line blocks in parallel. No second copy of the whole
    // image is made: an 8K film with AOVs is gigabytes.
    const float limit = float32 ? std::numeric_limits<float>::max() : 65504.0f;
    const size_t nch = size_t(image.channel_count()), width = size_t(image.width());
    const size_t row_values = nch * width;
    // About 16 MB per band, a whole number of ZIP's 16-line blocks.
    const int band_rows = int(std::max<size_t>(16, (size_t(16) << 20) / std::max<size_t>(1, row_values * 4) / 16 * 16));
    write_atomically(path, [&](const std::string& tmp) {
        Imf::Header header(image.width(), image.height());
        header.compression() = Imf::ZIP_COMPRESSION;
        // Metadata read from another file may repeat standard attributes (compression, ...):
        // those belong to this header.
        for (auto& [key, value] : image.metadata)
            if (header.find(key) == header.end()) header.insert(key, Imf::StringAttribute(value));
        for (size_t c = 0; c < nch; ++c) header.channels().insert(image.channels()[c], Imf::Channel(float32 ? Imf::FLOAT : Imf::HALF));
        Imf::OutputFile file(tmp.c_str(), header, exr_threads());
        std::vector<float> floats;
        std::vector<Imath::half> halves;
        const size_t size = float32 ? sizeof(float) : sizeof(Imath::half);
        for (int y0 = 0; y0 < image.height(); y0 += band_rows) {
            const int rows = std::min(band_rows, image.height() - y0);
            const float* source = image.data().data() + size_t(y0) * row_values;
            const size_t count = size_t(rows) * row_values;
            if (float32)
                floats.resize(count);
            else
                halves.resize(count);
            for (size_t i = 0; i < count; ++i) {
                const float v = std::isnan(source[i]) ? 0.0f : std::clamp(source[i], -limit, limit);
                if (float32)
                    floats[i] = v;
                else
                    halves[i] = Imath::half(v);
            }
            // A slice's base is where pixel (0, 0) would be: the band's first row is row y0.
            char* band = float32 ? reinterpret_cast<char*>(floats.data()) : reinterpret_cast<char*>(halves.data());
            const ptrdiff_t x_stride = ptrdiff_t(size * nch), y_stride = ptrdiff_t(size * row_values);
            Imf::FrameBuffer fb;
            for (size_t c = 0; c < nch; ++c)
                fb.insert(image.channels()[c],
                          Imf::Slice(float32 ? Imf::FLOAT : Imf::HALF, band + ptrdiff_t(c * size) - ptrdiff_t(y0) * y_stride,
                                     size_t(x_stride), size_t(y_stride)));
            file.setFrameBuffer(fb);
            file.writePixels(rows);
        }
    });
}

namespace {
// An 8-bit PNG file of a display-referred image's first four channels (libpng, core/png_file.h).
std::string png_of_display(const Image& image) {
    const int nch = std::min(image.channel_count(), 4);
    std::vector<unsigned char> bytes(size_t(image.width()) * image.height() * nch);
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            for (int c = 0; c < nch; ++c) {
                float v = image.at(x, y, c);
                v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
                bytes[(size_t(y) * image.width() + x) * nch + c] = static_cast<unsigned char>(std::lround(v * 255.0f));
            }
    return png_file_bytes(image.width(), image.height(), nch, bytes.data());
}
}  // namespace

void write_png_display(const Image& image, const std::string& path) { write_file_atomically(path, png_of_display(image)); }

std::string encode_png(const Image& display) { return png_of_display(display); }

Image linear_rgb(const Image& rendered) {
    auto has = [&](const char* a, const char* b, const char* c) {
        return rendered.channel_index(a) >= 0 && rendered.channel_index(b) >= 0 && rendered.channel_index(c) >= 0;
    };
    if (has("R", "G", "B")) return rendered.select_channels({"R", "G", "B"});
    Image rgb = Image::rgb(rendered.width(), rendered.height());
    rgb.metadata = rendered.metadata;
    if (has("X", "Y", "Z")) {
        int cx = rendered.channel_index("X"), cy = rendered.channel_index("Y"), cz = rendered.channel_index("Z");
        for (int y = 0; y < rendered.height(); ++y)
            for (int x = 0; x < rendered.width(); ++x)
                rgb.set_rgb(x, y, Spectrum(xyz_to_linear_srgb(Vec3d(rendered.at(x, y, cx), rendered.at(x, y, cy), rendered.at(x, y, cz)))));
        return rgb;
    }
    int cy = rendered.channel_index("Y");
    if (cy < 0) throw InputError("the image has neither R, G, B nor X, Y, Z nor Y channels");
    for (int y = 0; y < rendered.height(); ++y)
        for (int x = 0; x < rendered.width(); ++x) rgb.set_rgb(x, y, Spectrum(rendered.at(x, y, cy)));
    return rgb;
}

Image tonemap_srgb(const Image& image, float exposure) {
    float scale = std::exp2(exposure);
    Image display = Image::rgb(image.width(), image.height());
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                float v = image.at(x, y, std::min(c, image.channel_count() - 1)) * scale;
                display.at(x, y, c) = linear_to_srgb(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f));
            }
    return display;
}

}  // namespace candela
