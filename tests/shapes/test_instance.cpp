// shapegroup + instance: an instanced mesh renders as the flattened mesh does, Embree's memory
// does not grow with the number of instances, hits report the group's BSDFs with world-space
// geometry, and what Mitsuba forbids is an error at its line.

#include "core/bsdf.h"
#include "core/mesh.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <sstream>

using namespace candela;
using namespace candela::test;

namespace {

// A bumpy sphere as an OBJ: a latitude-longitude grid of (rings x 2 rings) quads, radius varying
// with position, so that normals and silhouettes are not those of any analytic shape; with uvs
// (phi / 2pi, theta / pi) or without.
std::string bumpy_obj(int rings, bool uvs = true) {
    std::ostringstream obj;
    obj.precision(9);
    const double pi = 3.14159265358979323846;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j < 2 * rings; ++j) {
            double theta = pi * i / rings, phi = pi * j / rings;
            double r = 1.0 + 0.15 * std::sin(5 * theta) * std::cos(3 * phi);
            obj << "v " << r * std::sin(theta) * std::cos(phi) << " " << r * std::sin(theta) * std::sin(phi) << " " << r * std::cos(theta)
                << "\n";
            if (uvs) obj << "vt " << double(j) / (2 * rings) << " " << double(i) / rings << "\n";
        }
    auto id = [&](int i, int j) { return i * 2 * rings + (j % (2 * rings)) + 1; };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < 2 * rings; ++j) {
            auto c = [&](int a, int b) { return std::to_string(id(a, b)) + (uvs ? "/" + std::to_string(id(a, b)) : ""); };
            if (i > 0) obj << "f " << c(i, j) << " " << c(i + 1, j) << " " << c(i, j + 1) << "\n";
            if (i + 1 < rings) obj << "f " << c(i, j + 1) << " " << c(i + 1, j) << " " << c(i + 1, j + 1) << "\n";
        }
    return obj.str();
}

const char* Stage = R"(<shape type="rectangle"><transform name="to_world"><scale value="6"/><translate z="-1.3"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></shape>
    <emitter type="directional"><vector name="direction" x="-1" y="1" z="-2"/><rgb name="irradiance" value="3"/></emitter>
    <emitter type="constant"><rgb name="radiance" value="0.3"/></emitter>
    <integrator type="path"><integer name="max_depth" value="4"/></integrator>
    <sensor type="perspective"><float name="fov" value="50"/>
        <transform name="to_world"><lookat origin="1, -5, 2" target="0, 0, 0" up="0, 0, 1"/></transform>
        <sampler type="independent"><integer name="sample_count" value="8"/></sampler>
        <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="48"/><rfilter type="box"/></film></sensor>)";

const char* Material =
    R"(<bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0.7, 0.2, 0.1"/><float name="alpha" value="0.2"/></bsdf>)";

Image render(const std::filesystem::path& dir, const std::string& body) {
    write_text(dir / "scene.xml", scene_xml(body + Stage));
    return render_file((dir / "scene.xml").string(), {}).image;
}

std::string mesh_shape(const std::string& transform) {
    return std::string("<shape type=\"obj\"><string name=\"filename\" value=\"bumpy.obj\"/>") + Material + transform + "</shape>";
}

std::string grouped(const std::string& transform) {
    return std::string("<shape type=\"shapegroup\" id=\"group\"><shape type=\"obj\"><string name=\"filename\" value=\"bumpy.obj\"/>") +
           Material + "</shape></shape><shape type=\"instance\"><ref id=\"group\"/>" + transform + "</shape>";
}

// A similarity (rotation, uniform scale, translation): under it the smooth vertex normals a
// mesh computes for itself (angle-weighted, Thuermer and Wuethrich) are the same whether computed
// before or after the transform. (A non-uniform scale changes the angles: the flattened mesh
// then shades with other normals than the instance, in Candela as in Mitsuba.)
const char* Placement =
    R"(<transform name="to_world"><scale value="0.9"/><rotate x="1" y="1" z="0" angle="35"/><translate x="0.3" y="-0.2" z="0.1"/></transform>)";

constexpr int InstanceTests = 1;  // statistical checks in this file (Sidak, 1% family-wise)

}  // namespace

TEST_CASE("instance: with an identity transform the image is the flattened mesh's, bit for bit", "[instance][render]") {
    auto dir = scratch_dir("instance-identity");
    write_text(dir / "bumpy.obj", bumpy_obj(24));
    Image flat = render(dir, mesh_shape("")), instanced = render(dir, grouped(""));
    // Embree maps the ray by the identity (exactly), intersects the same triangles with the
    // same arithmetic, and the identity transform is skipped when filling the hit: every
    // number along every path is the same.
    int differing = 0;
    for (size_t i = 0; i < flat.data().size(); ++i) differing += flat.data()[i] != instanced.data()[i];
    CHECK(differing == 0);
}

