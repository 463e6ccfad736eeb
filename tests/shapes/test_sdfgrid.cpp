// sdfgrid: a linear SDF is represented exactly (hits on the plane to root-finding precision,
// any to_world), a sphere's SDF converges to the sphere within the trilinear interpolation
// bound, smooth normals are continuous across voxel faces where analytic ones are not, the
// tessellation lies on the surface, and bad grids are errors at the filename's line.

#include "core/rng.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <fstream>
#include <functional>

using namespace candela;
using namespace candela::test;

namespace {

// Mitsuba's volume format with one float32 channel; sample (i, j, k) at (i, j, k) / (n - 1).
void write_vol(const std::filesystem::path& path, int n, const std::function<double(double, double, double)>& f, int channels = 1) {
    std::ofstream out(path, std::ios::binary);
    out.write("VOL", 3);
    out.put(3);
    int32_t header[5] = {1, n, n, n, channels};
    out.write(reinterpret_cast<const char*>(header), sizeof(header));
    float bbox[6] = {0, 0, 0, 1, 1, 1};
    out.write(reinterpret_cast<const char*>(bbox), sizeof(bbox));
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                for (int c = 0; c < channels; ++c) {
                    float v = float(f(double(x) / (n - 1), double(y) / (n - 1), double(z) / (n - 1)));
                    out.write(reinterpret_cast<const char*>(&v), 4);
                }
}

std::string grid(const std::string& file, const std::string& extra = "") {
    return "<shape type=\"sdfgrid\">\n<string name=\"filename\" value=\"" + file + "\"/>" + extra + "</shape>";
}

}  // namespace

TEST_CASE("sdfgrid: a linear SDF is a plane, hit exactly, with any to_world", "[sdfgrid]") {
    auto dir = scratch_dir("sdfgrid-plane");
    write_vol(dir / "plane.vol", 9, [](double, double, double z) { return z - 0.37; });
    for (const char* normals : {"smooth", "analytic"}) {
        INFO(normals);
        Ref<Scene> s = load_scene_xml_in(dir, grid("plane.vol", std::string("<string name=\"normals\" value=\"") + normals + "\"/>"));
        PCG32 rng(3, 1);
        for (int i = 0; i < 200; ++i) {
            Vec3 target(rng.next_float(), rng.next_float(), 0.37f);
            Vec3 o = target + Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 1.0f);
            SurfaceInteraction si;
            REQUIRE(s->intersect(Ray(o, glm::normalize(target - o)), si));
            CHECK(glm::length(si.p - target) < 1e-5f);
            CHECK(glm::length(si.n - Vec3(0, 0, 1)) < 1e-5f);
            CHECK(glm::length(si.shading.n - Vec3(0, 0, 1)) < 1e-5f);
        }
    }
    // Placed by a rotation and a scale: the plane z = 0.37 of the unit cube, moved.
    Ref<Scene> s =
        load_scene_xml_in(dir, grid("plane.vol", R"(<transform name="to_world"><scale value="2"/><rotate x="1" angle="90"/></transform>)"));
    SurfaceInteraction si;
    REQUIRE(s->intersect(Ray(Vec3(1, -3, 1), Vec3(0, 1, 0)), si));
    CHECK(si.p.y == Approx(-0.74f).epsilon(1e-5));
    CHECK(glm::length(si.n - Vec3(0, -1, 0)) < 1e-5f);
}

TEST_CASE("sdfgrid: a sphere's SDF gives the sphere within the interpolation error", "[sdfgrid]") {
    auto dir = scratch_dir("sdfgrid-sphere");
    const int n = 33;
    const double r = 0.3;
    write_vol(dir / "sphere.vol", n,
              [&](double x, double y, double z) { return std::sqrt(sqr(float(x - 0.5)) + sqr(float(y - 0.5)) + sqr(float(z - 0.5))) - r; });
    // Trilinear interpolation errs by at most h^2 / 8 times the second derivatives summed over
    // the axes; those of |p - c| are at most 1 / r: 3 h^2 / (8 r), h = 1 / 32.
    const double h = 1.0 / (n - 1), bound = 3 * h * h / (8 * r);
    double error_sum[2] = {0, 0};
    for (int mode = 0; mode < 2; ++mode) {
        Ref<Scene> s = load_scene_xml_in(dir, grid("sphere.vol", mode ? R"(<string name="normals" value="analytic"/>)" : ""));
        PCG32 rng(9, 2);
        double worst = 0.0;
        for (int i = 0; i < 500; ++i) {
            Vec3 d = glm::normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
            Vec3 o = Vec3(0.5f) - 2.0f * d + 0.15f * Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 0.0f);
            SurfaceInteraction si;
            REQUIRE(s->intersect(Ray(o, d), si));
            Vec3 radial = si.p - Vec3(0.5f);
            worst = std::max(worst, std::abs(double(glm::length(radial)) - r));
            error_sum[mode] += std::acos(std::min(1.0f, glm::dot(si.shading.n, glm::normalize(radial))));
        }
        INFO("mode " << mode << ": largest distance from the sphere " << worst << " (bound " << bound << ")");
        CHECK(worst <= bound);
    }
    INFO("mean normal error smooth " << error_sum[0] / 500 << ", analytic " << error_sum[1] / 500);
    CHECK(error_sum[0] < error_sum[1]);
    CHECK(error_sum[1] / 500 < 0.05);
}

