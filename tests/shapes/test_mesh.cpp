// Meshes: OBJ (tinyobjloader) and PLY (ascii, binary little and big endian) loading, concave
// n-gons triangulated by ear clipping, uv flipping, normals.

#include "core/mesh.h"
#include "core/xml.h"
#include "geometry2d/polygon.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <fstream>

using namespace candela;
using namespace candela::test;

namespace {

const Mesh& load_mesh(const std::filesystem::path& dir, const std::string& shape_xml, Ref<Scene>& keep) {
    write_text(dir / "scene.xml", scene_xml(shape_xml));
    keep = load_scene((dir / "scene.xml").string());
    REQUIRE(keep->shapes().size() == 1);
    auto* mesh = dynamic_cast<const Mesh*>(keep->shapes()[0].get());
    REQUIRE(mesh != nullptr);
    return *mesh;
}

double total_area(const Mesh& m) {
    double a = 0.0;
    for (auto& t : m.triangles())
        a += 0.5 * glm::length(glm::cross(m.positions()[t.y] - m.positions()[t.x], m.positions()[t.z] - m.positions()[t.x]));
    return a;
}

// An arrow-shaped concave hexagon in the z = 0 plane, counter-clockwise seen from +z; a fan from
// vertex 0 would cover area outside it.
const std::vector<Vec3> Arrow = {{0, 0, 0}, {4, 2, 0}, {0, 4, 0}, {1, 2.5f, 0}, {1, 1.5f, 0}, {0.5f, 1, 0}};

double arrow_area() {
    std::vector<glm::dvec2> p;
    for (auto& v : Arrow) p.emplace_back(v.x, v.y);
    return 0.5 * polygon_signed_area2(p);
}

void check_arrow_triangulation(const Mesh& m) {
    CHECK(m.triangle_count() == Arrow.size() - 2);
    CHECK(total_area(m) == Approx(arrow_area()).epsilon(1e-6));
    std::vector<glm::dvec2> poly;
    for (auto& v : Arrow) poly.emplace_back(v.x, v.y);
    for (auto& t : m.triangles()) {
        Vec3 a = m.positions()[t.x], b = m.positions()[t.y], c = m.positions()[t.z];
        Vec3 centroid = (a + b + c) / 3.0f;
        CHECK(point_in_polygon(poly, glm::dvec2(centroid.x, centroid.y)));
        CHECK(glm::cross(b - a, c - a).z > 0.0f);  // same winding as the polygon
    }
}

}  // namespace

TEST_CASE("obj: concave n-gons, uv flip, de-duplication and smooth normals", "[mesh]") {
    auto dir = scratch_dir("obj");
    std::string obj;
    for (auto& v : Arrow) obj += "v " + std::to_string(v.x) + " " + std::to_string(v.y) + " 0\n";
    obj += "vt 0 0\nvt 1 0.25\nvt 0 1\nvt 0.25 0.6\nvt 0.25 0.4\nvt 0.1 0.25\n";
    obj += "f 1/1 2/2 3/3 4/4 5/5 6/6\n";
    write_text(dir / "arrow.obj", obj);
    Ref<Scene> keep;
    const Mesh& m = load_mesh(dir, R"(<shape type="obj"><string name="filename" value="arrow.obj"/></shape>)", keep);
    check_arrow_triangulation(m);
    REQUIRE(m.uvs().size() == 6);
    CHECK(m.uvs()[1] == Vec2(1.0f, 0.75f));  // flip_tex_coords defaults to true
    // No normals in the file: smooth normals are computed (here all +z).
    REQUIRE(m.normals().size() == 6);
    for (auto& n : m.normals()) CHECK(glm::length(n - Vec3(0, 0, 1)) < 1e-5f);
    Ref<Scene> keep2;
    const Mesh& unflipped = load_mesh(
        dir, R"(<shape type="obj"><string name="filename" value="arrow.obj"/><boolean name="flip_tex_coords" value="false"/></shape>)",
        keep2);
    CHECK(unflipped.uvs()[1] == Vec2(1.0f, 0.25f));
}

TEST_CASE("obj: normals from the file, face_normals, and corners split by uv seams", "[mesh]") {
    auto dir = scratch_dir("obj-normals");
    // Two triangles sharing an edge; the shared vertices use different uvs on each side.
    write_text(dir / "two.obj",
               "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
               "vn 0 0 1\nvn 0 0.6 0.8\n"
               "f 1/1/1 2/2/1 3/3/2\nf 1/5/1 3/3/2 4/4/1\n");
    Ref<Scene> keep;
    const Mesh& m = load_mesh(dir, R"(<shape type="obj"><string name="filename" value="two.obj"/></shape>)", keep);
    CHECK(m.positions().size() == 5);  // vertex 1 appears with two different uvs
    CHECK(m.normals().size() == 5);
    Ref<Scene> keep2;
    const Mesh& flat = load_mesh(
        dir, R"(<shape type="obj"><string name="filename" value="two.obj"/><boolean name="face_normals" value="true"/></shape>)", keep2);
    CHECK(flat.normals().empty());
}

