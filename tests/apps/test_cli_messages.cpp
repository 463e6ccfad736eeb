// The mistakes a newcomer makes on the command line, one row each: the exit code, the words the
// message must hold (the problem and a way forward) and, for every refusal, that nothing was
// written. Rows that succeed with a warning check the warning and the file they write.

#include "tests/util.h"

#include <catch2/catch.hpp>

#include <set>

using namespace candela;
using namespace candela::test;

namespace {

namespace fs = std::filesystem;

// The files under `dir`, by path relative to it.
std::set<std::string> files_in(const fs::path& dir) {
    std::set<std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) files.insert(fs::relative(entry.path(), dir).string());
    return files;
}

struct Mistake {
    std::string args;                   // after `candela`, run in the work folder
    int code;                           // expected exit code
    std::vector<std::string> message;   // each must appear in stdout + stderr
    std::vector<std::string> absent;    // none may appear
    std::vector<std::string> writes{};  // files it must create (all others must not appear)
};

// Runs every row in `work` (which holds the inputs: cbox.xml and what setup() rendered).
void check_rows(const fs::path& work, const fs::path& logs, const std::vector<Mistake>& rows) {
    int index = 0;
    for (const Mistake& m : rows) {
        const std::set<std::string> before = files_in(work);
        const fs::path log = logs / ("row" + std::to_string(index++) + ".txt");
        const int code = run_command("cd '" + work.string() + "' && '" + candela_binary() + "' " + m.args, log);
        const std::string text = read_text(log);
        INFO("candela " << m.args << "\n" << text);
        CHECK(code == m.code);
        for (const std::string& words : m.message) CHECK_THAT(text, Catch::Contains(words));
        for (const std::string& words : m.absent) CHECK_THAT(text, !Catch::Contains(words));
        std::set<std::string> made;
        for (const std::string& f : files_in(work))
            if (!before.count(f)) made.insert(f);
        CHECK(made == std::set<std::string>(m.writes.begin(), m.writes.end()));
        for (const std::string& f : made) fs::remove_all(work / f);
    }
}

// A folder with the Cornell box at 8 x 8 (spp 8 by default), its render and --png preview, and a
// part holding samples 0:8 of 16.
fs::path setup(const std::string& name, fs::path& logs) {
    const fs::path dir = scratch_dir(name);
    const fs::path work = dir / "work";
    logs = dir / "logs";
    fs::create_directories(work);
    fs::create_directories(logs);
    std::string xml = read_text(source_path("scenes/validation/cbox.xml"));
    xml.replace(xml.find("name=\"spp\" value=\"64\""), 21, "name=\"spp\" value=\"8\"");
    xml.replace(xml.find("name=\"res\" value=\"256\""), 22, "name=\"res\" value=\"8\"");
    write_text(work / "cbox.xml", xml);
    const std::string candela = "cd '" + work.string() + "' && '" + candela_binary() + "' ";
    REQUIRE(run_command(candela + "render cbox.xml -o first.exr --png -q", logs / "setup1.txt") == 0);
    REQUIRE(run_command(candela + "render cbox.xml --spp 16 --samples 0:8 -o part.exr -q", logs / "setup2.txt") == 0);
    fs::create_directories(work / "folder");
    return work;
}

}  // namespace

