// serialized: a triangle mesh in Mitsuba's zlib-compressed binary format (Mitsuba 0.4 to 3).
//
// Parameters:
//   filename       string      the .serialized file (relative to the scene file)
//   shape_index    integer     which mesh of a file holding several (default 0, the first)
//   face_normals   boolean     ignore the file's normals and shade flat (default false)
//   flip_normals   boolean     swap front and back (default false)
//   to_world       transform   object to world (default identity)
//
// The format (all little endian), as Mitsuba's documentation describes it: each mesh is a
// uint16 0x041C and a uint16 version (3 or 4), then a zlib (DEFLATE) stream holding
//   uint32 flags: 0x0001 vertex normals, 0x0002 texture coordinates, 0x0008 vertex colours,
//                 0x0010 face normals, 0x1000 single precision, 0x2000 double precision;
//   (version 4 only) the mesh's name, a null-terminated UTF-8 string;
//   uint64 vertex count, uint64 triangle count;
//   positions (x y z per vertex), then normals, uvs (u v) and colours (r g b) when flagged, as
//   float or double; then the triangles as uint32 index triples (uint64 above 2^32 vertices).
// Meshes are concatenated; the file ends with the byte offset of every mesh (uint64 in version
// 4, uint32 in version 3) and the uint32 mesh count. Vertex colours become the mesh attribute
// "vertex_color". The face-normals flag is read but, as in Mitsuba 3's loader (its format
// description says otherwise), does not change the shading: the face_normals parameter does.
// Without normals in the file, smooth vertex normals are computed as for OBJ and PLY files.

#include "core/memory_budget.h"
#include "core/mesh.h"
#include "core/registry.h"

#include <zlib.h>

#include <cstring>
#include <fstream>
#include <sstream>

namespace candela {

namespace {

class SerializedError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

constexpr uint16_t FileMagic = 0x041C;
constexpr size_t MaxHeaderBytes = 1 << 16;  // flags, a name of up to 64 kB, the counts
constexpr uint64_t MaxDeflateRatio = 1032;
enum SerializedFlags : uint32_t {
    HasNormals = 0x0001,
    HasTexcoords = 0x0002,
    HasColors = 0x0008,
    SinglePrecision = 0x1000,
    DoublePrecision = 0x2000,
};

// Little-endian integers from a byte buffer (the format fixes the byte order).
uint64_t read_le(const unsigned char* p, int bytes) {
    uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}

// Inflates the zlib stream starting at `offset` until its end marker, or until it has given
// `limit` bytes; `complete` tells whether the end marker was reached.
std::vector<unsigned char> inflate_stream(const std::string& file, size_t offset, size_t limit, bool& complete) {
    z_stream zs;
    std::memset(&zs, 0, sizeof(zs));
    if (inflateInit(&zs) != Z_OK) throw SerializedError("cannot initialise zlib");
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(file.data() + offset));
    zs.avail_in = uInt(file.size() - offset);
    std::vector<unsigned char> out;
    int status = Z_OK;
    while (status == Z_OK && out.size() < limit) {
        size_t have = out.size();
        out.resize(have + std::min(size_t(1) << 20, limit - have));
        zs.next_out = out.data() + have;
        zs.avail_out = uInt(out.size() - have);
        status = inflate(&zs, Z_NO_FLUSH);
        out.resize(out.size() - zs.avail_out);
        if (status == Z_BUF_ERROR && zs.avail_in == 0) break;  // input ran out before the end
    }
    inflateEnd(&zs);
    complete = status == Z_STREAM_END;
    if (status == Z_OK || complete) return out;
    if (status == Z_BUF_ERROR) throw SerializedError("the compressed data is truncated");
    throw SerializedError(std::string("the compressed data is corrupt (zlib: ") + (zs.msg ? zs.msg : "error") + ")");
}

// Reads the decompressed fields in order, checking that each is there.
class FieldReader {
public:
    explicit FieldReader(const std::vector<unsigned char>& data) : data_(data) {}
    uint64_t integer(int bytes, const char* what) {
        need(size_t(bytes), what);
        uint64_t v = read_le(data_.data() + pos_, bytes);
        pos_ += size_t(bytes);
        return v;
    }
    std::string cstring() {
        std::string s;
        while (pos_ < data_.size() && data_[pos_] != 0) s += char(data_[pos_++]);
        if (pos_ >= data_.size()) throw SerializedError("the mesh name is not terminated");
        ++pos_;
        return s;
    }
    // `count` reals of 4 or 8 bytes.
    std::vector<float> reals(uint64_t count, bool dbl, const char* what) {
        size_t size = dbl ? 8 : 4;
        check_count(count, size, what);
        std::vector<float> out(static_cast<size_t>(count));
        for (size_t i = 0; i < out.size(); ++i) {
            uint64_t bits = read_le(data_.data() + pos_ + i * size, int(size));
            if (dbl) {
                double d;
                std::memcpy(&d, &bits, 8);
                out[i] = float(d);
            } else {
                uint32_t b = uint32_t(bits);
                std::memcpy(&out[i], &b, 4);
            }
        }
        pos_ += out.size() * size;
        return out;
    }
    void check_count(uint64_t count, size_t size, const char* what) {
        if (count > (data_.size() - pos_) / size) throw SerializedError(std::string("the data ends inside the ") + what);
    }
    size_t position() const { return pos_; }
    void need(size_t bytes, const char* what) {
        if (data_.size() - pos_ < bytes) throw SerializedError(std::string("the data ends inside the ") + what);
    }

private:
    const std::vector<unsigned char>& data_;
    size_t pos_ = 0;
};

}  // namespace

