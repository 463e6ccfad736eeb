// Meshes large enough to take the readers' and the mesh's bulk paths: binary PLY records read a
// buffer at a time (and across buffer refills), serialized fields inflated straight into the
// mesh's arrays (and double precision converted in chunks), and flat meshes too large to cache
// their triangle frames. Each must give exactly what the small-file paths give.

#include "core/mesh.h"
#include "core/scene.h"
#include "core/xml.h"
#include "tests/serialized_writer.h"
#include "tests/util.h"

#include <tbb/task_arena.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

using namespace candela;
using namespace candela::test;

namespace {

std::string ply_shape(const std::string& file, const std::string& extra = "") {
    return "<shape type=\"ply\"><string name=\"filename\" value=\"" + file + "\"/>" + extra + "</shape>";
}

// A wavy n x n grid; every 97th cell is one quad (a polygon of four corners), the others two
// triangles, so that triangle and polygon records interleave across the reader's buffers.
struct Grid {
    std::vector<glm::dvec3> positions;
    std::vector<unsigned char> red;
    std::vector<std::vector<int>> faces;
};

Grid make_grid(int n) {
    Grid g;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            g.positions.emplace_back(i * 0.01 + 1e-9 * j, j * 0.01, 0.05 * std::sin(0.3 * i) * std::cos(0.2 * j));
            g.red.push_back((unsigned char)((i * 7 + j) % 256));
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
            if ((j * n + i) % 97 == 0)
                g.faces.push_back({a, b, d, c});
            else {
                g.faces.push_back({a, b, d});
                g.faces.push_back({a, d, c});
            }
        }
    return g;
}

// Vertices as doubles x y z with an 8-bit red, green and blue (an attribute), faces as lists.
void write_grid_ply(const Grid& g, const std::filesystem::path& path, const std::string& format) {
    std::ofstream out(path, std::ios::binary);
    out << "ply\nformat " << format << " 1.0\nelement vertex " << g.positions.size()
        << "\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
        << "element face " << g.faces.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    out.precision(17);
    const bool big = format == "binary_big_endian";
    auto put = [&](const void* data, size_t n) {
        std::string bytes(static_cast<const char*>(data), n);
        if (big) std::reverse(bytes.begin(), bytes.end());
        out.write(bytes.data(), std::streamsize(n));
    };
    for (size_t v = 0; v < g.positions.size(); ++v) {
        const unsigned char rgb[3] = {g.red[v], 10, 250};
        if (format == "ascii") {
            out << g.positions[v].x << " " << g.positions[v].y << " " << g.positions[v].z << " " << int(rgb[0]) << " " << int(rgb[1]) << " "
                << int(rgb[2]) << "\n";
            continue;
        }
        for (int k = 0; k < 3; ++k) put(&g.positions[v][k], 8);
        for (unsigned char c : rgb) put(&c, 1);
    }
    for (const auto& f : g.faces) {
        if (format == "ascii") {
            out << f.size();
            for (int i : f) out << " " << i;
            out << "\n";
            continue;
        }
        const unsigned char n = (unsigned char)f.size();
        put(&n, 1);
        for (int i : f) put(&i, 4);
    }
}

// A wavy n x n grid of vertices, two triangles per cell; with `repeat_every`, also a triangle with
// a repeated corner (degenerate) after each cell whose index is a multiple of it, counted in
// `repeated`.
TestMesh wavy_grid(int n, int repeat_every = 0, size_t* repeated = nullptr) {
    TestMesh m;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            m.positions.emplace_back(0.01f * float(i), 0.01f * float(j), 0.05f * std::sin(0.3f * float(i)) * std::cos(0.2f * float(j)));
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            unsigned a = unsigned(j * n + i), b = a + 1, c = a + unsigned(n), d = c + 1;
            m.triangles.push_back({a, b, d});
            m.triangles.push_back({a, d, c});
            if (repeat_every > 0 && (j * n + i) % repeat_every == 0) {
                m.triangles.push_back({a, a, d});
                ++*repeated;
            }
        }
    return m;
}

}  // namespace

