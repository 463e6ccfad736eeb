// EXR files are read by OpenEXR itself (core/exr_input.h) instead of the OpenImageIO module: the
// same images as the module gives, checked against the module itself on files of every shape a
// renderer meets (layers and channel names, half and float channels, data windows away from the
// origin, tiles, attributes of several types); what it leaves to the module (several parts,
// 32-bit unsigned channels) still reads.

#include "core/exr_input.h"
#include "core/image.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfPreviewImage.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfStringVectorAttribute.h>
#include <OpenEXR/ImfTiledOutputFile.h>
#include <OpenEXR/ImfVecAttribute.h>

#include <cstring>
#include <random>

using namespace candela;
using namespace candela::test;

namespace {

struct ExrSpec {
    std::vector<std::string> channels;
    Imf::PixelType type = Imf::HALF;
    Imath::Box2i data_window{Imath::V2i(0, 0), Imath::V2i(6, 4)};
    int tile = 0;  // tile size, 0 for scan lines
};

// Random pixels of `spec`'s channels, written as OpenEXR lays them out, with attributes of
// several types.
void write_exr_file(const std::string& path, const ExrSpec& spec, uint32_t seed) {
    const Imath::Box2i& w = spec.data_window;
    const int width = w.max.x - w.min.x + 1, height = w.max.y - w.min.y + 1;
    Imf::Header header(Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(9, 9)), w);
    header.insert("note", Imf::StringAttribute("written by test_exr_input"));
    header.insert("candela.spp", Imf::StringAttribute("64"));
    header.insert("count", Imf::IntAttribute(-17));
    header.insert("exposure", Imf::FloatAttribute(0.1f));
    for (const std::string& c : spec.channels) header.channels().insert(c, Imf::Channel(spec.type));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> value(-2.0f, 70000.0f);
    const size_t n = size_t(width) * size_t(height) * spec.channels.size();
    std::vector<Imath::half> halves(n);
    std::vector<float> floats(n);
    std::vector<uint32_t> uints(n);
    for (size_t i = 0; i < n; ++i) {
        floats[i] = value(rng);
        halves[i] = Imath::half(floats[i] * 0.001f);
        uints[i] = uint32_t(rng() % 100000);
    }
    const size_t size = spec.type == Imf::FLOAT ? 4 : spec.type == Imf::HALF ? 2 : 4;
    const char* base = spec.type == Imf::FLOAT  ? reinterpret_cast<const char*>(floats.data())
                       : spec.type == Imf::HALF ? reinterpret_cast<const char*>(halves.data())
                                                : reinterpret_cast<const char*>(uints.data());
    Imf::FrameBuffer frame;
    const size_t x_stride = size * spec.channels.size();
    for (size_t c = 0; c < spec.channels.size(); ++c)
        frame.insert(spec.channels[c], Imf::Slice::Make(spec.type, base + c * size, w, x_stride, x_stride * size_t(width)));
    if (spec.tile > 0) {
        header.setTileDescription(Imf::TileDescription(unsigned(spec.tile), unsigned(spec.tile), Imf::ONE_LEVEL));
        Imf::TiledOutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
    } else {
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(height);
    }
}

// Both readers' results on `path` agree: size, channels in order, every value bit for bit, and
// the string attributes.
void check_same_as_module(const std::string& path) {
    INFO(path);
    Image direct = read_image(path);
    DecodedImage module;
    REQUIRE(module_codecs().read(path, "exr", true, module) == "");
    CHECK(direct.width() == module.header.width);
    CHECK(direct.height() == module.header.height);
    CHECK(direct.channels() == module.header.channels);
    CHECK(direct.integer_bits == module.header.integer_bits);
    REQUIRE(direct.data().size() == module.values.size());
    CHECK(std::memcmp(direct.data().data(), module.values.data(), module.values.size() * sizeof(float)) == 0);
    int strings = 0;
    for (const char* key : {"note", "candela.spp", "candela.partial"})
        if (module.header.metadata.count(key)) {
            CHECK(direct.metadata[key] == module.header.metadata[key]);
            ++strings;
        }
    CHECK(strings >= 1);
    CHECK(read_image_header(path).channels == module.header.channels);
}

}  // namespace

