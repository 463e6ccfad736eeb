// linearcurve and bsplinecurve: a thick straight curve is the cylinder of the same radius (hit
// for hit, and rendered with the same random numbers), Mitsuba's normal and uv conventions,
// and errors in curve files at their own file and line.

#include "core/rng.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

std::string curve_shape(const std::string& type, const std::string& file, const std::string& extra = "") {
    return "<shape type=\"" + type + "\">\n<string name=\"filename\" value=\"" + file + "\"/>" + extra + "</shape>";
}

// Rays from a circle of radius 3 around the z axis toward random points near the axis, both at
// heights in [0.2, 0.8]: they reach a tube of radius 0.3 around z in [0, 1] through its side.
void compare_with_cylinder(const Scene& curve, const Scene& cylinder, float t_tolerance, uint64_t seed) {
    PCG32 rng(seed, 3);
    int hits = 0, mismatched = 0;
    float worst_t = 0.0f, worst_n = 0.0f;
    for (int i = 0; i < 2000; ++i) {
        float a = TwoPi * rng.next_float();
        Vec3 o(3 * std::cos(a), 3 * std::sin(a), 0.2f + 0.6f * rng.next_float());
        Vec3 target(0.5f * (rng.next_float() - 0.5f), 0.5f * (rng.next_float() - 0.5f), 0.2f + 0.6f * rng.next_float());
        Ray ray(o, glm::normalize(target - o));
        SurfaceInteraction sc, sy;
        bool hc = curve.intersect(ray, sc), hy = cylinder.intersect(ray, sy);
        if (hc != hy) {
            ++mismatched;
            continue;
        }
        if (!hc) continue;
        ++hits;
        worst_t = std::max(worst_t, std::abs(sc.t - sy.t) / sy.t);
        worst_n = std::max(worst_n, glm::length(sc.n - sy.n));
    }
    INFO(hits << " hits; " << mismatched << " rays hit only one; worst relative t difference " << worst_t << ", worst normal difference "
              << worst_n);
    CHECK(hits > 1000);
    CHECK(mismatched <= 2);  // rays grazing the silhouette may fall either way
    CHECK(worst_t <= t_tolerance);
    CHECK(worst_n <= 20 * t_tolerance);
}

}  // namespace

TEST_CASE("curves: a thick straight curve is hit like a cylinder of the same radius", "[curves]") {
    auto dir = scratch_dir("curves-cylinder");
    write_text(dir / "line.txt", "0 0 0 0.3\n0 0 1 0.3\n");
    // A uniform cubic B-spline with collinear, evenly spaced control points is the straight
    // segment between (p0 + 4 p1 + p2) / 6 and (p1 + 4 p2 + p3) / 6: here z from 0 to 1.
    write_text(dir / "spline.txt", "0 0 -1 0.3\n0 0 0 0.3\n0 0 1 0.3\n0 0 2 0.3\n");
    Ref<Scene> cylinder = load_scene_xml_in(dir, R"(<shape type="cylinder"><float name="radius" value="0.3"/></shape>)");
    Ref<Scene> linear = load_scene_xml_in(dir, curve_shape("linearcurve", "line.txt"));
    Ref<Scene> spline = load_scene_xml_in(dir, curve_shape("bsplinecurve", "spline.txt"));
    // Embree intersects round linear curves in closed form (float precision) and B-splines by
    // iterating to a tolerance of about 1e-4 of the curve's size.
    compare_with_cylinder(*linear, *cylinder, 1e-5f, 1);
    compare_with_cylinder(*spline, *cylinder, 1e-3f, 2);
}

TEST_CASE("curves: a thick straight linear curve renders like the cylinder", "[curves][render]") {
    auto dir = scratch_dir("curves-render");
    write_text(dir / "line.txt", "0 0 0 0.3\n0 0 1 0.3\n");
    const char* rest =
        R"(<emitter type="directional"><vector name="direction" x="-1" y="2" z="-0.5"/><rgb name="irradiance" value="3"/></emitter>
        <emitter type="constant"><rgb name="radiance" value="0.2"/></emitter>
        <integrator type="path"><integer name="max_depth" value="3"/></integrator>
        <sensor type="perspective"><float name="fov" value="14"/>
            <transform name="to_world"><lookat origin="0.3, -3, 0.5" target="0, 0, 0.5" up="0, 0, 1"/></transform>
            <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
            <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="48"/><rfilter type="box"/></film></sensor>)";
    const char* material = R"(<bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0.6, 0.3, 0.2"/></bsdf>)";
    auto render = [&](const std::string& shape) {
        write_text(dir / "scene.xml", scene_xml(shape + rest));
        return render_file((dir / "scene.xml").string(), {}).image;
    };
    Image a = render(curve_shape("linearcurve", "line.txt", material));
    Image b = render(std::string("<shape type=\"cylinder\"><float name=\"radius\" value=\"0.3\"/>") + material + "</shape>");
    // The view holds only the tube's side (heights 0.13 to 0.87), where the two surfaces agree to
    // float precision, and both build their shading frames from a tangent around the axis
    // turning the same way: with the same random numbers, pixels agree to rounding.
    float worst = 0.0f;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) {
            float la = luminance(a.rgb_at(x, y)), lb = luminance(b.rgb_at(x, y));
            worst = std::max(worst, std::abs(la - lb) / std::max(std::max(la, lb), 1e-6f));
        }
    INFO("largest relative pixel difference " << worst);
    CHECK(worst <= 1e-3f);
}

