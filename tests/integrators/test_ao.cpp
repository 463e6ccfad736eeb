// Ambient occlusion against its analytic cases: an open plane is 1, a point at the foot of an
// infinite wall is 1/2, a disk overhead that subtends a cone of half-angle theta hides sin^2
// theta of the cosine-weighted hemisphere (uniform weighting would hide 1 - cos theta), the
// inside of a closed box is 0; ray_length (given and automatic) bounds the reach.

#include "core/sampler.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstring>

using namespace candela;
using namespace candela::test;

namespace {

constexpr int AoTests = 3;  // the z-tests of this file share a 1% family-wise level (Sidak)

Ref<Scene> ao_scene(const std::string& name, const std::string& ao_props, const std::string& shapes, const std::string& origin,
                    const std::string& target, Variant variant = Variant::ScalarRGB) {
    auto dir = scratch_dir("ao-" + name);
    write_text(dir / "scene.xml", scene_xml(R"(<integrator type="ao">)" + ao_props + R"(</integrator>
        <sensor type="perspective"><float name="fov" value="60"/>
            <transform name="to_world"><lookat origin=")" +
                                            origin + R"(" target=")" + target + R"(" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
            <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film>
        </sensor>)" + shapes));
    return load_scene((dir / "scene.xml").string(), {}, variant);
}

// The occlusion-free fraction at the point a ray from `origin` toward `target` hits, from n
// independent one-ray estimates (shading_samples 1): a binomial proportion.
MeanAndError ao_at(Scene& scene, const Vec3& origin, const Vec3& target, int n) {
    auto& integrator = dynamic_cast<SamplingIntegrator&>(scene.integrator());
    integrator.prepare(scene);
    Ref<Sampler> sampler = scene.sensor().sampler().clone();
    sampler->set_sample_count(n);
    Ray ray(origin, glm::normalize(target - origin));
    std::vector<double> values;
    for (int i = 0; i < n; ++i) {
        sampler->start(Vec2i(3, 5), uint32_t(i));
        SampleRecord record;
        values.push_back(integrator.sample_radiance(scene, *sampler, ray, record).x);
    }
    return mean_and_error(values);
}

const char* Big = R"(<transform name="to_world"><scale value="1000"/>)";

}  // namespace

TEST_CASE("ao: an unoccluded plane is 1 everywhere", "[ao]") {
    Ref<Scene> scene = ao_scene("plane", R"(<integer name="shading_samples" value="4"/>)",
                                std::string(R"(<shape type="rectangle">)") + Big + R"(<rotate x="1" angle="-90"/></transform></shape>)",
                                "0, 1, 0.5", "0, 0, -0.5");
    RenderResult r = scene->integrator().render(*scene, RenderOptions());
    for (float v : r.image.data()) REQUIRE(v == Approx(1.0f).margin(1e-6));
}

TEST_CASE("ao: in scalar_spectral an unoccluded plane is grey 1, a white emission's colour", "[ao][spectral]") {
    // Every sample's value is 1; what varies is the colour of white seen at three wavelengths
    // (the film's XYZ conversion), whose mean is white within the coefficient table's fit (5e-3,
    // the test of core/wavelengths). Checked per channel through the image's own error bars.
    Ref<Scene> scene = ao_scene("plane-spectral", R"(<integer name="shading_samples" value="4"/>)",
                                std::string(R"(<shape type="rectangle">)") + Big + R"(<rotate x="1" angle="-90"/></transform></shape>)",
                                "0, 1, 0.5", "0, 0, -0.5", Variant::ScalarSpectral);
    RenderResult r = scene->integrator().render(*scene, RenderOptions());
    const double z = two_sided_z(sidak(0.01, 3));
    for (int c = 0; c < 3; ++c) {
        MeanAndError m = channel_mean(r.image, c);
        INFO("channel " << c << ": mean " << m.mean << " +- " << m.std_error);
        CHECK(m.std_error > 0.0);  // the wavelengths did vary
        CHECK(std::abs(m.mean - 1.0) <= z * m.std_error + 5e-3);
    }
}

TEST_CASE("ao: the inside of a closed box is 0 with an unbounded ray length", "[ao]") {
    Ref<Scene> scene =
        ao_scene("box", R"(<integer name="shading_samples" value="4"/><float name="ray_length" value="1e30"/>)",
                 R"(<shape type="cube"><transform name="to_world"><scale value="2"/><rotate y="1" angle="20"/></transform></shape>)",
                 "0.3, -0.5, 0.2", "1, 0.3, -1");
    RenderResult r = scene->integrator().render(*scene, RenderOptions());
    for (float v : r.image.data()) REQUIRE(v == 0.0f);
}

TEST_CASE("ao: at the foot of an infinite wall half the cosine-weighted hemisphere is open", "[ao]") {
    // Floor y = 0 and wall x = 0, both 2 km wide; the point lies 1 cm from the wall (the part of
    // the hemisphere that misses a wall that wide is about 1e-5).
    Ref<Scene> scene = ao_scene("wall", R"(<float name="ray_length" value="1e30"/>)",
                                std::string(R"(<shape type="rectangle">)") + Big + R"(<rotate x="1" angle="-90"/></transform></shape>
                                    <shape type="rectangle">)" +
                                    Big + R"(<rotate y="1" angle="90"/></transform></shape>)",
                                "1, 1, 0", "0.01, 0, 0");
    MeanAndError m = ao_at(*scene, Vec3(1, 1, 0), Vec3(0.01f, 0, 0), 40000);
    double z = two_sided_z(sidak(0.01, AoTests));
    INFO("open fraction " << m.mean << " +- " << m.std_error);
    CHECK(std::abs(m.mean - 0.5) <= z * m.std_error);
    CHECK(m.std_error < 0.003);  // power: a bias of 1.5% would show
}