class SerializedMesh final : public Mesh {
public:
    explicit SerializedMesh(const Properties& props) : Mesh(props) {
        std::string path = props.get_file_path("filename");
        int shape_index = props.get_int("shape_index", 0);
        if (shape_index < 0) props.fail("shape_index", "shape_index must not be negative");
        bool face_normals = props.get_bool("face_normals", false);
        try {
            read(path, size_t(shape_index), face_normals, props.location_of("filename"));
        } catch (const SerializedError& e) {
            props.fail("filename",
                       "cannot read serialized mesh \"" + path + "\" (shape_index " + std::to_string(shape_index) + "): " + e.what());
        }
        finalize(props, !face_normals);
    }
    std::string to_string() const override { return "serialized"; }

private:
    // The size of the mesh's decompressed fields as its header declares them, checked before
    // anything is inflated in full: against what the compressed bytes can hold (DEFLATE expands
    // at most 1032:1, zlib's technical notes) and against the memory budget.
    uint64_t stream_size(const std::string& file, size_t offset, int version, const SourceLocation& location) const {
        bool complete = false;
        std::vector<unsigned char> head = inflate_stream(file, offset, MaxHeaderBytes, complete);
        FieldReader h(head);
        uint32_t flags = uint32_t(h.integer(4, "flags"));
        if (version == 4) h.cstring();
        uint64_t vertices = h.integer(8, "vertex count"), triangles = h.integer(8, "triangle count");
        const uint64_t header = h.position();
        bool dbl = (flags & DoublePrecision) != 0;
        if (dbl && (flags & SinglePrecision)) throw SerializedError("the flags ask for both single and double precision");
        uint64_t reals = 3 + ((flags & HasNormals) ? 3 : 0) + ((flags & HasTexcoords) ? 2 : 0) + ((flags & HasColors) ? 3 : 0);
        uint64_t index_bytes = vertices > 0xFFFFFFFFull ? 8 : 4;
        uint64_t size = saturating_add(header, saturating_add(saturating_mul(saturating_mul(vertices, reals), dbl ? 8 : 4),
                                                              saturating_mul(triangles, 3 * index_bytes)));
        uint64_t compressed = file.size() - offset;
        if (size / MaxDeflateRatio > compressed)
            throw SerializedError("the header declares " + std::to_string(vertices) + " vertices and " + std::to_string(triangles) +
                                  " triangles (" + format_bytes(size) + "), more than its " + format_bytes(compressed) +
                                  " of compressed data can hold");
        check_mesh_memory(vertices, triangles, size, location);
        return size;
    }

