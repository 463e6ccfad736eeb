// PNG files are read by libpng itself (core/png_file.h) instead of the OpenImageIO module: the
// same images and metadata as the module gives, checked against the module on files of every
// colour type and bit depth libpng writes, interlaced or not, with the chunks that become
// attributes; alpha left unassociated (as PNG stores it and Mitsuba reads it) on every pair of
// 8-bit value and alpha and every 16-bit value, and so taken by textures and environment maps;
// what it leaves to the module (Exif, XMP, names twice, damaged files, images over 65536 pixels
// wide) reads as the module reads it; a chunk longer than the file is refused before either reads. ICC profiles are left too, but libpng 1.6.39 dropped every
// small profile this test could make up ("iCCP: too short"), so that case is not exercised here.
// PNG files are written by libpng too: they read back exactly, by both readers.

#include "core/error.h"
#include "core/image.h"
#include "core/png_file.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/texture.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>

using namespace candela;
using namespace candela::test;

namespace {

struct PngSpec {
    int width = 37, height = 19;
    int bit_depth = 8;
    int color_type = PNG_COLOR_TYPE_RGB;
    bool interlaced = false;
    std::function<void(png_structp, png_infop)> chunks;                       // further chunks, before the image
    std::function<void(std::vector<unsigned char>&, size_t row_bytes)> edit;  // changes to the random rows
};

int file_channels(int color_type) {
    switch (color_type) {
        case PNG_COLOR_TYPE_GRAY:
        case PNG_COLOR_TYPE_PALETTE: return 1;
        case PNG_COLOR_TYPE_GRAY_ALPHA: return 2;
        case PNG_COLOR_TYPE_RGB: return 3;
        default: return 4;
    }
}

bool write_rows(png_structp png, png_infop info, const PngSpec& spec, std::vector<png_bytep>& rows) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_IHDR(png, info, png_uint_32(spec.width), png_uint_32(spec.height), spec.bit_depth, spec.color_type,
                 spec.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (spec.color_type == PNG_COLOR_TYPE_PALETTE) {
        // A full palette, so that every random index names an entry.
        std::vector<png_color> palette(size_t(1) << spec.bit_depth);
        for (size_t i = 0; i < palette.size(); ++i) palette[i] = png_color{png_byte(i * 37 + 11), png_byte(255 - i * 5), png_byte(i * 101)};
        png_set_PLTE(png, info, palette.data(), int(palette.size()));
    }
    if (spec.chunks) spec.chunks(png, info);
    png_write_info(png, info);
    png_write_image(png, rows.data());
    png_write_end(png, info);
    return true;
}

// Random samples (as the file stores them) of `spec`, changed by spec.edit, written by libpng.
void write_png_file(const std::string& path, const PngSpec& spec, uint32_t seed) {
    const size_t row_bytes = (size_t(spec.width) * size_t(file_channels(spec.color_type)) * size_t(spec.bit_depth) + 7) / 8;
    std::vector<unsigned char> samples(row_bytes * size_t(spec.height));
    std::mt19937 rng(seed);
    for (unsigned char& s : samples) s = (unsigned char)(rng() & 0xff);
    if (spec.edit) spec.edit(samples, row_bytes);
    std::vector<png_bytep> rows(size_t(spec.height));
    for (size_t y = 0; y < rows.size(); ++y) rows[y] = samples.data() + y * row_bytes;
    std::FILE* file = std::fopen(path.c_str(), "wb");
    REQUIRE(file != nullptr);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, file);
    const bool written = write_rows(png, info, spec, rows);
    png_destroy_write_struct(&png, &info);
    std::fclose(file);
    REQUIRE(written);
}