TEST_CASE("ply: large binary files, read a buffer of records at a time, give the same mesh as ascii", "[mesh]") {
    // 27-byte vertex records, 400^2 of them (4.3 MB): more than one 4 MB buffer, so the vertices
    // come in two batches and the faces' records straddle the buffers' ends.
    const Grid g = make_grid(400);
    auto dir = scratch_dir("ply-large");
    std::vector<MeshArray<Vec3>> positions, normals;
    std::vector<MeshArray<glm::uvec3>> triangles;
    std::vector<std::vector<float>> colours;
    for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        INFO(format);
        write_grid_ply(g, dir / (std::string(format) + ".ply"), format);
        Ref<Scene> keep;
        const Mesh& m = load_single_mesh(dir, ply_shape(std::string(format) + ".ply"), keep);
        REQUIRE(m.positions().size() == g.positions.size());
        // The quads become two triangles each: as many triangles as two per cell.
        CHECK(m.triangle_count() == size_t(2 * 399 * 399));
        REQUIRE(m.attributes().size() == 1);
        CHECK(m.attributes()[0].name == "vertex_color");
        positions.push_back(m.positions());
        normals.push_back(m.normals());
        triangles.push_back(m.triangles());
        colours.push_back(m.attributes()[0].values);
    }
    // Doubles rounded once to float, wherever they were read from.
    for (size_t v : {size_t(0), size_t(12345), g.positions.size() - 1}) CHECK(positions[1][v] == Vec3(g.positions[v]));
    for (size_t k = 1; k < 3; ++k) {
        CHECK(positions[k] == positions[0]);
        CHECK(triangles[k] == triangles[0]);
        CHECK(colours[k] == colours[0]);
        CHECK(normals[k] == normals[0]);  // smooth normals, computed the same way
    }
}

TEST_CASE("serialized: a large double-precision mesh is inflated field by field, as written", "[mesh][serialized]") {
    // 260^2 = 67,600 vertices: more than one 65536-value chunk of each double field.
    TestMesh m;
    m.double_precision = true;
    const int n = 260;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            m.positions.emplace_back(0.01f * float(i), 0.01f * float(j), 0.1f * std::sin(0.1f * float(i + j)));
            m.normals.push_back(glm::normalize(Vec3(0.1f * std::sin(float(i)), 0.1f, 1.0f)));
            m.uvs.emplace_back(float(i) / n, float(j) / n);
            m.colors.emplace_back(float(i % 7) / 7.0f, 0.5f, float(j % 5) / 5.0f);
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            unsigned a = unsigned(j * n + i), b = a + 1, c = a + unsigned(n), d = c + 1;
            m.triangles.push_back({a, b, d});
            m.triangles.push_back({a, d, c});
        }
    auto dir = scratch_dir("serialized-large");
    write_text(dir / "large.serialized", encode_file({m}, 4));
    Ref<Scene> keep;
    const Mesh& mesh =
        load_single_mesh(dir, "<shape type=\"serialized\"><string name=\"filename\" value=\"large.serialized\"/></shape>", keep);
    CHECK(mesh.positions() == m.positions);
    CHECK(mesh.triangles() == m.triangles);
    CHECK(mesh.uvs() == m.uvs);
    REQUIRE(mesh.normals().size() == m.normals.size());
    for (size_t v : {size_t(0), size_t(65535), size_t(65536), m.normals.size() - 1})
        CHECK(glm::length(mesh.normals()[v] - m.normals[v]) < 1e-6f);
    REQUIRE(mesh.attributes().size() == 1);
    std::vector<float> colours;
    for (const Vec3& c : m.colors) colours.insert(colours.end(), {c.x, c.y, c.z});
    CHECK(mesh.attributes()[0].values == colours);
}

