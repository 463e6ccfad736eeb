// The orthographic camera: Mitsuba's extent ([-1, 1] x [-1/aspect, 1/aspect] scaled by
// to_world), rays starting on the near plane, far_clip - near_clip long, all parallel.

#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {
Ref<Scene> ortho_scene(const std::string& extra, const std::string& transform, int w, int h, const std::string& body = "") {
    auto dir = scratch_dir("orthographic");
    std::string xml =
        scene_xml(R"(<sensor type="orthographic">)" + extra + R"(<transform name="to_world">)" + transform + R"(</transform>
    <film type="hdrfilm"><integer name="width" value=")" +
                  std::to_string(w) + R"("/><integer name="height" value=")" + std::to_string(h) +
                  R"("/><rfilter type="box"/></film><sampler type="independent"><integer name="sample_count" value="16"/></sampler>
</sensor>)" + body);
    write_text(dir / "scene.xml", xml);
    return load_scene((dir / "scene.xml").string());
}
}  // namespace

TEST_CASE("orthographic: to_world's scale sets the extent, rays start on the near plane", "[camera][orthographic]") {
    // Scale 10 x 10 viewed from (1, 1, 1) toward +y with +z up (the example of Mitsuba's
    // documentation): the view is 20 units wide, 10 high on a 2:1 film; camera +x is world -x.
    Ref<Scene> scene = ortho_scene(R"(<float name="near_clip" value="0.5"/><float name="far_clip" value="100"/>)",
                                   R"(<scale x="10" y="10"/><lookat origin="1, 1, 1" target="1, 2, 1" up="0, 0, 1"/>)", 200, 100);
    const Sensor& s = scene->sensor();
    auto check_ray = [&](Vec2 film, Vec3 origin) {
        Ray r = s.sample_ray(film, Vec2(0.5f));
        INFO("film " << film.x << ", " << film.y << ": origin " << r.o.x << ", " << r.o.y << ", " << r.o.z);
        CHECK(glm::length(r.o - origin) < 1e-4f);
        CHECK(glm::length(r.d - Vec3(0, 1, 0)) < 1e-6f);
        CHECK(r.tmin == 0.0f);
        CHECK(r.tmax == Approx(99.5f));
    };
    check_ray(Vec2(100, 50), Vec3(1.0f, 1.5f, 1.0f));              // centre, moved to the near plane
    check_ray(Vec2(0, 0), Vec3(1.0f - 10.0f, 1.5f, 1.0f + 5.0f));  // top-left corner: camera (+1, +1/2)
    check_ray(Vec2(200, 100), Vec3(1.0f + 10.0f, 1.5f, 1.0f - 5.0f));
    check_ray(Vec2(150, 25), Vec3(1.0f + 5.0f, 1.5f, 1.0f + 2.5f));
}

TEST_CASE("orthographic: an emitter covering a known part of the view fills that part of the image", "[camera][orthographic]") {
    // A 2 x 1 rectangle light facing the camera, in a 4 x 4 view (scale 2): exactly the middle
    // half of the columns and quarter of the rows, whatever its distance.
    const char* light =
        R"(<shape type="rectangle"><transform name="to_world"><scale x="1" y="0.5"/><rotate y="1" angle="180"/><translate z="7"/></transform>
        <emitter type="area"><rgb name="radiance" value="3"/></emitter></shape>)";
    Ref<Scene> scene = ortho_scene("", R"(<scale x="2" y="2"/>)", 32, 32, light);
    Image img = scene->integrator().render(*scene, RenderOptions()).image;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            bool inside = x >= 8 && x < 24 && y >= 12 && y < 20;
            INFO("pixel " << x << ", " << y);
            CHECK(img.at(x, y, 0) == Approx(inside ? 3.0f : 0.0f).margin(1e-5));
        }
}