// The direct reader's image and header are the module's, value for value and attribute for
// attribute (`direct` false: the direct reader leaves the file to the module, and read_image
// still gives the module's image or its error).
void check_same_as_module(const std::string& path, bool direct = true) {
    CAPTURE(path);
    DecodedImage module;
    const std::string module_error = module_codecs().read(path, "png", true, module);
    DecodedImage mine;
    REQUIRE(read_png(path, true, mine) == direct);
    if (!direct) {
        if (!module_error.empty()) {
            CHECK_THROWS_WITH(read_image(path), module_error);
            return;
        }
        Image image = read_image(path);
        mine.header.width = image.width();
        mine.header.height = image.height();
        mine.header.channels = image.channels();
        mine.header.metadata = image.metadata;
        mine.header.integer_bits = image.integer_bits;
        mine.values = image.data();
    }
    REQUIRE(module_error == "");
    CHECK(mine.header.width == module.header.width);
    CHECK(mine.header.height == module.header.height);
    CHECK(mine.header.channels == module.header.channels);
    CHECK(mine.header.integer_bits == module.header.integer_bits);
    CHECK(mine.header.metadata == module.header.metadata);
    REQUIRE(mine.values.size() == module.values.size());
    CHECK(std::memcmp(mine.values.data(), module.values.data(), module.values.size() * sizeof(float)) == 0);
    // The header alone, as read_image_header reads it.
    DecodedImage header_only;
    REQUIRE(read_png(path, false, header_only) == direct);
    if (direct) {
        CHECK(header_only.values.empty());
        CHECK(header_only.header.channels == module.header.channels);
        CHECK(header_only.header.metadata == module.header.metadata);
    }
}

// A file named `name` with the chunks `chunks` writes.
struct ChunkCase {
    const char* name;
    std::function<void(png_structp, png_infop)> chunks;
};

void add_text(png_structp png, png_infop info, const char* key, const char* text, int compression = PNG_TEXT_COMPRESSION_NONE) {
    png_text t{};
    t.compression = compression;
    t.key = const_cast<char*>(key);
    t.text = const_cast<char*>(text);
    png_set_text(png, info, &t, 1);
}

}  // namespace

TEST_CASE("images: a PNG file reads as the OpenImageIO module read it, every colour type and bit depth", "[image]") {
    auto dir = scratch_dir("png-input");
    struct Kind {
        int color_type;
        std::vector<int> depths;
    };
    const std::vector<Kind> kinds = {
        {PNG_COLOR_TYPE_GRAY, {1, 2, 4, 8, 16}}, {PNG_COLOR_TYPE_GRAY_ALPHA, {8, 16}},   {PNG_COLOR_TYPE_RGB, {8, 16}},
        {PNG_COLOR_TYPE_RGB_ALPHA, {8, 16}},     {PNG_COLOR_TYPE_PALETTE, {1, 2, 4, 8}},
    };
    int n = 0;
    for (const Kind& kind : kinds)
        for (int depth : kind.depths)
            for (bool interlaced : {false, true}) {
                PngSpec spec;
                spec.color_type = kind.color_type;
                spec.bit_depth = depth;
                spec.interlaced = interlaced;
                const std::string path = (dir / ("kind" + std::to_string(n) + ".png")).string();
                write_png_file(path, spec, uint32_t(n++));
                check_same_as_module(path);
            }
    // Transparency chunks become an alpha channel: a palette's alphas, a grey or RGB key colour
    // (the first pixel set to it, so that it occurs).
    PngSpec palette;
    palette.color_type = PNG_COLOR_TYPE_PALETTE;
    palette.chunks = [](png_structp png, png_infop info) {
        std::vector<png_byte> alphas(100);
        for (size_t i = 0; i < alphas.size(); ++i) alphas[i] = png_byte(i * 13);
        png_set_tRNS(png, info, alphas.data(), int(alphas.size()), nullptr);
    };
    write_png_file((dir / "palette_trns.png").string(), palette, 201);
    check_same_as_module((dir / "palette_trns.png").string());
    for (int depth : {8, 16})
        for (int color_type : {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_RGB}) {
            PngSpec keyed;
            keyed.color_type = color_type;
            keyed.bit_depth = depth;
            // The key colour as PNG gives it (red, green, blue, grey), and as the first pixel stores it.
            const png_color_16 key = depth == 8 ? png_color_16{0, 0x34, 0x56, 0x78, 0x12} : png_color_16{0, 0x1234, 0x0056, 0x0078, 0x0012};
            keyed.chunks = [key](png_structp png, png_infop info) {
                png_color_16 k = key;
                png_set_tRNS(png, info, nullptr, 0, &k);
            };
            keyed.edit = [key, depth, color_type](std::vector<unsigned char>& s, size_t) {
                const std::vector<uint16_t> first = color_type == PNG_COLOR_TYPE_GRAY ? std::vector<uint16_t>{key.gray}
                                                                                      : std::vector<uint16_t>{key.red, key.green, key.blue};
                for (size_t i = 0; i < first.size(); ++i) {
                    if (depth == 8) {
                        s[i] = (unsigned char)first[i];
                    } else {
                        s[2 * i] = (unsigned char)(first[i] >> 8);
                        s[2 * i + 1] = (unsigned char)(first[i] & 0xff);
                    }
                }
            };
            const std::string path = (dir / ("keyed" + std::to_string(n++) + ".png")).string();
            write_png_file(path, keyed, uint32_t(n));
            check_same_as_module(path);
            CHECK(read_image(path).channel_count() == (color_type == PNG_COLOR_TYPE_GRAY ? 2 : 4));
        }
}

