// The candela command line: render and compare, exit codes, metadata, and bad input that must
// stop with file:line, exit code 2 and no output file created or clobbered.

#include "core/image.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <regex>

using namespace candela;
using namespace candela::test;

namespace {
const std::string Cbox = source_path("scenes/validation/cbox.xml");

std::string render_cmd(const std::string& args) { return "'" + candela_binary() + "' render " + args; }
}  // namespace

TEST_CASE("cli: render writes an EXR with metadata, -D and --spp apply, --png writes a preview", "[cli]") {
    auto dir = scratch_dir("cli-render");
    auto out = dir / "box.exr";
    int code = run_command(render_cmd("'" + Cbox + "' -o '" + out.string() + "' -D res=24 --spp 3 --seed 7 --png"), dir / "log.txt");
    INFO(read_text(dir / "log.txt"));
    REQUIRE(code == 0);
    Image img = read_image(out.string());
    CHECK(img.width() == 24);
    CHECK(img.metadata["candela.spp"] == "3");
    CHECK(img.metadata["candela.seed"] == "7");
    CHECK(img.metadata["candela.partial"] == "false");
    CHECK(img.metadata["candela.scene"] == Cbox);
    CHECK(img.metadata.count("candela.renderTime") == 1);
    CHECK(img.metadata["candela.version"].size() > 0);
    CHECK(std::filesystem::exists(dir / "box.png"));
    // Not a terminal: no progress bar, but the one-line summary.
    std::string log = read_text(dir / "log.txt");
    CHECK_THAT(log, Catch::Contains("3 spp") && Catch::Contains("samples/s") && Catch::Contains("Mrays/s"));
    CHECK(log.find('\r') == std::string::npos);
    // --quiet silences it.
    REQUIRE(run_command(render_cmd("'" + Cbox + "' -o '" + out.string() + "' -D res=8 --spp 1 --quiet"), dir / "quiet.txt") == 0);
    CHECK(read_text(dir / "quiet.txt").empty());
}

TEST_CASE("cli: render --no-wavefront traces one path at a time and writes the same image", "[cli][wavefront]") {
    auto dir = scratch_dir("cli-wavefront");
    const std::string common = "'" + Cbox + "' -D res=20 --spp 4 --seed 3 --sampler ldsampler --quiet -o ";
    REQUIRE(run_command(render_cmd(common + "'" + (dir / "wave.exr").string() + "'"), dir / "wave.txt") == 0);
    REQUIRE(run_command(render_cmd(common + "'" + (dir / "one.exr").string() + "' --no-wavefront"), dir / "one.txt") == 0);
    const Image wave = read_image((dir / "wave.exr").string()), one = read_image((dir / "one.exr").string());
    CHECK(wave.data() == one.data());
    CHECK(wave.metadata.at("candela.rays") == one.metadata.at("candela.rays"));
}

TEST_CASE("cli: CANDELA_EMBREE_CONFIG selects Embree's kernels and a configuration Embree refuses is bad input", "[cli][wavefront]") {
    auto dir = scratch_dir("cli-embree-config");
    const std::string args = "'" + Cbox + "' -D res=20 --spp 4 --seed 3 --quiet -o ";
    // The SSE4.2 kernels answer the wave's 8-ray packets as two 4-ray ones (their hits may
    // differ from the widest kernels' in the last bits, so the image is not compared here; the
    // wave's test holds it to the one-path-at-a-time image under the same kernels).
    REQUIRE(run_command("CANDELA_EMBREE_CONFIG=isa=sse4.2 " + render_cmd(args + "'" + (dir / "sse.exr").string() + "'"), dir / "sse.txt") ==
            0);
    CHECK(all_finite_pixels(read_image((dir / "sse.exr").string())));
    // A configuration Embree cannot parse: exit code 2, the variable named, nothing written.
    const auto bad = dir / "bad.exr";
    CHECK(run_command("CANDELA_EMBREE_CONFIG='threads=x,,' " + render_cmd(args + "'" + bad.string() + "'"), dir / "bad.txt") == 2);
    CHECK_THAT(read_text(dir / "bad.txt"), Catch::Contains("CANDELA_EMBREE_CONFIG=\"threads=x,,\""));
    CHECK_FALSE(std::filesystem::exists(bad));
}