TEST_CASE("obj: a broken file is an error at the filename's line", "[mesh][errors]") {
    auto dir = scratch_dir("obj-bad");
    // Indices past the end, also ones whose byte offset overflows an int (found by fuzz_obj:
    // 3 * 827408843 overflowed, undefined behaviour, before the range check).
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"missing", "v 0 0 0\nv 1 0 0\nf 1 2 7\n"},
        {"huge_vertex", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 827408844\n"},
        {"huge_uv_and_normal", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1100000000/1 3/1/900000000\nf 1 2 827408844\n"},
    };
    for (const auto& [name, text] : bad) {
        INFO(name);
        write_text(dir / (name + ".obj"), text);
        write_text(dir / "scene.xml", scene_xml("<shape type=\"obj\">\n<string name=\"filename\" value=\"" + name + ".obj\"/>\n</shape>"));
        try {
            load_scene((dir / "scene.xml").string());
            FAIL("expected an error");
        } catch (const SceneError& e) {
            CHECK(e.location.line == 3);
            CHECK_THAT(std::string(e.what()), Catch::Contains(name + ".obj"));
        }
    }
}

namespace {
// Writes the arrow as a PLY file in the given format, with a comment, an extra per-vertex
// property and an extra element to skip.
void write_ply(const std::filesystem::path& path, const std::string& format) {
    std::ofstream out(path, std::ios::binary);
    out << "ply\nformat " << format << " 1.0\ncomment test arrow\nelement vertex 6\nproperty float x\nproperty float y\n"
        << "property float z\nproperty uchar red\nproperty float u\nproperty float v\nelement face 1\n"
        << "property list uchar int vertex_indices\nelement extra 2\nproperty short dummy\nend_header\n";
    bool big = format == "binary_big_endian";
    auto put = [&](const void* data, size_t n) {
        std::string bytes(static_cast<const char*>(data), n);
        if (big) std::reverse(bytes.begin(), bytes.end());
        out.write(bytes.data(), std::streamsize(n));
    };
    for (size_t i = 0; i < Arrow.size(); ++i) {
        float vals[3] = {Arrow[i].x, Arrow[i].y, 0.0f}, uv[2] = {0.1f * i, 0.2f * i};
        unsigned char red = 200;
        if (format == "ascii") {
            out << vals[0] << " " << vals[1] << " " << vals[2] << " " << int(red) << " " << uv[0] << " " << uv[1] << "\n";
        } else {
            for (float f : vals) put(&f, 4);
            put(&red, 1);
            for (float f : uv) put(&f, 4);
        }
    }
    if (format == "ascii") {
        out << "6 0 1 2 3 4 5\n1\n2\n";
    } else {
        unsigned char n = 6;
        put(&n, 1);
        for (int i = 0; i < 6; ++i) put(&i, 4);
        for (short s : {short(1), short(2)}) put(&s, 2);
    }
}
}  // namespace

TEST_CASE("ply: ascii and binary files of both endiannesses give the same mesh", "[mesh]") {
    auto dir = scratch_dir("ply");
    std::vector<std::vector<Vec3>> positions;
    std::vector<std::vector<Vec2>> uvs;
    for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        INFO(format);
        std::string name = std::string(format) + ".ply";
        write_ply(dir / name, format);
        Ref<Scene> keep;
        const Mesh& m = load_mesh(dir, "<shape type=\"ply\"><string name=\"filename\" value=\"" + name + "\"/></shape>", keep);
        check_arrow_triangulation(m);
        positions.push_back(m.positions());
        uvs.push_back(m.uvs());
        REQUIRE(m.uvs().size() == 6);
        CHECK(m.uvs()[2].y == Approx(0.4f));  // not flipped
    }
    CHECK(positions[0] == positions[1]);
    CHECK(positions[1] == positions[2]);
    CHECK(uvs[1] == uvs[2]);
}

TEST_CASE("ply: truncated and malformed files are errors", "[mesh][errors]") {
    auto dir = scratch_dir("ply-bad");
    write_ply(dir / "full.ply", "binary_little_endian");
    std::string bytes = read_text(dir / "full.ply");
    write_text(dir / "truncated.ply", bytes.substr(0, bytes.size() - 20));
    write_text(dir / "header.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0\n1\n2\n");
    write_text(dir / "notply.ply", "hello\n");
    for (const char* name : {"truncated.ply", "header.ply", "notply.ply"}) {
        INFO(name);
        write_text(dir / "scene.xml",
                   scene_xml(std::string("<shape type=\"ply\">\n<string name=\"filename\" value=\"") + name + "\"/>\n</shape>"));
        CHECK_THROWS_AS(load_scene((dir / "scene.xml").string()), SceneError);
    }
}

