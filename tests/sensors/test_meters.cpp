// The measuring sensors (radiancemeter, irradiancemeter, distant) and the batch sensor:
// readings that are exact where every sample carries the same value (a uniform sky, a uniform
// emitter filling the view), analytic irradiance and coverage within the estimator's own
// error, a batch's slices against their sensors alone, the order of a scene's sensors, and the
// errors a scene can make. Statistical checks are z-tests on the render's variance layer, each
// family at a 1% family-wise level (Sidak).

#include "core/error.h"
#include "core/scene.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

const std::string SceneFile = "scenes/meters_test.xml";

// A 1 x 1 float32 film with a box filter and an independent sampler.
std::string pixel_film(int spp) {
    return R"(<film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/><rfilter type="box"/>
              <string name="component_format" value="float32"/></film>
              <sampler type="independent"><integer name="sample_count" value=")" +
           std::to_string(spp) + R"("/></sampler>)";
}

Ref<Scene> load(const std::string& body, int sensor = 0) {
    return load_scene_from_string(scene_xml(body), source_path(SceneFile), {}, Variant::ScalarRGB, sensor);
}

RenderResult render(const Scene& scene, uint64_t seed = 1, std::vector<std::string> aovs = {}) {
    RenderOptions options;
    options.seed = seed;
    options.aovs = std::move(aovs);
    options.threads = 2;
    return scene.integrator().render(scene, options);
}

Spectrum pixel(const Image& image, int x = 0) { return Spectrum(image.at(x, 0, 0), image.at(x, 0, 1), image.at(x, 0, 2)); }

// The scene fails to load with a SceneError whose message contains `message`, at line `line`.
void fails_at(const std::string& body, int line, const std::string& message) {
    INFO(body);
    try {
        load(body);
        FAIL("expected an error: " << message);
    } catch (const SceneError& e) {
        CHECK_THAT(e.message(), Catch::Contains(message));
        CHECK(e.location.line == line);
    }
}

const std::string Sky = R"(<emitter type="constant"><rgb name="radiance" value="0.5, 1, 2"/></emitter>)";

}  // namespace

TEST_CASE("radiancemeter: reads the radiance along its one ray, given by origin and direction or by to_world", "[sensor][meters]") {
    // A uniform emitter square facing +z at z = 0, the sky behind the meter.
    const std::string emitter = Sky + R"(
        <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="3, 4, 5"/></emitter></shape>)";
    auto reading = [&](const std::string& pose) {
        Ref<Scene> scene = load(emitter + R"(<sensor type="radiancemeter">)" + pose + pixel_film(16) + "</sensor>");
        return pixel(render(*scene).image);
    };
    const Spectrum toward = reading(R"(<point name="origin" value="0.2, 0.3, 2"/><vector name="direction" value="0.1, -0.1, -1"/>)");
    CHECK(toward.x == Approx(3.0f).epsilon(1e-6));
    CHECK(toward.y == Approx(4.0f).epsilon(1e-6));
    CHECK(toward.z == Approx(5.0f).epsilon(1e-6));
    const Spectrum away = reading(R"(<point name="origin" value="0.2, 0.3, 2"/><vector name="direction" value="0, 0, 1"/>)");
    CHECK(away.x == Approx(0.5f).epsilon(1e-6));
    CHECK(away.z == Approx(2.0f).epsilon(1e-6));
    // to_world: the meter looks along its +z; it wins over origin and direction, as in Mitsuba.
    const Spectrum posed = reading(R"(<transform name="to_world"><lookat origin="0, 0, 3" target="0, 0, 0" up="0, 1, 0"/></transform>
                                      <point name="origin" value="0, 0, 3"/><vector name="direction" value="0, 0, 1"/>)");
    CHECK(posed.y == Approx(4.0f).epsilon(1e-6));
    // A meter lying on the emitter's surface, looking away from it, sees the sky (its ray starts
    // past Mitsuba's ray epsilon).
    const Spectrum on_surface = reading(R"(<point name="origin" value="0, 0, 0"/><vector name="direction" value="0, 0, 1"/>)");
    CHECK(on_surface.y == Approx(1.0f).epsilon(1e-6));
}

