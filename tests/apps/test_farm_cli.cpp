// The farm on the command line: render --samples/--crop write parts, merge refuses bad sets with
// exit code 2 and prints the command that renders what is missing, farm plan's commands run by a
// plain shell loop give the single render, farm status follows them, farm slurm writes scripts.
// (A real Slurm runs the farm in tests/farm/slurm_farm.sh.)

#include "core/image.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <csignal>
#include <fstream>
#include <sstream>

using namespace candela;
using namespace candela::test;

namespace {

const std::string Cbox = source_path("scenes/cbox.xml");

std::string program(const std::string& args) { return "'" + candela_binary() + "' " + args; }
std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }
// A small Cornell box render: the options every command of one render shares.
const std::string Render = "'" + Cbox + "' -D res=20 --spp 8 --seed 3 --aov variance,albedo";

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) out.push_back(line);
    return out;
}

// The per-pixel check of `candela compare`, which the Slurm test also uses.
bool same_render(const std::filesystem::path& a, const std::filesystem::path& b, const std::filesystem::path& log) {
    return run_command(program("compare " + q(a) + " " + q(b) + " --pixel-tolerance 1e-5"), log) == 0;
}

}  // namespace

TEST_CASE("farm cli: parts merge into the render, merge names what is missing and how to render it", "[farm][cli]") {
    auto dir = scratch_dir("farm-cli-merge");
    REQUIRE(run_command(program("render " + Render + " -q -o " + q(dir / "single.exr")), dir / "log.txt") == 0);
    REQUIRE(run_command(program("render " + Render + " -q --samples 0:3 -o " + q(dir / "adaptive.exr")), dir / "log.txt") == 0);
    REQUIRE(run_command(program("render " + Render + " -q --samples 5:8 --crop 0,0,20,9 -o " + q(dir / "b.exr")), dir / "log.txt") == 0);
    REQUIRE(run_command(program("render " + Render + " -q --samples 5:8 --crop 0,9,20,11 -o " + q(dir / "c.exr")), dir / "log.txt") == 0);
    Image part = read_image((dir / "b.exr").string());
    CHECK(part.width() == 20);
    CHECK(part.height() == 9);
    CHECK(part.metadata["candela.coverage"] == "0,0,20,9@5:8");
    CHECK(part.metadata["candela.seed"] == "3");
    CHECK(part.metadata["candela.sampler"] == "independent");
    CHECK(part.metadata["candela.sceneHash"].size() == 16);
    CHECK(part.metadata.count("candela.renderTime") == 1);

    // Samples 3:5 are missing: refused, with the command that renders them.
    const std::string merge =
        "merge " + q(dir / "adaptive.exr") + " " + q(dir / "b.exr") + " " + q(dir / "c.exr") + " -o " + q(dir / "merged.exr");
    CHECK(run_command(program(merge), dir / "missing.txt") == 2);
    CHECK_FALSE(std::filesystem::exists(dir / "merged.exr"));
    std::string log = read_text(dir / "missing.txt");
    INFO(log);
    CHECK_THAT(log, Catch::Contains("missing samples 3:5"));
    std::string command;
    for (const std::string& line : lines(log))
        if (line.find("--samples") != std::string::npos) command = line;
    REQUIRE_THAT(command, Catch::Contains("--samples 3:5"));
    // That command, as printed, completes the render.
    REQUIRE(run_command(command + " -q", dir / "rerender.txt") == 0);
    const std::string rerendered = (dir / "part-3-5.exr").string();
    REQUIRE(std::filesystem::exists(rerendered));
    REQUIRE(run_command(program(merge + " '" + rerendered + "'"), dir / "merge.txt") == 0);
    CHECK(same_render(dir / "merged.exr", dir / "single.exr", dir / "compare.txt"));
    Image merged = read_image((dir / "merged.exr").string());
    CHECK(merged.channels() == read_image((dir / "single.exr").string()).channels());
    CHECK(merged.metadata["candela.partial"] == "false");
    CHECK(merged.metadata["candela.spp"] == "8");

    // --allow-partial writes what there is, marked partial.
    REQUIRE(run_command(program("merge " + q(dir / "adaptive.exr") + " -o " + q(dir / "partial.exr") + " --allow-partial"),
                        dir / "partial.txt") == 0);
    CHECK(read_image((dir / "partial.exr").string()).metadata["candela.partial"] == "true");
}

