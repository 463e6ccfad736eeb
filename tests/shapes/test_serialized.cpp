// serialized: a writer here produces Mitsuba's format from its description (several meshes per
// file, versions 3 and 4, single and double precision, with and without normals, uvs and
// colours); the reader must give back exactly what was written. Broken files are errors at the
// filename's line.

#include "core/mesh.h"
#include "core/xml.h"
#include "tests/serialized_writer.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <fstream>

using namespace candela;
using namespace candela::test;

namespace {

// A small non-planar mesh: a tetrahedron with per-vertex data.
TestMesh tetrahedron(float scale) {
    TestMesh m;
    m.positions = {{0, 0, 0}, {scale, 0, 0}, {0, scale, 0}, {0, 0, scale}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
}

std::string serialized_shape(const std::string& file, int index, const std::string& extra = "") {
    return "<shape type=\"serialized\">\n<string name=\"filename\" value=\"" + file + "\"/>\n<integer name=\"shape_index\" value=\"" +
           std::to_string(index) + "\"/>" + extra + "</shape>";
}

}  // namespace

TEST_CASE("serialized: several meshes in one file round-trip through the reader", "[mesh][serialized]") {
    auto dir = scratch_dir("serialized");
    TestMesh full = tetrahedron(1.0f);
    for (size_t i = 0; i < full.positions.size(); ++i) {
        full.normals.push_back(glm::normalize(full.positions[i] - Vec3(0.2f)));
        full.uvs.emplace_back(0.1f * float(i), 1.0f - 0.2f * float(i));
    }
    TestMesh bare = tetrahedron(2.0f);
    bare.double_precision = true;
    bare.positions[3] = Vec3(0.1f, 0.3f, 1.7f);  // not representable exactly: read as double, rounded once
    TestMesh colored = tetrahedron(0.5f);
    colored.colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.25f, 0.5f, 0.75f}};
    colored.face_normals = true;
    std::vector<TestMesh> meshes = {full, bare, colored};

    for (int version : {3, 4}) {
        INFO("version " << version);
        std::string name = "meshes" + std::to_string(version) + ".serialized";
        write_text(dir / name, encode_file(meshes, version));
        for (int index = 0; index < 3; ++index) {
            INFO("shape_index " << index);
            Ref<Scene> keep;
            const Mesh& m = load_single_mesh(dir, serialized_shape(name, index), keep);
            const TestMesh& expected = meshes[size_t(index)];
            CHECK(m.positions() == expected.positions);
            CHECK(m.triangles() == expected.triangles);
            CHECK(m.uvs() == expected.uvs);
            if (index == 0) {
                REQUIRE(m.normals().size() == expected.normals.size());
                for (size_t i = 0; i < expected.normals.size(); ++i) CHECK(glm::length(m.normals()[i] - expected.normals[i]) < 1e-6f);
            }
            if (index == 1) CHECK(m.normals().size() == 4);  // none in the file: smooth ones computed
            if (index == 2) {
                CHECK(m.normals().size() == 4);  // the face-normals flag changes nothing, as in Mitsuba 3
                REQUIRE(m.attributes().size() == 1);
                CHECK(m.attributes()[0].name == "vertex_color");
                CHECK(m.attributes()[0].values == std::vector<float>({1, 0, 0, 0, 1, 0, 0, 0, 1, 0.25f, 0.5f, 0.75f}));
            } else {
                CHECK(m.attributes().empty());
            }
        }
    }
}