TEST_CASE("serialized: a large mesh equals the same mesh read from a PLY, its smooth normals bit for bit", "[mesh][serialized]") {
    // A wavy 320 x 320 grid (203,522 triangles and more), with degenerate triangles (a repeated
    // corner, three collinear corners) that finalize() drops. The same mesh as a binary PLY must
    // give the same positions, triangles and smooth normals exactly, with a to_world moving the
    // positions first, in single and double precision, on all threads and on one (the reader
    // inflates on one thread while a thread of its own follows: serialized.cpp's Follower).
    const int n = 320;
    size_t repeated = 0;
    TestMesh m = wavy_grid(n, 1009, &repeated);
    m.positions.emplace_back(-1.0f, -1.0f, 0.0f);  // three collinear vertices
    m.positions.emplace_back(-2.0f, -2.0f, 0.0f);
    m.positions.emplace_back(-3.0f, -3.0f, 0.0f);
    const unsigned last = unsigned(m.positions.size()) - 1;
    m.triangles.push_back({last - 2, last - 1, last});
    m.triangles.push_back({0, last - 2, 1});  // a proper triangle after them
    REQUIRE(m.triangles.size() > 3 * 65536);

    auto dir = scratch_dir("serialized-smooth");
    {
        std::ofstream out(dir / "grid.ply", std::ios::binary);
        out << "ply\nformat binary_little_endian 1.0\nelement vertex " << m.positions.size()
            << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << m.triangles.size()
            << "\nproperty list uchar int vertex_indices\nend_header\n";
        out.write(reinterpret_cast<const char*>(m.positions.data()), std::streamsize(m.positions.size() * sizeof(Vec3)));
        for (const glm::uvec3& t : m.triangles) {
            const unsigned char corners = 3;
            out.write(reinterpret_cast<const char*>(&corners), 1);
            out.write(reinterpret_cast<const char*>(&t), sizeof(t));
        }
    }
    write_text(dir / "grid.serialized", encode_file({m}, 4));
    TestMesh in_doubles = m;
    in_doubles.double_precision = true;
    write_text(dir / "grid_double.serialized", encode_file({in_doubles}, 3));

    const std::string to_world =
        "<transform name=\"to_world\"><rotate x=\"1\" y=\"2\" z=\"0.5\" angle=\"33\"/>"
        "<scale x=\"2\" y=\"0.5\" z=\"1.5\"/><translate x=\"0.25\"/></transform>";
    Ref<Scene> keep_ply;
    const Mesh& ply = load_single_mesh(dir, ply_shape("grid.ply", to_world), keep_ply);
    // The repeated corners are dropped (the collinear triangle may keep a tiny area after
    // to_world's rounding: kept or dropped, both readers must agree).
    REQUIRE(ply.triangle_count() + repeated <= m.triangles.size());
    REQUIRE(ply.normals().size() == m.positions.size());
    for (const std::string file : {"grid.serialized", "grid_double.serialized"})
        for (int threads : {0, 1}) {
            INFO(file << ", threads " << threads << " (0: all)");
            Ref<Scene> keep;
            const Mesh* mesh = nullptr;
            auto load = [&] {
                mesh = &load_single_mesh(
                    dir, "<shape type=\"serialized\"><string name=\"filename\" value=\"" + file + "\"/>" + to_world + "</shape>", keep);
            };
            if (threads == 0)
                load();
            else
                tbb::task_arena(threads).execute(load);
            CHECK(mesh->positions() == ply.positions());
            CHECK(mesh->triangles() == ply.triangles());
            CHECK(mesh->normals() == ply.normals());
            // The areas summed ahead by the follower, in finalize()'s chunks.
            CHECK(mesh->surface_area() == ply.surface_area());
            CHECK(mesh->bbox().min == ply.bbox().min);
            CHECK(mesh->bbox().max == ply.bbox().max);
        }

    // A triangle index out of range in the last slice: the error, not a write past the normals.
    TestMesh broken = m;
    broken.triangles.back().y = last + 1;
    write_text(dir / "broken.serialized", encode_file({broken}, 4));
    Ref<Scene> keep;
    CHECK_THROWS_WITH(
        load_single_mesh(dir, "<shape type=\"serialized\"><string name=\"filename\" value=\"broken.serialized\"/></shape>", keep),
        Catch::Contains("a triangle refers to vertex " + std::to_string(last + 1)));

    // The stream cut short, or corrupt, while the follower waits on it: the error, and the
    // follower stopped and joined (no hang, nothing read past the data).
    const std::string whole = encode_file({m}, 4);
    write_text(dir / "cut.serialized", whole.substr(0, whole.size() * 3 / 4));
    std::string corrupt = whole;
    for (size_t i = whole.size() / 2; i < whole.size() / 2 + 64; ++i) corrupt[i] = char(corrupt[i] ^ 0x5A);
    write_text(dir / "corrupt.serialized", corrupt);
    for (const char* file : {"cut.serialized", "corrupt.serialized"}) {
        INFO(file);
        CHECK_THROWS_WITH(load_single_mesh(dir,
                                           "<shape type=\"serialized\"><string name=\"filename\" value=\"" + std::string(file) +
                                               "\"/><boolean name=\"face_normals\" value=\"false\"/></shape>",
                                           keep),
                          Catch::Contains("cannot read serialized mesh"));
    }
    // Shaded flat (no normals to sum): the follower still prepares the rest, as finalize() would.
    Ref<Scene> keep_flat_ply, keep_flat;
    const std::string flat = "<boolean name=\"face_normals\" value=\"true\"/>";
    const Mesh& flat_ply = load_single_mesh(dir, ply_shape("grid.ply", to_world + flat), keep_flat_ply);
    const Mesh& flat_serialized = load_single_mesh(
        dir, "<shape type=\"serialized\"><string name=\"filename\" value=\"grid.serialized\"/>" + to_world + flat + "</shape>", keep_flat);
    CHECK(flat_serialized.normals().empty());
    CHECK(flat_serialized.positions() == flat_ply.positions());
    CHECK(flat_serialized.triangles() == flat_ply.triangles());
    CHECK(flat_serialized.surface_area() == flat_ply.surface_area());
}