TEST_CASE("ao: a disk overhead hides sin^2 of its half-angle (cosine weighting), ray_length bounds the reach", "[ao]") {
    // A disk of radius 1 at height sqrt(3) above the point: half-angle 30 degrees, so the open
    // fraction is 1 - sin^2(30) = 0.75 (uniform weighting would give cos 30 = 0.866).
    auto scene_with = [](const std::string& props, float floor_scale) {
        return ao_scene("disk", props,
                        R"(<shape type="rectangle"><transform name="to_world"><scale value=")" + std::to_string(floor_scale) +
                            R"("/><rotate x="1" angle="-90"/></transform></shape>
                           <shape type="disk"><transform name="to_world"><rotate x="1" angle="90"/><translate y="1.7320508"/></transform></shape>)",
                        "0.3, 0.5, 0", "0, 0, 0");
    };
    const Vec3 eye(0.3f, 0.5f, 0.0f), point(0.0f);
    double z = two_sided_z(sidak(0.01, AoTests));
    {
        Ref<Scene> scene = scene_with(R"(<float name="ray_length" value="1e30"/>)", 10.0f);
        MeanAndError m = ao_at(*scene, eye, point, 40000);
        INFO("open fraction " << m.mean << " +- " << m.std_error);
        CHECK(std::abs(m.mean - 0.75) <= z * m.std_error);
        CHECK(m.std_error < 0.003);
    }
    // Automatic length, half the scene's bounding-sphere radius: 7.1 with a 20 m floor (the disk
    // is in reach), 0.83 with a 1 m floor (it is not).
    {
        Ref<Scene> scene = scene_with("", 10.0f);
        MeanAndError m = ao_at(*scene, eye, point, 40000);
        INFO("automatic length, wide floor: " << m.mean << " +- " << m.std_error);
        CHECK(std::abs(m.mean - 0.75) <= z * m.std_error);
    }
    CHECK(ao_at(*scene_with("", 0.5f), eye, point, 2000).mean == 1.0);
    CHECK(ao_at(*scene_with(R"(<float name="ray_length" value="1.7"/>)", 10.0f), eye, point, 2000).mean == 1.0);
}

TEST_CASE("ao: bit-identical images with 1 and 2 threads, parameters are checked", "[ao][determinism]") {
    auto dir = scratch_dir("ao-determinism");
    std::string scene = read_text(source_path("scenes/validation/cbox.xml"));
    std::string path = "<integrator type=\"path\">\n        <integer name=\"max_depth\" value=\"-1\"/>\n    </integrator>";
    REQUIRE(scene.find(path) != std::string::npos);
    scene.replace(scene.find(path), path.size(), R"(<integrator type="ao"><integer name="shading_samples" value="3"/></integrator>)");
    write_text(dir / "cbox_ao.xml", scene);
    SceneParameters p = {{"res", "40"}, {"spp", "3"}};
    RenderResult one = render_file((dir / "cbox_ao.xml").string(), p, 1);
    RenderResult two = render_file((dir / "cbox_ao.xml").string(), p, 2);
    REQUIRE(one.image.data().size() == two.image.data().size());
    CHECK(std::memcmp(one.image.data().data(), two.image.data().data(), one.image.data().size() * sizeof(float)) == 0);
    double sum = 0.0;
    for (float v : one.image.data()) sum += v;
    CHECK(sum > 0.0);

    for (const char* bad : {R"(<integer name="shading_samples" value="0"/>)", R"(<float name="ray_length" value="0"/>)"}) {
        write_text(dir / "bad.xml", scene_xml(std::string(R"(<integrator type="ao">)") + bad + "</integrator>"));
        CHECK_THROWS_WITH(load_scene((dir / "bad.xml").string()), Catch::Contains("bad.xml:"));
    }
}