TEST_CASE("farm cli: merge refuses overlapping and foreign parts and non-parts with exit code 2", "[farm][cli][errors]") {
    auto dir = scratch_dir("farm-cli-refuse");
    auto part = [&](const std::string& name, const std::string& options) {
        REQUIRE(run_command(program("render " + options + " -q -o " + q(dir / name)), dir / "log.txt") == 0);
        return q(dir / name);
    };
    const std::string a = part("a.exr", Render + " --samples 0:4"), b = part("b.exr", Render + " --samples 4:8");
    const std::string overlapping = part("o.exr", Render + " --samples 2:6");
    const std::string seed = part("seed.exr", "'" + Cbox + "' -D res=20 --spp 8 --seed 4 --aov variance,albedo --samples 4:8");
    const std::string scene = part("scene.exr", "'" + Cbox + "' -D res=20 -D spp=2 --spp 8 --seed 3 --aov variance,albedo --samples 4:8");
    const std::string aovs = part("aovs.exr", "'" + Cbox + "' -D res=20 --spp 8 --seed 3 --samples 4:8");
    const std::string spectral = part("spectral.exr", Render + " --samples 4:8 --variant scalar_spectral");
    REQUIRE(run_command(program("render " + Render + " -q -o " + q(dir / "whole.exr")), dir / "log.txt") == 0);
    struct Case {
        std::string parts, message;
    };
    const Case cases[] = {{a + " " + b + " " + overlapping, "overlap"},
                          {a + " " + seed, "seed 3 against 4"},
                          {a + " " + scene, "scene hash"},
                          {a + " " + aovs, "AOVs"},
                          {a + " " + spectral, "variant scalar_rgb against scalar_spectral"},
                          {a + " " + q(dir / "whole.exr"), "not a part"},
                          {a + " " + q(dir / "nothing.exr"), "nothing.exr"}};
    for (const Case& c : cases) {
        INFO(c.parts);
        CHECK(run_command(program("merge " + c.parts + " -o " + q(dir / "out.exr")), dir / "refused.txt") == 2);
        CHECK_THAT(read_text(dir / "refused.txt"), Catch::Contains(c.message));
        CHECK_FALSE(std::filesystem::exists(dir / "out.exr"));
    }
    // Parts need an integrator whose samples are independent; --png needs a whole image.
    CHECK(run_command(program("render '" + Cbox + "' -D res=8 --mode raster --samples 0:1 -o " + q(dir / "r.exr")), dir / "raster.txt") ==
          2);
    CHECK_THAT(read_text(dir / "raster.txt"), Catch::Contains("cannot render a part"));
    // Adaptive sampling takes a pixel's next samples by its earlier ones and its neighbours'; a
    // progressive photon map's passes depend on all earlier passes: neither splits.
    CHECK(run_command(program("render " + Render + " --adaptive-threshold 0.05 --samples 0:4 -o " + q(dir / "adaptive.exr")),
                      dir / "adaptive.txt") == 2);
    CHECK_THAT(read_text(dir / "adaptive.txt"), Catch::Contains("adaptive sampling (--adaptive-threshold) cannot render a part"));
    CHECK(run_command(program("render " + Render + " --adaptive-threshold 0.05 --resume " + q(dir / "adaptive.exr") + " -o " +
                              q(dir / "adaptive.exr")),
                      dir / "adaptive-resume.txt") == 2);
    CHECK_THAT(read_text(dir / "adaptive-resume.txt"), Catch::Contains("cannot render a part (--samples, --crop), resume or checkpoint"));
    const std::string sppm_scene = (dir / "sppm.xml").string();
    std::string sppm = read_text(Cbox);
    const size_t at = sppm.find("<integrator type=\"path\">");
    REQUIRE(at != std::string::npos);
    sppm.replace(at, std::string("<integrator type=\"path\">").size(), "<integrator type=\"sppm\">");
    write_text(sppm_scene, sppm);
    CHECK(run_command(program("render " + q(sppm_scene) + " -D res=8 --spp 2 --samples 0:1 -o " + q(dir / "sppm.exr")), dir / "sppm.txt") ==
          2);
    CHECK_THAT(read_text(dir / "sppm.txt"),
               Catch::Contains("the sppm integrator cannot render a part") && Catch::Contains("photons of all earlier passes"));
    CHECK_FALSE(std::filesystem::exists(dir / "adaptive.exr"));
    CHECK_FALSE(std::filesystem::exists(dir / "sppm.exr"));
    CHECK(run_command(program("render " + Render + " --samples 0:1 --png -o " + q(dir / "p.exr")), dir / "png.txt") == 2);
    CHECK(run_command(program("render " + Render + " --samples 0:9 -o " + q(dir / "p.exr")), dir / "range.txt") == 2);
    CHECK_THAT(read_text(dir / "range.txt"), Catch::Contains("--samples 0:9 reaches past --spp 8"));
    CHECK(run_command(program("render " + Render + " --crop 15,0,10,5 -o " + q(dir / "p.exr")), dir / "crop.txt") == 2);
    CHECK_THAT(read_text(dir / "crop.txt"), Catch::Contains("not inside the 20 x 20 image"));
    CHECK_FALSE(std::filesystem::exists(dir / "p.exr"));
}