TEST_CASE("images: a PNG file's chunks become the module's attributes", "[image]") {
    auto dir = scratch_dir("png-attributes");
    const std::vector<ChunkCase> cases = {
        {"none", nullptr},
        {"srgb", [](png_structp png, png_infop info) { png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL); }},
        {"linear", [](png_structp png, png_infop info) { png_set_gAMA_fixed(png, info, 100000); }},
        {"gamma22", [](png_structp png, png_infop info) { png_set_gAMA_fixed(png, info, 45455); }},
        {"gamma18", [](png_structp png, png_infop info) { png_set_gAMA_fixed(png, info, 55556); }},
        {"gamma2", [](png_structp png, png_infop info) { png_set_gAMA_fixed(png, info, 50000); }},
        {"gamma_odd", [](png_structp png, png_infop info) { png_set_gAMA_fixed(png, info, 31234); }},
        {"gamma_and_srgb",
         [](png_structp png, png_infop info) {
             png_set_gAMA_fixed(png, info, 45455);
             png_set_sRGB(png, info, PNG_sRGB_INTENT_RELATIVE);
         }},
        {"per_metre", [](png_structp png, png_infop info) { png_set_pHYs(png, info, 2835, 2835, PNG_RESOLUTION_METER); }},
        {"aspect", [](png_structp png, png_infop info) { png_set_pHYs(png, info, 3, 2, PNG_RESOLUTION_UNKNOWN); }},
        {"odd_density", [](png_structp png, png_infop info) { png_set_pHYs(png, info, 11811, 3937, PNG_RESOLUTION_METER); }},
        {"time",
         [](png_structp png, png_infop info) {
             png_time t{2026, 12, 5, 23, 4, 59};
             png_set_tIME(png, info, &t);
         }},
        {"texts",
         [](png_structp png, png_infop info) {
             add_text(png, info, "Title", "a title");
             add_text(png, info, "Author", "an author", PNG_TEXT_COMPRESSION_zTXt);
             add_text(png, info, "Description", "a description", PNG_ITXT_COMPRESSION_NONE);
             add_text(png, info, "Comment", "");
             add_text(png, info, "Software", "test_png_input, compressed", PNG_ITXT_COMPRESSION_zTXt);
         }},
        {"background_and_offset",
         [](png_structp png, png_infop info) {
             png_color_16 background{0, 10, 20, 30, 0};
             png_set_bKGD(png, info, &background);
             png_set_oFFs(png, info, 5, -3, PNG_OFFSET_PIXEL);
         }},
    };
    int n = 0;
    for (const ChunkCase& c : cases)
        for (int color_type : {PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA}) {
            PngSpec spec;
            spec.color_type = color_type;
            spec.chunks = c.chunks;
            const std::string path = (dir / (std::string(c.name) + std::to_string(n++) + ".png")).string();
            write_png_file(path, spec, uint32_t(n));
            check_same_as_module(path);
        }
    // Spot checks of what the module gives, so that a change of both readers shows too.
    Image image = read_image((dir / "gamma226.png").string());
    CHECK(image.metadata["oiio:ColorSpace"] == "Gamma2.2");
    CHECK(read_image((dir / "texts24.png").string()).metadata["DocumentName"] == "a title");
    CHECK(read_image((dir / "none0.png").string()).metadata["oiio:ColorSpace"] == "sRGB");
}

