// Numerical robustness of the whole renderer: inputs at the edges of the models (degenerate
// triangles, zero-area emitters, alpha = 0 rough BSDFs, index-matched dielectrics, shading normals
// that face away or graze, scenes at 1e-6 and 1e6 scale, reflectances outside [0, 1]) render
// finite images, or stop with file:line where the input means nothing; and what the pixel loop
// drops as non-finite is counted, reported and recorded.
//
// How two renders are compared (`agree`): both carry the variance AOV (the variance of each
// pixel mean). The image is cut into 4 x 4-pixel blocks; per block and channel,
// z = (mean_a - mean_b) / sqrt(var_a + var_b), with the block variance the sum of its pixels'
// variances over 16^2. The renders use independent seeds unless noted; with the same seed the
// two estimates are positively correlated and the test is conservative. All 3 x 64 tests run
// at a family-wise 1% (Sidak). Power: every comparison also checks that the same test rejects
// the reference scene with its light 10% brighter (a shift of about 10 standard errors per
// block at these sample counts).

#include "analysis/statistics.h"
#include "core/image.h"
#include "core/integrator.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "core/warning.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

using namespace candela;
using namespace candela::test;

namespace {

constexpr int Res = 32, Block = 4, Spp = 64;

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}
std::string xyz(double x, double y, double z, double s) { return num(x * s) + ", " + num(y * s) + ", " + num(z * s); }

// A small box: floor and back wall (diffuse), an area light above, and `object` (a shape's
// inner XML: its bsdf) on a sphere of radius 0.5 standing on the floor; every length times `s`.
std::string box_scene(double s, const std::string& object_bsdf, double radiance = 5.0, bool with_object = true,
                      const std::string& floor = "") {
    // Unbounded paths (Russian roulette ends them): crossing an invisible interface still counts
    // as a bounce, so a depth limit would cut paths from one scene that it keeps in the other.
    std::string x =
        "<integrator type=\"path\"><integer name=\"max_depth\" value=\"-1\"/></integrator>\n"
        "<sensor type=\"perspective\"><float name=\"fov\" value=\"45\"/>\n"
        // The clipping distances are lengths too (Mitsuba's defaults: 0.01 and 1e4).
        "<float name=\"near_clip\" value=\"" +
        num(0.01 * s) + "\"/><float name=\"far_clip\" value=\"" + num(1e4 * s) +
        "\"/>\n"
        "<transform name=\"to_world\"><lookat origin=\"" +
        xyz(0, 1, 3.5, s) + "\" target=\"" + xyz(0, 0.7, 0, s) +
        "\" up=\"0, 1, 0\"/></transform>\n"
        "<sampler type=\"independent\"><integer name=\"sample_count\" value=\"" +
        std::to_string(Spp) +
        "\"/></sampler>\n"
        "<film type=\"hdrfilm\"><integer name=\"width\" value=\"" +
        std::to_string(Res) + "\"/><integer name=\"height\" value=\"" + std::to_string(Res) +
        "\"/><rfilter type=\"box\"/></film></sensor>\n";
    x += floor.empty() ? "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"" + num(2 * s) +
                             "\"/><rotate x=\"1\" angle=\"-90\"/></transform><bsdf type=\"diffuse\"/></shape>\n"
                       : floor;
    x += "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"" + num(2 * s) + "\"/><translate value=\"" +
         xyz(0, 1, -1, s) + "\"/></transform><bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"0.6, 0.3, 0.2\"/></bsdf></shape>\n";
    x += "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"" + num(0.5 * s) +
         "\"/><rotate x=\"1\" angle=\"90\"/><translate value=\"" + xyz(0, 2, 0, s) +
         "\"/></transform><emitter type=\"area\"><rgb name=\"radiance\" value=\"" + num(radiance) + "\"/></emitter></shape>\n";
    if (with_object)
        x += "<shape type=\"sphere\"><float name=\"radius\" value=\"" + num(0.5 * s) + "\"/><point name=\"center\" value=\"" +
             xyz(0, 0.5, 0, s) + "\"/>\n" + object_bsdf + "</shape>\n";
    return x;
}