// Waits (in the shell) until process $pid has installed a handler for signal number N (SigCgt in
// /proc/PID/status): a background job of a non-interactive shell starts with SIGINT ignored, and a
// signal sent before the handler is installed would be lost or kill the render outright.
std::string wait_for_handler(int signal) {
    return " for i in $(seq 600); do mask=$(awk '/^SigCgt/ {print $2}' /proc/$pid/status 2>/dev/null);"
           " [ -n \"$mask\" ] && [ $(( 0x$mask >> " +
           std::to_string(signal - 1) + " & 1 )) -ne 0 ] && break; sleep 0.05; done;";
}

// The resumable render: samples are deterministic per (seed, pixel, index), so an interrupted
// render continued with --resume adds exactly the samples the uninterrupted one takes; only the
// float32 sums of the partial file and the grouping of additions differ (relative 1e-7 per
// addition; bound 1e-5 as for merges). Where the interruption lands is up to the scheduler, which
// the check does not depend on: any coverage must resume to the same image.
TEST_CASE("farm cli: SIGTERM writes a resumable partial render, --resume gives the uninterrupted image, a checkpoint survives kill -9",
          "[farm][cli][interrupt]") {
    auto dir = scratch_dir("farm-cli-resume");
    // Long enough to be interrupted half a second in: about 1.2 s in a Release build; the
    // sanitizer builds, several times slower, take a quarter of the samples (2 s under ASan).
    const int spp = effort_scaled(1024, 256);
    const std::string options = "'" + Cbox + "' -D res=32 --spp " + std::to_string(spp) + " --seed 9 --aov variance,albedo --threads 1";
    REQUIRE(run_command(program("render " + options + " -q -o " + q(dir / "reference.exr")), dir / "log.txt") == 0);

    // SIGTERM half a second into the render: exit code 128 + 15, a part marked partial.
    const auto part = dir / "term.exr";
    std::string cmd = program("render " + options + " -o " + q(part)) + " & pid=$!;" + wait_for_handler(SIGTERM) +
                      " sleep 0.5; kill -TERM $pid; wait $pid";
    int code = run_command(cmd, dir / "term.txt");
    std::string log = read_text(dir / "term.txt");
    INFO(log);
    REQUIRE(code == 143);
    CHECK_THAT(log, Catch::Contains("interrupted") && Catch::Contains("--resume"));
    Image partial = read_image(part.string());
    CHECK(partial.metadata["candela.partial"] == "true");
    CHECK(partial.metadata.count("candela.partFormat") == 1);
    CHECK(std::stoll(partial.metadata["candela.samples"]) < spp * 32LL * 32);
    // The same command with --resume completes it.
    REQUIRE(run_command(program("render " + options + " -q --resume " + q(part) + " -o " + q(dir / "resumed.exr")), dir / "resume.txt") ==
            0);
    Image resumed = read_image((dir / "resumed.exr").string());
    CHECK(resumed.metadata["candela.partial"] == "false");
    CHECK(resumed.metadata.count("candela.partFormat") == 0);
    CHECK(same_render(dir / "resumed.exr", dir / "reference.exr", dir / "compare.txt"));
    INFO(read_text(dir / "compare.txt"));
    // A part of another render is refused.
    CHECK(run_command(program("render '" + Cbox + "' -D res=32 --spp " + std::to_string(spp) +
                              " --seed 10 --aov variance,albedo -q --resume " + q(part) + " -o " + q(dir / "x.exr")),
                      dir / "foreign.txt") == 2);
    CHECK_THAT(read_text(dir / "foreign.txt"), Catch::Contains("belongs to another render") && Catch::Contains("seed"));

    // kill -9 while a checkpoint is being written: stopped (SIGSTOP) once its temporary exists,
    // and only killed when the temporary is still there, i.e. the write has not been renamed into
    // place; else it continues and the next checkpoint is tried. The previous checkpoint stays
    // whole and resumes to the uninterrupted image.
    const auto ck = dir / "ck.exr";
    cmd = program("render " + options + " -q --checkpoint 0.0002 -o " + q(ck)) + " & pid=$!; tmp=" + q(dir) +
          "/.ck.tmp$pid.exr; killed=no;"
          " for i in $(seq 200000); do"
          "   if [ -e \"$tmp\" ] && [ -e " +
          q(ck) +
          " ]; then kill -STOP $pid;"
          "     if [ -e \"$tmp\" ]; then kill -KILL $pid; killed=yes; break; fi; kill -CONT $pid; fi;"
          "   kill -0 $pid 2>/dev/null || break; done;"
          " wait $pid; echo \"killed mid-write: $killed\"; ls -A " +
          q(dir);
    run_command(cmd, dir / "kill.txt");
    log = read_text(dir / "kill.txt");
    INFO(log);
    REQUIRE_THAT(log, Catch::Contains("killed mid-write: yes"));
    Image checkpoint = read_image(ck.string());
    CHECK(checkpoint.metadata["candela.partial"] == "true");
    REQUIRE(run_command(program("render " + options + " -q --resume " + q(ck) + " -o " + q(dir / "ck-resumed.exr")),
                        dir / "ck-resume.txt") == 0);
    CHECK(same_render(dir / "ck-resumed.exr", dir / "reference.exr", dir / "ck-compare.txt"));
    INFO(read_text(dir / "ck-compare.txt"));
}

