// The memory budget (core/memory_budget.h): sizes read and printed, the cap of --max-memory, and
// every buffer the input sizes checked before it is allocated: the film with its AOVs, the
// rasterizer's sample buffers, and meshes whose headers promise more than the file holds or more
// than memory allows.

#include "core/integrator.h"
#include "core/memory_budget.h"
#include "core/scene.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <fstream>
#include <limits>

using namespace candela;
using namespace candela::test;

namespace {

// Restores the uncapped budget when a test ends, however it ends.
struct MemoryLimitScope {
    explicit MemoryLimitScope(uint64_t bytes) { set_memory_limit(bytes); }
    ~MemoryLimitScope() { set_memory_limit(0); }
};

std::string film_scene(const std::string& width, const std::string& height, const std::string& integrator = "path") {
    return "<integrator type=\"" + integrator +
           "\"/>\n<sensor type=\"perspective\">\n<film type=\"hdrfilm\">\n<integer name=\"width\" value=\"" + width +
           "\"/><integer name=\"height\" value=\"" + height + "\"/>\n</film>\n</sensor>\n<shape type=\"sphere\"/>";
}

// Loads `body` and renders it with `aovs`; returns the error message, or "" when it rendered.
std::string render_error(const std::string& name, const std::string& body, std::vector<std::string> aovs = {}, int* line = nullptr) {
    Ref<Scene> scene = load_scene_xml(name, body);
    RenderOptions options;
    options.spp = 1;
    options.threads = 1;
    options.aovs = std::move(aovs);
    try {
        scene->integrator().render(*scene, options);
    } catch (const SceneError& e) {
        if (line) *line = e.location.line;
        return e.what();
    }
    return "";
}

void write_binary(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

std::string ply_scene(const std::string& file) {
    return "<shape type=\"ply\">\n<string name=\"filename\" value=\"" + file + "\"/>\n</shape>";
}

// Loads `body`; returns the SceneError's message and line, or "" when it loaded.
std::string load_error(const std::filesystem::path& dir, const std::string& body, int* line = nullptr) {
    write_text(dir / "scene.xml", scene_xml(body));
    try {
        load_scene((dir / "scene.xml").string());
    } catch (const SceneError& e) {
        if (line) *line = e.location.line;
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("memory budget: sizes are read as --max-memory takes them and printed in the same units", "[memory]") {
    CHECK(parse_memory_size("4G") == 4ull << 30);
    CHECK(parse_memory_size("512M") == 512ull << 20);
    CHECK(parse_memory_size("512MB") == 512ull << 20);
    CHECK(parse_memory_size("1.5GiB") == 3ull << 29);
    CHECK(parse_memory_size("64k") == 64ull << 10);
    CHECK(parse_memory_size("1000") == 1000);
    for (const char* bad : {"", "G", "-1G", "0", "4X", "4GG", "nan", "inf", "1e30"}) {
        INFO(bad);
        CHECK_THROWS_AS(parse_memory_size(bad), InputError);
    }
    CHECK(format_bytes(100) == "100 B");
    CHECK(format_bytes(512ull << 20) == "512 MB");
    CHECK(format_bytes(uint64_t(6.1 * double(1ull << 30))) == "6.1 GB");
    CHECK(format_bytes(190ull << 30) == "190 GB");
    const uint64_t max = std::numeric_limits<uint64_t>::max();
    CHECK(saturating_mul(max / 2, 3) == max);
    CHECK(saturating_mul(0, max) == 0);
    CHECK(saturating_add(max - 1, 2) == max);
}

TEST_CASE("memory budget: the cap counts what the process already holds", "[memory]") {
    const uint64_t held = resident_memory();
    REQUIRE(held > 0);
    MemoryLimitScope cap(held + (64ull << 20));
    CHECK(memory_available() <= 64ull << 20);
    CHECK_NOTHROW(check_memory(1ull << 20, "a small buffer"));
    try {
        check_memory(1ull << 30, "a large buffer", SourceLocation{"scene.xml", 7});
        FAIL("expected an error");
    } catch (const SceneError& e) {
        CHECK(e.location.line == 7);
        CHECK_THAT(std::string(e.what()),
                   Catch::StartsWith("scene.xml:7: a large buffer needs 1.0 GB; ") && Catch::Contains("under --max-memory"));
    }
    CHECK_THROWS_AS(check_memory(1ull << 30, "a large buffer"), InputError);  // no location: an input error
}

TEST_CASE("memory budget: a film beyond memory stops at the film's line before any allocation", "[memory]") {
    // 2e9 x 8 pixels with three AOVs: hundreds of gigabytes; the check comes before the tiles.
    int line = 0;
    std::string error = render_error("budget-film", film_scene("2000000000", "8"), {"albedo", "normal", "depth"}, &line);
    INFO(error);
    CHECK(line == 4);  // the <film> element
    // The estimate's exact size follows the per-pixel statistics' layout; terabytes it must be.
    CHECK_THAT(error,
               Catch::Contains("film 2000000000 x 8 with 3 AOVs needs ") && Catch::Contains(" TB; ") && Catch::Contains(" available"));
    // The rasterizer's per-sample buffers are checked likewise.
    error = render_error("budget-raster", film_scene("2000000000", "8", "raster"), {}, &line);
    INFO(error);
    CHECK(line == 4);
    CHECK_THAT(error, Catch::Contains("film 2000000000 x 8 rasterized with 1 sample per pixel needs "));
    // Under a cap, a film that fits the machine but not the cap stops too, and a small one renders.
    MemoryLimitScope cap(resident_memory() + (32ull << 20));
    error = render_error("budget-cap", film_scene("4000", "4000"), {"variance"});
    CHECK_THAT(error, Catch::Contains("film 4000 x 4000 with 1 AOV needs ") && Catch::Contains("under --max-memory"));
    CHECK(render_error("budget-small", film_scene("16", "16"), {"variance"}) == "");
}

TEST_CASE("memory budget: a PLY header that promises more than the file holds is refused before reading", "[memory][ply]") {
    auto dir = scratch_dir("budget-ply");
    const std::string header_end =
        "property float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    // Binary: three vertices and one face take 3 * 12 + 1 + 12 bytes; a billion vertices cannot fit.
    std::string body;
    for (float v : {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) body.append(reinterpret_cast<const char*>(&v), sizeof v);
    body += std::string("\x03\0\0\0\0\x01\0\0\0\x02\0\0\0", 13);
    write_binary(dir / "honest.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + header_end + body);
    write_binary(dir / "lying.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\n" + header_end + body);
    write_binary(dir / "lying_ascii.ply", "ply\nformat ascii 1.0\nelement vertex 100\n" + header_end + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    int line = 0;
    CHECK(load_error(dir, ply_scene("honest.ply")) == "");
    for (const char* file : {"lying.ply", "lying_ascii.ply"}) {
        INFO(file);
        std::string error = load_error(dir, ply_scene(file), &line);
        INFO(error);
        CHECK(line == 3);  // the filename's line
        CHECK_THAT(error, Catch::Contains("the header promises") && Catch::Contains("bytes after its header"));
    }
}

TEST_CASE("memory budget: a mesh beyond the budget stops at its filename's line", "[memory][ply]") {
    auto dir = scratch_dir("budget-mesh");
    // An honest binary PLY of 200,000 vertices (2.4 MB) and one face: its mesh needs about 13 MB.
    const int n = 200000;
    std::string bytes =
        "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) +
        "\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (int i = 0; i < n; ++i) {
        float p[3] = {float(i % 3 == 1), float(i % 3 == 2), 0.0f};
        bytes.append(reinterpret_cast<const char*>(p), sizeof p);
    }
    bytes += std::string("\x03\0\0\0\0\x01\0\0\0\x02\0\0\0", 13);
    write_binary(dir / "big.ply", bytes);
    CHECK(load_error(dir, ply_scene("big.ply")) == "");
    MemoryLimitScope cap(resident_memory() + (4ull << 20));
    int line = 0;
    std::string error = load_error(dir, ply_scene("big.ply"), &line);
    INFO(error);
    CHECK(line == 3);
    CHECK_THAT(error, Catch::Contains("mesh of 200000 vertices and 1 triangles needs") && Catch::Contains("under --max-memory"));
}