TEST_CASE("cli messages: bad numbers say what a value must be", "[cli][errors]") {
    fs::path logs;
    const fs::path work = setup("cli-messages-numbers", logs);
    const std::vector<Mistake> rows = {
        {"render cbox.xml --spp 0", 2, {"--spp must be a whole number of samples, at least 1 (got 0)"}, {"1797693"}},
        {"render cbox.xml --spp -5", 2, {"--spp must be a whole number of samples, at least 1 (got -5)"}, {}},
        {"render cbox.xml --spp abc", 2, {"--spp must be a whole number of samples, at least 1 (got abc)"}, {}},
        {"render cbox.xml --spp 4.5", 2, {"--spp must be a whole number of samples, at least 1 (got 4.5)"}, {"Could not convert"}},
        {"render cbox.xml --spp 99999999999", 2, {"--spp must be a whole number of samples, at most 1073741824 (got 99999999999)"}, {}},
        {"render cbox.xml --threads -1", 2, {"--threads must be a whole number of threads, at least 0 (got -1)"}, {}},
        {"render cbox.xml --seed -1", 2, {"--seed must be a whole number, at least 0 (got -1)"}, {}},
        {"render cbox.xml --checkpoint 0", 2, {"--checkpoint must be a number greater than 0 (got 0)"}, {}},
        {"compare first.exr first.exr --tolerance -1", 2, {"--tolerance must be a number, 0 or more (got -1)"}, {}},
        {"compare first.exr first.exr --heatmap-range nan", 2, {"--heatmap-range must be a number greater than 0 (got nan)"}, {}},
        {"farm plan cbox.xml -o farm.exr --parts 0", 2, {"--parts must be a whole number of parts, at least 1 (got 0)"}, {}},
        {"estimate irradiance cbox.xml --at 0,0,0 --normal 0,1,0 -n 0",
         2,
         {"-n must be a whole number of samples, at least 1 (got 0)"},
         {}},
        {"converge cbox.xml --alpha 2", 2, {"--alpha must be a significance level greater than 0 and at most 0.5 (got 2)"}, {}},
        {"view cbox.xml --port 70000", 2, {"--port must be a whole number, at most 65535 (got 70000)"}, {}},
        {"validate folder --reference-spp 0", 2, {"--reference-spp must be a whole number of samples, at least 1 (got 0)"}, {}},
        {"render cbox.xml --mode rastr", 2, {"--mode must be one of path, raster (got rastr); did you mean raster?"}, {}},
        {"render cbox.xml --sampler sobel", 2, {"--sampler must be one of", "did you mean sobol?"}, {}},
        {"estimate radiance cbox.xml --origin 0,1,3 --direction 0,0,-1 --light-sampler unifrom", 2, {"did you mean uniform?"}, {}},
        // Every error, one style: "error: ..." (scene errors "file:line: ...").
        {"render cbox.xml --spp 0", 2, {"error: --spp"}, {}},
    };
    check_rows(work, logs, rows);
}

TEST_CASE("cli messages: misspelled commands and options get the nearest name and the list", "[cli][errors]") {
    fs::path logs;
    const fs::path work = setup("cli-messages-names", logs);
    const std::vector<Mistake> rows = {
        {"rendr cbox.xml", 2, {"unknown command \"rendr\"; did you mean \"render\"?", "compare-modes", "candela COMMAND --help"}, {}},
        {"compare_modes cbox.xml", 2, {"did you mean \"compare-modes\"?"}, {"A subcommand is required"}},
        {"farm pln cbox.xml", 2, {"unknown command \"pln\" for candela farm; did you mean \"plan\"?", "slurm", "status"}, {}},
        {"estimate irradiance_ cbox.xml", 2, {"did you mean \"irradiance\"?"}, {}},
        {"", 2, {"candela needs a command", "render"}, {}},
        {"help", 0, {"render", "compare-modes", "farm"}, {}},
        {"render cbox.xml --sp 4", 2, {"unknown option --sp for candela render; did you mean --spp?"}, {"were not expected"}},
        {"render cbox.xml --thread 2", 2, {"did you mean --threads?"}, {}},
        {"compare first.exr first.exr --tolerence 0.1", 2, {"did you mean --tolerance?"}, {}},
        {"farm plan cbox.xml -o f.exr --parts 2 --part 2", 2, {"unknown option --part for candela farm plan"}, {}},
        {"render", 2, {"candela render needs its input: scene", "--help"}, {}},
        {"render --spp 4", 2, {"candela render needs its input: scene"}, {}},
        {"render cbox.xml first.exr", 2, {"one scene file, please: got cbox.xml and also first.exr"}, {}},
        // Raster options: the value is checked before whether the mode is raster.
        {"render cbox.xml --shading phog", 2, {"--shading: shading must be one of", "did you mean phong?"}, {"need --mode raster"}},
        {"render cbox.xml --shading phong -o x.exr", 2, {"need --mode raster"}, {}},
        // Missing inputs and values name what is missing and show the usage line.
        {"compare first.exr", 2, {"candela compare needs its input: reference", "usage: candela compare TEST REFERENCE"}, {}},
        {"merge", 2, {"candela merge needs its input: parts", "usage: candela merge PARTS..."}, {}},
        {"merge first.exr", 2, {"candela merge needs --output"}, {}},
        {"render cbox.xml -o", 2, {"option --output needs a value after it"}, {}},
        {"estimate irradiance cbox.xml", 2, {"candela estimate irradiance needs --at"}, {}},
        {"--verison", 2, {"unknown option --verison for candela; did you mean --version?", "render"}, {}},
    };
    check_rows(work, logs, rows);
}