TEST_CASE("cli: OpenImageIO is loaded only when a program reads an image other than EXR and PNG", "[cli][images]") {
    // Its ~250 libraries took about 0.25-0.45 s at every start (core/image_codecs.h). The dynamic
    // loader's own log (LD_DEBUG=files) names every library it loads and every dlopen.
    auto dir = scratch_dir("cli-image-module");
    auto out = (dir / "box.exr").string();
    const std::string render = "LD_DEBUG=files " + render_cmd("'" + Cbox + "' -o '" + out + "' -D res=8 --spp 1 --quiet");
    REQUIRE(run_command(render, dir / "exr.txt") == 0);
    std::string log = read_text(dir / "exr.txt");
    CHECK_THAT(log, Catch::Contains("libembree3"));  // the log is there
    CHECK_THAT(log, !Catch::Contains("libOpenImageIO") && !Catch::Contains("libcandela_images"));
    // Nor does a PNG preview: libpng writes it (core/png_file.h).
    REQUIRE(run_command(render + " --png", dir / "png.txt") == 0);
    log = read_text(dir / "png.txt");
    CHECK_THAT(log, !Catch::Contains("libOpenImageIO") && !Catch::Contains("libcandela_images"));
    CHECK(std::filesystem::exists(dir / "box.png"));
    // Reading EXR files does not: OpenEXR reads them (core/exr_input.h); compare reads two.
    REQUIRE(run_command("LD_DEBUG=files '" + candela_binary() + "' compare '" + out + "' '" + out + "'", dir / "compare.txt") == 0);
    log = read_text(dir / "compare.txt");
    CHECK_THAT(log, !Catch::Contains("libOpenImageIO") && Catch::Contains("RMSE            0"));
    // Nor does reading a PNG: libpng reads it.
    const std::string png = (dir / "box.png").string();
    REQUIRE(run_command("LD_DEBUG=files '" + candela_binary() + "' compare --allow-ldr '" + png + "' '" + png + "'",
                        dir / "compare_png.txt") == 0);
    CHECK_THAT(read_text(dir / "compare_png.txt"), !Catch::Contains("libOpenImageIO") && Catch::Contains("RMSE            0"));
    // Reading another format (here a plain-text PPM) loads the module, and OpenImageIO with it.
    write_text(dir / "grey.ppm", "P3\n2 1\n255\n10 20 30 40 50 60\n");
    const std::string ppm = (dir / "grey.ppm").string();
    REQUIRE(run_command("LD_DEBUG=files '" + candela_binary() + "' compare --allow-ldr '" + ppm + "' '" + ppm + "'",
                        dir / "compare_ppm.txt") == 0);
    CHECK_THAT(read_text(dir / "compare_ppm.txt"),
               Catch::Contains("libcandela_images") && Catch::Contains("libOpenImageIO") && Catch::Contains("RMSE            0"));
}