TEST_CASE("mesh: a flat mesh too large to cache its triangle frames gives every hit the same frame", "[mesh]") {
    // 726 x 726 vertices: 1,051,250 triangles, past the 2^20 of the frame cache; the small mesh
    // is the large one's first two triangles. Both are shaded flat (face_normals).
    auto dir = scratch_dir("mesh-flat-large");
    auto write = [&](const std::string& name, int n) {
        std::ofstream out(dir / name, std::ios::binary);
        const size_t triangles = size_t(2) * size_t(n - 1) * size_t(n - 1);
        out << "ply\nformat binary_little_endian 1.0\nelement vertex " << n * n
            << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << triangles
            << "\nproperty list uchar int vertex_indices\nend_header\n";
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const float p[3] = {float(i), float(j), 0.3f * float((i * 31 + j * 17) % 5)};
                out.write(reinterpret_cast<const char*>(p), 12);
            }
        for (int j = 0; j + 1 < n; ++j)
            for (int i = 0; i + 1 < n; ++i) {
                const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
                const int two[2][3] = {{a, b, d}, {a, d, c}};
                for (const auto& t : two) {
                    const unsigned char three = 3;
                    out.write(reinterpret_cast<const char*>(&three), 1);
                    out.write(reinterpret_cast<const char*>(t), 12);
                }
            }
    };
    write("large.ply", 726);
    write("small.ply", 2);
    const std::string flat = "<boolean name=\"face_normals\" value=\"true\"/>";
    Ref<Scene> keep_large, keep_small;
    load_single_mesh(dir, ply_shape("large.ply", flat), keep_large);
    load_single_mesh(dir, ply_shape("small.ply", flat), keep_small);
    // Rays straight down onto both triangles of the first cell.
    for (const Vec2& xy : {Vec2(0.7f, 0.2f), Vec2(0.2f, 0.7f)}) {
        INFO(xy.x << ", " << xy.y);
        Ray ray(Vec3(xy.x, xy.y, 10.0f), Vec3(0.0f, 0.0f, -1.0f));
        SurfaceInteraction large, small;
        REQUIRE(keep_large->intersect(ray, large));
        REQUIRE(keep_small->intersect(ray, small));
        CHECK(large.n == small.n);
        CHECK(large.dpdu == small.dpdu);
        CHECK(large.dpdv == small.dpdv);
        CHECK(large.shading.n == small.shading.n);
        CHECK(large.shading.s == small.shading.s);
        CHECK(large.shading.t == small.shading.t);
    }
}

