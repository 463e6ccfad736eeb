// Resource limits on the command line: a film too large for the machine stops at once, at the
// film's line, with exit code 2 and without allocating it; --max-memory caps every buffer, the
// photon maps of sppm and photonmapper included.

#include "core/image.h"
#include "integrators/photons.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <regex>
#include <tuple>

using namespace candela;
using namespace candela::test;

namespace {

std::string film_scene(int width, int height) {
    return scene_xml("<sensor type=\"perspective\">\n<film type=\"hdrfilm\">\n<integer name=\"width\" value=\"" + std::to_string(width) +
                     "\"/><integer name=\"height\" value=\"" + std::to_string(height) +
                     "\"/>\n</film>\n</sensor>\n<shape type=\"sphere\"/>");
}

// A shell prefix that limits the command's memory to 3 GB: its address space (ulimit -v), or in
// the AddressSanitizer build, whose shadow memory alone reserves terabytes of address space, its
// resident set and any single allocation (ASan's own limits; the build's other options stay).
std::string memory_limit_3gb() {
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
    return "ASAN_OPTIONS=hard_rss_limit_mb=3000:max_allocation_size_mb=3000 ";
#endif
#endif
    return "ulimit -v 3000000; ";
}

std::string render_cmd(const std::filesystem::path& scene, const std::filesystem::path& out, const std::string& extra) {
    return "'" + candela_binary() + "' render '" + scene.string() + "' -o '" + out.string() + "' --spp 1 --threads 1 " + extra;
}

// A sphere over a floor under a constant sky, seen by a 16 x 16 camera, rendered by `integrator`
// (on the file's line 6): light paths from the sky that reach the floor by the sphere store
// photons there for both photon integrators.
std::string photon_scene(const std::string& integrator) {
    return scene_xml(
        "<sensor type=\"perspective\"><transform name=\"to_world\"><lookat origin=\"0, 2, 6\" target=\"0, 0, 0\" up=\"0, 1, 0\"/></transform>\n"
        "<film type=\"hdrfilm\"><integer name=\"width\" value=\"16\"/><integer name=\"height\" value=\"16\"/></film></sensor>\n"
        "<emitter type=\"constant\"/>\n<shape type=\"sphere\"/>\n" +
        integrator +
        "\n<shape type=\"rectangle\"><transform name=\"to_world\"><rotate x=\"1\" angle=\"-90\"/><scale value=\"4\"/>"
        "<translate y=\"-1\"/></transform></shape>");
}

}  // namespace

TEST_CASE("limits: a 2e9 x 8 film stops with exit code 2 at the film's line without allocating it", "[cli][memory]") {
    auto dir = scratch_dir("limits-film");
    write_text(dir / "huge.xml", film_scene(2000000000, 8));
    write_text(dir / "small.xml", film_scene(8, 8));
    // Under a 3 GB limit an attempt to allocate the film (tens of gigabytes, in millions of tiles)
    // would end in "out of memory" instead of the budget's message; the small film shows that the
    // limit leaves room for an ordinary render.
    const std::string limit = memory_limit_3gb();
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

TEST_CASE("limits: photon maps beyond --max-memory stop sppm and photonmapper at the integrator's line",
          "[cli][memory][sppm][photonmapper]") {
    auto dir = scratch_dir("limits-photons");
    // 2e9 light paths per pass (sppm) or 2e9 stored photons (photonmapper) need tens of gigabytes
    // at over 50 bytes per photon; the same scenes with 20000 fit well within 512 MB.
    const std::string sppm = "<integrator type=\"sppm\"><integer name=\"photon_count\" value=\"";
    const std::string photonmapper =
        "<integrator type=\"photonmapper\"><integer name=\"glossy_samples\" value=\"2\"/><integer name=\"global_photons\" value=\"";
    const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
        {"sppm", sppm, "sppm with 2000000000 light paths per pass ("},
        {"photonmapper", photonmapper, "photonmapper's maps of 2000000000 global and 0 caustic photons needs "}};
    for (const auto& [name, integrator, message] : cases) {
        INFO(name);
        write_text(dir / (name + "-huge.xml"), photon_scene(integrator + "2000000000\"/></integrator>"));
        write_text(dir / (name + "-small.xml"), photon_scene(integrator + "20000\"/></integrator>"));
        int code = run_command(render_cmd(dir / (name + "-huge.xml"), dir / (name + "-huge.exr"), "--max-memory 512M"),
                               dir / (name + "-huge.txt"));
        std::string log = read_text(dir / (name + "-huge.txt"));
        INFO(log);
        CHECK(code == 2);
        CHECK_THAT(log, Catch::Contains(name + "-huge.xml:6: " + message) && Catch::Contains("under --max-memory 512 MB"));
        CHECK_FALSE(std::filesystem::exists(dir / (name + "-huge.exr")));
        CHECK(run_command(render_cmd(dir / (name + "-small.xml"), dir / (name + "-small.exr"), "--max-memory 512M"),
                          dir / (name + "-small.txt")) == 0);
    }
}

TEST_CASE("limits: photonmapper's budget counts the spectral variant's binned irradiance points", "[cli][memory][photonmapper][spectral]") {
    // The same 2e9 global photons in both variants: the spectral maps add a histogram of
    // SpectralBins floats to each of the 5e8 irradiance points (photons keep their size).
    auto dir = scratch_dir("limits-photons-spectral");
    write_text(dir / "huge.xml",
               photon_scene("<integrator type=\"photonmapper\"><integer name=\"global_photons\" value=\"2000000000\"/></integrator>"));
    auto needed_gb = [&](const std::string& variant) {
        run_command(render_cmd(dir / "huge.xml", dir / "huge.exr", "--max-memory 512M --variant " + variant), dir / (variant + ".txt"));
        const std::string log = read_text(dir / (variant + ".txt"));
        INFO(log);
        std::smatch m;
        REQUIRE(std::regex_search(log, m, std::regex("photonmapper's maps of 2000000000 global and 0 caustic photons needs ([0-9]+) GB")));
        return std::stod(m[1]);
    };
    const double rgb = needed_gb("scalar_rgb"), spectral = needed_gb("scalar_spectral");
    const double bins_gb = 5e8 * SpectralBins * sizeof(float) / double(1u << 30);
    INFO("scalar_rgb " << rgb << " GB, scalar_spectral " << spectral << " GB, bins " << bins_gb << " GB");
    CHECK(std::abs(spectral - rgb - bins_gb) <= 1.0);  // each figure is rounded to the gigabyte
}
