// Ctrl-C and SIGTERM through the command line (core/stop.h): every family of integrators stops
// within 2 seconds of the signal with exit code 128 + signal, whatever it is doing (a pixel loop,
// light-path passes, photon maps, a radiosity solve, a bake, a scene still loading), leaves no
// temporary file behind, and what it writes is a partial render. Before issue 28 an sppm render
// with a 9-sample stratified sampler ignored SIGTERM forever (its camera pass never ended).

#include "core/image.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <csignal>
#include <fstream>
#include <regex>

using namespace candela;
using namespace candela::test;

namespace {

std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

// Shell: waits until $pid handles `signal` (SigCgt in /proc/PID/status), then `delay` seconds,
// sends it, and prints "rc=<exit code> ms=<milliseconds from the signal to the exit>".
std::string signal_after_start(const std::string& command, int signal, double delay, int count = 1) {
    std::string kill;
    for (int i = 0; i < count; ++i) kill += " kill -" + std::to_string(signal) + " $pid 2>/dev/null; sleep 0.05;";
    char delay_text[32];
    std::snprintf(delay_text, sizeof delay_text, "%.2f", delay);
    return command +
           " & pid=$!; for i in $(seq 600); do mask=$(awk '/^SigCgt/ {print $2}' /proc/$pid/status 2>/dev/null);"
           " [ -n \"$mask\" ] && [ $(( 0x$mask >> " +
           std::to_string(signal - 1) + " & 1 )) -ne 0 ] && break; sleep 0.02; done; sleep " + delay_text + "; t0=$(date +%s%N);" + kill +
           " wait $pid; rc=$?; t1=$(date +%s%N); echo \"rc=$rc ms=$(( (t1 - t0) / 1000000 ))\"";
}

struct Stopped {
    int code = -1;
    long milliseconds = -1;
};

Stopped parse_stopped(const std::string& log) {
    std::smatch m;
    Stopped s;
    if (std::regex_search(log, m, std::regex(R"(rc=(\d+) ms=(\d+))"))) {
        s.code = std::stoi(m[1]);
        s.milliseconds = std::stol(m[2]);
    }
    return s;
}

// The validation Cornell box with `integrator` in place of its path tracer.
std::string scene_with(const std::filesystem::path& dir, const std::string& name, const std::string& integrator) {
    std::string xml = read_text(source_path("scenes/validation/cbox.xml"));
    xml = std::regex_replace(xml, std::regex(R"(<integrator type="path">[\s\S]*?</integrator>)"), integrator);
    REQUIRE(xml.find(integrator) != std::string::npos);
    const auto path = dir / (name + ".xml");
    write_text(path, xml);
    return path.string();
}

bool temporaries_left(const std::filesystem::path& dir) {
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        if (entry.path().filename().string().find(".tmp") != std::string::npos) return true;
    return false;
}

struct Family {
    std::string name, integrator, options;
};

}  // namespace

TEST_CASE("cli: SIGTERM and Ctrl-C stop every integrator family within 2 seconds with 143 or 130", "[cli][interrupt]") {
    const auto dir = scratch_dir("stop-signals");
    // Each far too long to finish: the signal lands in its main loop.
    const std::vector<Family> families = {
        {"path", R"(<integrator type="path"/>)", "--spp 1000000"},
        {"volpath", R"(<integrator type="volpath"/>)", "--spp 1000000"},
        {"direct", R"(<integrator type="direct"/>)", "--spp 1000000"},
        {"ao", R"(<integrator type="ao"/>)", "--spp 10000000"},
        {"ptracer", R"(<integrator type="ptracer"/>)", "--spp 1000000"},
        // The issue's render: 9 stratified samples (the scene's independent sampler replaced).
        {"sppm", R"(<integrator type="sppm"><integer name="photon_count" value="20000"/></integrator>)",
         "--spp 1000000 --sampler stratified"},
        {"photonmapper", R"(<integrator type="photonmapper"><integer name="global_photons" value="200000"/></integrator>)",
         "--spp 1000000"},
        {"radiosity",
         R"(<integrator type="radiosity"><integer name="subdivisions" value="24"/><float name="tolerance" value="1e-9"/>
            <integer name="max_iterations" value="100000000"/></integrator>)",
         "--spp 4"},
        {"raster bake", R"(<integrator type="raster"><string name="lighting" value="baked"/><string name="bake" value="path"/>
            <integer name="bake_samples" value="100000000"/></integrator>)",
         ""},
    };
    for (const Family& f : families) {
        for (int signal : {SIGTERM, SIGINT}) {
            INFO(f.name << (signal == SIGTERM ? ", SIGTERM" : ", SIGINT"));
            const std::string scene = scene_with(dir, "scene", f.integrator);
            const auto out = dir / "out.exr";
            std::filesystem::remove(out);
            const std::string render = "'" + candela_binary() + "' render " + q(scene) + " -D res=64 " + f.options + " -q -o " + q(out);
            run_command(signal_after_start(render, signal, 0.7), dir / "log.txt");
            const std::string log = read_text(dir / "log.txt");
            INFO(log);
            const Stopped s = parse_stopped(log);
            CHECK(s.code == 128 + signal);
            CHECK(s.milliseconds >= 0);
            CHECK(s.milliseconds <= 2000);
            CHECK_FALSE(temporaries_left(dir));
            // What was written is marked partial (a whole image would be a lie).
            if (std::filesystem::exists(out)) CHECK(read_image(out.string()).metadata["candela.partial"] == "true");
        }
    }
}

