// Camera conventions: a known pixel's ray direction, every fov_axis, the 35 mm focal length, the
// principal point offset (with the rasterizer's camera), and the parameters accepted as Mitsuba does.

#include "core/xml.h"
#include "integrators/raster/raster_scene.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {
Ref<Scene> camera_scene(const std::string& sensor_props, int w, int h) {
    auto dir = scratch_dir("camera");
    std::string xml = scene_xml(R"(<sensor type="perspective">)" + sensor_props + R"(
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value=")" +
                                std::to_string(w) + R"("/><integer name="height" value=")" + std::to_string(h) + R"("/></film>
</sensor>)");
    write_text(dir / "scene.xml", xml);
    return load_scene((dir / "scene.xml").string());
}

float angle_to_axis(const Ray& r) { return degrees(std::acos(glm::dot(r.d, Vec3(0, 0, -1)))); }
}  // namespace

TEST_CASE("camera: a known pixel's ray follows Mitsuba's conventions", "[camera]") {
    Ref<Scene> scene = camera_scene(R"(<float name="fov" value="90"/>)", 200, 100);
    const Sensor& s = scene->sensor();
    // The centre of the top-left pixel: camera +x is image left, so it looks toward world -x
    // (the camera looks down -z with +y up), and up.
    Ray r = s.sample_ray(Vec2(0.5f, 0.5f), Vec2(0.5f));
    Vec3 expected = glm::normalize(Vec3(-0.995f, 0.495f, -1.0f));
    CHECK(glm::length(r.d - expected) < 1e-5f);
    CHECK(glm::length(r.o - Vec3(0, 0, 5)) < 1e-6f);
    // The image centre looks straight along the view direction.
    Ray c = s.sample_ray(Vec2(100, 50), Vec2(0.5f));
    CHECK(glm::length(c.d - Vec3(0, 0, -1)) < 1e-6f);
    // The near clip plane sits at camera depth 0.01 for every ray.
    CHECK(r.tmin * glm::dot(r.d, Vec3(0, 0, -1)) == Approx(0.01f));
}

TEST_CASE("camera: fov_axis picks the axis the fov spans", "[camera]") {
    const float fov = 60.0f;
    struct Case {
        const char* axis;
        int w, h;
        Vec2 edge_point;  // film position whose ray makes the angle fov/2 with the view axis
    };
    // A 200x100 film (aspect 2) and a 100x200 film (aspect 1/2).
    const Case cases[] = {
        {"x", 200, 100, Vec2(0, 50)},        {"y", 200, 100, Vec2(100, 0)},     {"diagonal", 200, 100, Vec2(0, 0)},
        {"smaller", 200, 100, Vec2(100, 0)}, {"larger", 200, 100, Vec2(0, 50)}, {"smaller", 100, 200, Vec2(0, 100)},
        {"larger", 100, 200, Vec2(50, 0)},
    };
    for (const Case& c : cases) {
        INFO("fov_axis " << c.axis << " on " << c.w << "x" << c.h);
        Ref<Scene> scene =
            camera_scene(std::string(R"(<float name="fov" value="60"/><string name="fov_axis" value=")") + c.axis + "\"/>", c.w, c.h);
        CHECK(angle_to_axis(scene->sensor().sample_ray(c.edge_point, Vec2(0.5f))) == Approx(fov / 2).epsilon(1e-5));
    }
}

TEST_CASE("camera: focal_length sets the fov on the 35 mm diagonal", "[camera]") {
    Ref<Scene> scene = camera_scene(R"(<string name="focal_length" value="50mm"/>)", 300, 200);
    float expected = degrees(std::atan(std::sqrt(36.0f * 36.0f + 24.0f * 24.0f) / 100.0f));
    CHECK(angle_to_axis(scene->sensor().sample_ray(Vec2(0, 0), Vec2(0.5f))) == Approx(expected).epsilon(1e-5));
}