TEST_CASE("cli: bad input exits with code 2, names file:line, and leaves outputs alone", "[cli][errors]") {
    auto dir = scratch_dir("cli-errors");
    write_text(dir / "unused.xml",
               "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n<float name=\"radios\" value=\"1\"/>\n</shape>\n</scene>\n");
    write_text(dir / "malformed.xml", "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n</scene>\n");
    write_text(dir / "unknown.xml", "<scene version=\"3.0.0\">\n\n<bsdf type=\"velvet\"/>\n</scene>\n");
    write_text(
        dir / "nan.xml",
        "<scene version=\"3.0.0\">\n<shape type=\"sphere\"><transform name=\"to_world\">\n\n<translate x=\"nan\"/>\n</transform></shape>\n</scene>\n");
    write_text(dir / "nomesh.xml",
               "<scene version=\"3.0.0\">\n<shape type=\"ply\"><string name=\"filename\" value=\"missing.ply\"/></shape>\n</scene>\n");
    write_text(dir / "notexture.xml",
               "<scene version=\"3.0.0\">\n<shape type=\"sphere\"><bsdf type=\"diffuse\">\n<texture type=\"bitmap\" name=\"reflectance\">\n"
               "<string name=\"filename\" value=\"nope.png\"/>\n</texture></bsdf></shape>\n</scene>\n");
    struct Case {
        const char* scene;
        std::string where;
    };
    const Case cases[] = {{"unused.xml", "unused.xml:3: "},
                          {"malformed.xml", "malformed.xml:3: "},
                          {"unknown.xml", "unknown.xml:3: "},
                          {"nan.xml", "nan.xml:4: "},
                          {"nomesh.xml", "nomesh.xml:2: "},
                          {"notexture.xml", "notexture.xml:4: "},
                          {"does-not-exist.xml", "does-not-exist.xml"}};
    for (const Case& c : cases) {
        INFO(c.scene);
        auto fresh = dir / (std::string(c.scene) + ".exr");
        auto existing = dir / "existing.exr";
        write_text(existing, "precious");
        int code = run_command(render_cmd("'" + (dir / c.scene).string() + "' -o '" + fresh.string() + "'"), dir / "log.txt");
        std::string log = read_text(dir / "log.txt");
        INFO(log);
        CHECK(code == 2);
        CHECK_THAT(log, Catch::Contains(c.where));
        CHECK(!std::filesystem::exists(fresh));
        code = run_command(render_cmd("'" + (dir / c.scene).string() + "' -o '" + existing.string() + "'"), dir / "log.txt");
        CHECK(code == 2);
        CHECK(read_text(existing) == "precious");  // not clobbered
    }
    // No stray temporaries either.
    for (auto& entry : std::filesystem::directory_iterator(dir)) CHECK(entry.path().filename().string().find(".tmp") == std::string::npos);
}

