// Textures: Mitsuba's bitmap conventions (v = 0 is the top row, texel centres at half-integers),
// wrap modes, sRGB decoding, nearest and bilinear filtering, to_uv, the checkerboard's parity,
// and the MIP pyramid.

#include "core/image.h"
#include "core/registry.h"
#include "core/rng.h"
#include "core/texture.h"
#include "core/xml.h"
#include "tests/support/vol_writer.h"
#include "tests/util.h"
#include "textures/mipmap.h"

#include <catch2/catch.hpp>

#include <Imath/half.h>

using namespace candela;
using namespace candela::test;

namespace {
// A 4x2 image: row 0 (top) red ramps, row 1 (bottom) green ramps.
void write_test_image(const std::filesystem::path& path, bool png) {
    Image img = Image::rgb(4, 2);
    for (int x = 0; x < 4; ++x) {
        img.set_rgb(x, 0, Spectrum(0.25f * x, 0, 0));
        img.set_rgb(x, 1, Spectrum(0, 0.25f * x, 0));
    }
    if (png)
        write_png_display(img, path.string());
    else
        write_exr(img, path.string(), true);
}

Ref<Texture> load_bitmap(const std::filesystem::path& dir, const std::string& file, const std::string& extra = "") {
    Properties props("bitmap", SourceLocation{(dir / "virtual.xml").string(), 1});
    props.set_string("filename", file);
    if (extra.find("nearest") != std::string::npos) props.set_string("filter_type", "nearest");
    if (extra.find("clamp") != std::string::npos) props.set_string("wrap_mode", "clamp");
    if (extra.find("mirror") != std::string::npos) props.set_string("wrap_mode", "mirror");
    if (extra.find("raw") != std::string::npos) props.set_bool("raw", true);
    return create_plugin_as<Texture>(ObjectKind::Texture, props);
}
}  // namespace

TEST_CASE("bitmap: v = 0 is the top row and texel centres sit at half-integers", "[texture]") {
    auto dir = scratch_dir("bitmap");
    write_test_image(dir / "ramp.exr", false);
    auto tex = load_bitmap(dir, "ramp.exr", "nearest");
    // Texel (x, y) covers u in [x / 4, (x + 1) / 4), v in [y / 2, (y + 1) / 2).
    CHECK(tex->eval(Vec2(0.3f, 0.25f)) == Spectrum(0.25f, 0, 0));  // texel (1, 0): top row
    CHECK(tex->eval(Vec2(0.8f, 0.75f)) == Spectrum(0, 0.75f, 0));  // texel (3, 1): bottom row
    auto bilinear = load_bitmap(dir, "ramp.exr");
    // At a texel centre bilinear equals the texel; halfway between two centres, their mean.
    CHECK(bilinear->eval(Vec2(0.375f, 0.25f)).x == Approx(0.25f));
    CHECK(bilinear->eval(Vec2(0.5f, 0.25f)).x == Approx(0.375f));
    CHECK(bilinear->eval(Vec2(0.5f, 0.5f)).x == Approx(0.1875f));  // between the rows
}

TEST_CASE("bitmap: wrap modes repeat, mirror and clamp", "[texture]") {
    auto dir = scratch_dir("bitmap-wrap");
    write_test_image(dir / "ramp.exr", false);
    auto repeat = load_bitmap(dir, "ramp.exr", "nearest"), mirror = load_bitmap(dir, "ramp.exr", "nearest mirror"),
         clamp = load_bitmap(dir, "ramp.exr", "nearest clamp");
    CHECK(repeat->eval(Vec2(1.3f, 0.25f)) == repeat->eval(Vec2(0.3f, 0.25f)));
    CHECK(repeat->eval(Vec2(-0.2f, 0.25f)) == Spectrum(0.75f, 0, 0));  // wraps to texel 3
    CHECK(mirror->eval(Vec2(-0.2f, 0.25f)) == Spectrum(0.0f, 0, 0));   // reflects to texel 0
    CHECK(mirror->eval(Vec2(1.1f, 0.25f)) == Spectrum(0.75f, 0, 0));   // reflects to texel 3
    CHECK(clamp->eval(Vec2(3.0f, 0.25f)) == Spectrum(0.75f, 0, 0));
    CHECK(clamp->eval(Vec2(-3.0f, 0.75f)) == Spectrum(0, 0, 0));
}

