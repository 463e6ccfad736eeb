// A ray that starts exactly on an analytic surface does not hit its own origin: sphere, cylinder,
// disk and sdfgrid take hits strictly beyond the ray's tmin (shapes/analytic_shape.h). From a
// point exactly on the surface (here points of the formulas with no rounding error: a sphere's
// points on the axes, a cylinder's and a disk's, a plane of an SDF on grid values), with tmin 0,
// going out must miss and going in must find the far side.

#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <fstream>

using namespace candela;
using namespace candela::test;

namespace {

// Whether the ray from o along d hits anything; its distance in `t`.
bool hit_from(const Scene& scene, const Vec3& o, const Vec3& d, float& t) {
    SurfaceInteraction si;
    if (!scene.intersect(Ray(o, d), si)) return false;
    t = si.t;
    return true;
}

}  // namespace

TEST_CASE("shapes: a ray starting on an analytic surface does not hit its own origin", "[shapes]") {
    auto dir = scratch_dir("ray-start");
    struct Case {
        const char* name;
        std::string xml;
        Vec3 origin, inward;
        float far_side;  // distance to the surface along `inward` (0: none, a one-sheet surface)
    };
    // A plane z = 0.375 of a linear SDF, on the grid's values: 8 voxels across, 0.375 = 3/8.
    {
        std::ofstream out(dir / "plane.vol", std::ios::binary);
        out.write("VOL", 3);
        out.put(3);
        int32_t header[5] = {1, 9, 9, 9, 1};
        out.write(reinterpret_cast<const char*>(header), sizeof(header));
        float bbox[6] = {0, 0, 0, 1, 1, 1};
        out.write(reinterpret_cast<const char*>(bbox), sizeof(bbox));
        for (int z = 0; z < 9; ++z)
            for (int i = 0; i < 81; ++i) {
                float v = float(z) / 8.0f - 0.375f;
                out.write(reinterpret_cast<const char*>(&v), 4);
            }
    }
    const Case cases[] = {
        {"sphere, pole", R"(<shape type="sphere"/>)", Vec3(0, 0, 1), Vec3(0, 0, -1), 2.0f},
        {"sphere, equator", R"(<shape type="sphere"/>)", Vec3(1, 0, 0), Vec3(-1, 0, 0), 2.0f},
        {"cylinder", R"(<shape type="cylinder"/>)", Vec3(1, 0, 0.5f), Vec3(-1, 0, 0), 2.0f},
        {"disk", R"(<shape type="disk"/>)", Vec3(0, 0, 0), Vec3(0, 0, -1), 0.0f},
        {"sdfgrid", R"(<shape type="sdfgrid"><string name="filename" value="plane.vol"/></shape>)", Vec3(0.5f, 0.5f, 0.375f),
         Vec3(0, 0, -1), 0.0f},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        Ref<Scene> scene = load_scene_xml_in(dir, c.xml);
        float t = -1.0f;
        // Leaving outward: nothing beyond.
        CHECK_FALSE(hit_from(*scene, c.origin, -c.inward, t));
        // Leaving inward: the far side, or nothing for a one-sheet surface.
        if (c.far_side > 0.0f) {
            REQUIRE(hit_from(*scene, c.origin, c.inward, t));
            CHECK(t == Approx(c.far_side));
        } else {
            CHECK_FALSE(hit_from(*scene, c.origin, c.inward, t));
        }
        // And from just before the surface the surface itself is hit.
        REQUIRE(hit_from(*scene, c.origin - 0.5f * c.inward, c.inward, t));
        CHECK(t == Approx(0.5f));
    }
}