TEST_CASE("images: a PNG file's alpha stays unassociated, as the module (asked so) reads it, every 8-bit pair and 16-bit value",
          "[image]") {
    auto dir = scratch_dir("png-alpha");
    // 8-bit RGBA: R runs over every value along x, alpha over every value along y.
    PngSpec pairs;
    pairs.width = 256;
    pairs.height = 256;
    pairs.color_type = PNG_COLOR_TYPE_RGB_ALPHA;
    pairs.edit = [](std::vector<unsigned char>& s, size_t row_bytes) {
        for (size_t y = 0; y < 256; ++y)
            for (size_t x = 0; x < 256; ++x) {
                unsigned char* p = s.data() + y * row_bytes + x * 4;
                p[0] = (unsigned char)x;
                p[3] = (unsigned char)y;
            }
    };
    write_png_file((dir / "pairs.png").string(), pairs, 1);
    check_same_as_module((dir / "pairs.png").string());
    // A gamma other than 1 changes nothing either (OpenImageIO would associate alpha another way).
    pairs.chunks = [](png_structp png, png_infop info) { png_set_gAMA_fixed(png, info, 45455); };
    write_png_file((dir / "pairs_gamma.png").string(), pairs, 1);
    check_same_as_module((dir / "pairs_gamma.png").string());
    // 16-bit grey: every value once; 16-bit grey and alpha: random pairs, alpha 0 and 65535 included.
    PngSpec grey;
    grey.width = 256;
    grey.height = 256;
    grey.color_type = PNG_COLOR_TYPE_GRAY;
    grey.bit_depth = 16;
    grey.edit = [](std::vector<unsigned char>& s, size_t) {
        for (size_t i = 0; i < 65536; ++i) {
            s[2 * i] = (unsigned char)(i >> 8);
            s[2 * i + 1] = (unsigned char)(i & 0xff);
        }
    };
    write_png_file((dir / "grey16.png").string(), grey, 2);
    check_same_as_module((dir / "grey16.png").string());
    PngSpec grey_alpha = grey;
    grey_alpha.color_type = PNG_COLOR_TYPE_GRAY_ALPHA;
    grey_alpha.edit = [](std::vector<unsigned char>& s, size_t row_bytes) {
        for (size_t x = 0; x < 256; ++x) {
            s[x * 4 + 2] = s[x * 4 + 3] = 0;                             // alpha 0 in the first row
            s[row_bytes + x * 4 + 2] = s[row_bytes + x * 4 + 3] = 0xff;  // alpha 65535 in the second
        }
    };
    write_png_file((dir / "grey_alpha16.png").string(), grey_alpha, 3);
    check_same_as_module((dir / "grey_alpha16.png").string());
    grey_alpha.chunks = [](png_structp png, png_infop info) { png_set_gAMA_fixed(png, info, 55556); };
    write_png_file((dir / "grey_alpha16_gamma.png").string(), grey_alpha, 4);
    check_same_as_module((dir / "grey_alpha16_gamma.png").string());
}