TEST_CASE("bitmap: 8-bit images are decoded from sRGB unless raw", "[texture]") {
    auto dir = scratch_dir("bitmap-srgb");
    Image img = Image::rgb(2, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) img.set_rgb(x, y, Spectrum(128.0f / 255.0f));
    write_png_display(img, (dir / "grey.png").string());
    CHECK(load_bitmap(dir, "grey.png")->eval(Vec2(0.5f)).x == Approx(srgb_to_linear(128.0f / 255.0f)).epsilon(1e-5));
    CHECK(load_bitmap(dir, "grey.png", "raw")->eval(Vec2(0.5f)).x == Approx(128.0f / 255.0f).epsilon(1e-5));
    CHECK(srgb_to_linear(128.0f / 255.0f) == Approx(0.2158605f).epsilon(1e-5));  // the IEC 61966-2-1 curve
}

TEST_CASE("checkerboard: parity, defaults and to_uv", "[texture]") {
    Properties props("checkerboard", SourceLocation{"t", 1});
    props.set_transform("to_uv", Transform::scale(Vec3(2, 2, 1)));
    auto tex = create_plugin_as<Texture>(ObjectKind::Texture, props);
    // After scaling by 2: (0.1, 0.1) -> (0.2, 0.2): both fractions <= 0.5 -> color0 (0.4).
    CHECK(tex->eval(Vec2(0.1f, 0.1f)) == Spectrum(0.4f));
    CHECK(tex->eval(Vec2(0.3f, 0.1f)) == Spectrum(0.2f));  // (0.6, 0.2): differ -> color1
    CHECK(tex->eval(Vec2(0.3f, 0.3f)) == Spectrum(0.4f));  // (0.6, 0.6): both > 0.5 -> color0
    CHECK(tex->eval_1(Vec2(0.1f, 0.1f)) == Approx(0.2f));  // scalar lookups use the other parity
    CHECK(tex->mean() == Spectrum(0.3f));
}

TEST_CASE("mipmap: levels average their footprint, trilinear blends levels", "[texture]") {
    // 8x8 checkerboard of single texels: every level above 0 is uniformly grey 0.5.
    std::vector<Spectrum> texels(64);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) texels[size_t(y) * 8 + x] = Spectrum(float((x + y) % 2));
    MipMap mip(texels, 8, 8, WrapMode::Repeat);
    REQUIRE(mip.levels() == 4);
    CHECK(mip.width(3) == 1);
    CHECK(mip.texel(1, 2, 1).x == Approx(0.5f));
    CHECK(mip.texel(3, 0, 0).x == Approx(0.5f));
    CHECK(mip.mean().x == Approx(0.5f));
    // A footprint of one texel reads level 0; a footprint of the whole texture the top level.
    CHECK(mip.trilinear(Vec2(1.5f / 8, 0.5f / 8), 1.0f / 8).x == Approx(1.0f));
    CHECK(mip.trilinear(Vec2(0.3f, 0.7f), 1.0f).x == Approx(0.5f));
    // Odd sizes: a 3x1 image [0, 3, 6] halves to 2 texels covering 1.5 source texels each,
    // [(0 + 3 / 2) / 1.5, (3 / 2 + 6) / 1.5] = [1, 5], and then to their mean 3.
    MipMap odd({Spectrum(0.0f), Spectrum(3.0f), Spectrum(6.0f)}, 3, 1, WrapMode::Clamp);
    CHECK(odd.levels() == 3);
    CHECK(odd.texel(1, 0, 0).x == Approx(1.0f));
    CHECK(odd.texel(1, 1, 0).x == Approx(5.0f));
    CHECK(odd.texel(2, 0, 0).x == Approx(3.0f));
}