TEST_CASE("radiancemeter: a disk seen at its exact centre reflects the sky (rays leaving the centre do not hit the disk)",
          "[sensor][meters][statistical]") {
    // Found with the radiancemeter: an untransformed disk's centre has no rounding error, so
    // rays leaving it start on the plane, and the disk took them as hits at t = 0: black.
    const int spp = effort_scaled(4096, 1024);
    Ref<Scene> scene = load(Sky + R"(<shape type="disk"/><sensor type="radiancemeter"><point name="origin" value="0, 0, 2"/>
        <vector name="direction" value="0, 0, -1"/>)" +
                            pixel_film(spp) + "</sensor>");
    const RenderResult r = render(*scene, 7, {"variance"});
    const double z = two_sided_z(sidak(0.01, 3));
    for (int ch = 0; ch < 3; ++ch) {
        // Mitsuba's default BSDF, diffuse of reflectance 0.5, under a uniform sky L: 0.5 L.
        const double expected = 0.5 * (ch == 0 ? 0.5 : ch == 1 ? 1.0 : 2.0);
        MeanAndVariance m = block_mean(r.image, ch, 0, 0, 1);
        INFO("channel " << ch << ": " << m.mean << " +- " << std::sqrt(m.variance_of_mean));
        CHECK(std::abs(m.mean - expected) <= z * std::sqrt(m.variance_of_mean));
        CHECK(std::sqrt(m.variance_of_mean) < 0.05 * expected);
    }
}

TEST_CASE("irradiancemeter: pi times a uniform sky's radiance, on a rectangle and on a sphere, in every sample", "[sensor][meters]") {
    for (const std::string& shape :
         {std::string(R"(<shape type="rectangle"><transform name="to_world"><rotate x="1" angle="30"/>
                                                        <scale value="3"/></transform>)"),
          std::string(R"(<shape type="sphere"><point name="center" value="1, 2, 3"/><float name="radius" value="0.7"/>)")}) {
        INFO(shape);
        Ref<Scene> scene = load(Sky + shape + R"(<sensor type="irradiancemeter">)" + pixel_film(256) + "</sensor></shape>");
        const Spectrum e = pixel(render(*scene).image);
        CHECK(e.x == Approx(0.5 * Pi).epsilon(1e-5));
        CHECK(e.y == Approx(1.0 * Pi).epsilon(1e-5));
        CHECK(e.z == Approx(2.0 * Pi).epsilon(1e-5));
    }
}

TEST_CASE("irradiancemeter: a sphere light's irradiance pi L (R / d)^2, by path and by ptracer, within their own error",
          "[sensor][meters][statistical]") {
    // A 2 mm square meter facing +z at the origin; a sphere light of radius 0.5 at distance 2:
    // E = pi L sin^2(alpha), sin(alpha) = R / d, over the whole meter to a relative 1e-6.
    const double expected = Pi * 2.0 * (0.5 / 2.0) * (0.5 / 2.0);
    const double z = two_sided_z(sidak(0.01, 6));
    for (const std::string integrator : {"path", "ptracer"}) {
        INFO(integrator);
        const int spp = effort_scaled(integrator == std::string("path") ? 65536 : 16384, 4096);
        Ref<Scene> scene = load(R"(<integrator type=")" + integrator + R"("/>
            <shape type="sphere"><point name="center" value="0, 0, 2"/><float name="radius" value="0.5"/>
                <emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>
            <shape type="rectangle"><transform name="to_world"><scale value="0.001"/></transform>
                <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
                <sensor type="irradiancemeter">)" +
                                pixel_film(spp) + "</sensor></shape>");
        const RenderResult r = render(*scene, 3, {"variance"});
        for (int ch = 0; ch < 3; ++ch) {
            MeanAndVariance m = block_mean(r.image, ch, 0, 0, 1);
            const double se = std::sqrt(m.variance_of_mean);
            INFO("channel " << ch << ": " << m.mean << " +- " << se << " against " << expected);
            CHECK(std::abs(m.mean - expected) <= z * se);
            CHECK(se < 0.03 * expected / std::sqrt(test_effort()));  // power: a 10% error would show
        }
    }
}