TEST_CASE("instance: a transformed instance renders as the mesh transformed in place", "[instance][render]") {
    auto dir = scratch_dir("instance-placed");
    // With uvs, every shading frame is built from dp/du, which the instance's transform carries
    // exactly as moving the vertices does. The flattened mesh is intersected in world space with
    // vertices moved by to_world in float, the instance in its own space with the ray moved by
    // the inverse: hit points agree to float rounding (1e-7 relative), the random numbers are
    // the same, so every pixel agrees to rounding amplified along a few bounces (1e-4 allows a
    // factor 1000).
    write_text(dir / "bumpy.obj", bumpy_obj(24, true));
    Image flat = render(dir, mesh_shape(Placement)), instanced = render(dir, grouped(Placement));
    float worst = 0.0f;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) {
            float a = luminance(flat.rgb_at(x, y)), b = luminance(instanced.rgb_at(x, y));
            worst = std::max(worst, std::abs(a - b) / std::max(std::max(a, b), 1e-6f));
        }
    INFO("largest relative pixel difference " << worst);
    CHECK(worst <= 1e-4f);
    // Without uvs the tangents come from the normal alone (coordinate_system), a choice that does
    // not follow the transform: BSDF samples turn about the normal, so the two images are two
    // independent-looking estimates of the same picture. Their paired pixel difference must
    // have zero mean within its standard error.
    write_text(dir / "bumpy.obj", bumpy_obj(24, false));
    flat = render(dir, mesh_shape(Placement));
    instanced = render(dir, grouped(Placement));
    std::vector<double> diff;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) diff.push_back(double(luminance(flat.rgb_at(x, y))) - double(luminance(instanced.rgb_at(x, y))));
    MeanAndError d = mean_and_error(diff);
    INFO("mean difference " << d.mean << " +- " << d.std_error);
    CHECK(d.std_error > 0.0);
    CHECK(std::abs(d.mean) <= two_sided_z(sidak(0.01, InstanceTests)) * d.std_error);
}

TEST_CASE("instance: Embree memory grows with distinct meshes, not with instances", "[instance][memory]") {
    auto dir = scratch_dir("instance-memory");
    write_text(dir / "bumpy.obj", bumpy_obj(60));  // 14,160 triangles
    const int copies = 16;
    std::string flat,
        instanced =
            "<shape type=\"shapegroup\" id=\"g\"><shape type=\"obj\"><string name=\"filename\" value=\"bumpy.obj\"/></shape></shape>";
    for (int i = 0; i < copies; ++i) {
        std::string t = "<transform name=\"to_world\"><rotate z=\"1\" angle=\"" + std::to_string(7 * i) + "\"/><translate x=\"" +
                        std::to_string(3 * (i % 4)) + "\" y=\"" + std::to_string(3 * (i / 4)) + "\"/></transform>";
        flat += "<shape type=\"obj\"><string name=\"filename\" value=\"bumpy.obj\"/>" + t + "</shape>";
        instanced += "<shape type=\"instance\"><ref id=\"g\"/>" + t + "</shape>";
    }
    auto bytes = [&](const std::string& body) {
        Ref<Scene> s = load_scene_xml_in(dir, body);
        return s->accel().embree_bytes();
    };
    int64_t one = bytes("<shape type=\"obj\"><string name=\"filename\" value=\"bumpy.obj\"/></shape>");
    int64_t many_flat = bytes(flat), many_instanced = bytes(instanced);
    INFO("Embree bytes: one mesh " << one << ", " << copies << " copies " << many_flat << ", " << copies << " instances "
                                   << many_instanced);
    CHECK(one > 14160 * 12);                // at least the index data
    CHECK(many_flat > (copies / 2) * one);  // copies cost their size each
    CHECK(many_instanced < 2 * one);        // instances cost a transform each
    // The triangles stored: one mesh's, whatever the number of instances.
    Ref<Scene> s = load_scene_xml_in(dir, instanced);
    CHECK(s->shapes().size() == size_t(copies));
}