RenderResult render_scene(const std::string& name, const std::string& body, uint64_t seed) {
    Ref<Scene> scene = load_scene_xml(name, body);
    RenderOptions options;
    options.seed = seed;
    options.aovs = {"variance"};
    return scene->integrator().render(*scene, options);
}

// Every value finite and nothing dropped.
void check_finite(const RenderResult& r) {
    CHECK(r.stats.nonfinite == 0);
    int nonfinite = 0;
    for (float v : r.image.data()) nonfinite += !std::isfinite(v);
    CHECK(nonfinite == 0);
}

// The block z-test described at the top of the file; `worst` receives the largest |z|.
bool agree(const Image& a, const Image& b, double* worst = nullptr) {
    const int blocks = Res / Block, tests = blocks * blocks * 3;
    const double threshold = two_sided_z(sidak(0.01, tests));
    const int va = a.channel_index("variance.R"), vb = b.channel_index("variance.R");
    REQUIRE(va >= 0);
    REQUIRE(vb >= 0);
    double max_z = 0.0;
    for (int by = 0; by < blocks; ++by)
        for (int bx = 0; bx < blocks; ++bx)
            for (int c = 0; c < 3; ++c) {
                double ma = 0, mb = 0, var = 0;
                for (int y = by * Block; y < (by + 1) * Block; ++y)
                    for (int x = bx * Block; x < (bx + 1) * Block; ++x) {
                        ma += a.at(x, y, c);
                        mb += b.at(x, y, c);
                        var += double(a.at(x, y, va + c)) + b.at(x, y, vb + c);
                    }
                const double n = Block * Block;
                // A floor of 1e-5 relative for noiseless blocks (float rounding of the sums).
                double sd = std::sqrt(var / (n * n) + std::pow(1e-5 * std::max(std::abs(ma), std::abs(mb)) / n, 2));
                double z = sd > 0 ? std::abs(ma - mb) / n / sd : (ma == mb ? 0.0 : INFINITY);
                max_z = std::max(max_z, z);
            }
    if (worst) *worst = max_z;
    return max_z <= threshold;
}

// `test` (rendered with seed 2) agrees with `reference` (seed 1), and the test has the power
// to see the reference's light 10% brighter.
void check_agrees(const std::string& name, const std::string& test, const std::string& reference, const std::string& brighter_reference) {
    RenderResult t = render_scene(name + "-test", test, 2), r = render_scene(name + "-ref", reference, 1);
    check_finite(t);
    check_finite(r);
    double z = 0;
    bool same = agree(t.image, r.image, &z);
    INFO(name << ": largest block |z| " << z);
    CHECK(same);
    RenderResult bright = render_scene(name + "-bright", brighter_reference, 1);
    bool sees_change = !agree(t.image, bright.image, &z);
    INFO(name << ": largest block |z| against the brighter light " << z);
    CHECK(sees_change);
}