TEST_CASE("distant: the radiance leaving toward it, at a point, averaged over a target shape or the scene's cross-section",
          "[sensor][meters][statistical]") {
    // An emitter square of side 2 facing +z; the sensor looks down -z.
    const std::string emitter = R"(<shape type="rectangle"><emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>)";
    auto distant = [&](const std::string& target, int spp) {
        return load(emitter + R"(<sensor type="distant"><vector name="direction" value="0, 0, -1"/>)" + target + pixel_film(spp) +
                    "</sensor>");
    };
    // Every ray hits the emitter: exact.
    CHECK(pixel(render(*distant(R"(<point name="target" value="0.3, -0.2, 0"/>)", 16)).image).x == Approx(2.0f).epsilon(1e-6));
    CHECK(pixel(render(
                    *distant(R"(<shape type="rectangle" name="target"><transform name="to_world"><scale value="0.5"/></transform></shape>)",
                             16))
                    .image)
              .y == Approx(2.0f).epsilon(1e-6));
    // A target square of side 4 around it: a quarter of the rays hit, mean 0.5. The default
    // target, the scene's bounding sphere (radius sqrt 2, the square's), crossed by a disk of
    // area 2 pi: 2 * 4 / (2 pi).
    const double z = two_sided_z(sidak(0.01, 2));
    const int spp = effort_scaled(16384, 2048);
    struct Case {
        std::string target;
        double expected;
    };
    for (const Case& c :
         {Case{R"(<shape type="rectangle" name="target"><transform name="to_world"><scale value="2"/></transform></shape>)", 0.5},
          Case{"", 8.0 / (2.0 * Pi)}}) {
        INFO("target " << c.target);
        const RenderResult r = render(*distant(c.target, spp), 5, {"variance"});
        MeanAndVariance m = block_mean(r.image, 0, 0, 0, 1);
        const double se = std::sqrt(m.variance_of_mean);
        INFO(m.mean << " +- " << se << " against " << c.expected);
        CHECK(std::abs(m.mean - c.expected) <= z * se);
        CHECK(se < 0.02 / std::sqrt(test_effort()));
    }
}

TEST_CASE("batch: each slice of the film is its sensor's view at the slice's size, and meters in a batch keep their weights",
          "[sensor][meters]") {
    const std::string second = R"(<sensor type="perspective"><float name="fov" value="30"/>
            <transform name="to_world"><lookat origin="0.3, 0.2, 3" target="0, -0.3, 0" up="0, 1, 0"/></transform>)";
    const std::string first = R"(<sensor type="thinlens"><float name="fov" value="40"/><float name="aperture_radius" value="0.1"/>
            <float name="focus_distance" value="3"/>
            <transform name="to_world"><lookat origin="0, 0, 3.9" target="0, 0, 0" up="0, 1, 0"/></transform>)";
    // In the batch each sub-sensor keeps a film of another aspect, which the batch overrides.
    const std::string other_film = R"(<film type="hdrfilm"><integer name="width" value="100"/><integer name="height" value="50"/></film>)";
    Ref<Scene> batch =
        load(R"(<sensor type="batch">)" + first + other_film + "</sensor>" + second + other_film + "</sensor>" +
             R"(<film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="32"/></film></sensor>)");
    Ref<Scene> alone_first = load(first + box_film(32, 4) + "</sensor>");
    Ref<Scene> alone_second = load(second + box_film(32, 4) + "</sensor>");
    for (float y : {0.0f, 0.25f, 13.5f, 31.75f})
        for (float x : {0.0f, 0.5f, 7.25f, 31.75f})  // x + 32 exact in float
            for (int slice : {0, 1}) {
                const Scene& alone = slice == 0 ? *alone_first : *alone_second;
                Ray a = batch->sensor().sample_ray(Vec2(x + 32.0f * float(slice), y), Vec2(0.3f, 0.8f), 0.0f);
                Ray b = alone.sensor().sample_ray(Vec2(x, y), Vec2(0.3f, 0.8f), 0.0f);
                INFO("slice " << slice << " at " << x << ", " << y);
                CHECK(a.o == b.o);
                CHECK(a.d == b.d);
                CHECK(a.tmin == b.tmin);
            }
    // A radiance meter and an irradiance meter side by side under a uniform sky: L and pi L.
    // The meters insist on 1 x 1 films of their own, as Mitsuba's do.
    Ref<Scene> meters = load(Sky + R"(<sensor type="batch">
            <sensor type="radiancemeter">)" +
                             pixel_film(1) + R"(</sensor>
            <shape type="sphere"><sensor type="irradiancemeter">)" +
                             pixel_film(1) + R"(</sensor></shape>
            <film type="hdrfilm"><integer name="width" value="2"/><integer name="height" value="1"/><rfilter type="box"/>
                <string name="component_format" value="float32"/></film></sensor>)");
    const Image image = render(*meters).image;
    CHECK(pixel(image, 0).y == Approx(1.0f).epsilon(1e-6));
    CHECK(pixel(image, 1).y == Approx(Pi).epsilon(1e-5));
}