TEST_CASE("cli: a second SIGTERM ends a render at once, and other commands stop at the first with 143", "[cli][interrupt]") {
    const auto dir = scratch_dir("stop-twice");
    const std::string scene = scene_with(dir, "scene", R"(<integrator type="path"/>)");
    const std::string render = "'" + candela_binary() + "' render " + q(scene) + " -D res=64 --spp 1000000 -q -o " + q(dir / "out.exr");
    run_command(signal_after_start(render, SIGTERM, 0.5, 2), dir / "log.txt");
    Stopped s = parse_stopped(read_text(dir / "log.txt"));
    CHECK(s.code == 143);
    CHECK(s.milliseconds <= 2000);
    CHECK_FALSE(temporaries_left(dir));

    // compare-modes promises no partial output: the first signal ends it.
    const std::string compare =
        "'" + candela_binary() + "' compare-modes " + q(scene) + " -D res=64 --reference-spp 1000000 -o " + q(dir / "modes.png");
    run_command(signal_after_start(compare, SIGTERM, 0.5), dir / "compare.txt");
    const std::string log = read_text(dir / "compare.txt");
    INFO(log);
    s = parse_stopped(log);
    CHECK(s.code == 143);
    CHECK(s.milliseconds <= 2000);
}

TEST_CASE("cli: SIGTERM as soon as a render starts, while its large mesh loads, ends it within 2 seconds", "[cli][interrupt]") {
    // A 2-million-triangle binary PLY: loading it and building its BVH poll no stop flag; the
    // watchdog (core/stop.h) ends the process StopDeadlineSeconds after the signal if the render
    // loop has not (in a fast build the load may end first, and the render loop stops instead).
    const auto dir = scratch_dir("stop-loading");
    const int n = 1000;  // n x n quads, 2 n^2 triangles
    {
        std::ofstream ply(dir / "grid.ply", std::ios::binary);
        ply << "ply\nformat binary_little_endian 1.0\nelement vertex " << (n + 1) * (n + 1) << "\nproperty float x\nproperty float y\n"
            << "property float z\nelement face " << 2 * n * n << "\nproperty list uchar int vertex_indices\nend_header\n";
        for (int y = 0; y <= n; ++y)
            for (int x = 0; x <= n; ++x) {
                const float v[3] = {float(x) / n - 0.5f, float(y) / n - 0.5f, 0.01f * float((x * 7 + y * 13) % 5)};
                ply.write(reinterpret_cast<const char*>(v), sizeof v);
            }
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const int a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
                const int triangles[2][3] = {{a, b, d}, {a, d, c}};
                for (const auto& tri : triangles) {
                    const unsigned char three = 3;
                    ply.write(reinterpret_cast<const char*>(&three), 1);
                    ply.write(reinterpret_cast<const char*>(tri), sizeof tri);
                }
            }
    }
    const std::string scene = scene_with(dir, "mesh", R"(<integrator type="path"/>
        <shape type="ply"><string name="filename" value="grid.ply"/><bsdf type="diffuse"/></shape>)");
    const std::string render = "'" + candela_binary() + "' render " + q(scene) + " -D res=64 --spp 1000000 -q -o " + q(dir / "out.exr");
    run_command(signal_after_start(render, SIGTERM, 0.0), dir / "log.txt");
    const std::string log = read_text(dir / "log.txt");
    INFO(log);
    const Stopped s = parse_stopped(log);
    CHECK(s.code == 143);
    CHECK(s.milliseconds <= 2000);
    CHECK_FALSE(temporaries_left(dir));
}