TEST_CASE("images: what the PNG reader leaves to the module reads as the module reads it", "[image]") {
    auto dir = scratch_dir("png-left");
    const std::vector<ChunkCase> cases = {
        {"exif",
         [](png_structp png, png_infop info) {
             // A little-endian TIFF header with one directory entry: Orientation 1.
             static unsigned char exif[] = {'I', 'I', 42, 0, 8, 0, 0, 0, 1, 0, 0x12, 0x01, 3, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0};
             png_set_eXIf_1(png, info, png_uint_32(sizeof exif), exif);
         }},
        {"xmp",
         [](png_structp png, png_infop info) { add_text(png, info, "XML:com.adobe.xmp", "<x:xmpmeta xmlns:x=\"adobe:ns:meta/\"/>"); }},
        {"twice",
         [](png_structp png, png_infop info) {
             png_time t{2026, 1, 2, 3, 4, 5};
             png_set_tIME(png, info, &t);
             add_text(png, info, "DateTime", "not a time");
         }},
        {"colour_space_text", [](png_structp png, png_infop info) { add_text(png, info, "oiio:colorspace", "linear"); }},
    };
    for (const ChunkCase& c : cases) {
        PngSpec spec;
        spec.chunks = c.chunks;
        const std::string path = (dir / (std::string(c.name) + ".png")).string();
        write_png_file(path, spec, 7);
        check_same_as_module(path, false);
    }
    // Damaged files: cut inside the image data, and a byte of it changed.
    PngSpec plain;
    plain.width = 64;
    plain.height = 64;
    write_png_file((dir / "plain.png").string(), plain, 8);
    const std::string bytes = read_text(dir / "plain.png");
    // A file cut inside its image data is refused before either reader allocates (its IDAT chunk
    // declares more bytes than the file has left), and so is a text chunk declaring 2 GB in a
    // file of a few hundred bytes (fuzz_image: both readers allocated and zeroed 2.2 GB).
    write_text(dir / "cut.png", bytes.substr(0, bytes.size() / 2));
    CHECK_THROWS_WITH(read_image((dir / "cut.png").string()), Catch::Contains("chunk \"IDAT\" declares"));
    CHECK(png_chunk_problem((dir / "plain.png").string()).empty());
    std::string huge = bytes.substr(0, 33) + std::string("\x7e\x00\x00\x14tEXtTitle", 13) + bytes.substr(33, 300);
    write_text(dir / "huge_text.png", huge);
    CHECK_THROWS_WITH(read_image((dir / "huge_text.png").string()), Catch::Contains("chunk \"tEXt\" declares 2113929236 bytes"));
    std::string changed = bytes;
    changed[changed.size() / 2] = char(changed[changed.size() / 2] ^ 0x5a);
    write_text(dir / "changed.png", changed);
    check_same_as_module((dir / "changed.png").string(), false);
    // Wider than OpenImageIO reads.
    PngSpec wide;
    wide.width = 65537;
    wide.height = 1;
    wide.color_type = PNG_COLOR_TYPE_GRAY;
    wide.bit_depth = 1;
    write_png_file((dir / "wide.png").string(), wide, 9);
    check_same_as_module((dir / "wide.png").string(), false);
}

TEST_CASE("images: a PNG written by libpng reads back exactly, by libpng and by the module", "[image]") {
    auto dir = scratch_dir("png-output");
    std::mt19937 rng(11);
    for (int channels = 1; channels <= 4; ++channels)
        for (bool opaque : {true, false}) {
            const int width = 53, height = 29;
            std::vector<unsigned char> bytes(size_t(width) * height * channels);
            for (size_t i = 0; i < bytes.size(); ++i) {
                const bool alpha = (channels == 2 || channels == 4) && i % size_t(channels) == size_t(channels - 1);
                bytes[i] = alpha && opaque ? 255 : (unsigned char)(rng() & 0xff);
            }
            const std::string path = (dir / ("written" + std::to_string(channels) + (opaque ? "o" : "t") + ".png")).string();
            write_text(path, png_file_bytes(width, height, channels, bytes.data()));
            check_same_as_module(path);
            Image image = read_image(path);
            CHECK(image.metadata["oiio:ColorSpace"] == "sRGB");
            REQUIRE(image.data().size() == bytes.size());
            if (!opaque && (channels == 2 || channels == 4)) continue;  // alpha is associated when read
            for (size_t i = 0; i < bytes.size(); ++i) REQUIRE(image.data()[i] == float(bytes[i]) * (1.0f / 255.0f));
        }
    const unsigned char pixel[5] = {1, 2, 3, 4, 5};
    CHECK_THROWS_AS(png_file_bytes(1, 1, 5, pixel), InputError);
    CHECK_THROWS_AS(png_file_bytes(0, 1, 3, pixel), InputError);
    // A display image written as a file, whole (core/image.h).
    Image display(3, 2, {"R", "G", "B"});
    for (size_t i = 0; i < display.data().size(); ++i) display.data()[i] = float(i) / 17.0f;
    write_png_display(display, (dir / "display.png").string());
    Image back = read_image((dir / "display.png").string());
    for (size_t i = 0; i < display.data().size(); ++i)
        CHECK(back.data()[i] == float(std::lround(display.data()[i] * 255.0f)) * (1.0f / 255.0f));
    CHECK(encode_png(display) == read_text(dir / "display.png"));
}