TEST_CASE("images: an EXR file reads as the OpenImageIO module read it, without loading the module", "[image]") {
    auto dir = scratch_dir("exr-input");
    const std::vector<std::vector<std::string>> channel_sets = {
        {"R", "G", "B"},
        {"Y"},
        {"R", "G", "B", "A", "Z", "variance.R", "variance.G", "variance.B", "albedo.R", "albedo.G", "albedo.B", "foo", "Y"},
        {"diffuse.A", "diffuse.B", "diffuse.R", "diffuse.G", "B", "G", "R"},
        {"Alpha", "Red", "Green", "Blue", "depth", "Depth", "ZBack", "a", "r", "imag", "real", "GA", "AR"},
        {"u", "v"},
        {"Y", "RY", "BY"},
        {"x.y.R", "x.y.G", "x.R", "zz", ".R", "R."},
        {"X", "Y", "Z"},
        {"R", "G", "B", "dd.y", "nn.X", "nn.Y", "nn.Z", "pos.X", "pos.Y", "pos.Z"},
        {"Y", "A", "R", "U", "V", "W", "x", "z"},
        {"P.x", "P.y", "P.z", "P.w", "N.X", "N.Z", "a.X", "a.A", "a.Y", "X", "R", "G", "B", "Y", "Z", "A"},
    };
    int n = 0;
    for (const auto& channels : channel_sets)
        for (Imf::PixelType type : {Imf::HALF, Imf::FLOAT}) {
            ExrSpec spec;
            spec.channels = channels;
            spec.type = type;
            const std::string path = (dir / ("set" + std::to_string(n) + ".exr")).string();
            write_exr_file(path, spec, uint32_t(n++));
            check_same_as_module(path);
        }
    // A data window away from the origin (and outside the display window), tiles that do not
    // divide it, and 32-bit unsigned channels.
    ExrSpec moved;
    moved.channels = {"R", "G", "B", "A"};
    moved.data_window = Imath::Box2i(Imath::V2i(-3, 5), Imath::V2i(30, 21));
    write_exr_file((dir / "moved.exr").string(), moved, 101);
    check_same_as_module((dir / "moved.exr").string());
    moved.tile = 16;
    moved.type = Imf::FLOAT;
    write_exr_file((dir / "tiled.exr").string(), moved, 102);
    check_same_as_module((dir / "tiled.exr").string());
    // 32-bit unsigned channels are left to the module (it scales them to [0, 1]).
    moved.type = Imf::UINT;
    moved.channels = {"id", "R"};
    write_exr_file((dir / "uint.exr").string(), moved, 103);
    check_same_as_module((dir / "uint.exr").string());
    DecodedImage unused;
    std::string error;
    CHECK_FALSE(read_exr((dir / "uint.exr").string(), true, 0, unused, error));
    // Attributes other than strings, as text under their OpenEXR names.
    Image image = read_image((dir / "moved.exr").string());
    CHECK(image.metadata["count"] == "-17");
    CHECK(std::stof(image.metadata["exposure"]) == 0.1f);
    CHECK(image.metadata.count("compression") == 0);  // a required attribute: the header's own
    // Candela's own films (write_exr) read back the same way.
    Image film(5, 3, {"R", "G", "B", "albedo.R", "albedo.G", "albedo.B"});
    for (size_t i = 0; i < film.data().size(); ++i) film.data()[i] = float(i) * 0.25f;
    film.metadata["candela.partial"] = "false";
    write_exr(film, (dir / "film.exr").string(), true);
    check_same_as_module((dir / "film.exr").string());
    CHECK(read_image((dir / "film.exr").string()).data() == film.data());
}