void write_file(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

// Loads `body` from a scratch scene; the SceneError's message and line, or "" when it loaded.
std::string load_error(const std::string& name, const std::string& body, int* line = nullptr) {
    try {
        load_scene_xml(name, body);
    } catch (const SceneError& e) {
        if (line) *line = e.location.line;
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("robustness: scenes scaled by 1e-6 and 1e6 render the unscaled image", "[robustness][scale]") {
    const std::string bsdf = "<bsdf type=\"roughconductor\"><float name=\"alpha\" value=\"0.2\"/></bsdf>";
    for (double s : {1e-6, 1e6}) {
        INFO("scale " << s);
        check_agrees("scale-" + num(s), box_scene(s, bsdf), box_scene(1.0, bsdf), box_scene(1.0, bsdf, 5.5));
    }
}

TEST_CASE("robustness: rough BSDFs with alpha = 0 render as their smooth counterparts", "[robustness][alpha]") {
    struct Pair {
        const char* name;
        std::string rough, smooth;
    };
    const Pair pairs[] = {
        {"conductor-ggx",
         "<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"0\"/></bsdf>",
         "<bsdf type=\"conductor\"/>"},
        {"conductor-beckmann",
         "<bsdf type=\"roughconductor\"><float name=\"alpha_u\" value=\"0\"/><float name=\"alpha_v\" value=\"0\"/></bsdf>",
         "<bsdf type=\"conductor\"/>"},
        {"dielectric", "<bsdf type=\"roughdielectric\"><float name=\"alpha\" value=\"0\"/></bsdf>", "<bsdf type=\"dielectric\"/>"},
        {"plastic", "<bsdf type=\"roughplastic\"><float name=\"alpha\" value=\"0\"/></bsdf>", "<bsdf type=\"plastic\"/>"},
    };
    for (const Pair& p : pairs) {
        INFO(p.name);
        check_agrees(std::string("alpha0-") + p.name, box_scene(1, p.rough), box_scene(1, p.smooth), box_scene(1, p.smooth, 5.5));
    }
    // A negative roughness still means nothing.
    int line = 0;
    CHECK_THAT(load_error("alpha-negative", "<bsdf type=\"roughconductor\">\n<float name=\"alpha\" value=\"-0.1\"/></bsdf>", &line),
               Catch::Contains("must not be negative"));
    CHECK(line == 3);
}

TEST_CASE("robustness: dielectrics of index 1 are invisible", "[robustness][ior]") {
    const std::string matched = "<float name=\"int_ior\" value=\"1.33\"/><float name=\"ext_ior\" value=\"1.33\"/>";
    const std::string without = box_scene(1, "", 5.0, false), brighter = box_scene(1, "", 5.5, false);
    check_agrees("ior1-smooth", box_scene(1, "<bsdf type=\"dielectric\">" + matched + "</bsdf>"), without, brighter);
    check_agrees("ior1-rough", box_scene(1, "<bsdf type=\"roughdielectric\"><float name=\"alpha\" value=\"0.3\"/>" + matched + "</bsdf>"),
                 without, brighter);
    check_agrees("ior1-thin", box_scene(1, "<bsdf type=\"thindielectric\">" + matched + "</bsdf>"), without, brighter);
}

TEST_CASE("robustness: degenerate triangles are dropped, and a mesh of nothing else is an error", "[robustness][mesh]") {
    auto dir = scratch_dir("robust-degenerate");
    const std::string quad = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n";
    const std::string faces = "f 1 3 2\nf 1 4 3\n";
    // Repeated corners, collinear corners, and a sliver whose area underflows.
    // Repeated corners, collinear corners, and a sliver whose area underflows to 0 in float.
    const std::string extra = "v 0 0 0\nv 1e-30 0 0\nv 0 0 1e-30\nv 0 0 -1\n";
    const std::string degenerate = "f 1 1 2\nf 1 8 2\nf 5 6 7\nf 3 3 3\n";
    write_file(dir / "clean.obj", quad + extra + faces);
    write_file(dir / "dirty.obj", quad + extra + degenerate + faces);
    write_file(dir / "nothing.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n");
    auto floor = [&](const std::string& file) {
        return "<shape type=\"obj\"><string name=\"filename\" value=\"" + (dir / file).string() +
               "\"/><transform name=\"to_world\"><scale value=\"2\"/></transform><bsdf type=\"diffuse\"/></shape>\n";
    };
    const std::string sphere = "<bsdf type=\"diffuse\"/>";
    RenderResult clean = render_scene("degenerate-clean", box_scene(1, sphere, 5, true, floor("clean.obj")), 1);
    RenderResult dirty = render_scene("degenerate-dirty", box_scene(1, sphere, 5, true, floor("dirty.obj")), 1);
    check_finite(dirty);
    // The dropped triangles leave the same mesh: the same image, bit for bit.
    CHECK(dirty.image.data() == clean.image.data());
    // As an emitter, too.
    auto light = [&](const std::string& file) {
        return "<shape type=\"obj\"><string name=\"filename\" value=\"" + (dir / file).string() +
               "\"/><transform name=\"to_world\"><scale value=\"0.3\"/><translate y=\"1.9\"/></transform><emitter type=\"area\"/></shape>\n";
    };
    RenderResult lit_clean = render_scene("degenerate-light-clean", box_scene(1, sphere) + light("clean.obj"), 1);
    RenderResult lit_dirty = render_scene("degenerate-light-dirty", box_scene(1, sphere) + light("dirty.obj"), 1);
    check_finite(lit_dirty);
    CHECK(lit_dirty.image.data() == lit_clean.image.data());
    int line = 0;
    std::string error = load_error("degenerate-nothing",
                                   "<shape type=\"obj\">\n<string name=\"filename\" value=\"" + (dir / "nothing.obj").string() +
                                       "\"/><emitter type=\"area\"/></shape>",
                                   &line);
    // Mesh data errors name the mesh file, at the line of its filename property.
    CHECK_THAT(error, Catch::Contains("nothing.obj\": no triangle has a non-zero area"));
    CHECK(line == 3);
}

TEST_CASE("robustness: shading normals that face away or graze give finite images", "[robustness][normals]") {
    auto dir = scratch_dir("robust-normals");
    // A floor quad whose vertex normals face away from its face (-y), lie in its plane (grazing)
    // or nearly so, or vanish.
    struct Normals {
        const char* name;
        const char* n;
    };
    const Normals cases[] = {{"backfacing", "0 -1 0"}, {"grazing", "1 0 0"}, {"near-grazing", "1 1e-6 0"}, {"zero", "0 0 0"}};
    const char* bsdfs[] = {"<bsdf type=\"diffuse\"/>",         "<bsdf type=\"plastic\"/>",
                           "<bsdf type=\"roughconductor\"/>",  "<bsdf type=\"dielectric\"/>",
                           "<bsdf type=\"roughdielectric\"/>", "<bsdf type=\"twosided\"><bsdf type=\"roughplastic\"/></bsdf>"};
    for (const Normals& c : cases) {
        std::string obj = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nvn " + std::string(c.n) + "\nf 1//1 3//1 2//1\nf 1//1 4//1 3//1\n";
        write_file(dir / (std::string(c.name) + ".obj"), obj);
        for (const char* bsdf : bsdfs) {
            INFO(c.name << " " << bsdf);
            std::string floor = "<shape type=\"obj\"><string name=\"filename\" value=\"" + (dir / (std::string(c.name) + ".obj")).string() +
                                "\"/><transform name=\"to_world\"><scale value=\"2\"/></transform>" + bsdf + "</shape>\n";
            check_finite(render_scene("normals", box_scene(1, bsdf, 5, true, floor), 1));
        }
    }
}

TEST_CASE("robustness: a reflectance above 1 is a warning at its line, a negative one an error", "[robustness][reflectance]") {
    std::vector<std::string> warnings;
    WarningSink previous = set_warning_sink([&](const std::string& w) { warnings.push_back(w); });
    std::string error =
        load_error("reflectance-high", "<bsdf type=\"diffuse\">\n<rgb name=\"reflectance\" value=\"1.5, 0.5, 0.5\"/></bsdf>");
    set_warning_sink(previous);
    CHECK(error == "");
    REQUIRE(warnings.size() == 1);
    CHECK_THAT(warnings[0], Catch::Contains("scene.xml:3: warning: reflectance (1.5, 0.5, 0.5) exceeds 1, which is physically impossible"));
    int line = 0;
    for (const char* bad : {"<bsdf type=\"diffuse\">\n<rgb name=\"reflectance\" value=\"-1\"/></bsdf>",
                            "<bsdf type=\"plastic\">\n<rgb name=\"diffuse_reflectance\" value=\"0.5, -0.1, 0.5\"/></bsdf>",
                            "<bsdf type=\"dielectric\">\n<float name=\"specular_transmittance\" value=\"-2\"/></bsdf>"}) {
        INFO(bad);
        CHECK_THAT(load_error("reflectance-negative", bad, &line), Catch::Contains("is not a reflectance: it must lie between 0 and 1"));
        CHECK(line == 3);
    }
}

namespace {
// Returns NaN for a quarter of the samples and +inf for another quarter, 1 otherwise.
class PoisonedIntegrator final : public SamplingIntegrator {
public:
    Spectrum sample_radiance(const Scene&, Sampler& sampler, const Ray&, SampleRecord&) const override {
        float u = sampler.next_1d();
        if (u < 0.25f) return Spectrum(NAN);
        if (u < 0.5f) return Spectrum(0.0f, INFINITY, 0.0f);
        return Spectrum(1.0f);
    }
};
}  // namespace

TEST_CASE("robustness: non-finite samples are dropped and counted, never written", "[robustness][nonfinite]") {
    Ref<Scene> scene = load_scene_xml("poisoned", pinhole_camera("0, 0, 1", "0, 0, 0", 16, 16) + "<shape type=\"sphere\"/>");
    PoisonedIntegrator integrator;
    RenderOptions options;
    options.spp = 16;
    options.aovs = {"variance", "albedo"};
    RenderResult r = integrator.render(*scene, options);
    // About half of 4096 samples: the binomial's standard deviation is 32, so [1800, 2300]
    // covers it by more than 7 sigma.
    CHECK(r.stats.samples == 16 * 16 * 16);
    CHECK(r.stats.nonfinite > 1800);
    CHECK(r.stats.nonfinite < 2300);
    for (float v : r.image.data()) REQUIRE(std::isfinite(v));
    // What survives is the constant 1.
    CHECK(r.image.at(8, 8, 0) == 1.0f);
}

TEST_CASE("robustness: finite samples too large to sum in a pixel are dropped, and the image stays finite", "[robustness][nonfinite]") {
    // Every sample sees an emitter of 3e38, a finite float: 16 of them summed into one pixel of
    // a float image block overflow to infinity (fuzz_image found it with a PFM texture of such
    // values). Samples beyond MaxSampleMagnitude (1e30) are dropped and counted instead.
    Ref<Scene> scene = load_scene_xml("huge", pinhole_camera("0, 0, 1", "0, 0, 0", 8, 8) +
                                                  "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"10\"/></transform>"
                                                  "<emitter type=\"area\"><rgb name=\"radiance\" value=\"3e38\"/></emitter></shape>");
    RenderOptions options;
    options.spp = 16;
    RenderResult r = scene->integrator().render(*scene, options);
    CHECK(r.stats.nonfinite == 8 * 8 * 16);
    for (float v : r.image.data()) REQUIRE(std::isfinite(v));
}

TEST_CASE("robustness: the count of dropped samples is printed and kept in the EXR", "[robustness][nonfinite][cli]") {
    auto dir = scratch_dir("robust-overflow");
    // A light at the largest float radiance close above a white floor: direct lighting
    // overflows to infinity, which the pixel loop must drop, count and report.
    write_text(
        dir / "scene.xml",
        scene_xml(
            pinhole_camera("0, 0.02, 3", "0, 0, 0", 16, 16) +
            "<shape type=\"rectangle\"><transform name=\"to_world\"><rotate x=\"1\" angle=\"-90\"/></transform>"
            "<bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"1\"/></bsdf></shape>\n"
            "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"3\"/><rotate x=\"1\" angle=\"90\"/><translate y=\"0.05\"/></transform>"
            "<emitter type=\"area\"><rgb name=\"radiance\" value=\"3.4e38\"/></emitter></shape>"));
    int code = run_command(
        "'" + candela_binary() + "' render '" + (dir / "scene.xml").string() + "' -o '" + (dir / "out.exr").string() + "' --spp 4",
        dir / "log.txt");
    std::string log = read_text(dir / "log.txt");
    INFO(log);
    REQUIRE(code == 0);
    CHECK_THAT(log, Catch::Contains("samples were NaN, infinite or beyond 1e30 and were dropped"));
    Image img = read_image((dir / "out.exr").string());
    REQUIRE(img.metadata.count("candela.nonfiniteSamples") == 1);
    CHECK(std::stoll(img.metadata["candela.nonfiniteSamples"]) > 0);
    for (float v : img.data()) REQUIRE(std::isfinite(v));
}
