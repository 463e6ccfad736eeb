// Mesh attributes: Mitsuba 3's naming of extra PLY vertex and face properties, and the
// mesh_attribute texture that reads them at a hit (interpolated per vertex, constant per face),
// on plain meshes and through instances; what it cannot answer is an error at its line.

#include "core/bsdf.h"
#include "core/mesh.h"
#include "core/texture.h"
#include "core/warning.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

// A unit square in z = 0 (a quad face, split in two) and a triangle beside it, with extra
// vertex and face properties of every kind the naming rules distinguish.
const char* AttributePly = R"(ply
format ascii 1.0
element vertex 7
property float x
property float y
property float z
property uchar red
property uchar green
property uchar blue
property float mass_x
property float dir_x
property float dir_y
property float dir_z
property float lonely
property float pair_0
property float pair_1
property float tint_r
property float tint_g
property float tint_b
element face 2
property list uchar int vertex_indices
property float w_1
property float w_2
property float w_3
end_header
0 0 0 255 128 0 0.5 1 0 0 9 1 2 0.1 0.2 0.3
1 0 0 0 255 0 1.5 0 1 0 9 1 2 0.1 0.2 0.3
1 1 0 0 0 255 2.5 0 0 1 9 1 2 0.1 0.2 0.3
0 1 0 255 255 255 3.5 1 1 0 9 1 2 0.1 0.2 0.3
2 0 0 0 0 0 4.5 1 0 0 9 1 2 0.4 0.5 0.6
3 0 0 0 0 0 5.5 0 1 0 9 1 2 0.4 0.5 0.6
2 1 0 0 0 0 6.5 0 0 1 9 1 2 0.4 0.5 0.6
4 0 1 2 3 0.25 0.5 0.75
3 4 5 6 1 2 3
)";

const MeshAttribute* find(const Mesh& m, const std::string& name) {
    for (const MeshAttribute& a : m.attributes())
        if (a.name == name) return &a;
    return nullptr;
}

// The reflectance a ray straight down onto the z = 0 plane at (x, y) sees.
Spectrum albedo_at(const Scene& s, float x, float y) {
    SurfaceInteraction si;
    REQUIRE(s.intersect(Ray(Vec3(x, y, 1), Vec3(0, 0, -1)), si));
    return si.shape->bsdf()->albedo(si);
}

std::string textured(const std::string& name, const std::string& extra = "") {
    return "<shape type=\"ply\"><string name=\"filename\" value=\"attr.ply\"/><bsdf type=\"diffuse\">\n<texture type=\"mesh_attribute\" name=\"reflectance\">\n"
           "<string name=\"name\" value=\"" +
           name + "\"/>" + extra + "</texture></bsdf></shape>";
}

}  // namespace

TEST_CASE("ply: extra properties become vertex_ and face_ attributes named as in Mitsuba", "[mesh][attributes]") {
    auto dir = scratch_dir("ply-attributes");
    write_text(dir / "attr.ply", AttributePly);
    std::vector<std::string> warnings;
    WarningSink previous = set_warning_sink([&](const std::string& line) { warnings.push_back(line); });
    Ref<Scene> s = load_scene_xml_in(dir, "<shape type=\"ply\"><string name=\"filename\" value=\"attr.ply\"/></shape>");
    set_warning_sink(previous);
    REQUIRE(warnings.size() == 1);  // the properties left out, named, as Mitsuba warns
    CHECK_THAT(warnings[0], Catch::EndsWith("ignored: lonely, pair_0, pair_1"));
    const Mesh& m = dynamic_cast<const Mesh&>(*s->shapes()[0]);
    std::vector<std::string> names;
    for (const MeshAttribute& a : m.attributes()) names.push_back(a.name + "/" + std::to_string(a.channels) + (a.per_face ? "f" : "v"));
    // lonely (no suffix) and pair_0 pair_1 (two components) are not attributes, as in Mitsuba.
    CHECK(names == std::vector<std::string>({"vertex_color/3v", "vertex_mass/1v", "vertex_dir/3v", "vertex_tint_color/3v", "face_w/3f"}));
    // 8-bit colours: normalised and decoded from sRGB.
    const MeshAttribute* color = find(m, "vertex_color");
    REQUIRE(color);
    CHECK(color->values[0] == 1.0f);
    CHECK(color->values[1] == Approx(srgb_to_linear(128.0f / 255.0f)));
    CHECK(color->values[2] == 0.0f);
    CHECK(find(m, "vertex_mass")->values[3] == 3.5f);  // floats as they are
    // The quad became two triangles, each with the quad's face attribute.
    REQUIRE(m.triangle_count() == 3);
    CHECK(find(m, "face_w")->values == std::vector<float>({0.25f, 0.5f, 0.75f, 0.25f, 0.5f, 0.75f, 1, 2, 3}));
}