TEST_CASE("cli messages: wrong files and scene mistakes say what the file is and what to do", "[cli][errors]") {
    fs::path logs;
    const fs::path work = setup("cli-messages-files", logs);
    write_text(work / "pathtracer.xml", "<scene version=\"3.0.0\">\n<integrator type=\"pathtracer\"/>\n</scene>\n");
    write_text(work / "misspelled.xml",
               "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n<bsdf type=\"diffuse\">\n<rgb name=\"reflectence\" value=\"0.5\"/>\n"
               "</bsdf>\n</shape>\n</scene>\n");
    write_text(work / "glass.xml", "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n<bsdf type=\"glass\"/>\n</shape>\n</scene>\n");
    const std::vector<Mistake> rows = {
        {"render nosuch.xml", 2, {"nosuch.xml: no such file"}, {}},
        {"render folder", 2, {"folder: is a directory"}, {}},
        {"render first.exr", 2, {"first.exr: this is an OpenEXR image, not a scene file"}, {"malformed XML"}},
        {"render first.png", 2, {"first.png: this is a PNG image, not a scene file"}, {}},
        {"render pathtracer.xml", 2, {"pathtracer.xml:2:", "did you mean \"path\"", "particle"}, {}},
        {"render misspelled.xml", 2, {"misspelled.xml:4:", "reflectence", "did you mean \"reflectance\"?"}, {}},
        {"render glass.xml", 2, {"glass.xml:3:", "dielectric"}, {}},
        // The image is OpenEXR whatever its name says; a PNG name points to --png.
        {"render cbox.xml -o out.png", 2, {"-o out.png: the image is written as OpenEXR", "-o out.exr", "--png"}, {}},
        {"render cbox.xml -o out", 2, {"-o out.exr"}, {}},
        // Radiance metrics refuse the 8-bit preview unless asked for.
        {"compare first.exr first.png",
         2,
         {"first.png: the reference is a 8-bit image", "not radiance", "--allow-ldr"},
         {"mean rel. diff"}},
        {"compare first.png first.exr", 2, {"first.png: the test image is a 8-bit image"}, {}},
        {"compare first.png first.png --allow-ldr", 0, {"RMSE            0"}, {}},
        {"compare first.exr first.exr --heatmap heat.png", 0, {"MARE            0.000%", "wrote heat.png"}, {}, {"heat.png"}},
    };
    check_rows(work, logs, rows);
}

TEST_CASE("cli messages: -D names, option order, ignored options and sample ranges", "[cli][errors]") {
    fs::path logs;
    const fs::path work = setup("cli-messages-scene", logs);
    const std::vector<Mistake> rows = {
        // A -D the scene never uses renders, with a warning naming the scene's parameters.
        {"render cbox.xml -D rez=4 -o a.exr -q",
         0,
         {"-D rez=4: the scene has no parameter \"rez\"; did you mean \"res\"?", "res, spp"},
         {},
         {"a.exr"}},
        // -D before the scene, -D repeated, and the older -D a=1 b=2.
        {"render -D res=4 cbox.xml -o b.exr", 0, {"wrote b.exr"}, {}, {"b.exr"}},
        {"render cbox.xml -D res=4 -D spp=2 -o c.exr", 0, {"wrote c.exr", "2 spp"}, {}, {"c.exr"}},
        {"render -D res=4 spp=2 cbox.xml -o d.exr", 0, {"wrote d.exr", "2 spp"}, {}, {"d.exr"}},
        {"render cbox.xml -D res4", 2, {"-D expects name=value, got \"res4\""}, {}},
        // Options the raster mode does not take are named, with the one it does.
        {"render cbox.xml --mode raster --spp 4 -o r.exr", 0, {"--spp 4 does not apply to the raster mode", "--aa"}, {}, {"r.exr"}},
        // --threads beyond the cores is capped with a word, not TBB's raw warning.
        {"render cbox.xml --threads 999 -o t.exr", 0, {"--threads 999: this machine has"}, {"TBB Warning"}, {"t.exr"}},
        {"render --help", 0, {"default 0: one per core"}, {}},
        // Sample ranges: past the scene's sampler's count, the --spp that fits.
        {"render cbox.xml --samples 8:16 -o p.exr",
         2,
         {"--samples 8:16 reaches past the render's 8 samples per pixel", "independent sampler", "--spp 16 --samples 8:16"},
         {"non-empty part"}},
        {"render cbox.xml --spp 16 --samples 8:16 -o p.exr", 0, {"wrote p.exr", "part: samples 8:16 of 16"}, {"(part)"}, {"p.exr"}},
        {"merge part.exr -o m.exr", 2, {"the parts hold 8 of 16 spp of the 8 x 8 image", "--samples 8:16"}, {}},
        {"merge part.exr -o m.exr --allow-partial", 0, {"1 part, 8 of 16 spp"}, {}, {"m.exr"}},
        {"render cbox.xml --png -o v.exr", 0, {"wrote v.png"}, {}, {"v.exr", "v.png"}},
        // estimate's sample count is -n; --samples still works, with a note.
        {"estimate irradiance cbox.xml --at 0,0,0 --normal 0,1,0 --samples 64", 0, {"64 samples", "-n"}, {}},
        {"estimate irradiance cbox.xml --at 0,0,0 --normal 0,1,0 -n 64", 0, {"64 samples"}, {"warning"}},
        // compare-modes' default list leaves out raster-gi; asked for on a scene with no ambient
        // light it gets a word.
        {"compare-modes --help", 0, {"default raster,baked,radiosity,path"}, {}},
    };
    check_rows(work, logs, rows);
}