TEST_CASE("mipmap: every level keeps the image's mean, for odd and even sizes", "[texture]") {
    PCG32 rng(12, 5);
    for (int height = 1; height <= 13; ++height)
        for (int width = 1; width <= 19; ++width) {
            std::vector<Spectrum> texels(size_t(width) * height);
            for (Spectrum& t : texels) t = Spectrum(rng.next_float(), 4.0f * rng.next_float(), rng.next_float() * rng.next_float());
            MipMap mip(texels, width, height, WrapMode::Repeat);
            const Spectrum mean = mip.mean();
            for (int level = 1; level < mip.levels(); ++level) {
                // Texels of a level cover equal areas, so the level's plain mean is the image's.
                double sum[3] = {0, 0, 0};
                for (int y = 0; y < mip.height(level); ++y)
                    for (int x = 0; x < mip.width(level); ++x)
                        for (int c = 0; c < 3; ++c) sum[c] += mip.texel(level, x, y)[c];
                double count = double(mip.width(level)) * mip.height(level);
                INFO(width << "x" << height << " level " << level << " (" << mip.width(level) << "x" << mip.height(level) << ")");
                // float32 rounding over a few levels of weighted sums: well below 1e-5 relative.
                for (int c = 0; c < 3; ++c) CHECK(sum[c] / count == Approx(mean[c]).epsilon(1e-5));
            }
            CHECK(mip.width(mip.levels() - 1) == 1);
            CHECK(mip.height(mip.levels() - 1) == 1);
        }
}

TEST_CASE("bitmap: a missing or unreadable image is an error at the filename's line", "[texture][errors]") {
    auto dir = scratch_dir("bitmap-bad");
    write_text(dir / "broken.png", "not an image");
    write_text(dir / "scene.xml", scene_xml("<shape type=\"sphere\"><bsdf type=\"diffuse\"><texture type=\"bitmap\" name=\"reflectance\">\n"
                                            "<string name=\"filename\" value=\"broken.png\"/>\n</texture></bsdf></shape>"));
    try {
        load_scene((dir / "scene.xml").string());
        FAIL("expected an error");
    } catch (const SceneError& e) {
        CHECK(e.location.line == 3);
        CHECK_THAT(std::string(e.what()), Catch::Contains("broken.png"));
    }
}

namespace {
// A 2 x 2 x 4 DDS volume texture (uncompressed RGBA8), built byte by byte.
std::string dds_volume() {
    std::string bytes = "DDS ";
    auto u32 = [&](uint32_t v) {
        for (int i = 0; i < 4; ++i) bytes += char((v >> (8 * i)) & 0xff);
    };
    const uint32_t w = 2, h = 2, depth = 4;
    u32(124);                                        // header size
    u32(0x1 | 0x2 | 0x4 | 0x1000 | 0x800000);        // caps, height, width, pixel format, depth
    u32(h), u32(w), u32(w * 4), u32(depth), u32(0);  // height, width, pitch, depth, mip levels
    for (int i = 0; i < 11; ++i) u32(0);             // reserved
    u32(32), u32(0x40 | 0x1), u32(0), u32(32);       // pixel format: size, RGB + alpha, no fourCC, 32 bits
    u32(0x00ff0000), u32(0x0000ff00), u32(0x000000ff), u32(0xff000000);
    u32(0x1000 | 0x8), u32(0x200000), u32(0), u32(0), u32(0);  // caps: texture, complex; volume
    bytes += std::string(w * h * depth * 4, char(100));
    return bytes;
}
}  // namespace

