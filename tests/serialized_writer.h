#pragma once
// A writer of Mitsuba's .serialized mesh format, from its description (see shapes/serialized.cpp):
// the serialized tests round-trip through it, and the docs-scene smoke tests make their
// matpreview.serialized stand-in with it.

#include "core/math.h"
#include "core/mesh_array.h"

#include <string>
#include <vector>

namespace candela::test {

struct TestMesh {
    MeshArray<Vec3> positions, normals, colors;  // the types Mesh holds, to compare with them
    MeshArray<Vec2> uvs;
    MeshArray<glm::uvec3> triangles;
    bool double_precision = false, face_normals = false;
    std::string name = "mesh";
    uint64_t declared_vertices = 0;  // the vertex count the header states, when not the true one
};

// One mesh: the uncompressed header (0x041C, version 3 or 4), then its fields compressed with zlib.
std::string encode_mesh(const TestMesh& m, int version);
// Meshes one after another, then the dictionary of their offsets and their count.
std::string encode_file(const std::vector<TestMesh>& meshes, int version);

}  // namespace candela::test