TEST_CASE("cli messages: farm plan names what it wrote and keeps an existing plan", "[cli][farm]") {
    fs::path logs;
    const fs::path work = setup("cli-messages-farm", logs);
    const std::vector<Mistake> rows = {
        {"farm plan cbox.xml -o farm.exr --parts 2",
         0,
         {"wrote the plan", "farm-farm/plan.txt", "2 parts"},
         {},
         {"farm-farm", "farm-farm/plan.txt", "farm-farm/parts", "farm-farm/logs"}},
    };
    check_rows(work, logs, rows);
    // Planned again over the same folder: refused, the first plan kept.
    const std::string candela = "cd '" + work.string() + "' && '" + candela_binary() + "' ";
    REQUIRE(run_command(candela + "farm plan cbox.xml -o farm.exr --parts 2", logs / "first.txt") == 0);
    const std::string plan = read_text(work / "farm-farm" / "plan.txt");
    CHECK(run_command(candela + "farm plan cbox.xml -o farm.exr --parts 4", logs / "again.txt") == 2);
    CHECK_THAT(read_text(logs / "again.txt"), Catch::Contains("already has a farm plan") && Catch::Contains("--force"));
    CHECK(read_text(work / "farm-farm" / "plan.txt") == plan);
    CHECK(run_command(candela + "farm plan cbox.xml -o farm.exr --parts 4 --force", logs / "forced.txt") == 0);
    CHECK(read_text(work / "farm-farm" / "plan.txt") != plan);
}

TEST_CASE("cli messages: validate marks a reference of another size failed, by name, and goes on", "[cli][validate]") {
    fs::path logs;
    const fs::path work = setup("cli-messages-validate", logs);
    const fs::path set = work / "set";
    fs::create_directories(set / "refs");
    fs::copy_file(work / "cbox.xml", set / "good.xml");
    fs::copy_file(work / "cbox.xml", set / "wrong.xml");
    const std::string candela = "cd '" + work.string() + "' && '" + candela_binary() + "' ";
    REQUIRE(run_command(candela + "render cbox.xml --spp 256 -o set/refs/good.exr -q", logs / "ref1.txt") == 0);
    REQUIRE(run_command(candela + "render cbox.xml -D res=16 --spp 4 -o set/refs/wrong.exr -q", logs / "ref2.txt") == 0);
    const std::vector<Mistake> rows = {
        {"validate set -o report.html --spp 64",
         1,
         {"wrong        FAIL  not compared: the reference set/refs/wrong.exr is 16 x 16, the scene renders 8 x 8", "good ",
          "per-pixel z-test", "of 2 scenes pass; wrote the report report.html"},
         {},
         {"report.html"}},
    };
    check_rows(work, logs, rows);
}