TEST_CASE("camera: the principal point offset shifts the image as Mitsuba's does", "[camera]") {
    Ref<Scene> scene = camera_scene(R"(<float name="fov" value="90"/><float name="principal_point_offset_x" value="0.1"/>
        <float name="principal_point_offset_y" value="-0.2"/>)",
                                    200, 100);
    const Sensor& s = scene->sensor();
    // Film position s looks where s + offset looks unshifted, so the view axis meets the film at
    // (0.5, 0.5) - offset = (0.4, 0.7), pixel (80, 70).
    CHECK(glm::length(s.sample_ray(Vec2(80, 70), Vec2(0.5f)).d - Vec3(0, 0, -1)) < 1e-6f);
    // The top-left pixel's centre, (0.0025, 0.005) of the film, looks through (0.1025, -0.195):
    // camera-space (1 - 0.205, (1 + 0.39) / 2, 1); camera +x is world -x here.
    Vec3 expected = glm::normalize(Vec3(-0.795f, 0.695f, -1.0f));
    CHECK(glm::length(s.sample_ray(Vec2(0.5f), Vec2(0.5f)).d - expected) < 1e-5f);

    // The rasterizer's camera puts every point where the path tracer's ray through it starts.
    raster::RasterCamera cam = raster::RasterCamera::from_pinhole(*s.pinhole());
    for (Vec2 pixel : {Vec2(80.5f, 70.5f), Vec2(3.25f, 91.5f), Vec2(190.0f, 10.0f)}) {
        Ray r = s.sample_ray(pixel, Vec2(0.5f));
        Vec4 c = cam.clip(r.o + 3.0f * r.d);
        Vec2 projected((c.x / c.w + 1.0f) * 0.5f * 200.0f, (c.y / c.w + 1.0f) * 0.5f * 100.0f);
        INFO("pixel " << pixel.x << ", " << pixel.y << " -> " << projected.x << ", " << projected.y);
        CHECK(glm::length(projected - pixel) < 1e-3f);
    }
}

TEST_CASE("camera: focus_distance and shutter times are accepted, srf is refused in RGB", "[camera]") {
    Ref<Scene> plain = camera_scene(R"(<float name="fov" value="40"/>)", 64, 48);
    Ref<Scene> focused = camera_scene(R"(<float name="fov" value="40"/><float name="focus_distance" value="6"/>
        <float name="shutter_open" value="0"/><float name="shutter_close" value="0.5"/>)",
                                      64, 48);
    for (Vec2 p : {Vec2(0.0f), Vec2(13.7f, 40.2f)}) {
        Ray a = plain->sensor().sample_ray(p, Vec2(0.3f, 0.9f)), b = focused->sensor().sample_ray(p, Vec2(0.3f, 0.9f));
        CHECK(a.o == b.o);
        CHECK(a.d == b.d);
    }
    CHECK_THROWS_WITH(camera_scene(R"(<float name="fov" value="40"/><spectrum name="srf" value="1"/>)", 64, 48),
                      Catch::Contains("srf") && Catch::Contains("spectral"));
    CHECK_THROWS_WITH(camera_scene(R"(<string name="focal_length" value="35mm"/><string name="fov_axis" value="y"/>)", 64, 48),
                      Catch::Contains("fov_axis"));
}

TEST_CASE("camera: jitter false puts every sample at its pixel's centre, cone_scale is accepted", "[camera]") {
    // A disk light of radiance 1 seen through a box filter: jittered samples give its edge pixels
    // fractions of 1 (the share of the pixel it covers), centred samples give 0 or 1 exactly.
    auto image = [](const std::string& jitter) {
        auto dir = scratch_dir("camera-jitter");
        write_text(dir / "scene.xml", scene_xml(R"(<sensor type="perspective"><float name="fov" value="30"/>)" + jitter + R"(
    <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/><rfilter type="box"/></film></sensor>
<shape type="disk"><transform name="to_world"><rotate y="1" angle="180"/><scale value="0.5"/><translate z="2"/></transform>
    <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)"));
        Ref<Scene> scene = load_scene((dir / "scene.xml").string());
        return scene->integrator().render(*scene, RenderOptions()).image;
    };
    auto count = [](const Image& img, int& zero, int& one, int& between) {
        zero = one = between = 0;
        for (int y = 0; y < img.height(); ++y)
            for (int x = 0; x < img.width(); ++x) {
                float v = img.at(x, y, 0);
                (v == 0.0f ? zero : v == 1.0f ? one : between) += 1;
            }
    };
    int zero, one, between;
    count(image(R"(<boolean name="jitter" value="false"/><float name="cone_scale" value="2"/>)"), zero, one, between);
    CHECK(between == 0);
    CHECK(zero > 0);
    CHECK(one > 0);
    count(image(""), zero, one, between);
    CHECK(between > 0);
    CHECK_THROWS_WITH(camera_scene(R"(<float name="fov" value="40"/><float name="cone_scale" value="0"/>)", 8, 8),
                      Catch::Contains("cone_scale"));
}