TEST_CASE("farm cli: plan's commands run by a shell loop give the render, status follows the parts", "[farm][cli]") {
    auto dir = scratch_dir("farm-cli-plan");
    // -a is passed on, absolute, so that a part run anywhere finds the scene's files.
    const std::string options = "'" + Cbox + "' -D res=20 --spp 7 --seed 5 --aov variance -a " + q(dir);
    REQUIRE(run_command(program("render " + options + " -q -o " + q(dir / "single.exr")), dir / "log.txt") == 0);
    // stdout holds the commands, one per line, for a script; stderr says where the plan went.
    REQUIRE(
        run_command(program("farm plan " + options + " --parts 3 --regions 2x1 -o " + q(dir / "out.exr")) + " 2>" + q(dir / "notes.txt"),
                    dir / "plan.txt") == 0);
    CHECK_THAT(read_text(dir / "notes.txt"), Catch::Contains("wrote the plan " + (dir / "out-farm" / "plan.txt").string() + " (6 parts"));
    std::vector<std::string> commands = lines(read_text(dir / "plan.txt"));
    INFO(read_text(dir / "plan.txt"));
    REQUIRE(commands.size() == 3 * 2 + 1);
    CHECK_THAT(commands[0], Catch::Contains("--samples 0:2") && Catch::Contains("--crop 0,0,10,20"));
    CHECK_THAT(commands[5], Catch::Contains("--samples 4:7") && Catch::Contains("--crop 10,0,10,20"));
    CHECK_THAT(commands[6], Catch::Contains(" merge "));
    CHECK_THAT(commands[0], Catch::Contains(" -a ") && Catch::Contains(dir.string()));
    const auto workdir = dir / "out-farm";

    REQUIRE(run_command(program("farm status " + q(workdir)), dir / "status0.txt") == 0);
    CHECK_THAT(read_text(dir / "status0.txt"), Catch::Contains("0 of 6 parts done") && Catch::Contains("missing: tasks 0-5"));
    // Four of six parts, in a plain loop.
    for (int i : {0, 1, 3, 4}) REQUIRE(run_command(commands[i], dir / "task.txt") == 0);
    REQUIRE(run_command(program("farm status " + q(workdir)), dir / "status4.txt") == 0);
    std::string status = read_text(dir / "status4.txt");
    INFO(status);
    CHECK_THAT(status, Catch::Contains("4 of 6 parts done") && Catch::Contains("missing: tasks 2,5") && Catch::Contains("time left"));
    CHECK_THAT(status, Catch::Contains("task 2 (samples 4:7 of pixels 0,0,10,20)"));
    CHECK(run_command(commands[6], dir / "merge-early.txt") == 2);
    for (int i : {2, 5}) REQUIRE(run_command(commands[i], dir / "task.txt") == 0);
    REQUIRE(run_command(program("farm status " + q(workdir)), dir / "status6.txt") == 0);
    CHECK_THAT(read_text(dir / "status6.txt"), Catch::Contains("6 of 6 parts done") && Catch::Contains("complete"));
    REQUIRE(run_command(commands[6], dir / "merge.txt") == 0);
    CHECK(same_render(dir / "out.exr", dir / "single.exr", dir / "compare.txt"));
    CHECK_THAT(read_text(dir / "compare.txt"), Catch::Contains("agree                yes"));
}

