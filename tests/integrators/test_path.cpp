// The path tracer end to end: the analytic furnace (with error bars from the render itself) and
// scale robustness of ray offsets.

#include "core/ray.h"
#include "core/scene.h"
#include "core/xml.h"
#include "integrators/estimators.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <regex>

using namespace candela;
using namespace candela::test;

namespace {

// Every pixel of a furnace has the same expectation and (box filter) independent samples: the
// pixel values are i.i.d., so their mean has a standard error computed from their spread.
MeanAndError pixel_mean(const Image& img, int channel) {
    std::vector<double> v;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) v.push_back(img.at(x, y, channel));
    return mean_and_error(v);
}

constexpr int FurnaceTests = 10;  // the z-tests below share a 1% family-wise level (Sidak)

void check_furnace(double rho, int max_depth, double expected, const SceneParameters& extra = {}) {
    SceneParameters p = {{"rho", std::to_string(rho)}, {"max_depth", std::to_string(max_depth)}, {"Le", "1"}};
    for (auto& [k, v] : extra) p[k] = v;
    RenderResult r = render_file(source_path("scenes/furnace/closed_sphere.xml"), p);
    MeanAndError m = pixel_mean(r.image, 0);
    double z = two_sided_z(sidak(0.01, FurnaceTests));
    INFO("rho " << rho << " max_depth " << max_depth << ": mean " << m.mean << " +- " << m.std_error << " expected " << expected
                << " (z threshold " << z << ")");
    // Beyond the noise, two systematic effects of float32 arithmetic: ray offsets move path
    // vertices by up to OffsetSafety * sqrt(3) * gamma_7 of their magnitude at each end of a
    // segment, and accumulation rounds at about 1e-6. They matter only where the estimator has
    // (next to) no variance, as at max_depth 1 and 2 here.
    const double systematic = 2.0 * OffsetSafety * std::sqrt(3.0) * gamma_bound(7) + 1e-6;
    CHECK(std::abs(m.mean - expected) <= z * m.std_error + systematic * expected);
    CHECK(m.std_error < 0.01 * expected);  // the test has power: errors of 1% and more would show
    CHECK(r.stats.nonfinite == 0);
}

}  // namespace

TEST_CASE("furnace: a closed emitting diffuse sphere renders Le / (1 - rho)", "[render][furnace]") {
    check_furnace(0.5, -1, 2.0);
    check_furnace(0.9, -1, 10.0, {{"spp", "256"}});
}

TEST_CASE("furnace: max_depth truncates the path sum (Mitsuba semantics)", "[render][furnace]") {
    check_furnace(0.5, 3, 1.0 + 0.5 + 0.25);  // emitters seen directly, one and two bounces
    check_furnace(0.8, 1, 1.0);               // only emitters seen directly
    check_furnace(0.8, 2, 1.8);               // direct illumination
}

TEST_CASE("furnace: ray offsets hold when the scene is scaled by 1000 or by 1/1000", "[render][furnace]") {
    check_furnace(0.5, -1, 2.0, {{"radius", "1000"}});
    check_furnace(0.5, -1, 2.0, {{"radius", "0.001"}, {"near_clip", "1e-5"}});
}

TEST_CASE("furnace: lossless BSDFs under a uniform environment render exactly 1", "[render][furnace]") {
    for (const char* name : {"white_diffuse", "white_dielectric", "white_conductor"}) {
        RenderResult r = render_file(source_path(std::string("scenes/furnace/") + name + ".xml"), {});
        MeanAndError m = pixel_mean(r.image, 1);
        double z = two_sided_z(sidak(0.01, FurnaceTests));
        INFO(name << ": mean " << m.mean << " +- " << m.std_error);
        const double systematic = 2.0 * OffsetSafety * std::sqrt(3.0) * gamma_bound(7) + 1e-6;
        CHECK(std::abs(m.mean - 1.0) <= z * m.std_error + systematic);
        CHECK(m.std_error < 0.01);
        CHECK(r.stats.nonfinite == 0);
    }
}

TEST_CASE("integrator settings: path and irradiance report a bad light_sampler or rr_depth at its line", "[render][errors]") {
    auto dir = scratch_dir("path-settings");
    struct Case {
        const char* property;  // on line 3 of the scene, after max_depth on line 2
        const char* message;
    };
    const Case cases[] = {{"<string name=\"light_sampler\" value=\"bogus\"/>", "unknown light_sampler \"bogus\""},
                          {"<integer name=\"rr_depth\" value=\"0\"/>", "rr_depth must be positive"}};
    for (const char* type : {"path", "irradiance"})
        for (const Case& c : cases) {
            // scene_xml puts the body from line 2 on: the integrator, max_depth, then the bad property.
            write_text(dir / "scene.xml", scene_xml(std::string("<integrator type=\"") + type +
                                                    "\">\n<integer name=\"max_depth\" value=\"4\"/>\n" + c.property + "\n</integrator>"));
            INFO(type << ": " << c.property);
            try {
                load_scene((dir / "scene.xml").string());
                FAIL_CHECK("expected an error");
            } catch (const SceneError& e) {
                CHECK(e.location.line == 4);
                CHECK_THAT(std::string(e.what()), Catch::Contains(c.message));
            }
        }
}