TEST_CASE("bitmap and envmap: volume images and images too large to read are errors at the filename's line", "[texture][errors]") {
    // A DDS volume texture made read_image hand OpenImageIO a 2D buffer for depth times as many
    // values (a heap overflow: ASan saw the heap corrupted at the next free). A header claiming
    // 100000 x 100000 pixels made it allocate 120 GB (std::bad_alloc, or an abort under ASan).
    auto dir = scratch_dir("bitmap-size");
    write_text(dir / "volume.dds", dds_volume());
    write_text(dir / "huge.pfm", "PF\n100000 100000\n-1.0\n" + std::string(64, '\0'));
    // Within the size limit, but promising more than the file holds: 8000 x 8000 pixels made
    // read_image allocate 768 MB before OpenImageIO found the data missing (fuzz_image).
    write_text(dir / "short.pfm", "PF\n8000 8000\n-1.0\n" + std::string(64, '\0'));
    write_text(dir / "short.ppm", "P6\n8000 8000\n255\n" + std::string(64, '\0'));
    // A 293-byte DDS cube map on which OpenImageIO 2.4's DDS reader spins for minutes (found by
    // fuzz_image; the corpus file's first byte chose the extension): DDS is not read at all now.
    // Neither is a DDS file named .png (OpenImageIO tries every reader by content).
    std::string cube = read_text(source_path("fuzz/corpus/image/regression-dds-cube-hang")).substr(1);
    write_text(dir / "cube.dds", cube);
    write_text(dir / "cube.png", cube);
    // A 3-line OpenEXR 3997700 pixels wide and a 3-line BMP 3801092 wide: OpenImageIO allocates
    // 256 lines at a time (6 and 2.9 GB) before reading (found by fuzz_image).
    write_text(dir / "wide.exr", read_text(source_path("fuzz/corpus/image/regression-exr-wide-blocks")).substr(1));
    write_text(dir / "wide.bmp", read_text(source_path("fuzz/corpus/image/regression-bmp-wide-blocks")).substr(1));
    // A 2.6 kB OpenEXR file whose header declares a string attribute of 1.8 GB: OpenEXR allocates
    // and zeroes it before reading (15 s, 2.2 GB; found by fuzz_part).
    write_text(dir / "attribute.exr", read_text(source_path("fuzz/corpus/part/regression-exr-huge-attribute.exr")));
    // A 1.9 kB OpenEXR file whose channel list declares 515 bytes and runs 4 past them: OpenEXR
    // reads on from the list's real end, out of step with the declared sizes checked, and meets a
    // 1.8 GB attribute (found by fuzz_part).
    write_text(dir / "step.exr", read_text(source_path("fuzz/corpus/part/regression-exr-attribute-size-out-of-step.exr")));
    // A part whose data window is 458760 pixels wide, with 21 channels and one of them 32-bit
    // unsigned (left to OpenImageIO): OpenEXR allocated its 16-line ZIP buffer, 616 MB, when the
    // file was opened, before the size was checked (30 s under AddressSanitizer; fuzz_part).
    write_text(dir / "line.exr", read_text(source_path("fuzz/corpus/part/regression-exr-wide-line-buffer.exr")));
    for (const char* name : {"volume.dds", "huge.pfm", "short.pfm", "short.ppm", "cube.dds", "cube.png", "wide.exr", "wide.bmp",
                             "attribute.exr", "step.exr", "line.exr"}) {
        for (const char* use : {"texture", "envmap"}) {
            INFO(name << " as " << use);
            std::string body =
                std::string(use) == "texture"
                    ? "<shape type=\"sphere\"><bsdf type=\"diffuse\"><texture type=\"bitmap\" name=\"reflectance\">\n"
                      "<string name=\"filename\" value=\"" +
                          std::string(name) + "\"/>\n</texture></bsdf></shape>"
                    : "<emitter type=\"envmap\">\n<string name=\"filename\" value=\"" + std::string(name) + "\"/>\n</emitter>";
            write_text(dir / "scene.xml", scene_xml(body));
            try {
                load_scene((dir / "scene.xml").string());
                FAIL("expected an error");
            } catch (const SceneError& e) {
                CHECK(e.location.line == 3);
                CHECK_THAT(std::string(e.what()), Catch::Contains(name));
                // Refused from the header, before anything is allocated for the pixels.
                if (std::string(name).rfind("short", 0) == 0)
                    CHECK_THAT(std::string(e.what()), Catch::Contains("header promises 8000 x 8000 pixels"));
                if (std::string(name) == "wide.exr") CHECK_THAT(std::string(e.what()), Catch::Contains("(read as 3997700 x 256)"));
                if (std::string(name) == "wide.bmp") CHECK_THAT(std::string(e.what()), Catch::Contains("(read as 3801092 x 256)"));
                if (std::string(name) == "attribute.exr")
                    CHECK_THAT(std::string(e.what()), Catch::Contains("attribute \"candela.started\" declares 1802661646 bytes"));
                if (std::string(name) == "line.exr")
                    CHECK_THAT(std::string(e.what()), Catch::Contains("(read as 458760 x 256) and 21 channels"));
                if (std::string(name) == "step.exr")
                    CHECK_THAT(std::string(e.what()),
                               Catch::Contains("attribute \"channels\" of type chlist declares 515 bytes, but its value runs past them"));
            }
        }
    }
}