TEST_CASE("images: a multi-part EXR file is left to the module, which reads its first part", "[image]") {
    auto dir = scratch_dir("exr-multipart");
    const std::string path = (dir / "parts.exr").string();
    {
        std::vector<Imf::Header> headers;
        for (const char* name : {"beauty", "extra"}) {
            Imf::Header h(4, 3);
            h.setName(name);
            h.setType(Imf::SCANLINEIMAGE);
            h.insert("note", Imf::StringAttribute(name));
            h.insert("candela.spp", Imf::StringAttribute("1"));
            for (const char* c : {"R", "G", "B"}) h.channels().insert(c, Imf::Channel(Imf::FLOAT));
            headers.push_back(h);
        }
        Imf::MultiPartOutputFile file(path.c_str(), headers.data(), int(headers.size()));
        for (int part = 0; part < 2; ++part) {
            std::vector<float> values(4 * 3 * 3, float(part + 1));
            Imf::FrameBuffer frame;
            for (size_t c = 0; c < 3; ++c)
                frame.insert(std::string(1, "RGB"[c]), Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data() + c), 12, 48));
            Imf::OutputPart out(file, part);
            out.setFrameBuffer(frame);
            out.writePixels(3);
        }
    }
    DecodedImage direct;
    std::string error;
    CHECK_FALSE(read_exr(path, true, 0, direct, error));
    check_same_as_module(path);
    CHECK(read_image(path).data()[0] == 1.0f);
}

TEST_CASE("images: an EXR attribute whose declared size disagrees with its value is refused before OpenEXR reads on out of step",
          "[image][errors]") {
    // OpenEXR 3.1 reads a typed attribute by its own length and then goes on from where it
    // stopped; the declared sizes are checked against what the file has left (exr_header_problem),
    // so the two must agree or a later attribute escapes the check (fuzz_part found a channel list
    // running 4 bytes past its size, then a 1.8 GB attribute).
    auto dir = scratch_dir("exr-attribute-sizes");
    const std::string path = (dir / "good.exr").string();
    {
        Imf::Header header(4, 3);
        for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
        header.insert("note", Imf::StringAttribute("sizes"));
        header.insert("count", Imf::IntAttribute(5));
        header.insert("offset", Imf::V2fAttribute(Imath::V2f(0.5f, 1.5f)));
        header.insert("names", Imf::StringVectorAttribute({"first", "", "third one"}));
        header.setPreviewImage(Imf::PreviewImage(2, 3));
        std::vector<float> values(4 * 3 * 3, 0.25f);
        Imf::FrameBuffer frame;
        for (size_t c = 0; c < 3; ++c)
            frame.insert(std::string(1, "RGB"[c]), Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data() + c), 12, 48));
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(3);
    }
    // What OpenEXR writes agrees with itself: every type above walks to its declared size.
    CHECK(exr_header_problem(path) == "");
    CHECK(read_image(path).data()[0] == 0.25f);
    const std::string bytes = read_text(path);
    struct Case {
        const char* name;
        const char* type;
    };
    for (const Case& c : {Case{"count", "int"}, Case{"offset", "v2f"}, Case{"dataWindow", "box2i"}, Case{"channels", "chlist"},
                          Case{"names", "stringvector"}, Case{"preview", "preview"}}) {
        const size_t at = bytes.find(std::string(c.name) + '\0' + c.type + '\0');
        REQUIRE(at != std::string::npos);
        const size_t size_at = at + std::strlen(c.name) + std::strlen(c.type) + 2;
        for (int change : {-1, +1}) {
            INFO(c.name << " size " << change);
            std::string changed = bytes;
            changed[size_at] = char(uint8_t(changed[size_at]) + change);
            const std::string bad = (dir / "bad.exr").string();
            write_text(bad, changed);
            const std::string problem = exr_header_problem(bad);
            CHECK_THAT(problem, Catch::Contains("bad.exr: cannot read image: its header's attribute \"" + std::string(c.name) +
                                                "\" of type " + c.type + " declares"));
            CHECK_THROWS_WITH(read_image(bad), Catch::Contains(problem));
        }
    }
}
