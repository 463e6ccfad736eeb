// Meshes: OBJ (shapes/obj_reader.h) and PLY (ascii, binary little and big endian) loading, concave
// n-gons triangulated by ear clipping, uv flipping, normals.

#include "core/mesh.h"
#include "core/parallel.h"
#include "core/xml.h"
#include "geometry2d/polygon.h"
#include "shapes/obj_reader.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <array>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

using namespace candela;
using namespace candela::test;

namespace {

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

// Loads `text` as an OBJ file through the plugin and expects an error naming the file and line.
void check_obj_error(const std::filesystem::path& dir, const std::string& name, const std::string& text, int obj_line,
                     const std::string& what) {
    INFO(name << ": " << text);
    write_text(dir / (name + ".obj"), text);
    write_text(dir / "scene.xml", scene_xml("<shape type=\"obj\">\n<string name=\"filename\" value=\"" + name + ".obj\"/>\n</shape>"));
    try {
        load_scene((dir / "scene.xml").string());
        FAIL("expected an error");
    } catch (const SceneError& e) {
        CHECK(e.location.line == 3);
        CHECK_THAT(std::string(e.what()), Catch::Contains(name + ".obj\"" + (obj_line ? ", line " + std::to_string(obj_line) + ": " : "")));
        CHECK_THAT(std::string(e.what()), Catch::Contains(what));
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
    const Mesh& m = load_single_mesh(dir, R"(<shape type="obj"><string name="filename" value="arrow.obj"/></shape>)", keep);
    check_arrow_triangulation(m);
    REQUIRE(m.uvs().size() == 6);
    CHECK(m.uvs()[1] == Vec2(1.0f, 0.75f));  // flip_tex_coords defaults to true
    // No normals in the file: smooth normals are computed (here all +z).
    REQUIRE(m.normals().size() == 6);
    for (auto& n : m.normals()) CHECK(glm::length(n - Vec3(0, 0, 1)) < 1e-5f);
    Ref<Scene> keep2;
    const Mesh& unflipped = load_single_mesh(
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
    const Mesh& m = load_single_mesh(dir, R"(<shape type="obj"><string name="filename" value="two.obj"/></shape>)", keep);
    CHECK(m.positions().size() == 5);  // vertex 1 appears with two different uvs
    CHECK(m.normals().size() == 5);
    Ref<Scene> keep2;
    const Mesh& flat = load_single_mesh(
        dir, R"(<shape type="obj"><string name="filename" value="two.obj"/><boolean name="face_normals" value="true"/></shape>)", keep2);
    CHECK(flat.normals().empty());
}

TEST_CASE("obj: a broken file is an error at the filename's line", "[mesh][errors]") {
    auto dir = scratch_dir("obj-bad");
    // Indices past the end, also ones whose byte offset overflows an int (found by fuzz_obj:
    // 3 * 827408843 overflowed, undefined behaviour, before the range check).
    check_obj_error(dir, "missing", "v 0 0 0\nv 1 0 0\nf 1 2 7\n", 3, "vertex 7, which does not exist (the file has 2)");
    check_obj_error(dir, "huge_vertex", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 827408844\n", 4, "vertex 827408844, which does not exist");
    check_obj_error(dir, "huge_uv_and_normal",
                    "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1100000000/1 3/1/900000000\nf 1 2 827408844\n", 6,
                    "texture coordinate 1100000000, which does not exist");
}

namespace {

// A straightforward reading of OBJ text, line by line with string streams, merging corners in a
// std::map in the order the faces first use them (what the plugin did with tinyobjloader): the
// reference the parallel reader is compared against. Only for well-formed text.
struct ReferenceObj {
    MeshArray<Vec3> positions, normals;
    MeshArray<Vec2> uvs;
    MeshArray<glm::uvec3> triangles;
};
ReferenceObj reference_obj(const std::string& text, bool ignore_normals = false) {
    std::vector<Vec3> v, vn;
    std::vector<Vec2> vt;
    std::vector<std::vector<std::array<int, 3>>> faces;
    std::string unified = text;
    for (size_t i = 0; i < unified.size(); ++i)
        if (unified[i] == '\r') unified[i] = (i + 1 < unified.size() && unified[i + 1] == '\n') ? ' ' : '\n';
    std::istringstream lines(unified);
    std::string line;
    while (std::getline(lines, line)) {
        line = line.substr(0, line.find('#'));
        std::istringstream in(line);
        std::string key;
        in >> key;
        if (key == "v" || key == "vn") {
            float x, y, z;
            in >> x >> y >> z;
            (key == "v" ? v : vn).emplace_back(x, y, z);
        } else if (key == "vt") {
            float a = 0.0f, b = 0.0f;
            in >> a >> b;
            vt.emplace_back(a, 1.0f - b);
        } else if (key == "f") {
            std::vector<std::array<int, 3>> face;
            std::string corner;
            while (in >> corner) {
                std::array<int, 3> idx = {-1, -1, -1};
                const int counts[3] = {int(v.size()), int(vt.size()), int(vn.size())};
                size_t at = 0;
                for (int k = 0; k < 3 && at <= corner.size(); ++k) {
                    size_t slash = corner.find('/', at);
                    std::string part = corner.substr(at, slash == std::string::npos ? std::string::npos : slash - at);
                    if (!part.empty()) {
                        int i = std::stoi(part);
                        idx[k] = i > 0 ? i - 1 : counts[k] + i;
                    }
                    if (slash == std::string::npos) break;
                    at = slash + 1;
                }
                if (ignore_normals || vn.empty()) idx[2] = -1;
                face.push_back(idx);
            }
            if (face.size() >= 3) faces.push_back(face);
        }
    }
    ReferenceObj r;
    std::map<std::array<int, 3>, unsigned> vertex_of;
    bool any_uv = false, every_normal = true;
    for (const auto& face : faces) {
        std::vector<unsigned> ids;
        for (const auto& idx : face) {
            auto [it, inserted] = vertex_of.emplace(idx, unsigned(r.positions.size()));
            if (inserted) {
                r.positions.push_back(v[size_t(idx[0])]);
                r.uvs.push_back(idx[1] >= 0 ? vt[size_t(idx[1])] : Vec2(0.0f));
                r.normals.push_back(idx[2] >= 0 ? vn[size_t(idx[2])] : Vec3(0.0f));
                any_uv |= idx[1] >= 0;
                every_normal &= idx[2] >= 0;
            }
            ids.push_back(it->second);
        }
        if (ids.size() == 3) {
            r.triangles.emplace_back(ids[0], ids[1], ids[2]);
            continue;
        }
        std::vector<Vec3> pts;
        for (unsigned id : ids) pts.push_back(r.positions[id]);
        for (auto& t : triangulate_polygon_3d(pts)) r.triangles.emplace_back(ids[size_t(t[0])], ids[size_t(t[1])], ids[size_t(t[2])]);
    }
    if (!any_uv) r.uvs.clear();
    if (!every_normal || r.positions.empty()) r.normals.clear();
    return r;
}

ReferenceObj read_chunked(const std::string& text, size_t chunk_bytes, int threads, bool ignore_normals = false) {
    ReferenceObj r;
    ObjReadOptions options;
    options.chunk_bytes = chunk_bytes;
    options.ignore_normals = ignore_normals;
    thread_arena(threads).execute([&] { read_obj(text.data(), text.size(), options, r.positions, r.uvs, r.normals, r.triangles); });
    return r;
}

void check_same(const ReferenceObj& a, const ReferenceObj& b) {
    CHECK(a.positions == b.positions);
    CHECK(a.uvs == b.uvs);
    CHECK(a.normals == b.normals);
    CHECK(a.triangles == b.triangles);
}

// A w x h grid of quads near the z = 0 plane, written row by row: every `uv_every`-th quad as a
// quad with uvs and relative indices, the others as two triangles naming positions only (with
// uv_every 0, only those: the faces use the positions first out of the file's order).
std::string grid_obj(int w, int h, int uv_every, const char* eol = "\n") {
    std::string s = "# grid" + std::string(eol);
    char buf[128];
    for (int y = 0; y <= h; ++y)
        for (int x = 0; x <= w; ++x) {
            std::snprintf(buf, sizeof buf, "v %.4f %.4f %.3g%s", x * 0.01, y * 0.01, 0.001 * ((x * 7 + y * 3) % 5), eol);
            s += buf;
            if (uv_every) {
                std::snprintf(buf, sizeof buf, "vt %.4f %.4f%s", x / double(w), y / double(h), eol);
                s += buf;
            }
        }
    const int n = (w + 1) * (h + 1);
    for (int y = 0, q = 0; y < h; ++y)
        for (int x = 0; x < w; ++x, ++q) {
            int a = y * (w + 1) + x + 1, b = a + 1, c = a + w + 2, d = a + w + 1;
            if (uv_every && q % uv_every == 0)
                std::snprintf(buf, sizeof buf, "f %d/%d %d/%d %d/%d %d/%d%s", a - n - 1, a - n - 1, b, b, c - n - 1, c, d, d - n - 1, eol);
            else
                std::snprintf(buf, sizeof buf, "f %d %d %d%sf %d %d %d%s", a, b, c, eol, a, c, d, eol);
            s += buf;
        }
    return s;
}

// A strip of n triangles whose faces use the positions first in the file's order.
std::string strip_obj(int n) {
    std::string s;
    for (int i = 0; i < n + 2; ++i) s += "v " + std::to_string(i / 2) + " " + std::to_string(i % 2) + " 0\n";
    for (int i = 1; i <= n; ++i)
        s += "f " + std::to_string(i) + " " + std::to_string(i % 2 ? i + 1 : i + 2) + " " + std::to_string(i % 2 ? i + 2 : i + 1) + "\n";
    return s;
}

}  // namespace

TEST_CASE("obj: corner forms, relative indices, CRLF, comments and skipped lines", "[mesh]") {
    const std::string text =
        "# made by hand\r\nmtllib none.mtl\r\no thing\r\n"
        "v 0 0 0 1\r\nv 1 0 0 0.5 0.25 1\r\n  v  1 1 0\r\nv 0 1 0 # a comment\r\n"
        "vt 0 0\r\nvt 1 0 0\r\nvt 1 1\r\nvt 0 1\r\nvt +0.5\r\nvn 0 0 1\r\n"
        "g group\r\ns 1\r\nusemtl red\r\n"
        "f 1/1/1 2/2/1 3/3/1\r\n"     // v/vt/vn
        "f -4//-1 -2//-1 -1//-1\r\n"  // v//vn, relative
        "f 1/1 3/3 4/4\r\n"           // v/vt
        "f 1 2 3 \r\n"                // v
        "\tf\t2  3\t4#comment\r\n"    // tabs
        "f 1 2\r\nl 1 2\r\np 1\r\nvp 0.5\r\ns off\r\n";
    auto dir = scratch_dir("obj-forms");
    write_text(dir / "forms.obj", text);
    Ref<Scene> keep;
    const Mesh& m = load_single_mesh(dir, R"(<shape type="obj"><string name="filename" value="forms.obj"/></shape>)", keep);
    // (v, vt, vn) keys in first-use order: 3 + 3 + 3 + 3 + 1 vertices.
    const std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const std::vector<int> position_of = {0, 1, 2, 0, 2, 3, 0, 2, 3, 0, 1, 2, 3};
    REQUIRE(m.positions().size() == position_of.size());
    for (size_t i = 0; i < position_of.size(); ++i) CHECK(m.positions()[i] == p[size_t(position_of[i])]);
    const MeshArray<glm::uvec3> triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {9, 10, 11}, {10, 11, 12}};
    CHECK(m.triangles() == triangles);
    REQUIRE(m.uvs().size() == 13);
    CHECK(m.uvs()[1] == Vec2(1.0f, 1.0f));  // vt 1 0, flipped
    CHECK(m.uvs()[8] == Vec2(0.0f, 0.0f));  // vt 0 1, flipped
    CHECK(m.uvs()[3] == Vec2(0.0f, 0.0f));  // no uv
    CHECK(m.normals().size() == 13);        // not every corner has one: smooth normals instead
    check_same(read_chunked(text, 0, 1), reference_obj(text));

    // The same file with \n and with \r line ends reads the same.
    std::string lf = text, cr = text;
    lf.erase(std::remove(lf.begin(), lf.end(), '\r'), lf.end());
    cr.erase(std::remove(cr.begin(), cr.end(), '\n'), cr.end());
    for (size_t chunk : {size_t(0), size_t(1), size_t(5)}) {
        check_same(read_chunked(lf, chunk, 2), read_chunked(text, 0, 1));
        check_same(read_chunked(cr, chunk, 2), read_chunked(text, 0, 1));
    }
}

TEST_CASE("obj: the mesh does not depend on chunks or threads, and matches a plain reading", "[mesh]") {
    struct Case {
        const char* name;
        std::string text;
    };
    const std::vector<Case> cases = {
        {"uvs, quads and relative indices", grid_obj(40, 30, 3)},
        {"positions only, first use out of file order", grid_obj(40, 30, 0)},
        {"positions only, first use in file order", strip_obj(2000)},
        {"with \\r\\n", grid_obj(20, 10, 4, "\r\n")},
        {"with \\r", grid_obj(20, 10, 0, "\r")},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        const ReferenceObj reference = reference_obj(c.text);
        REQUIRE(!reference.triangles.empty());
        for (size_t chunk : {size_t(0), size_t(1), size_t(13), size_t(1000), size_t(1) << 30})
            for (int threads : {1, 2}) {
                INFO("chunk bytes " << chunk << ", " << threads << " threads");
                check_same(read_chunked(c.text, chunk, threads), reference);
            }
    }
    // Unused positions are dropped, as the merge drops them.
    const ReferenceObj sparse = read_chunked("v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 2 3 4\n", 0, 1);
    CHECK(sparse.positions == MeshArray<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    CHECK(sparse.triangles == MeshArray<glm::uvec3>{{0, 1, 2}});
}

TEST_CASE("obj: a file of many chunks loads the same with 1 and 2 threads", "[mesh]") {
    // About 5 MB: the plugin cuts it into about 64 chunks.
    auto dir = scratch_dir("obj-large");
    const std::string text = grid_obj(250, 250, 7);
    REQUIRE(text.size() > (size_t(1) << 20));
    write_text(dir / "large.obj", text);
    std::vector<MeshArray<Vec3>> positions;
    std::vector<MeshArray<glm::uvec3>> triangles;
    for (int threads : {1, 2}) {
        thread_arena(threads).execute([&] {
            Ref<Scene> keep;
            const Mesh& m = load_single_mesh(dir, R"(<shape type="obj"><string name="filename" value="large.obj"/></shape>)", keep);
            positions.push_back(m.positions());
            triangles.push_back(m.triangles());
        });
    }
    const ReferenceObj reference = reference_obj(text);
    CHECK(triangles[0].size() == reference.triangles.size());
    CHECK(triangles[0] == reference.triangles);
    CHECK(positions[0] == positions[1]);
    CHECK(triangles[0] == triangles[1]);
}

TEST_CASE("obj: malformed numbers and indices are errors naming the file and line", "[mesh][errors]") {
    auto dir = scratch_dir("obj-malformed");
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    check_obj_error(dir, "letters", "v 0 0 0\nv 1 x 0\n", 2, "malformed number \"x\"");
    check_obj_error(dir, "suffix", "v 0 0 0\nv 1 2.5e 0\n", 2, "malformed number \"2.5e\"");
    check_obj_error(dir, "missing", "v 0 0 0\n\nv 1 0\n", 3, "a number is missing");
    check_obj_error(dir, "nan", "v 0 0 nan\n", 1, "not a finite number");
    check_obj_error(dir, "huge", "v 0 0 1e39\n", 1, "out of range");
    check_obj_error(dir, "crlf", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 0\r\n", 4, "vertex 0");
    check_obj_error(dir, "zero_uv", tri + "vt 0 0\nf 1/0 2/1 3/1\n", 5, "texture coordinate 0");
    check_obj_error(dir, "past_end", tri + "f 1 2 4\n", 4, "vertex 4, which does not exist (the file has 3)");
    check_obj_error(dir, "past_end_normal", tri + "vn 0 0 1\nf 1//1 2//2 3//1\n", 5, "normal 2, which does not exist");
    check_obj_error(dir, "before_first", tri + "f -1 -2 -4\n", 4, "vertex -4, before the first");
    check_obj_error(dir, "corner", tri + "f 1/ 2 3\n", 4, "malformed face corner \"1/\"");
    check_obj_error(dir, "corner_slashes", tri + "vt 0 0\nvn 0 0 1\nf 1/1/1/1 2 3\n", 6, "malformed face corner \"1/1/1/1\"");
    check_obj_error(dir, "continued", tri + "f 1 2 \\\n3\n", 4, "malformed face corner \"\\\"");
    check_obj_error(dir, "overflow", tri + "f 1 2 99999999999999999999\n", 4, "out of range");
    // The first error of the file, whatever chunk finds one first.
    std::string late = grid_obj(100, 100, 0) + "f 1 2 x\n";
    std::string early = "v 0 0 y\n" + late;
    for (int threads : {1, 2})
        for (size_t chunk : {size_t(0), size_t(100)}) {
            try {
                read_chunked(early, chunk, threads);
                FAIL("expected an error");
            } catch (const ObjError& e) {
                CHECK(e.line == 1);
            }
            try {
                read_chunked(late, chunk, threads);
                FAIL("expected an error");
            } catch (const ObjError& e) {
                CHECK(e.line == size_t(std::count(late.begin(), late.end(), '\n')));
            }
        }
    // Underflowing numbers are their nearest float; an empty file has no faces.
    const ReferenceObj tiny = read_chunked("v 1e-50 1e-400 -1e-40\n" + tri + "f 1 2 3\n", 0, 1);
    REQUIRE(tiny.positions.size() == 3);
    CHECK(tiny.positions[0].x == 0.0f);
    CHECK(tiny.positions[0].y == 0.0f);
    CHECK(tiny.positions[0].z < 0.0f);
    check_obj_error(dir, "empty", "", 0, "has no faces");
    check_obj_error(dir, "no_faces", tri + "f 1 2\n", 0, "has no faces");
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
    std::vector<MeshArray<Vec3>> positions;
    std::vector<MeshArray<Vec2>> uvs;
    for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        INFO(format);
        std::string name = std::string(format) + ".ply";
        write_ply(dir / name, format);
        Ref<Scene> keep;
        const Mesh& m = load_single_mesh(dir, "<shape type=\"ply\"><string name=\"filename\" value=\"" + name + "\"/></shape>", keep);
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
    const Mesh& m = load_single_mesh(dir, "<shape type=\"ply\"><string name=\"filename\" value=\"texcoord.ply\"/></shape>", keep);
    CHECK(m.triangle_count() == 1);
}