TEST_CASE("integrator settings: the estimators refuse the same bad settings", "[estimate][errors]") {
    auto dir = scratch_dir("estimator-settings");
    write_text(dir / "scene.xml", scene_xml("<emitter type=\"constant\"/>"));
    Ref<Scene> scene = load_scene((dir / "scene.xml").string());
    EstimatorOptions o;
    o.samples = 16;
    o.path.light_sampler = "bogus";
    CHECK_THROWS_WITH(estimate_irradiance(*scene, Vec3(0.0f), Vec3(0, 1, 0), o), Catch::Contains("unknown light_sampler \"bogus\""));
    o.path.light_sampler = "tree";
    o.path.rr_depth = 0;
    CHECK_THROWS_WITH(estimate_radiance(*scene, Vec3(0.0f), Vec3(0, 1, 0), o), Catch::Contains("rr_depth must be positive"));
}

TEST_CASE("prb: Mitsuba's PRB integrator renders forward as the path tracer with prb's defaults", "[render]") {
    // PRB's primal estimate is the path tracer's; its max_depth defaults to 6 (path's: unbounded).
    // The validation Cornell box, 8 x 8, same seed: prb equals path with max_depth 6 bit for bit.
    auto render_with = [](const std::string& integrator) {
        std::string xml = read_text(source_path("scenes/validation/cbox.xml"));
        xml = std::regex_replace(xml, std::regex(R"(<integrator type="path">[\s\S]*?</integrator>)"), integrator);
        Ref<Scene> scene = load_scene_from_string(xml, source_path("scenes/validation/prb.xml"), {{"res", "8"}, {"spp", "16"}});
        RenderOptions options;
        options.seed = 11;
        return scene->integrator().render(*scene, options).image.data();
    };
    const auto prb = render_with(R"(<integrator type="prb"/>)");
    CHECK(prb == render_with(R"(<integrator type="path"><integer name="max_depth" value="6"/></integrator>)"));
    CHECK(prb != render_with(R"(<integrator type="path"/>)"));
    CHECK(render_with(
              R"(<integrator type="prb"><integer name="max_depth" value="3"/><boolean name="hide_emitters" value="true"/></integrator>)") ==
          render_with(
              R"(<integrator type="path"><integer name="max_depth" value="3"/><boolean name="hide_emitters" value="true"/></integrator>)"));
    // As Mitsuba's, not in the polarized variant.
    CHECK_THROWS_WITH(load_scene_from_string(scene_xml(R"(<integrator type="prb"/>)"), "prb.xml", {}, Variant::ScalarSpectralPolarized),
                      Catch::Contains("prb does not render in variant scalar_spectral_polarized"));
}

TEST_CASE("path: Russian roulette ends a path before its next ray is traced (Mitsuba's order)", "[render][furnace]") {
    // The closed furnace sphere (albedo 0.5, Le 1) with roulette from the first vertex: at each
    // vertex q = min(max(beta), 0.95) = 0.5 and a survivor's beta returns to 1, so a path has
    // 1 + G vertices with G geometric (P(G >= k) = 0.5^k): E = 2, variance 2. Each vertex traces one
    // shadow ray (every point of the sphere faces every other inside it) and, if it survives,
    // its extension ray: 2 (1 + G) rays per sample, mean 4, variance 8. Deciding the roulette
    // after tracing the extension ray (as Candela did before) gives 5.
    std::string xml = read_text(source_path("scenes/furnace/closed_sphere.xml"));
    xml = std::regex_replace(xml, std::regex(R"(<integer name="max_depth" value="\$max_depth"/>)"),
                             R"($&<integer name="rr_depth" value="1"/>)");
    Ref<Scene> scene = load_scene_from_string(xml, source_path("scenes/furnace/roulette.xml"), {{"res", "16"}, {"spp", "256"}});
    RenderOptions options;
    options.seed = 3;
    RenderResult r = scene->integrator().render(*scene, options);
    const double n = double(r.stats.samples), z = two_sided_z(sidak(0.01, 2));
    const double rays_per_sample = double(r.stats.rays) / n;
    INFO("rays per sample " << rays_per_sample << " over " << n << " samples");
    CHECK(std::abs(rays_per_sample - 4.0) <= z * std::sqrt(8.0 / n));
    MeanAndError m = pixel_mean(r.image, 0);
    INFO("mean " << m.mean << " +- " << m.std_error);
    CHECK(std::abs(m.mean - 2.0) <= z * m.std_error);
}

TEST_CASE("path and volpath render a scene without media bit for bit", "[render]") {
    // One surface vertex (integrators/surface_step.h) and one order of its numbers and roulette:
    // without media volpath is the path tracer. Diffuse walls and a glass sphere (its eta^2 in
    // the roulette), the scenes' samplers and ldsampler.
    for (const char* name : {"cbox", "glass"})
        for (const char* sampler : {"", "ldsampler"}) {
            auto render_with = [&](const std::string& integrator) {
                std::string xml = read_text(source_path(std::string("scenes/validation/") + name + ".xml"));
                xml = std::regex_replace(xml, std::regex(R"(<integrator type="path">)"), "<integrator type=\"" + integrator + "\">");
                Ref<Scene> scene =
                    load_scene_from_string(xml, source_path("scenes/validation/volpath.xml"), {{"res", "16"}, {"spp", "16"}});
                RenderOptions options;
                options.seed = 5;
                options.sampler = sampler;
                return scene->integrator().render(*scene, options);
            };
            INFO(name << " with sampler '" << sampler << "'");
            const RenderResult path = render_with("path"), volpath = render_with("volpath");
            CHECK(path.image.data() == volpath.image.data());
            CHECK(path.stats.rays == volpath.stats.rays);
        }
}