TEST_CASE("serialized: to_world, flip_normals and face_normals apply as for other meshes", "[mesh][serialized]") {
    auto dir = scratch_dir("serialized-params");
    TestMesh m = tetrahedron(1.0f);
    for (const Vec3& p : m.positions) m.normals.push_back(squared_length(p) > 0 ? glm::normalize(p) : Vec3(-0.57735f));
    write_text(dir / "one.serialized", encode_file({m}, 4));
    Ref<Scene> keep, keep2;
    const Mesh& moved = load_single_mesh(
        dir,
        serialized_shape("one.serialized", 0,
                         "<transform name=\"to_world\"><translate x=\"5\"/></transform><boolean name=\"flip_normals\" value=\"true\"/>"),
        keep);
    CHECK(moved.positions()[1] == Vec3(6, 0, 0));
    CHECK(moved.flip_normals());
    const Mesh& flat =
        load_single_mesh(dir, serialized_shape("one.serialized", 0, "<boolean name=\"face_normals\" value=\"true\"/>"), keep2);
    CHECK(flat.normals().empty());
}

TEST_CASE("serialized: broken files are errors at the filename's line", "[mesh][serialized][errors]") {
    auto dir = scratch_dir("serialized-bad");
    std::vector<TestMesh> meshes = {tetrahedron(1.0f), tetrahedron(2.0f)};
    std::string good = encode_file(meshes, 4);
    std::string first_mesh = encode_mesh(meshes[0], 4);
    std::string corrupt = good;
    corrupt[first_mesh.size() / 2] = char(corrupt[first_mesh.size() / 2] ^ 0x5A);  // inside the first mesh's zlib data
    std::string bad_magic = good;
    bad_magic[0] = 0x1D;
    std::string bad_dictionary = good;
    bad_dictionary[good.size() - 5] = char(0x7F);  // the last offset now points far past the end
    struct Case {
        const char* name;
        std::string bytes;
        int index;
    };
    std::vector<Case> cases = {{"truncated", good.substr(0, first_mesh.size() - 10), 0},
                               {"corrupt", corrupt, 0},
                               {"magic", bad_magic, 0},
                               {"dictionary", bad_dictionary, 1},
                               {"index", good, 2},
                               {"empty", "", 0},
                               {"version", good.substr(0, 2) + std::string("\x07\x00", 2) + good.substr(4), 0}};
    for (const Case& c : cases) {
        INFO(c.name);
        write_text(dir / (std::string(c.name) + ".serialized"), c.bytes);
        write_text(dir / "scene.xml", scene_xml(serialized_shape(std::string(c.name) + ".serialized", c.index)));
        try {
            load_scene((dir / "scene.xml").string());
            FAIL("expected an error");
        } catch (const SceneError& e) {
            INFO(e.what());
            CHECK(e.location.line == 3);  // the <string name="filename"> line
        }
    }
}

TEST_CASE("serialized: a header that declares more than the file can hold is refused before inflating",
          "[mesh][serialized][errors][memory]") {
    auto dir = scratch_dir("serialized-lying");
    // A tetrahedron's fields under a header declaring a billion vertices (12 GB of positions):
    // more than its hundred-odd compressed bytes can expand to, DEFLATE expanding at most 1032:1.
    TestMesh lying = tetrahedron(1.0f);
    lying.declared_vertices = 1000000000;
    // Declaring three of its four vertices leaves data beyond what the header accounts for.
    TestMesh short_count = tetrahedron(1.0f);
    short_count.declared_vertices = 3;
    struct Case {
        const char* name;
        TestMesh mesh;
        const char* message;
    };
    for (const Case& c : {Case{"lying", lying, "the header declares 1000000000 vertices and 4 triangles"},
                          Case{"short", short_count, "holds more than its header declares"}}) {
        INFO(c.name);
        write_text(dir / (std::string(c.name) + ".serialized"), encode_file({c.mesh}, 4));
        write_text(dir / "scene.xml", scene_xml(serialized_shape(std::string(c.name) + ".serialized", 0)));
        try {
            load_scene((dir / "scene.xml").string());
            FAIL("expected an error");
        } catch (const SceneError& e) {
            INFO(e.what());
            CHECK(e.location.line == 3);
            CHECK_THAT(std::string(e.what()), Catch::Contains(c.message));
        }
    }
}
