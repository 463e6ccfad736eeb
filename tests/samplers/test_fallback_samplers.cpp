// FALLBACK samplers: Mitsuba 3's stratified, multijitter, orthogonal and ldsampler load with their
// parameters, round the sample count as Mitsuba does, warn once, and render exactly what the
// independent sampler renders with that count and seed (until they are implemented).

#include "core/warning.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstring>

using namespace candela;
using namespace candela::test;

namespace {

std::string scene_with_sampler(const std::string& sampler) {
    std::string scene = read_text(source_path("scenes/validation/cbox.xml"));
    const std::string from = "<sampler type=\"independent\">", to = "</sampler>";
    size_t a = scene.find(from), b = scene.find(to, a);
    return scene.substr(0, a) + sampler + scene.substr(b + to.size());
}

}  // namespace

TEST_CASE("samplers: Mitsuba's other samplers load and fall back to the independent sampler", "[sampler]") {
    struct Case {
        std::string xml;
        int requested, rounded;
    };
    const std::vector<Case> cases = {
        {R"(<sampler type="stratified"><integer name="sample_count" value="5"/><boolean name="jitter" value="false"/>
            <integer name="seed" value="3"/></sampler>)", 5, 9},
        {R"(<sampler type="multijitter"><integer name="sample_count" value="5"/><boolean name="jitter" value="true"/>
            <integer name="seed" value="3"/></sampler>)", 5, 6},
        {R"(<sampler type="orthogonal"><integer name="sample_count" value="16"/><integer name="strength" value="2"/>
            <boolean name="jitter" value="true"/><integer name="seed" value="3"/></sampler>)", 16, 25},
        {R"(<sampler type="ldsampler"><integer name="sample_count" value="17"/><integer name="seed" value="3"/></sampler>)", 17, 64},
        {R"(<sampler type="stratified"><integer name="sample_count" value="4"/><integer name="seed" value="3"/></sampler>)", 4, 4},
    };
    auto dir = scratch_dir("fallback-samplers");
    for (const Case& c : cases) {
        INFO(c.xml);
        std::vector<std::string> warnings;
        WarningSink previous = set_warning_sink([&](const std::string& line) { warnings.push_back(line); });
        write_text(dir / "fallback.xml", scene_with_sampler(c.xml));
        Ref<Scene> scene = load_scene((dir / "fallback.xml").string(), {{"res", "16"}});
        set_warning_sink(previous);
        REQUIRE(warnings.size() == 1);
        CHECK_THAT(warnings[0], Catch::Contains("fallback.xml:") && Catch::Contains("is not implemented yet; using the independent sampler instead (sample_count " +
                                                                                  std::to_string(c.rounded)));
        if (c.rounded != c.requested) CHECK_THAT(warnings[0], Catch::Contains(std::to_string(c.requested) + " rounded as Mitsuba does"));
        // The same image, bit for bit, as the independent sampler with the rounded count and seed.
        write_text(dir / "independent.xml",
                   scene_with_sampler("<sampler type=\"independent\"><integer name=\"sample_count\" value=\"" + std::to_string(c.rounded) +
                                      "\"/><integer name=\"seed\" value=\"3\"/></sampler>"));
        RenderResult fallback = scene->integrator().render(*scene, RenderOptions());
        RenderResult independent = render_file((dir / "independent.xml").string(), {{"res", "16"}});
        REQUIRE(fallback.image.data().size() == independent.image.data().size());
        CHECK(std::memcmp(fallback.image.data().data(), independent.image.data().data(), fallback.image.data().size() * sizeof(float)) == 0);
    }
}

TEST_CASE("samplers: the fallback samplers check their parameters", "[sampler][errors]") {
    auto dir = scratch_dir("fallback-sampler-errors");
    std::vector<std::string> warnings;
    WarningSink previous = set_warning_sink([&](const std::string& line) { warnings.push_back(line); });
    struct Case {
        std::string xml;
        const char* message;
    };
    const std::vector<Case> cases = {
        {"<sampler type=\"stratified\"><float name=\"jitter\" value=\"1\"/></sampler>", "has type float, expected boolean"},
        {"<sampler type=\"ldsampler\"><boolean name=\"jitter\" value=\"true\"/></sampler>", "unused property \"jitter\""},
        {"<sampler type=\"orthogonal\"><integer name=\"strength\" value=\"1\"/></sampler>", "strength must be at least 2"},
        {"<sampler type=\"multijitter\"><integer name=\"sample_count\" value=\"0\"/></sampler>", "sample_count must be positive"},
        {"<sampler type=\"sobol\"/>", "unknown sampler type \"sobol\" (nearest supported:"},
    };
    for (const Case& c : cases) {
        INFO(c.xml);
        write_text(dir / "scene.xml", scene_with_sampler(c.xml));
        CHECK_THROWS_WITH(load_scene((dir / "scene.xml").string()), Catch::Contains(c.message));
    }
    set_warning_sink(previous);
}