TEST_CASE("ply: a face corner one past the last vertex is an error, also in a polygon", "[mesh][errors]") {
    // The off-by-one planted in the index check to test the robustness CI (README "Sanitizers and
    // fuzzing"): fuzz_ply found it in 10 s as a heap overflow in the polygon triangulation; its
    // input is kept in fuzz/corpus/ply/regression-planted-index-equals-count.ply.
    auto dir = scratch_dir("ply-index");
    const std::string header =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    write_text(dir / "triangle.ply", header + "3 0 1 4\n");
    write_text(dir / "quad.ply", header + "4 0 1 2 4\n");
    write_text(dir / "found.ply", read_text(source_path("fuzz/corpus/ply/regression-planted-index-equals-count.ply")));
    for (const char* name : {"triangle.ply", "quad.ply", "found.ply"}) {
        INFO(name);
        write_text(dir / "scene.xml",
                   scene_xml(std::string("<shape type=\"ply\">\n<string name=\"filename\" value=\"") + name + "\"/>\n</shape>"));
        CHECK_THROWS_AS(load_scene((dir / "scene.xml").string()), SceneError);
    }
}

TEST_CASE("ply: an element without properties is skipped at once, however many it counts", "[mesh][errors]") {
    // Found by fuzz_ply (a time-out in CI): 444444444444444 elements of no properties were
    // skipped one by one. The file holds no faces, which is the error it must reach at once.
    auto dir = scratch_dir("ply-empty-element");
    write_text(dir / "found.ply", read_text(source_path("fuzz/corpus/ply/regression-empty-element-count")));
    write_text(dir / "scene.xml", scene_xml("<shape type=\"ply\">\n<string name=\"filename\" value=\"found.ply\"/>\n</shape>"));
    try {
        load_scene((dir / "scene.xml").string());
        FAIL("expected an error");
    } catch (const SceneError& e) {
        CHECK_THAT(std::string(e.what()), Catch::Contains("has no faces"));
    }
}

TEST_CASE("ply: values outside their declared type, bad list types and huge counts are errors", "[mesh][errors]") {
    // Found by fuzz_ply: an ascii index beyond every integer type reached undefined behaviour
    // (a double converted to an integer it does not fit) instead of an error. Every case names
    // the PLY file at the filename's line.
    auto dir = scratch_dir("ply-types");
    const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
    auto face_file = [&](const std::string& face_header, const std::string& faces) {
        return header + face_header + "end_header\n" + vertices + faces;
    };
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"huge_index",
         face_file("element face 1\nproperty list uint8 uint16 vertex_index\n", "3 0 1 40000000000000000000000000000000000000\n")},
        {"fractional_index", face_file("element face 1\nproperty list uchar int vertex_indices\n", "3 0 1 1.5\n")},
        {"negative_unsigned", face_file("element face 1\nproperty list uchar uint vertex_indices\n", "3 0 1 -2\n")},
        {"float_count", face_file("element face 1\nproperty list float int vertex_indices\n", "3 0 1 2\n")},
        {"float_indices", face_file("element face 1\nproperty list uchar float vertex_indices\n", "3 0 1 2\n")},
        {"negative_count", face_file("element face 1\nproperty list char int vertex_indices\n", "-3 0 1 2\n")},
        {"float_overflow",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1e300 0 0\n0 1 0\n3 0 1 2\n"},
        {"double_overflow",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1e300 0 0\n0 1 0\n3 0 1 2\n"},
        {"nan_uv",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty float u\n"
         "property float v\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 nan 0\n0 1 0 0 1\n3 0 1 2\n"},
        {"huge_count",
         "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n"},
    };
    for (const auto& [name, text] : bad) {
        INFO(name);
        write_text(dir / (name + ".ply"), text);
        write_text(dir / "scene.xml", scene_xml("<shape type=\"ply\">\n<string name=\"filename\" value=\"" + name + ".ply\"/>\n</shape>"));
        try {
            load_scene((dir / "scene.xml").string());
            FAIL("expected an error");
        } catch (const SceneError& e) {
            CHECK(e.location.line == 3);
            CHECK_THAT(std::string(e.what()), Catch::Contains(name + ".ply"));
        }
    }
    // A face element's other lists are skipped, not read as vertex indices.
    write_text(dir / "texcoord.ply",
               face_file("element face 1\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\n",
                         "3 0 1 2 6 0.5 0.5 7.5 0 0 1\n"));
    Ref<Scene> keep;
    const Mesh& m = load_mesh(dir, "<shape type=\"ply\"><string name=\"filename\" value=\"texcoord.ply\"/></shape>", keep);
    CHECK(m.triangle_count() == 1);
}