TEST_CASE("images: an RGBA PNG's colour is read as stored, and textures and environment maps take it so, sRGB-decoded",
          "[image][texture]") {
    // Mitsuba's Bitmap keeps a PNG's alpha unassociated; its bitmap texture and envmap drop alpha
    // and decode the 8-bit sRGB colour. Before, Candela premultiplied the colour by alpha on
    // reading (OpenImageIO's default): a half-transparent texel of (200, 100, 50) read as
    // (100, 50, 25), and an 8-bit environment map was taken as linear radiance.
    auto dir = scratch_dir("png-rgba-colour");
    PngSpec spec;
    spec.width = 4;
    spec.height = 2;
    spec.color_type = PNG_COLOR_TYPE_RGB_ALPHA;
    spec.edit = [](std::vector<unsigned char>& s, size_t) {
        for (size_t i = 0; i < 8; ++i) {
            s[4 * i] = 200;
            s[4 * i + 1] = 100;
            s[4 * i + 2] = 50;
            s[4 * i + 3] = 128;
        }
    };
    const std::string path = (dir / "half.png").string();
    write_png_file(path, spec, 1);
    const Image image = read_image(path);
    const float stored[4] = {200.0f / 255.0f, 100.0f / 255.0f, 50.0f / 255.0f, 128.0f / 255.0f};
    for (int c = 0; c < 4; ++c) CHECK(image.at(1, 1, c) == Approx(stored[c]).epsilon(1e-6));
    const Spectrum expected(srgb_to_linear(stored[0]), srgb_to_linear(stored[1]), srgb_to_linear(stored[2]));
    for (int c = 0; c < 3; ++c) CHECK(image.linear_rgb_at(1, 1)[c] == Approx(expected[c]).epsilon(1e-6));
    // Seen directly, the (constant) environment map is its decoded colour; so is a diffuse plane's
    // albedo read from the texture (eval at any uv).
    Ref<Scene> scene = load_scene_from_string(scene_xml(R"(<integrator type="path"/>
        <sensor type="perspective"><sampler type="independent"><integer name="sample_count" value="1"/></sampler>
            <film type="hdrfilm"><integer name="width" value="2"/><integer name="height" value="2"/><rfilter type="box"/>
                <string name="component_format" value="float32"/></film></sensor>
        <emitter type="envmap"><string name="filename" value="half.png"/></emitter>)"),
                                              (dir / "env.xml").string());
    const Image seen = scene->integrator().render(*scene, RenderOptions()).image;
    for (int c = 0; c < 3; ++c) CHECK(seen.at(0, 0, c) == Approx(expected[c]).epsilon(1e-6));
    Properties props("bitmap", SourceLocation{(dir / "virtual.xml").string(), 1});
    props.set_string("filename", "half.png");
    const Spectrum texel = create_plugin_as<Texture>(ObjectKind::Texture, props)->eval(Vec2(0.4f, 0.6f));
    for (int c = 0; c < 3; ++c) CHECK(texel[c] == Approx(expected[c]).epsilon(1e-6));
}