TEST_CASE("curves: Mitsuba's normals and uv: u around the curve, v along all segments", "[curves]") {
    auto dir = scratch_dir("curves-uv");
    write_text(dir / "two.txt", "0 0 0 0.5\n2 0 0 0.5\n4 0 0 0.5\n");
    Ref<Scene> s =
        load_scene_xml_in(dir, curve_shape("linearcurve", "two.txt", "<transform name=\"to_world\"><translate y=\"1\"/></transform>"));
    SurfaceInteraction si;
    REQUIRE(s->intersect(Ray(Vec3(1, 1, 3), Vec3(0, 0, -1)), si));
    CHECK(si.t == Approx(2.5f));
    CHECK(glm::length(si.n - Vec3(0, 0, 1)) < 1e-5f);
    // Tangent +x: v_rot = +z, v_rad = v_rot x tangent = +y; u = atan2(r.v_rot, r.v_rad) / 2pi.
    CHECK(si.uv.x == Approx(0.25f));
    CHECK(si.uv.y == Approx(0.25f));  // (0.5 + segment 0) / 2 segments
    REQUIRE(s->intersect(Ray(Vec3(3, 4, 0), Vec3(0, -1, 0)), si));
    CHECK(si.uv.x == Approx(0.0f).margin(1e-6));
    CHECK(si.uv.y == Approx(0.75f));
    // The shading frame: s around the curve, t along it.
    CHECK(std::abs(glm::dot(si.shading.t, Vec3(1, 0, 0))) == Approx(1.0f));
    // Radii are not scaled by to_world; rays from inside a tube do not hit it.
    Ref<Scene> scaled =
        load_scene_xml_in(dir, curve_shape("linearcurve", "two.txt", "<transform name=\"to_world\"><scale value=\"2\"/></transform>"));
    REQUIRE(scaled->intersect(Ray(Vec3(2, 0, 3), Vec3(0, 0, -1)), si));
    CHECK(si.t == Approx(2.5f));
    CHECK(!scaled->intersect(Ray(Vec3(2, 0, 0), Vec3(0, 0, 1)), si));
    Ref<Scene> flipped = load_scene_xml_in(dir, curve_shape("linearcurve", "two.txt", "<boolean name=\"flip_normals\" value=\"true\"/>"));
    REQUIRE(flipped->intersect(Ray(Vec3(1, 0, 3), Vec3(0, 0, -1)), si));
    CHECK(glm::length(si.n - Vec3(0, 0, -1)) < 1e-5f);
}

TEST_CASE("curves: errors in a curve file name that file and line", "[curves][errors]") {
    auto dir = scratch_dir("curves-errors");
    struct Case {
        const char* type;
        const char* text;
        int line;
    };
    const Case cases[] = {
        {"linearcurve", "0 0 0 0.1\n1 0 0\n", 2},
        {"linearcurve", "0 0 0 0.1\n1 0 x 0.1\n", 2},
        {"linearcurve", "0 0 0 0.1\n1 0 0 0.1\n\n\n2 0 0 0.1\n\n", 5},
        {"linearcurve", "0 0 0 0.1\n1 0 0 -0.1\n", 2},
        {"linearcurve", "0 0 0 0.1\n1 0 0 nan\n", 2},
        {"bsplinecurve", "0 0 0 0.1\n1 0 0 0.1\n2 0 0 0.1\n3 0 0 0.1\n\n4 0 0 0.1\n5 0 0 0.1\n6 0 0 0.1\n", 6},
    };
    for (const Case& c : cases) {
        INFO(c.type << ": " << c.text);
        write_text(dir / "bad.txt", c.text);
        try {
            load_scene_xml_in(dir, curve_shape(c.type, "bad.txt"));
            FAIL("expected an error");
        } catch (const SceneError& e) {
            INFO(e.what());
            CHECK(e.location.file == (dir / "bad.txt").string());
            CHECK(e.location.line == c.line);
        }
    }
    // An empty file, or an emitter on a curve: errors at the scene's lines.
    write_text(dir / "empty.txt", "\n\n");
    try {
        load_scene_xml_in(dir, curve_shape("linearcurve", "empty.txt"));
        FAIL("expected an error");
    } catch (const SceneError& e) {
        CHECK(e.location.line == 3);
    }
    write_text(dir / "ok.txt", "0 0 0 0.1\n1 0 0 0.1\n");
    CHECK_THROWS_AS(load_scene_xml_in(dir, curve_shape("linearcurve", "ok.txt", "<emitter type=\"area\"/>")), SceneError);
}