    // Loads mesh `index`.
    void read(const std::string& path, size_t index, bool skip_normals, const SourceLocation& location) {
        std::ifstream in(path, std::ios::binary);
        if (!in) throw SerializedError("cannot open the file");
        std::stringstream ss;
        ss << in.rdbuf();
        const std::string file = ss.str();
        auto bytes = [&](size_t at) { return reinterpret_cast<const unsigned char*>(file.data() + at); };
        if (file.size() < 4 || read_le(bytes(0), 2) != FileMagic) throw SerializedError("not a serialized mesh (no 0x041C header)");
        int version = int(read_le(bytes(2), 2));
        if (version != 3 && version != 4)
            throw SerializedError("unsupported format version " + std::to_string(version) + " (3 and 4 are read)");

        size_t offset = 0;
        if (index > 0) {
            // The dictionary at the end: the offsets of all meshes, then their count.
            if (file.size() < 8) throw SerializedError("the file is too short for its mesh dictionary");
            uint64_t count = read_le(bytes(file.size() - 4), 4);
            size_t entry = version == 4 ? 8 : 4;
            if (count > (file.size() - 4) / entry) throw SerializedError("the mesh dictionary at the end of the file is corrupt");
            if (index >= count)
                throw SerializedError("the file holds " + std::to_string(count) + " meshes, so there is no index " + std::to_string(index));
            uint64_t at = read_le(bytes(file.size() - 4 - entry * size_t(count - index)), int(entry));
            if (at + 4 > file.size() || read_le(bytes(size_t(at)), 2) != FileMagic)
                throw SerializedError("the dictionary's offset of this mesh does not point at a mesh header");
            offset = size_t(at);
        }
        const uint64_t data_size = stream_size(file, offset + 4, version, location);
        bool complete = false;
        // One byte more than declared shows a stream that holds more than its header says.
        std::vector<unsigned char> data = inflate_stream(file, offset + 4, size_t(data_size) + 1, complete);
        if (!complete) throw SerializedError("the compressed data holds more than its header declares");
        FieldReader r(data);
        uint32_t flags = uint32_t(r.integer(4, "flags"));
        if (version == 4) r.cstring();
        uint64_t vertex_count = r.integer(8, "vertex count"), triangle_count = r.integer(8, "triangle count");
        bool dbl = (flags & DoublePrecision) != 0;

        std::vector<float> p = r.reals(vertex_count * 3, dbl, "vertex positions");
        positions_.resize(size_t(vertex_count));
        for (size_t i = 0; i < positions_.size(); ++i) positions_[i] = Vec3(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
        if (flags & HasNormals) {
            std::vector<float> n = r.reals(vertex_count * 3, dbl, "vertex normals");
            if (!skip_normals) {
                normals_.resize(size_t(vertex_count));
                for (size_t i = 0; i < normals_.size(); ++i) normals_[i] = Vec3(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
            }
        }
        if (flags & HasTexcoords) {
            std::vector<float> t = r.reals(vertex_count * 2, dbl, "texture coordinates");
            uvs_.resize(size_t(vertex_count));
            for (size_t i = 0; i < uvs_.size(); ++i) uvs_[i] = Vec2(t[2 * i], t[2 * i + 1]);
        }
        if (flags & HasColors)
            attributes_.push_back(MeshAttribute{"vertex_color", false, 3, r.reals(vertex_count * 3, dbl, "vertex colours")});
        int index_bytes = vertex_count > 0xFFFFFFFFull ? 8 : 4;
        r.check_count(triangle_count * 3, size_t(index_bytes), "triangle indices");
        triangles_.resize(size_t(triangle_count));
        for (auto& t : triangles_) {
            uint64_t a = r.integer(index_bytes, "triangle indices"), b = r.integer(index_bytes, "triangle indices"),
                     c = r.integer(index_bytes, "triangle indices");
            if (a >= vertex_count || b >= vertex_count || c >= vertex_count)
                throw SerializedError("a triangle refers to vertex " + std::to_string(std::max(a, std::max(b, c))) + " of " +
                                      std::to_string(vertex_count));
            t = glm::uvec3(unsigned(a), unsigned(b), unsigned(c));
        }
        if (triangles_.empty()) throw SerializedError("the mesh has no triangles");
    }
};

CANDELA_REGISTER(SerializedMesh, ObjectKind::Shape, "serialized");

}  // namespace candela