TEST_CASE("bitmap: the reader is chosen by the file's content (TGA by extension), as Mitsuba's Bitmap does", "[texture][errors]") {
    // Only the chosen reader sees the file: OpenImageIO's own open would try all of its readers on
    // a file the first one fails on, and one of those allocated 36 GB for a fuzzed input.
    auto dir = scratch_dir("bitmap-by-content");
    write_test_image(dir / "png_named.exr", true);
    write_test_image(dir / "exr_named.png", false);
    for (const char* name : {"png_named.exr", "exr_named.png"}) {
        INFO(name);
        Ref<Texture> t = load_bitmap(dir, name, "nearest raw");
        // Texel (2, 0): red 0.5 (8-bit in the PNG: 128/255 or 127/255 after rounding).
        CHECK(t->eval(Vec2(2.5f / 4, 0.25f)).x == Approx(0.5f).margin(1.0f / 255));
    }
    write_text(dir / "picture.gif", "GIF89a" + std::string(64, '\0'));
    try {
        load_bitmap(dir, "picture.gif");
        FAIL("expected an error");
    } catch (const SceneError& e) {
        CHECK_THAT(std::string(e.what()),
                   Catch::Contains("picture.gif: is ") && Catch::Contains("Candela reads the formats Mitsuba 3 does"));
    }
}

namespace {
Ref<Texture> load_with(const std::filesystem::path& dir, const std::string& file, const std::string& format) {
    Properties props("bitmap", SourceLocation{(dir / "virtual.xml").string(), 1});
    props.set_string("filename", file);
    props.set_string("filter_type", "nearest");
    if (!format.empty()) props.set_string("format", format);
    props.set_bool("accel", false);  // Mitsuba's CUDA texture units: accepted, nothing to switch here
    return create_plugin_as<Texture>(ObjectKind::Texture, props);
}
}  // namespace

TEST_CASE("bitmap: format stores texels in float32, float16 or 8 bits as Mitsuba does", "[texture]") {
    auto dir = scratch_dir("bitmap-format");
    Image img = Image::rgb(1, 1);
    const Spectrum value(0.1234567f, 1.0f / 3.0f, 2.5f);
    img.set_rgb(0, 0, value);
    write_exr(img, (dir / "values.exr").string(), true);
    Spectrum half_value(float(half(value.x)), float(half(value.y)), float(half(value.z)));
    CHECK(load_with(dir, "values.exr", "")->eval(Vec2(0.5f)) == value);      // variant: float32
    CHECK(load_with(dir, "values.exr", "auto")->eval(Vec2(0.5f)) == value);  // a float file: float32
    CHECK(load_with(dir, "values.exr", "float16")->eval(Vec2(0.5f)) == half_value);
    CHECK(load_with(dir, "values.exr", "fp16")->eval(Vec2(0.5f)) == half_value);
    CHECK(half_value != value);
    // 8 bits: [0, 1], 256 levels.
    CHECK(load_with(dir, "values.exr", "uint8")->eval(Vec2(0.5f)) == Spectrum(std::round(0.1234567f * 255) / 255, 85.0f / 255, 1.0f));
    // An 8-bit sRGB file keeps its encoding in 8 bits and is decoded on lookup: the same values.
    Image grey = Image::rgb(1, 1);
    grey.set_rgb(0, 0, Spectrum(100.0f / 255.0f));
    write_png_display(grey, (dir / "grey.png").string());
    Spectrum decoded = load_with(dir, "grey.png", "variant")->eval(Vec2(0.5f));
    CHECK(load_with(dir, "grey.png", "uint8")->eval(Vec2(0.5f)) == decoded);
    CHECK(load_with(dir, "grey.png", "auto")->eval(Vec2(0.5f)) == decoded);
}