namespace {

// A mesh made in memory whose finalize() finds the first `prepared` triangles prepared (the
// serialized reader's follower hands the rest over at the end of an area chunk, or stops short
// at an error), or nothing prepared (npos).
class PartlyPreparedMesh : public Mesh {
public:
    static constexpr size_t npos = ~size_t(0);
    static constexpr size_t Chunk = AreaChunk;
    PartlyPreparedMesh(const Properties& props, const TestMesh& m, size_t prepared) : Mesh(props) {
        positions_.assign(m.positions.begin(), m.positions.end());
        triangles_.assign(m.triangles.begin(), m.triangles.end());
        if (prepared != npos) {
            prepare_normal_sums();
            REQUIRE(prepare_positions());
            REQUIRE(prepare_triangles(0, prepared));
        }
        finalize(props, true);
    }
};

}  // namespace

TEST_CASE("mesh: a preparation handed over at an area chunk's end is continued, bit for bit", "[mesh][serialized]") {
    // A wavy 300 x 300 grid (179,402 triangles: two whole area chunks and part of a third).
    // However much a reader prepared ahead, finalize() must give the mesh it gives from nothing:
    // continued from a whole chunk (0, 1 or 2 of them, all), or done afresh after a stop
    // elsewhere; with degenerate triangles in the prepared part or after it (all normals then
    // summed again after the compaction).
    TestMesh m = wavy_grid(300);
    const size_t chunk = PartlyPreparedMesh::Chunk;
    REQUIRE(m.triangles.size() > 2 * chunk);
    REQUIRE(m.triangles.size() < 3 * chunk);
    Properties props("test", SourceLocation{});
    props.set_transform("to_world", Transform::rotate(Vec3(1.0f, 2.0f, 0.5f), 33.0f));

    TestMesh degenerate_early = m, degenerate_late = m;
    degenerate_early.triangles[100] = {5, 5, 6};
    degenerate_late.triangles[2 * chunk + 100] = {7, 7, 8};
    for (const TestMesh* grid : {&m, &degenerate_early, &degenerate_late}) {
        const PartlyPreparedMesh fresh(props, *grid, PartlyPreparedMesh::npos);
        REQUIRE(fresh.normals().size() == grid->positions.size());
        for (size_t prepared : {size_t(0), chunk, 2 * chunk, grid->triangles.size(), chunk + 1024, size_t(5000)}) {
            INFO("prepared " << prepared << ", degenerate " << (grid == &m ? "none" : grid == &degenerate_early ? "early" : "late"));
            const PartlyPreparedMesh mesh(props, *grid, prepared);
            CHECK(mesh.positions() == fresh.positions());
            CHECK(mesh.triangles() == fresh.triangles());
            CHECK(mesh.normals() == fresh.normals());
            CHECK(mesh.surface_area() == fresh.surface_area());
            CHECK(mesh.bbox().min == fresh.bbox().min);
            CHECK(mesh.bbox().max == fresh.bbox().max);
        }
    }
}