TEST_CASE("instance: hits shade with the group's BSDFs and world-space geometry", "[instance]") {
    auto dir = scratch_dir("instance-hits");
    Ref<Scene> s = load_scene_xml_in(dir, R"(<shape type="shapegroup" id="g">
            <shape type="sphere"><float name="radius" value="0.5"/><bsdf type="diffuse" id="red"><rgb name="reflectance" value="0.8, 0.1, 0.1"/></bsdf></shape>
            <shape type="cube"><transform name="to_world"><scale value="0.25"/><translate x="2"/></transform><bsdf type="diffuse" id="blue"><rgb name="reflectance" value="0.1, 0.1, 0.8"/></bsdf></shape>
        </shape>
        <shape type="instance"><ref id="g"/><transform name="to_world"><scale x="2" y="1" z="1"/><translate y="3"/></transform></shape>
        <shape type="instance"><ref id="g"/><transform name="to_world"><rotate z="1" angle="90"/></transform></shape>)");
    REQUIRE(s->shapes().size() == 2);
    // First instance: the sphere stretched to an ellipsoid with semi-axes (1, 0.5, 0.5) at y = 3.
    SurfaceInteraction si;
    REQUIRE(s->intersect(Ray(Vec3(-5, 3, 0), Vec3(1, 0, 0)), si));
    CHECK(si.t == Approx(4.0f));
    CHECK(glm::length(si.n - Vec3(-1, 0, 0)) < 1e-5f);
    CHECK(si.shape->bsdf()->albedo(si) == Spectrum(0.8f, 0.1f, 0.1f));
    // An oblique point of the ellipsoid: the normal is the gradient of x^2 + 4 y'^2 + 4 z^2.
    Vec3 target(0.5f, 3.0f + 0.25f, 0.5f * std::sqrt(1.0f - 0.25f - 0.25f));
    REQUIRE(s->intersect(Ray(target + Vec3(0, 0, 2), Vec3(0, 0, -1)), si));
    CHECK(glm::length(si.p - target) < 1e-5f);
    Vec3 gradient = glm::normalize(Vec3(2 * target.x, 8 * (target.y - 3), 8 * target.z));
    CHECK(glm::length(si.n - gradient) < 1e-5f);
    CHECK(glm::dot(si.shading.n, si.n) == Approx(1.0f));
    // Second instance, rotated 90 degrees about z: its cube now sits at y = 2 and is blue.
    REQUIRE(s->intersect(Ray(Vec3(5, 2, 0.1f), Vec3(-1, 0, 0)), si));
    CHECK(si.t == Approx(5.0f - 0.25f));
    CHECK(glm::length(si.n - Vec3(1, 0, 0)) < 1e-5f);
    CHECK(si.shape->bsdf()->albedo(si) == Spectrum(0.1f, 0.1f, 0.8f));
    CHECK(s->occluded(Ray(Vec3(5, 2, 0.1f), Vec3(-1, 0, 0), 10.0f)));
    CHECK(!s->occluded(Ray(Vec3(5, 2, 0.1f), Vec3(-1, 0, 0), 4.0f)));
    // The rasterizer sees each member with its own BSDF, placed by the instance.
    std::vector<TessellatedPart> parts;
    s->shapes()[1]->tessellate_parts(parts, 16);
    REQUIRE(parts.size() == 2);
    CHECK(parts[1].shape->bsdf()->albedo(si) == Spectrum(0.1f, 0.1f, 0.8f));
    BoundingBox cube;
    for (const Vec3& p : parts[1].triangles.positions) cube.expand(p);
    CHECK(glm::length(cube.center() - Vec3(0, 2, 0)) < 1e-5f);
}

TEST_CASE("instance: what Mitsuba forbids in shape groups and instances is an error at its line", "[instance][errors]") {
    auto dir = scratch_dir("instance-errors");
    const char* sphere = "<shape type=\"sphere\"/>";
    struct Case {
        const char* what;
        std::string body;
        int line;
    };
    std::vector<Case> cases = {
        {"emitter in a group", "<shape type=\"shapegroup\" id=\"g\">\n<shape type=\"sphere\">\n<emitter type=\"area\"/></shape></shape>",
         3},
        {"nested group", std::string("<shape type=\"shapegroup\" id=\"g\">\n<shape type=\"shapegroup\">") + sphere + "</shape></shape>", 3},
        {"instance in a group",
         std::string("<shape type=\"shapegroup\" id=\"g\">") + sphere +
             "</shape><shape type=\"shapegroup\">\n<shape type=\"instance\"><ref id=\"g\"/></shape></shape>",
         3},
        {"group with to_world",
         std::string("<shape type=\"shapegroup\">") + sphere + "\n<transform name=\"to_world\"><translate x=\"1\"/></transform></shape>",
         3},
        {"group with a bsdf", std::string("<shape type=\"shapegroup\">") + sphere + "\n<bsdf type=\"diffuse\"/></shape>", 3},
        {"group with a stray property",
         std::string("<shape type=\"shapegroup\">") + sphere + "\n<float name=\"radius\" value=\"2\"/></shape>", 3},
        {"empty group", "<shape type=\"shapegroup\">\n</shape>", 2},
        {"instance of a sphere", std::string("<shape type=\"instance\">") + sphere + "</shape>", 2},
        {"instance with a bsdf",
         std::string("<shape type=\"shapegroup\" id=\"g\">") + sphere +
             "</shape>\n<shape type=\"instance\"><ref id=\"g\"/><bsdf type=\"diffuse\"/></shape>",
         3},
        {"instance without a group", "\n<shape type=\"instance\"/>", 3},
        {"instance with an emitter",
         std::string("<shape type=\"shapegroup\" id=\"g\">") + sphere +
             "</shape>\n<shape type=\"instance\"><ref id=\"g\"/><emitter type=\"area\"/></shape>",
         3},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        try {
            load_scene_xml_in(dir, c.body);
            FAIL("expected an error");
        } catch (const SceneError& e) {
            INFO(e.what());
            CHECK(e.location.line == c.line);
        }
    }
}