TEST_CASE("cli: -a adds search folders for the scene's files (mitsuba -a)", "[cli][path]") {
    auto dir = scratch_dir("cli-search-path");
    std::filesystem::create_directories(dir / "scenes");
    std::filesystem::create_directories(dir / "common" / "meshes");
    std::filesystem::create_directories(dir / "empty");
    write_text(dir / "common" / "meshes" / "quad.obj", "v -1 -1 2\nv -1 1 2\nv 1 1 2\nv 1 -1 2\nf 1 2 3 4\n");
    write_text(dir / "scenes" / "s.xml", scene_xml(R"(<sensor type="perspective"><float name="fov" value="20"/>
  <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
<shape type="obj"><string name="filename" value="meshes/quad.obj"/><emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>)"));
    std::string scene = "'" + (dir / "scenes" / "s.xml").string() + "'", out = (dir / "out.exr").string();
    CHECK(run_command(render_cmd(scene + " -o '" + out + "' --spp 1"), dir / "missing.txt") == 2);
    CHECK_THAT(read_text(dir / "missing.txt"), Catch::Contains("file not found: \"meshes/quad.obj\""));
    CHECK_FALSE(std::filesystem::exists(out));
    int code = run_command(
        render_cmd(scene + " -o '" + out + "' --spp 1 -q -a '" + (dir / "empty").string() + ";" + (dir / "common").string() + "'"),
        dir / "found.txt");
    INFO(read_text(dir / "found.txt"));
    REQUIRE(code == 0);
    CHECK(read_image(out).at(1, 1, 0) == Approx(2.0f));
    CHECK(run_command(render_cmd(scene + " -o '" + out + "' --spp 1 -a '" + (dir / "nowhere").string() + "'"), dir / "nowhere.txt") == 2);
    CHECK_THAT(read_text(dir / "nowhere.txt"), Catch::Contains("search folder") && Catch::Contains("nowhere"));
}

TEST_CASE("cli: an unwritable output path or a bad option exits with code 2 before rendering", "[cli][errors]") {
    auto dir = scratch_dir("cli-output");
    CHECK(run_command(render_cmd("'" + Cbox + "' -o '" + (dir / "no/such/dir/out.exr").string() + "'"), dir / "log.txt") == 2);
    CHECK_THAT(read_text(dir / "log.txt"), Catch::Contains("does not exist"));
    CHECK(run_command(render_cmd("'" + Cbox + "' -o '" + dir.string() + "'"), dir / "log.txt") == 2);
    CHECK(run_command(render_cmd("'" + Cbox + "' -o '" + (dir / "x.exr").string() + "' -D novalue"), dir / "log.txt") == 2);
    CHECK_THAT(read_text(dir / "log.txt"), Catch::Contains("name=value"));
    CHECK(run_command(render_cmd("'" + Cbox + "' --spp -3"), dir / "log.txt") == 2);
    CHECK(run_command("'" + candela_binary() + "' frobnicate", dir / "log.txt") == 2);
    CHECK(!std::filesystem::exists(dir / "x.exr"));
}

TEST_CASE("cli: output paths that are directories, read-only, devices or on a full disk fail with exit code 2 and keep the earlier file",
          "[cli][errors]") {
    namespace fs = std::filesystem;
    auto dir = scratch_dir("cli-output-safety");
    const std::string scene = "'" + Cbox + "' -D res=32 --spp 2";
    auto expect_refused = [&](const std::string& command, const std::string& message) {
        int code = run_command(command, dir / "log.txt");
        std::string log = read_text(dir / "log.txt");
        INFO(command << "\n" << log);
        CHECK(code == 2);
        CHECK_THAT(log, Catch::Contains(message));
    };
    // A directory in the way stays a directory, with its contents.
    fs::create_directories(dir / "taken.exr");
    write_text(dir / "taken.exr" / "inside.txt", "kept");
    expect_refused(render_cmd(scene + " -o '" + (dir / "taken.exr").string() + "'"), "it is a directory");
    CHECK(read_text(dir / "taken.exr" / "inside.txt") == "kept");
    // A read-only file, as the image and as the --png preview (checked before rendering).
    write_text(dir / "locked.exr", "precious");
    write_text(dir / "open.png", "precious");
    fs::permissions(dir / "locked.exr", fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
    fs::permissions(dir / "open.png", fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
    expect_refused(render_cmd(scene + " -o '" + (dir / "locked.exr").string() + "'"), "read-only");
    write_text(dir / "open.exr", "precious too");
    expect_refused(render_cmd(scene + " -o '" + (dir / "open.exr").string() + "' --png"), "read-only");
    CHECK(read_text(dir / "locked.exr") == "precious");
    CHECK(read_text(dir / "open.png") == "precious");
    CHECK(read_text(dir / "open.exr") == "precious too");
    // A read-only folder.
    fs::create_directories(dir / "shelf");
    fs::permissions(dir / "shelf", fs::perms::owner_read | fs::perms::owner_exec);
    expect_refused(render_cmd(scene + " -o '" + (dir / "shelf" / "new.exr").string() + "'"), "not writable");
    CHECK(fs::is_empty(dir / "shelf"));
    fs::permissions(dir / "shelf", fs::perms::owner_all);
    // A device: the image is written beside the target and renamed, which would replace
    // /dev/full by a plain file; refused instead, and the device stays.
    expect_refused(render_cmd(scene + " -o /dev/full"), "not a regular file");
    CHECK(fs::is_character_file("/dev/full"));
    // A full disk, as the render sees it: the file-size limit makes every write past 1 KiB fail
    // (EFBIG; SIGXFSZ ignored, as a full disk sends no signal) while the render itself runs.
    write_text(dir / "earlier.exr", "precious");
    expect_refused("( trap '' XFSZ; ulimit -f 1; exec " + render_cmd(scene + " -o '" + (dir / "earlier.exr").string() + "'") + " )",
                   "cannot write");
    CHECK(read_text(dir / "earlier.exr") == "precious");
    // The HTML report of validate: refused before any scene renders.
    write_text(dir / "report.html", "precious");
    fs::permissions(dir / "report.html", fs::perms::owner_read);
    expect_refused(
        "'" + candela_binary() + "' validate '" + source_path("scenes/validation") + "' -o '" + (dir / "report.html").string() + "'",
        "read-only");
    expect_refused("'" + candela_binary() + "' validate '" + source_path("scenes/validation") + "' -o /dev/full", "not a regular file");
    CHECK(read_text(dir / "report.html") == "precious");
    for (auto& entry : fs::directory_iterator(dir)) CHECK(entry.path().filename().string().find(".tmp") == std::string::npos);
}

TEST_CASE("cli: Ctrl-C writes the image so far, marked partial, and exits non-zero", "[cli][interrupt]") {
    auto dir = scratch_dir("cli-interrupt");
    auto out = dir / "partial.exr";
    // A render far too long to finish; SIGINT once its handler is installed.
    std::string cmd = interrupt_after_start(render_cmd("'" + Cbox + "' -o '" + out.string() + "' --spp 100000"));
    int code = run_command(cmd, dir / "log.txt");
    INFO(read_text(dir / "log.txt"));
    CHECK(code == 130);
    REQUIRE(std::filesystem::exists(out));
    Image img = read_image(out.string());
    CHECK(img.metadata["candela.partial"] == "true");
    CHECK(std::stoll(img.metadata["candela.samples"]) < 100000LL * 256 * 256);
    CHECK_THAT(read_text(dir / "log.txt"), Catch::Contains("interrupted"));
}

TEST_CASE("cli: compare reports metrics and its exit code says whether images agree", "[cli][compare]") {
    auto dir = scratch_dir("cli-compare");
    auto a = dir / "a.exr", b = dir / "b.exr", scaled = dir / "scaled.exr";
    REQUIRE(run_command(render_cmd("'" + Cbox + "' -o '" + a.string() + "' -D res=32 --spp 16 --seed 1 -q"), dir / "log.txt") == 0);
    REQUIRE(run_command(render_cmd("'" + Cbox + "' -o '" + b.string() + "' -D res=32 --spp 16 --seed 2 -q"), dir / "log.txt") == 0);
    Image img = read_image(a.string());
    for (float& v : img.data()) v *= 1.05f;
    write_exr(img, scaled.string(), true);
    std::string compare = "'" + candela_binary() + "' compare ";
    CHECK(run_command(compare + "'" + a.string() + "' '" + a.string() + "' --tolerance 0.01", dir / "same.txt") == 0);
    CHECK_THAT(read_text(dir / "same.txt"), Catch::Contains("RMSE            0\n"));
    CHECK(run_command(
              compare + "'" + scaled.string() + "' '" + a.string() + "' --tolerance 0.01 --heatmap '" + (dir / "heat.png").string() + "'",
              dir / "scaled.txt") == 1);
    std::string log = read_text(dir / "scaled.txt");
    CHECK_THAT(log, Catch::Contains("+5.000%") && Catch::Contains("agree           no"));
    CHECK(std::filesystem::exists(dir / "heat.png"));
    // Without --tolerance it only reports.
    CHECK(run_command(compare + "'" + scaled.string() + "' '" + a.string() + "'", dir / "report.txt") == 0);
    // Images of different sizes are bad input.
    REQUIRE(run_command(render_cmd("'" + Cbox + "' -o '" + b.string() + "' -D res=16 --spp 1 -q"), dir / "log.txt") == 0);
    CHECK(run_command(compare + "'" + a.string() + "' '" + b.string() + "'", dir / "size.txt") == 2);
}

TEST_CASE("cli: estimate prints irradiance and radiance with error bars", "[cli][estimate]") {
    auto dir = scratch_dir("cli-estimate");
    std::string lights = source_path("scenes/validation/lights.xml");
    REQUIRE(run_command("'" + candela_binary() + "' estimate irradiance '" + lights + "' --at 0,0,0 --normal 0,1,0 --samples 20000",
                        dir / "irr.txt") == 0);
    std::string irr = read_text(dir / "irr.txt");
    CHECK_THAT(irr, Catch::Contains("standard error") && Catch::Contains("95% interval") && Catch::Contains("luminance") &&
                        Catch::Contains("W/m^2"));
    REQUIRE(run_command("'" + candela_binary() + "' estimate radiance '" + lights + "' --origin 0,1,3 --direction 0,-0.3,-1 -n 5000",
                        dir / "rad.txt") == 0);
    CHECK_THAT(read_text(dir / "rad.txt"), Catch::Contains("W/m^2/sr"));
    CHECK(run_command("'" + candela_binary() + "' estimate irradiance '" + lights + "' --at 0,0 --normal 0,1,0", dir / "bad.txt") == 2);
    CHECK_THAT(read_text(dir / "bad.txt"), Catch::Contains("three numbers"));
}

TEST_CASE("cli: the irradiance integrator renders a false-colour map with a legend", "[cli][estimate]") {
    auto dir = scratch_dir("cli-irradiance-map");
    std::string scene = read_text(source_path("scenes/validation/lights.xml"));
    std::string from = "<integrator type=\"path\"><integer name=\"max_depth\" value=\"-1\"/></integrator>";
    REQUIRE(scene.find(from) != std::string::npos);
    scene.replace(scene.find(from), from.size(), "<integrator type=\"irradiance\"/>");
    write_text(dir / "map.xml", scene);
    // Paths in the scene are relative: none here besides the scene itself.
    REQUIRE(
        run_command(render_cmd("'" + (dir / "map.xml").string() + "' -o '" + (dir / "map.exr").string() + "' -D res=64 --spp 8 --png -q"),
                    dir / "log.txt") == 0);
    Image png = read_image((dir / "map.png").string());
    CHECK(png.width() > 64);  // the legend is added on the right
    Image exr = read_image((dir / "map.exr").string());
    CHECK(exr.width() == 64);
}

TEST_CASE("cli: float16 and float32 films write EXRs of that pixel type", "[cli]") {
    auto dir = scratch_dir("cli-half");
    std::string scene = read_text(Cbox);
    std::string f32 = "<string name=\"component_format\" value=\"float32\"/>";
    REQUIRE(scene.find(f32) != std::string::npos);
    scene.replace(scene.find(f32), f32.size(), "");  // the default: float16
    write_text(dir / "half.xml", scene);
    REQUIRE(run_command(render_cmd("'" + (dir / "half.xml").string() + "' -o '" + (dir / "half.exr").string() + "' -D res=16 --spp 2 -q"),
                        dir / "log.txt") == 0);
    CHECK_THAT(read_text(dir / "log.txt"), !Catch::Contains("error"));
    Image img = read_image((dir / "half.exr").string());
    CHECK(img.width() == 16);
    CHECK(img.rgb_at(8, 8).x > 0.0f);
    CHECK(run_command("oiiotool --info -v '" + (dir / "half.exr").string() + "' | grep -q half", dir / "info.txt") == 0);
}

TEST_CASE("cli: --mode raster with its options", "[cli][raster]") {
    auto dir = scratch_dir("cli-raster");
    auto out = dir / "raster.exr";
    REQUIRE(run_command(render_cmd("'" + Cbox + "' -o '" + out.string() +
                                   "' --mode raster --shading gouraud --reflection phong --shadows volume --aa 4 "
                                   "--aa-filter tent --texture-filter bilinear --wireframe --light-gizmos --png -q"),
                        dir / "log.txt") == 0);
    Image img = read_image(out.string());
    CHECK(img.width() == 256);
    CHECK(std::filesystem::exists(dir / "raster.png"));
    // The summary of a rasterized frame is its frame time, not sample and ray rates.
    REQUIRE(run_command(render_cmd("'" + Cbox + "' -o '" + out.string() + "' --mode raster --aa 4 -D res=32"), dir / "summary.txt") == 0);
    std::string summary = read_text(dir / "summary.txt");
    CHECK_THAT(summary, Catch::Contains("ms per frame, 4 samples per pixel") && !Catch::Contains("Mrays/s") && !Catch::Contains("spp"));
    // --help lists the accepted values of every raster option.
    REQUIRE(run_command(render_cmd("--help"), dir / "help.txt") == 0);
    std::string help = read_text(dir / "help.txt");
    for (const char* option :
         {"--shading flat|gouraud|phong", "--reflection phong|blinn", "--shadows none|map|volume", "--aa-filter box|tent|gaussian",
          "--texture-filter nearest|bilinear|trilinear", "--environment-mapping latlong|cube", "integer >= 1", "--ao N",
          "--environment-lighting ibl|average", "--lighting local|baked", "--bake radiosity|path"})
        CHECK_THAT(help, Catch::Contains(option));
    CHECK_THAT(help, !Catch::Contains("see integrators/raster"));
    // Raster options without raster mode, and bad values, are bad input.
    CHECK(run_command(render_cmd("'" + Cbox + "' -o '" + out.string() + "' --shading phong"), dir / "log.txt") == 2);
    CHECK_THAT(read_text(dir / "log.txt"), Catch::Contains("need --mode raster"));
    CHECK(run_command(render_cmd("'" + Cbox + "' -o '" + out.string() + "' --mode raster --shadows fuzzy"), dir / "log.txt") == 2);
    CHECK_THAT(read_text(dir / "log.txt"), Catch::Contains("shadows must be one of none map volume"));
    // The integrator can also be chosen in the scene, with the same options as properties.
    std::string scene = read_text(Cbox);
    size_t begin = scene.find("<integrator type=\"path\">"), end = scene.find("</integrator>", begin) + 13;
    REQUIRE(begin != std::string::npos);
    scene.replace(begin, end - begin,
                  "<integrator type=\"raster\"><string name=\"shading\" value=\"flat\"/><integer name=\"aa\" value=\"4\"/></integrator>");
    write_text(dir / "raster.xml", scene);
    REQUIRE(run_command(render_cmd("'" + (dir / "raster.xml").string() + "' -o '" + out.string() + "' -q"), dir / "log2.txt") == 0);
    CHECK(read_image(out.string()).metadata["candela.integrator"] == "raster");
}

TEST_CASE("cli: compare-modes compares any list of methods with a path-traced reference", "[cli][raster]") {
    auto dir = scratch_dir("cli-compare-modes");
    const std::string cmd = "'" + candela_binary() + "' compare-modes '" + Cbox + "' -D res=32 --spp 4 --reference-spp 16 ";
    // Every kind of method: raster with a command-line option, its shorthands with parameters,
    // registry integrators with parameters, the scene's own path tracer.
    const std::string methods =
        "raster,raster-gi:ambient=0.1,baked:bake_patch_area=0.3,radiosity:max_patch_area=0.3:final_gather=false,path";
    REQUIRE(run_command(cmd + "--aa 4 --methods '" + methods + "' -o '" + (dir / "cmp.png").string() + "' --table '" +
                            (dir / "cmp.md").string() + "'",
                        dir / "cmp.txt") == 0);
    std::string log = read_text(dir / "cmp.txt"), table = read_text(dir / "cmp.md");
    CHECK_THAT(log, Catch::Contains("| method | time (s) |") && Catch::Contains("relMSE") && Catch::Contains("block MARE") &&
                        Catch::Contains("Reference: path tracer, 16 spp"));
    for (const std::string m : {"| raster |", "| raster-gi:ambient=0.1 |", "| baked:bake_patch_area=0.3 |",
                                "| radiosity:max_patch_area=0.3:final_gather=false |", "| path |"}) {
        CHECK_THAT(log, Catch::Contains(m));
        CHECK_THAT(table, Catch::Contains(m));
    }
    // One picture: the reference and five methods side by side, each above its heatmap.
    Image sheet = read_image((dir / "cmp.png").string());
    CHECK(sheet.width() > 6 * 32);
    CHECK(sheet.height() > 2 * 32);
    // A method the registry does not know, or a parameter no integrator reads, stops before any
    // render with the method named.
    CHECK(run_command(cmd + "--methods raster,pathh -o '" + (dir / "bad.png").string() + "'", dir / "bad.txt") == 2);
    CHECK_THAT(read_text(dir / "bad.txt"), Catch::Contains("--methods pathh") && Catch::Contains("nearest supported: \"path\""));
    CHECK(run_command(cmd + "--methods radiosity:patches=3 -o '" + (dir / "bad.png").string() + "'", dir / "bad.txt") == 2);
    CHECK_THAT(read_text(dir / "bad.txt"), Catch::Contains("unused property \"patches\""));
    CHECK(run_command(cmd + "--methods raster:ao -o '" + (dir / "bad.png").string() + "'", dir / "bad.txt") == 2);
    CHECK_THAT(read_text(dir / "bad.txt"), Catch::Contains("is not key=value"));
    CHECK_FALSE(std::filesystem::exists(dir / "bad.png"));
    // A reference from a file must match the film.
    CHECK(run_command(cmd + "--methods raster --reference '" + source_path("scenes/validation/refs/cbox.exr") + "' -o '" +
                          (dir / "bad.png").string() + "'",
                      dir / "bad.txt") == 2);
    CHECK_THAT(read_text(dir / "bad.txt"), Catch::Contains("the reference is 256x256, the scene renders 32x32"));
}

TEST_CASE("cli: sample counts beyond 2^30 are refused with the range, before anything is written", "[cli][errors]") {
    // Before issue 28, --spp 2000000000 overflowed int while the samplers rounded it (stratified's
    // r * r, ldsampler's, the power of two of sobol and zsobol).
    auto dir = scratch_dir("cli-sample-range");
    const auto out = dir / "out.exr";
    struct Case {
        std::string options, message;
    };
    const std::vector<Case> cases = {
        {"--spp 2000000000", "--spp must be a whole number of samples, at most 1073741824 (got 2000000000)"},
        {"--spp 1073741825 --sampler sobol", "at most 1073741824"},
        {"--spp 8 --samples 0:2000000000", "--samples 0:2000000000 reaches past --spp 8"},
        {"-D spp=3000000000", "lies beyond the integers Candela reads"},
    };
    for (const Case& c : cases) {
        INFO(c.options);
        CHECK(run_command(render_cmd("'" + Cbox + "' -o '" + out.string() + "' -D res=8 " + c.options), dir / "log.txt") == 2);
        const std::string log = read_text(dir / "log.txt");
        INFO(log);
        CHECK_THAT(log, Catch::Contains(c.message));
        CHECK_FALSE(std::filesystem::exists(out));
    }
}

TEST_CASE("cli: -s/--sensor chooses which of a scene's sensors to render (mitsuba -s), in farm parts too", "[cli]") {
    // Two cameras with films of different sizes, so the image says which one rendered. Mitsuba 3
    // loads every sensor of a scene and renders the one -s names (0 by default).
    auto dir = scratch_dir("cli-sensor");
    const std::string camera = R"(<sensor type="perspective"><float name="fov" value="40"/>
            <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="2"/></sampler>
            <film type="hdrfilm"><integer name="width" value="WIDTH"/><integer name="height" value="6"/></film></sensor>)";
    auto with_width = [&](const char* width) { return std::regex_replace(camera, std::regex("WIDTH"), width); };
    write_text(dir / "two.xml", "<scene version=\"3.0.0\">" + with_width("8") + with_width("12") +
                                    R"(<shape type="sphere"><bsdf type="diffuse"/></shape>
        <emitter type="constant"/></scene>)");
    const std::string scene = "'" + (dir / "two.xml").string() + "'";
    const auto out = dir / "out.exr";
    for (const auto& [option, width] : std::vector<std::pair<std::string, int>>{{"", 8}, {"-s 0", 8}, {"-s 1", 12}, {"--sensor 1", 12}}) {
        INFO(option);
        REQUIRE(run_command(render_cmd(scene + " -o '" + out.string() + "' -q " + option), dir / "log.txt") == 0);
        CHECK(read_image(out.string()).width() == width);
    }
    std::filesystem::remove(out);
    CHECK(run_command(render_cmd(scene + " -o '" + out.string() + "' --sensor 2"), dir / "log.txt") == 2);
    CHECK_THAT(read_text(dir / "log.txt"),
               Catch::Contains("two.xml") && Catch::Contains("sensor index 2 is out of range: the scene has 2 sensors (indices 0 to 1)"));
    CHECK_FALSE(std::filesystem::exists(out));
    // A farm's parts render the same sensor, and a part of another sensor is another render.
    const std::string farm = "'" + candela_binary() + "' farm plan " + scene + " -o '" + (dir / "farm.exr").string() + "' --parts 2 -s 1";
    REQUIRE(run_command(farm + " 2>/dev/null", dir / "farm.txt") == 0);
    const std::string commands = read_text(dir / "farm.txt");
    INFO(commands);
    CHECK_THAT(commands, Catch::Contains("--sensor 1"));
}