TEST_CASE("farm cli: farm slurm writes a job array and a merge job without submitting", "[farm][cli]") {
    auto dir = scratch_dir("farm-cli-slurm");
    REQUIRE(run_command(program("farm slurm '" + Cbox +
                                "' -D res=16 --parts 4 --spp 8 --partition gpu --time 1:00:00 --mem 2G "
                                "--threads-per-task 2 --workdir " +
                                q(dir / "work") + " -o " + q(dir / "out.exr")),
                        dir / "log.txt") == 0);
    std::string render = read_text(dir / "work" / "render.sbatch"), merge = read_text(dir / "work" / "merge.sbatch");
    CHECK_THAT(render, Catch::Contains("#SBATCH --array=0-3") && Catch::Contains("#SBATCH --cpus-per-task=2") &&
                           Catch::Contains("#SBATCH --partition=gpu") && Catch::Contains("#SBATCH --time=1:00:00") &&
                           Catch::Contains("#SBATCH --mem=2G") && Catch::Contains("--samples 6:8") && Catch::Contains("--threads 2"));
    CHECK_THAT(merge, Catch::Contains("#SBATCH --kill-on-invalid-dep=yes") && Catch::Contains(" merge "));
    CHECK_THAT(read_text(dir / "log.txt"), Catch::Contains("--dependency=afterok:"));
    CHECK(run_command("bash -n " + q(dir / "work" / "render.sbatch") + " && bash -n " + q(dir / "work" / "merge.sbatch"),
                      dir / "syntax.txt") == 0);
    // Task 1 of the array, run as Slurm would run it.
    REQUIRE(run_command("SLURM_ARRAY_TASK_ID=1 bash " + q(dir / "work" / "render.sbatch"), dir / "task.txt") == 0);
    CHECK(read_image((dir / "work" / "parts" / "part-00001.exr").string()).metadata["candela.coverage"] == "0,0,16,16@2:4");
    CHECK(run_command("SLURM_ARRAY_TASK_ID=9 bash " + q(dir / "work" / "render.sbatch"), dir / "task.txt") == 2);
    // More parts than samples: refused.
    CHECK(run_command(program("farm plan '" + Cbox + "' -D res=16 --parts 9 --spp 8 -o " + q(dir / "x.exr")), dir / "bad.txt") == 2);
    CHECK_THAT(read_text(dir / "bad.txt"), Catch::Contains("--parts 9 exceeds"));
}
