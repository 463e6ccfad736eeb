// Resource limits on the command line: a film too large for the machine stops at once, at the
// film's line, with exit code 2 and without allocating it; --max-memory caps every buffer.

#include "core/image.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

std::string film_scene(int width, int height) {
    return scene_xml("<sensor type=\"perspective\">\n<film type=\"hdrfilm\">\n<integer name=\"width\" value=\"" + std::to_string(width) +
                     "\"/><integer name=\"height\" value=\"" + std::to_string(height) + "\"/>\n</film>\n</sensor>\n<shape type=\"sphere\"/>");
}

std::string render_cmd(const std::filesystem::path& scene, const std::filesystem::path& out, const std::string& extra) {
    return "'" + candela_binary() + "' render '" + scene.string() + "' -o '" + out.string() + "' --spp 1 --threads 1 " + extra;
}

}  // namespace

TEST_CASE("limits: a 2e9 x 8 film stops with exit code 2 at the film's line without allocating it", "[cli][memory]") {
    auto dir = scratch_dir("limits-film");
    write_text(dir / "huge.xml", film_scene(2000000000, 8));
    write_text(dir / "small.xml", film_scene(8, 8));
    // Under a 3 GB address-space limit an attempt to allocate the film (tens of gigabytes, in
    // millions of tiles) would end in "out of memory" instead of the budget's message; the small
    // film shows that the limit leaves room for an ordinary render.
    const std::string limit = "ulimit -v 3000000; ";
    REQUIRE(run_command(limit + render_cmd(dir / "small.xml", dir / "small.exr", "--aov albedo,normal,depth"), dir / "small.txt") == 0);
    int code = run_command(limit + render_cmd(dir / "huge.xml", dir / "huge.exr", "--aov albedo,normal,depth"), dir / "huge.txt");
    std::string log = read_text(dir / "huge.txt");
    INFO(log);
    CHECK(code == 2);
    CHECK_THAT(log, Catch::Contains("huge.xml:3: film 2000000000 x 8 with 3 AOVs needs ") && Catch::Contains(" GB available"));
    CHECK_THAT(log, !Catch::Contains("out of memory"));
    CHECK_FALSE(std::filesystem::exists(dir / "huge.exr"));
}

TEST_CASE("limits: --max-memory caps the film, and a bad size is an input error", "[cli][memory]") {
    auto dir = scratch_dir("limits-max-memory");
    write_text(dir / "large.xml", film_scene(4000, 4000));
    write_text(dir / "small.xml", film_scene(16, 16));
    // 16 million pixels need over a gigabyte of tiles and sums: far beyond 512 MB, which the
    // 16 x 16 render keeps well within.
    int code = run_command(render_cmd(dir / "large.xml", dir / "large.exr", "--max-memory 512M"), dir / "large.txt");
    std::string log = read_text(dir / "large.txt");
    INFO(log);
    CHECK(code == 2);
    CHECK_THAT(log, Catch::Contains("large.xml:3: film 4000 x 4000 needs ") && Catch::Contains("under --max-memory 512 MB"));
    CHECK_FALSE(std::filesystem::exists(dir / "large.exr"));
    CHECK(run_command(render_cmd(dir / "small.xml", dir / "small.exr", "--max-memory 512M"), dir / "small.txt") == 0);
    code = run_command(render_cmd(dir / "small.xml", dir / "bad.exr", "--max-memory 12Q"), dir / "bad.txt");
    CHECK(code == 2);
    CHECK_THAT(read_text(dir / "bad.txt"), Catch::Contains("--max-memory expects a size"));
}