TEST_CASE("mesh_attribute: vertex attributes interpolate, face attributes are constant, scale applies", "[texture][attributes]") {
    auto dir = scratch_dir("mesh-attribute");
    write_text(dir / "attr.ply", AttributePly);
    Ref<Scene> vertex = load_scene_xml_in(dir, textured("vertex_dir"));
    // In the triangle (4, 5, 6) at (2.25, 0.25): barycentrics 0.5, 0.25, 0.25 of the
    // directions (1,0,0), (0,1,0), (0,0,1).
    Spectrum v = albedo_at(*vertex, 2.25f, 0.25f);
    CHECK(glm::length(v - Spectrum(0.5f, 0.25f, 0.25f)) < 1e-5f);
    Ref<Scene> face = load_scene_xml_in(dir, textured("face_w", "<float name=\"scale\" value=\"0.1\"/>"));
    CHECK(glm::length(albedo_at(*face, 0.2f, 0.7f) - Spectrum(0.025f, 0.05f, 0.075f)) < 1e-6f);
    CHECK(glm::length(albedo_at(*face, 2.2f, 0.3f) - Spectrum(0.1f, 0.2f, 0.3f)) < 1e-6f);
    // One channel reads as grey; roughness-like scalar lookups take the luminance.
    Ref<Scene> mass = load_scene_xml_in(dir, textured("vertex_mass", "<float name=\"scale\" value=\"0.2\"/>"));
    Spectrum grey = albedo_at(*mass, 2.25f, 0.25f);
    CHECK(grey.x == Approx(0.2f * (0.5f * 4.5f + 0.25f * 5.5f + 0.25f * 6.5f)));
    CHECK(grey.x == grey.y);
}

TEST_CASE("mesh_attribute: through an instance the group's mesh attributes are read", "[texture][attributes][instance]") {
    auto dir = scratch_dir("mesh-attribute-instance");
    write_text(dir / "attr.ply", AttributePly);
    Ref<Scene> s = load_scene_xml_in(
        dir,
        "<shape type=\"shapegroup\" id=\"g\">" + textured("vertex_dir") +
            "</shape><shape type=\"instance\"><ref id=\"g\"/><transform name=\"to_world\"><scale value=\"2\"/><translate x=\"10\"/></transform></shape>");
    CHECK(glm::length(albedo_at(*s, 14.5f, 0.5f) - Spectrum(0.5f, 0.25f, 0.25f)) < 1e-5f);
}

TEST_CASE("mesh_attribute: a constant vertex colour renders as the same rgb reflectance", "[texture][attributes][render]") {
    auto dir = scratch_dir("mesh-attribute-render");
    std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float r\n"
        "property float g\nproperty float b\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (const char* xy : {"-1 -1", "1 -1", "1 1", "-1 1"}) ply += std::string(xy) + " 0 0.3 0.5 0.7\n";
    write_text(dir / "quad.ply", ply + "4 0 1 2 3\n");
    const char* rest = R"(<emitter type="constant"/><integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <sensor type="perspective"><transform name="to_world"><lookat origin="0.5, -2, 2" target="0, 0, 0" up="0, 0, 1"/></transform>
            <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
            <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/></film></sensor>)";
    std::vector<Image> images;
    for (const char* reflectance :
         {R"(<texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_color"/></texture>)",
          R"(<rgb name="reflectance" value="0.3, 0.5, 0.7"/>)"}) {
        write_text(dir / "scene.xml",
                   scene_xml(std::string("<shape type=\"ply\"><string name=\"filename\" value=\"quad.ply\"/><bsdf type=\"diffuse\">") +
                             reflectance + "</bsdf></shape>" + rest));
        images.push_back(render_file((dir / "scene.xml").string(), {}).image);
    }
    // Interpolating three equal values with barycentrics that sum to one rounds by at most a
    // few units in the last place.
    float worst = 0.0f;
    for (size_t i = 0; i < images[0].data().size(); ++i)
        worst = std::max(worst, std::abs(images[0].data()[i] - images[1].data()[i]) / std::max(images[1].data()[i], 1e-6f));
    CHECK(worst <= 1e-6f);
}

TEST_CASE("mesh_attribute: a bad name, a missing attribute and uv-only uses are errors at the texture's line",
          "[texture][attributes][errors]") {
    auto dir = scratch_dir("mesh-attribute-errors");
    write_text(dir / "attr.ply", AttributePly);
    try {
        load_scene_xml_in(dir, textured("color"));
        FAIL("expected an error");
    } catch (const SceneError& e) {
        CHECK(e.location.line == 4);  // the <string name="name"> line
    }
    Ref<Scene> s = load_scene_xml_in(dir, textured("vertex_nothing"));
    try {
        albedo_at(*s, 0.5f, 0.5f);
        FAIL("expected an error");
    } catch (const SceneError& e) {
        CHECK(e.location.line == 3);  // the <texture> line
    }
    // The rasterizer looks textures up by uv alone: a mesh attribute cannot answer that.
    write_text(dir / "scene.xml", scene_xml(textured("vertex_color") + R"(<emitter type="constant"/><integrator type="raster"/>
        <sensor type="perspective"><transform name="to_world"><lookat origin="1, 0.5, 3" target="1, 0.5, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>)"));
    try {
        render_file((dir / "scene.xml").string(), {});
        FAIL("expected an error");
    } catch (const SceneError& e) {
        INFO(e.what());
        CHECK(e.location.line == 3);
    }
}
