#include "tests/serialized_writer.h"

#include <catch2/catch.hpp>

#include <zlib.h>

#include <cstring>

namespace candela::test {

namespace {

void put(std::string& out, uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) out += char((v >> (8 * i)) & 0xFF);
}
void put_real(std::string& out, float v, bool dbl) {
    if (dbl) {
        double d = v;
        uint64_t bits;
        std::memcpy(&bits, &d, 8);
        put(out, bits, 8);
    } else {
        uint32_t bits;
        std::memcpy(&bits, &v, 4);
        put(out, bits, 4);
    }
}

}  // namespace

std::string encode_mesh(const TestMesh& m, int version) {
    std::string raw;
    uint32_t flags = m.double_precision ? 0x2000 : 0x1000;
    if (!m.normals.empty()) flags |= 0x0001;
    if (!m.uvs.empty()) flags |= 0x0002;
    if (!m.colors.empty()) flags |= 0x0008;
    if (m.face_normals) flags |= 0x0010;
    put(raw, flags, 4);
    if (version == 4) raw += m.name + '\0';
    put(raw, m.declared_vertices ? m.declared_vertices : m.positions.size(), 8);
    put(raw, m.triangles.size(), 8);
    for (const Vec3& p : m.positions)
        for (int k = 0; k < 3; ++k) put_real(raw, p[k], m.double_precision);
    for (const Vec3& n : m.normals)
        for (int k = 0; k < 3; ++k) put_real(raw, n[k], m.double_precision);
    for (const Vec2& uv : m.uvs)
        for (int k = 0; k < 2; ++k) put_real(raw, uv[k], m.double_precision);
    for (const Vec3& c : m.colors)
        for (int k = 0; k < 3; ++k) put_real(raw, c[k], m.double_precision);
    for (const glm::uvec3& t : m.triangles)
        for (int k = 0; k < 3; ++k) put(raw, t[k], 4);
    uLongf size = compressBound(uLong(raw.size()));
    std::string packed(size, '\0');
    REQUIRE(compress2(reinterpret_cast<Bytef*>(packed.data()), &size, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()), 9) ==
            Z_OK);
    packed.resize(size);
    std::string out;
    put(out, 0x041C, 2);
    put(out, uint64_t(version), 2);
    return out + packed;
}

std::string encode_file(const std::vector<TestMesh>& meshes, int version) {
    std::string file;
    std::vector<uint64_t> offsets;
    for (const TestMesh& m : meshes) {
        offsets.push_back(file.size());
        file += encode_mesh(m, version);
    }
    for (uint64_t o : offsets) put(file, o, version == 4 ? 8 : 4);
    put(file, meshes.size(), 4);
    return file;
}

}  // namespace candela::test