TEST_CASE("bitmap: filter types without support and unknown formats are errors", "[texture][errors]") {
    auto dir = scratch_dir("bitmap-options");
    Image img = Image::rgb(2, 2);
    write_exr(img, (dir / "black.exr").string(), true);
    for (const char* filter : {"trilinear", "anisotropic", "cubic"}) {
        INFO(filter);
        Properties props("bitmap", SourceLocation{(dir / "virtual.xml").string(), 1});
        props.set_string("filename", "black.exr");
        props.set_string("filter_type", filter);
        CHECK_THROWS_AS(create_plugin(ObjectKind::Texture, props), SceneError);
    }
    CHECK_THROWS_AS(load_with(dir, "black.exr", "float64"), SceneError);
}

TEST_CASE("volume texture: a surface point takes the volume's value at its world position", "[texture][volume]") {
    // Two voxels (nearest filtering) over [-1, 1]^3: (1, 2, 3) where x < 0, (4, 5, 6) where x > 0,
    // as the radiance of an emitter square at z = 0, read by two radiance meters.
    const auto dir = scratch_dir("volume-texture");
    write_vol(dir / "two.vol", glm::ivec3(2, 1, 1), 3, {1, 2, 3, 4, 5, 6});
    auto meter = [](float x) {
        return R"(<sensor type="radiancemeter"><point name="origin" value=")" + std::to_string(x) +
               R"(, 0.3, 1"/><vector name="direction" value="0, 0, -1"/><film type="hdrfilm"><integer name="width" value="1"/>
               <integer name="height" value="1"/><rfilter type="box"/><string name="component_format" value="float32"/></film>
               <sampler type="independent"><integer name="sample_count" value="4"/></sampler></sensor>)";
    };
    const std::string body = R"(<shape type="rectangle"><emitter type="area"><texture type="volume" name="radiance">
            <volume type="gridvolume" name="volume"><string name="filename" value="two.vol"/><string name="filter_type" value="nearest"/>
                <transform name="to_world"><scale value="2"/><translate value="-1, -1, -1"/></transform></volume>
        </texture></emitter></shape>)" +
                             meter(-0.5f) + meter(0.5f);
    for (int sensor : {0, 1}) {
        write_text(dir / "scene.xml", scene_xml(body));
        Ref<Scene> scene = load_scene((dir / "scene.xml").string(), {}, Variant::ScalarRGB, sensor);
        const Image image = scene->integrator().render(*scene, RenderOptions()).image;
        for (int c = 0; c < 3; ++c) CHECK(image.at(0, 0, c) == Approx(float(1 + c + 3 * sensor)).epsilon(1e-6));
    }
    // A constant: 0.75 by default, or the given value, everywhere.
    for (const auto& [xml, value] : {std::pair<std::string, float>{R"(<texture type="volume" name="radiance"/>)", 0.75f},
                                     {R"(<texture type="volume" name="radiance"><float name="volume" value="2.5"/></texture>)", 2.5f}}) {
        write_text(dir / "scene.xml",
                   scene_xml(R"(<shape type="rectangle"><emitter type="area">)" + xml + "</emitter></shape>" + meter(0.2f)));
        Ref<Scene> scene = load_scene((dir / "scene.xml").string());
        CHECK(scene->integrator().render(*scene, RenderOptions()).image.at(0, 0, 1) == Approx(value).epsilon(1e-6));
    }
}