TEST_CASE("sdfgrid: smooth normals are continuous across voxel faces, analytic ones are not", "[sdfgrid]") {
    auto dir = scratch_dir("sdfgrid-smooth");
    write_vol(dir / "sphere.vol", 9, [](double x, double y, double z) {
        return std::sqrt((x - 0.5) * (x - 0.5) + (y - 0.45) * (y - 0.45) + (z - 0.5) * (z - 0.5)) - 0.3;
    });
    // Two rays a hair apart on either side of the voxel face x = 3 / 8.
    double jump[2];
    for (int mode = 0; mode < 2; ++mode) {
        Ref<Scene> s = load_scene_xml_in(dir, grid("sphere.vol", mode ? R"(<string name="normals" value="analytic"/>)" : ""));
        SurfaceInteraction a, b;
        REQUIRE(s->intersect(Ray(Vec3(0.375f - 1e-4f, 0.55f, 2.0f), Vec3(0, 0, -1)), a));
        REQUIRE(s->intersect(Ray(Vec3(0.375f + 1e-4f, 0.55f, 2.0f), Vec3(0, 0, -1)), b));
        jump[mode] = glm::length(a.shading.n - b.shading.n);
    }
    INFO("normal jump smooth " << jump[0] << ", analytic " << jump[1]);
    CHECK(jump[0] < 2e-3);
    CHECK(jump[1] > 1e-2);
}

TEST_CASE("sdfgrid: the rasterizer's triangles lie on the surface, facing out", "[sdfgrid]") {
    auto dir = scratch_dir("sdfgrid-tessellate");
    write_vol(dir / "plane.vol", 5, [](double x, double y, double z) { return z - 0.3 - 0.1 * x; });
    Ref<Scene> s = load_scene_xml_in(dir, grid("plane.vol"));
    TriangleSoup soup;
    s->shapes()[0]->tessellate(soup, 64);
    REQUIRE(!soup.triangles.empty());
    double area = 0.0;
    for (const auto& t : soup.triangles) {
        Vec3 a = soup.positions[t.x], b = soup.positions[t.y], c = soup.positions[t.z];
        for (const Vec3& p : {a, b, c}) CHECK(std::abs(p.z - 0.3f - 0.1f * p.x) < 1e-5f);
        Vec3 face = glm::cross(b - a, c - a);
        CHECK(glm::dot(face, Vec3(-0.1f, 0, 1)) > 0.0f);
        area += 0.5 * glm::length(face);
    }
    CHECK(area == Approx(std::sqrt(1.01)).epsilon(1e-4));  // the tilted unit square
}

TEST_CASE("sdfgrid: bad grids and unsupported uses are errors at their lines", "[sdfgrid][errors]") {
    auto dir = scratch_dir("sdfgrid-errors");
    write_vol(
        dir / "three.vol", 4, [](double, double, double z) { return z - 0.5; }, 3);
    write_vol(dir / "empty.vol", 4, [](double, double, double) { return 1.0; });
    write_vol(dir / "ok.vol", 4, [](double, double, double z) { return z - 0.5; });
    std::string ok = read_text(dir / "ok.vol");
    write_text(dir / "short.vol", ok.substr(0, ok.size() - 8));
    write_text(dir / "notvol.vol", "PLY and more text than a header needs, really quite a lot more");
    for (const char* name : {"three.vol", "empty.vol", "short.vol", "notvol.vol"}) {
        INFO(name);
        try {
            load_scene_xml_in(dir, grid(name));
            FAIL("expected an error");
        } catch (const SceneError& e) {
            INFO(e.what());
            CHECK(e.location.line == 3);
        }
    }
    CHECK_THROWS_AS(load_scene_xml_in(dir, grid("ok.vol", R"(<string name="normals" value="flat"/>)")), SceneError);
    CHECK_THROWS_AS(load_scene_xml_in(dir, grid("ok.vol", R"(<emitter type="area"/>)")), SceneError);
}