TEST_CASE("a scene's sensors: its own in document order, then those nested in shapes (Mitsuba's numbering)", "[sensor][meters]") {
    const std::string body = Sky + R"(
        <shape type="sphere"><sensor type="irradiancemeter">)" +
                             pixel_film(4) +
                             R"(</sensor></shape>
        <sensor type="radiancemeter">)" +
                             pixel_film(4) +
                             R"(</sensor>
        <sensor type="distant">)" +
                             pixel_film(4) + "</sensor>";
    const std::vector<std::string> expected = {"radiancemeter", "distant", "irradiancemeter"};
    for (int i = 0; i < 3; ++i) {
        Ref<Scene> scene = load(body, i);
        CHECK(scene->sensor_count() == 3);
        CHECK(scene->sensor().to_string() == expected[size_t(i)]);
    }
}

TEST_CASE("the measuring sensors' mistakes are errors at their lines", "[sensor][meters][errors]") {
    // Lines count from scene_xml's <scene> line (1); bodies start on line 2.
    fails_at(R"(<sensor type="radiancemeter">
                <film type="hdrfilm"><integer name="width" value="2"/><integer name="height" value="1"/></film></sensor>)",
             3, "film must be 1 x 1 pixel, not 2 x 1");
    fails_at(R"(<sensor type="radiancemeter"><point name="origin" value="0, 0, 1"/>)" + pixel_film(1) + "</sensor>", 2, "needs both");
    fails_at(R"(<sensor type="radiancemeter"><point name="origin" value="0, 0, 1"/><vector name="direction" value="0, 0, 0"/>)" +
                 pixel_film(1) + "</sensor>",
             2, "must not be zero");
    fails_at(R"(<sensor type="irradiancemeter">)" + pixel_film(1) + "</sensor>", 2, "must be nested in the shape");
    fails_at(R"(<shape type="sphere"><sensor type="irradiancemeter"><transform name="to_world"><translate x="1"/></transform>)" +
                 pixel_film(1) + "</sensor></shape>",
             2, "takes no to_world");
    fails_at(R"(<shape type="sphere"><sensor type="perspective"/></shape>)", 2, "cannot be nested in a shape");
    fails_at(R"(<sensor type="distant"><vector name="direction" value="0, 0, 1"/>
                <transform name="to_world"><translate x="1"/></transform>)" +
                 pixel_film(1) + "</sensor>",
             2, "either direction or to_world");
    fails_at(R"(<sensor type="distant"><float name="target" value="1"/>)" + pixel_film(1) + "</sensor>", 2, "a point or a shape");
    fails_at(R"(<sensor type="batch"><sensor type="perspective"/><sensor type="perspective"/>
                <film type="hdrfilm"><integer name="width" value="5"/><integer name="height" value="4"/></film></sensor>)",
             2, "must be a multiple of its number of sensors (2)");
    fails_at(R"(<sensor type="batch">
                <sensor type="radiancemeter">)" +
                 pixel_film(1) + R"(</sensor>
                <film type="hdrfilm"><integer name="width" value="2"/><integer name="height" value="1"/></film></sensor>)",
             3, "slice of a batch must be 1 x 1");
    fails_at(R"(<sensor type="batch">)" + pixel_film(1) + "</sensor>", 2, "at least one sensor");
    // The particle tracer cannot reach a delta sensor.
    Ref<Scene> scene = load(Sky + R"(<integrator type="ptracer"/><sensor type="radiancemeter">)" + pixel_film(1) + "</sensor>");
    CHECK_THROWS_WITH(render(*scene), Catch::Contains("light paths cannot reach it"));
}
