// Camera conventions: a known pixel's ray direction, every fov_axis, and the 35 mm focal length.

#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {
Ref<Scene> camera_scene(const std::string& sensor_props, int w, int h) {
    auto dir = scratch_dir("camera");
    std::string xml = scene_xml(R"(<sensor type="perspective">)" + sensor_props + R"(
    <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value=")" + std::to_string(w) + R"("/><integer name="height" value=")" +
                                std::to_string(h) + R"("/></film>
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
        {"x", 200, 100, Vec2(0, 50)},      {"y", 200, 100, Vec2(100, 0)},    {"diagonal", 200, 100, Vec2(0, 0)},
        {"smaller", 200, 100, Vec2(100, 0)}, {"larger", 200, 100, Vec2(0, 50)}, {"smaller", 100, 200, Vec2(0, 100)},
        {"larger", 100, 200, Vec2(50, 0)},
    };
    for (const Case& c : cases) {
        INFO("fov_axis " << c.axis << " on " << c.w << "x" << c.h);
        Ref<Scene> scene = camera_scene(std::string(R"(<float name="fov" value="60"/><string name="fov_axis" value=")") + c.axis + "\"/>", c.w, c.h);
        CHECK(angle_to_axis(scene->sensor().sample_ray(c.edge_point, Vec2(0.5f))) == Approx(fov / 2).epsilon(1e-5));
    }
}

TEST_CASE("camera: focal_length sets the fov on the 35 mm diagonal", "[camera]") {
    Ref<Scene> scene = camera_scene(R"(<string name="focal_length" value="50mm"/>)", 300, 200);
    float expected = degrees(std::atan(std::sqrt(36.0f * 36.0f + 24.0f * 24.0f) / 100.0f));
    CHECK(angle_to_axis(scene->sensor().sample_ray(Vec2(0, 0), Vec2(0.5f))) == Approx(expected).epsilon(1e-5));
}

