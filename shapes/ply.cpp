// ply: a Stanford PLY triangle mesh (ascii, binary_little_endian or binary_big_endian).
// Debian packages no PLY library, so this file holds a small reader.
//
// Parameters:
//   filename       string      the .ply file (relative to the scene file)
//   to_world       transform   object to world (default identity)
//   face_normals   boolean     ignore the file's normals and shade flat (default false)
//   flip_normals   boolean     swap front and back (default false)
// Vertex properties read: x y z, nx ny nz, and uv as u v, s t, texture_u texture_v or
// texture_s texture_t (not flipped). Faces: the list vertex_indices (or vertex_index); polygons
// are triangulated by ear clipping (each triangle keeps its polygon's face attributes). Other
// elements are skipped.
//
// Other properties become mesh attributes (read by the mesh_attribute texture), named as in
// Mitsuba 3: r g b [a] or red green blue [alpha] become "vertex_color" (or "face_color" on
// faces); consecutive properties <prefix>_<c> whose one-letter suffixes run x y z [w], r g b [a],
// 0 1 2 [3] or 1 2 3 [4] become "vertex_<prefix>" ("vertex_<prefix>_color" for r g b), with 1 or
// 3 components. Properties without such a suffix, or groups of 2 or 4, are not attributes.
// Integer-typed attribute values are normalised by their type's maximum and decoded from sRGB
// to linear, as Mitsuba's loader does (8-bit colours 0..255 become linear 0..1).

#include "core/mapped_file.h"
#include "core/memory_budget.h"
#include "core/mesh.h"
#include "core/parallel.h"
#include "core/registry.h"
#include "core/warning.h"
#include "geometry2d/polygon.h"

#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

namespace candela {

namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64, Invalid };

PlyType parse_type(const std::string& s) {
    if (s == "char" || s == "int8") return PlyType::Int8;
    if (s == "uchar" || s == "uint8") return PlyType::UInt8;
    if (s == "short" || s == "int16") return PlyType::Int16;
    if (s == "ushort" || s == "uint16") return PlyType::UInt16;
    if (s == "int" || s == "int32") return PlyType::Int32;
    if (s == "uint" || s == "uint32") return PlyType::UInt32;
    if (s == "float" || s == "float32") return PlyType::Float32;
    if (s == "double" || s == "float64") return PlyType::Float64;
    return PlyType::Invalid;
}

bool is_integer_type(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64 && t != PlyType::Invalid; }

// Whether `v` (read from an ascii file) is a value of type `t`: integer types need an integer
// in their range, float32 a value in its range (infinities and NaN pass; the mesh rejects them).
bool representable(double v, PlyType t) {
    switch (t) {
        case PlyType::Int8: return v == std::floor(v) && v >= -128.0 && v <= 127.0;
        case PlyType::UInt8: return v == std::floor(v) && v >= 0.0 && v <= 255.0;
        case PlyType::Int16: return v == std::floor(v) && v >= -32768.0 && v <= 32767.0;
        case PlyType::UInt16: return v == std::floor(v) && v >= 0.0 && v <= 65535.0;
        case PlyType::Int32: return v == std::floor(v) && v >= -2147483648.0 && v <= 2147483647.0;
        case PlyType::UInt32: return v == std::floor(v) && v >= 0.0 && v <= 4294967295.0;
        case PlyType::Float32: return !std::isfinite(v) || std::abs(v) <= double(std::numeric_limits<float>::max());
        case PlyType::Float64: return true;
        default: return false;
    }
}

size_t type_size(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8: return 1;
        case PlyType::Int16:
        case PlyType::UInt16: return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
        default: return 0;
    }
}

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Invalid;
    bool is_list = false;
    PlyType count_type = PlyType::Invalid;
};

struct PlyElement {
    std::string name;
    size_t count = 0;
    std::vector<PlyProperty> properties;
};

// A mesh attribute and the element properties it is read from, in component order.
struct PlyAttribute {
    std::string name;
    std::vector<int> properties;
};

int find_property(const PlyElement& e, const std::string& name) {
    for (size_t i = 0; i < e.properties.size(); ++i)
        if (e.properties[i].name == name && !e.properties[i].is_list) return int(i);
    return -1;
}

// Mitsuba 3's grouping of the properties that are not geometry into attributes named
// "<kind>_<prefix>" (see the comment at the top of this file).
// Properties that fit no attribute are added to `ignored`.
std::vector<PlyAttribute> group_attributes(const PlyElement& e, const std::string& kind, std::vector<std::string> reserved,
                                           std::vector<std::string>& ignored) {
    std::vector<PlyAttribute> out;
    for (const char* names : {"r g b a", "red green blue alpha"}) {
        std::istringstream ss(names);
        std::vector<int> idx;
        for (std::string n; ss >> n;) idx.push_back(find_property(e, n));
        if (idx[0] < 0 || idx[1] < 0 || idx[2] < 0) continue;
        if (idx[3] < 0) idx.pop_back();
        out.push_back({kind + "color", idx});
        break;
    }
    for (const char* n : {"r", "g", "b", "a", "red", "green", "blue", "alpha"}) reserved.push_back(n);
    // Suffix sequences by component: {x, y, z, w}, {r, g, b, a}, {0, 1, 2, 3}, {1, 2, 3, 4}.
    const char* sequences[4] = {"xyzw", "rgba", "0123", "1234"};
    std::vector<std::string> seen;
    PlyAttribute current;
    int sequence = -1;
    std::string prefix;
    bool broken = false;  // the prefix continues, but not in its sequence: not an attribute
    auto flush = [&] {
        size_t n = current.properties.size();
        if ((n == 1 || n == 3) && !broken) {
            current.name = kind + prefix + (sequence == 1 ? "_color" : "");
            out.push_back(current);
        } else {
            for (int k : current.properties) ignored.push_back(e.properties[size_t(k)].name);
        }
        if (n > 0) seen.push_back(prefix);
        current = PlyAttribute();
        sequence = -1;
        broken = false;
    };
    for (size_t i = 0; i < e.properties.size(); ++i) {
        const PlyProperty& p = e.properties[i];
        if (p.is_list || std::find(reserved.begin(), reserved.end(), p.name) != reserved.end()) continue;
        size_t underscore = p.name.find_last_of('_');
        bool suffixed = underscore != std::string::npos && underscore + 2 == p.name.size();
        std::string pre = suffixed ? p.name.substr(0, underscore) : "";
        char c = suffixed ? p.name.back() : 0;
        if (sequence >= 0 && suffixed && pre == prefix &&
            (current.properties.size() >= 4 || c != sequences[sequence][current.properties.size()]))
            broken = true;
        if (sequence >= 0 && (!suffixed || pre != prefix || broken)) flush();
        if (!suffixed || std::find(seen.begin(), seen.end(), pre) != seen.end()) {
            ignored.push_back(p.name);
            continue;
        }
        if (sequence < 0) {
            for (int k = 0; k < 4; ++k)
                if (c == sequences[k][0]) sequence = k;
            if (sequence < 0) {
                ignored.push_back(p.name);
                continue;
            }
            prefix = pre;
        }
        current.properties.push_back(int(i));
    }
    if (sequence >= 0) flush();
    return out;
}

// An integer attribute value normalised to [0, 1] by its type's range and decoded from sRGB.
double attribute_value(double v, PlyType type) {
    double max = 0.0;
    switch (type) {
        case PlyType::Int8: max = 127.0; break;
        case PlyType::UInt8: max = 255.0; break;
        case PlyType::Int16: max = 32767.0; break;
        case PlyType::UInt16: max = 65535.0; break;
        case PlyType::Int32: max = 2147483647.0; break;
        case PlyType::UInt32: max = 4294967295.0; break;
        default: return v;
    }
    return srgb_to_linear(float(v / max));
}

class PlyError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A value of type T from the bytes at `p`.
template <class T>
double bytes_as(const unsigned char* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return double(v);
}

// One binary value of type `type` at `p`, in the file's byte order (`swap`: it differs from
// the host's).
inline double decode(const unsigned char* p, PlyType type, bool swap) {
    unsigned char buf[8];
    const size_t n = type_size(type);
    std::memcpy(buf, p, n);
    if (swap) std::reverse(buf, buf + n);
    switch (type) {
        case PlyType::Int8: return bytes_as<int8_t>(buf);
        case PlyType::UInt8: return bytes_as<uint8_t>(buf);
        case PlyType::Int16: return bytes_as<int16_t>(buf);
        case PlyType::UInt16: return bytes_as<uint16_t>(buf);
        case PlyType::Int32: return bytes_as<int32_t>(buf);
        case PlyType::UInt32: return bytes_as<uint32_t>(buf);
        case PlyType::Float32: return bytes_as<float>(buf);
        case PlyType::Float64: return bytes_as<double>(buf);
        default: throw PlyError("invalid property type");
    }
}

// Reads the body in the file's encoding: ascii value by value from the stream, binary straight
// from the file's memory map (a read call per value would cost more than the decoding, and the
// map is no copy of the file).
class PlyBodyReader {
public:
    // `binary_body`: the bytes after the header (binary formats only).
    PlyBodyReader(std::istream& in, int format, int first_line, const unsigned char* binary_body, size_t binary_size)
        : in_(in), format_(format), line_(first_line), data_(binary_body), size_(binary_size) {
        const uint16_t probe = 1;
        const bool host_big = *reinterpret_cast<const unsigned char*>(&probe) == 0;
        swap_ = format == 2 ? !host_big : host_big;
    }

    bool binary() const { return format_ != 0; }
    bool swap() const { return swap_; }

    double read(PlyType type) {
        if (format_ == 0) return read_ascii(type);
        return decode(take(type_size(type)), type, swap_);
    }
    // Binary: the next `n` bytes, without consuming them.
    const unsigned char* peek(size_t n) const {
        if (size_ - pos_ < n) throw PlyError("unexpected end of file");
        return data_ + pos_;
    }
    // Binary: the next `n` bytes.
    const unsigned char* take(size_t n) {
        const unsigned char* p = peek(n);
        pos_ += n;
        return p;
    }
    // Binary: how many bytes are left.
    size_t left() const { return size_ - pos_; }
    // ascii: each element instance sits on its own line.
    void end_element() {
        if (format_ == 0) {
            tokens_.clear();
            token_ = 0;
            have_line_ = false;
        }
    }
    int line() const { return line_; }

private:
    double read_ascii(PlyType type) {
        while (!have_line_ || token_ >= tokens_.size()) {
            if (have_line_) throw PlyError("too few values on line " + std::to_string(line_));
            std::string text;
            if (!std::getline(in_, text)) throw PlyError("unexpected end of file");
            ++line_;
            std::istringstream ss(text);
            tokens_.clear();
            token_ = 0;
            for (std::string t; ss >> t;) tokens_.push_back(t);
            have_line_ = !tokens_.empty();
        }
        const std::string& t = tokens_[token_++];
        char* end = nullptr;
        double v = std::strtod(t.c_str(), &end);
        if (end == t.c_str() || *end != '\0') throw PlyError("bad number \"" + t + "\" on line " + std::to_string(line_));
        if (!representable(v, type))
            throw PlyError("\"" + t + "\" on line " + std::to_string(line_) + " is not a value of the property's type");
        return v;
    }

    std::istream& in_;
    int format_;  // 0 ascii, 1 little endian, 2 big endian
    bool swap_ = false;
    int line_;
    const unsigned char* data_;  // binary: the body, its size, and the bytes read
    size_t size_, pos_ = 0;
    std::vector<std::string> tokens_;
    size_t token_ = 0;
    bool have_line_ = false;
};

}  // namespace

class PlyMesh final : public Mesh {
public:
    explicit PlyMesh(const Properties& props) : Mesh(props) {
        std::string path = props.get_file_path("filename");
        bool face_normals = props.get_bool("face_normals", false);
        try {
            read(path, face_normals, props.location_of("filename"));
        } catch (const PlyError& e) {
            props.fail("filename", "cannot read PLY file \"" + path + "\": " + e.what());
        }
        if (triangles_.empty()) props.fail("filename", "PLY file \"" + path + "\" has no faces");
        if (!ignored_.empty()) {  // as Mitsuba warns
            std::string names;
            for (const std::string& n : ignored_) names += (names.empty() ? "" : ", ") + n;
            warn(props.location_of("filename"),
                 "PLY properties that form no mesh attribute (<prefix>_<x y z | r g b | 0 1 2 | 1 2 3>, 1 or 3 of them) are ignored: " +
                     names);
        }
        finalize(props, !face_normals);
    }
    std::string to_string() const override { return "ply"; }

private:
    std::vector<std::string> ignored_;  // properties that are neither geometry nor attributes

    void read(const std::string& path, bool face_normals, const SourceLocation& location) {
        std::ifstream in(path, std::ios::binary);
        if (!in) throw PlyError("cannot open file");
        std::string line;
        int line_no = 0;
        auto next_line = [&]() -> bool {
            if (!std::getline(in, line)) return false;
            ++line_no;
            if (!line.empty() && line.back() == '\r') line.pop_back();
            return true;
        };
        if (!next_line() || line != "ply") throw PlyError("not a PLY file (line 1 must be \"ply\")");
        int format = -1;
        std::vector<PlyElement> elements;
        for (;;) {
            if (!next_line()) throw PlyError("header has no end_header");
            std::istringstream ss(line);
            std::string word;
            ss >> word;
            auto where = " (line " + std::to_string(line_no) + ")";
            if (word == "end_header") break;
            if (word.empty() || word == "comment" || word == "obj_info") continue;
            if (word == "format") {
                std::string f, version;
                ss >> f >> version;
                if (f == "ascii")
                    format = 0;
                else if (f == "binary_little_endian")
                    format = 1;
                else if (f == "binary_big_endian")
                    format = 2;
                else
                    throw PlyError("unknown format \"" + f + "\"" + where);
            } else if (word == "element") {
                PlyElement e;
                long long count = -1;
                ss >> e.name >> count;
                if (e.name.empty() || count < 0) throw PlyError("malformed element line" + where);
                e.count = size_t(count);
                elements.push_back(e);
            } else if (word == "property") {
                if (elements.empty()) throw PlyError("property before any element" + where);
                PlyProperty p;
                std::string t;
                ss >> t;
                if (t == "list") {
                    std::string ct, it;
                    ss >> ct >> it >> p.name;
                    p.is_list = true;
                    p.count_type = parse_type(ct);
                    p.type = parse_type(it);
                    if (p.count_type == PlyType::Invalid) throw PlyError("unknown type \"" + ct + "\"" + where);
                    if (!is_integer_type(p.count_type)) throw PlyError("a list's count must have an integer type" + where);
                } else {
                    p.type = parse_type(t);
                    ss >> p.name;
                }
                if (p.type == PlyType::Invalid || p.name.empty()) throw PlyError("malformed property line" + where);
                elements.back().properties.push_back(p);
            } else {
                throw PlyError("unexpected header line \"" + line + "\"" + where);
            }
        }
        if (format < 0) throw PlyError("header has no format line");
        check_body_size(elements, format, in);
        uint64_t vertices = 0, faces = 0;
        for (const PlyElement& e : elements) {
            if (e.name == "vertex") vertices = saturating_add(vertices, e.count);
            if (e.name == "face") faces = saturating_add(faces, e.count);
        }
        check_mesh_memory(vertices, faces, 0, location);

        // Binary bodies are read from the file's memory map.
        std::unique_ptr<MappedFile> mapped;
        size_t body_start = 0;
        if (format != 0) {
            body_start = size_t(in.tellg());
            try {
                mapped = std::make_unique<MappedFile>(path);
            } catch (const std::runtime_error& e) {
                throw PlyError(e.what());
            }
            if (mapped->size() < body_start) throw PlyError("the file changed while it was read");
        }
        PlyBodyReader body(in, format, line_no, mapped ? mapped->data() + body_start : nullptr, mapped ? mapped->size() - body_start : 0);
        for (const PlyElement& e : elements) {
            if (e.name == "vertex")
                read_vertices(e, body, face_normals);
            else if (e.name == "face")
                read_faces(e, body);
            else
                skip(e, body);
        }
    }

    // Refuses a header that promises more elements than the rest of the file can hold, before
    // anything is allocated for them: in binary, every scalar takes its type's size and every
    // list at least its count; in ascii, every value at least one character and a separator.
    static void check_body_size(const std::vector<PlyElement>& elements, int format, std::istream& in) {
        const std::streamoff body_start = in.tellg();
        in.seekg(0, std::ios::end);
        const std::streamoff file_end = in.tellg();
        in.seekg(body_start);
        if (body_start < 0 || file_end < body_start) throw PlyError("cannot determine the file size");
        const uint64_t available = uint64_t(file_end - body_start);
        uint64_t needed = 0;
        std::string promised;
        for (const PlyElement& e : elements) {
            uint64_t per_element = 0;
            for (const PlyProperty& p : e.properties) per_element += format == 0 ? 2 : type_size(p.is_list ? p.count_type : p.type);
            needed = saturating_add(needed, saturating_mul(e.count, per_element));
            promised += (promised.empty() ? "" : ", ") + std::to_string(e.count) + " " + e.name + (e.count == 1 ? "" : "s");
        }
        if (format == 0 && needed > 0) --needed;  // the last value needs no separator
        if (needed > available)
            throw PlyError("the header promises " + promised + ", at least " + std::to_string(needed) + " bytes, but the file holds only " +
                           std::to_string(available) + " bytes after its header");
    }

    // The first of `names` that the element has as a scalar property.
    static int find(const PlyElement& e, std::initializer_list<const char*> names) {
        for (const char* n : names)
            if (int i = find_property(e, n); i >= 0) return i;
        return -1;
    }

    void read_vertices(const PlyElement& e, PlyBodyReader& body, bool face_normals) {
        int ix = find(e, {"x"}), iy = find(e, {"y"}), iz = find(e, {"z"});
        if (ix < 0 || iy < 0 || iz < 0) throw PlyError("vertex element lacks x, y or z");
        int inx = find(e, {"nx"}), iny = find(e, {"ny"}), inz = find(e, {"nz"});
        int iu = find(e, {"u", "s", "texture_u", "texture_s"}), iv = find(e, {"v", "t", "texture_v", "texture_t"});
        bool normals = inx >= 0 && iny >= 0 && inz >= 0 && !face_normals, uvs = iu >= 0 && iv >= 0;
        std::vector<std::string> reserved = {"x", "y", "z", "nx", "ny", "nz"};
        if (uvs) reserved.insert(reserved.end(), {e.properties[size_t(iu)].name, e.properties[size_t(iv)].name});
        std::vector<PlyAttribute> attributes = group_attributes(e, "vertex_", reserved, ignored_);
        size_t first_attribute = attributes_.size();
        for (const PlyAttribute& a : attributes) attributes_.push_back(MeshAttribute{a.name, false, int(a.properties.size()), {}});
        // The count comes from the file, which check_body_size() found large enough to hold it.
        // One element of spare capacity: Embree's padding (Mesh::update_derived).
        positions_.reserve(positions_.size() + e.count + 1);
        if (body.binary() &&
            read_fixed_vertices(e, body, {ix, iy, iz}, normals ? std::array<int, 3>{inx, iny, inz} : std::array<int, 3>{}, normals,
                                uvs ? std::array<int, 2>{iu, iv} : std::array<int, 2>{}, uvs, attributes, first_attribute))
            return;
        std::vector<double> values(e.properties.size());
        for (size_t i = 0; i < e.count; ++i) {
            for (size_t k = 0; k < e.properties.size(); ++k) {
                const PlyProperty& p = e.properties[k];
                if (p.is_list) {
                    size_t n = read_count(p, body);
                    for (size_t j = 0; j < n; ++j) body.read(p.type);
                    values[k] = 0.0;
                } else {
                    values[k] = body.read(p.type);
                }
            }
            body.end_element();
            positions_.emplace_back(to_float(values[ix]), to_float(values[iy]), to_float(values[iz]));
            if (normals) normals_.emplace_back(to_float(values[inx]), to_float(values[iny]), to_float(values[inz]));
            if (uvs) uvs_.emplace_back(to_float(values[iu]), to_float(values[iv]));
            append_attributes(e, attributes, values, first_attribute);
        }
    }

    // Binary vertices without list properties are records of one size: read a buffer of them at
    // a time and decode it in parallel chunks, straight into the mesh's arrays (each record
    // writes only its own elements). False (nothing read) for records of another kind.
    bool read_fixed_vertices(const PlyElement& e, PlyBodyReader& body, std::array<int, 3> position, std::array<int, 3> normal, bool normals,
                             std::array<int, 2> uv, bool uvs, const std::vector<PlyAttribute>& attributes, size_t first_attribute) {
        std::vector<size_t> offset(e.properties.size());
        size_t record = 0;
        for (size_t k = 0; k < e.properties.size(); ++k) {
            if (e.properties[k].is_list) return false;
            offset[k] = record;
            record += type_size(e.properties[k].type);
        }
        if (record == 0) return false;
        const size_t base = positions_.size();
        positions_.resize(base + e.count);
        // Mesh arrays resize without zero-filling (core/mesh_array.h): an earlier vertex element
        // without normals or uvs leaves a gap, zeroed here as it always was; this element's range
        // is written below.
        if (normals) {
            normals_.resize(base, Vec3(0.0f));
            normals_.resize(base + e.count);
        }
        if (uvs) {
            uvs_.resize(base, Vec2(0.0f));
            uvs_.resize(base + e.count);
        }
        for (size_t a = 0; a < attributes.size(); ++a)
            attributes_[first_attribute + a].values.resize((base + e.count) * attributes[a].properties.size());
        const bool swap = body.swap();
        // check_body_size() found the records in the file: count * record does not overflow.
        const unsigned char* data = body.take(e.count * record);
        populate_pages_in_parallel(data, e.count * record, false);
        populate_pages_in_parallel(positions_.data() + base, e.count * sizeof(Vec3), true);
        if (normals) populate_pages_in_parallel(normals_.data() + base, e.count * sizeof(Vec3), true);
        if (uvs) populate_pages_in_parallel(uvs_.data() + base, e.count * sizeof(Vec2), true);
        auto value = [&](const unsigned char* r, int k) {
            return to_float(decode(r + offset[size_t(k)], e.properties[size_t(k)].type, swap));
        };
        parallel_chunks(e.count, 1 << 14, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                const unsigned char* r = data + i * record;
                const size_t v = base + i;
                positions_[v] = Vec3(value(r, position[0]), value(r, position[1]), value(r, position[2]));
                if (normals) normals_[v] = Vec3(value(r, normal[0]), value(r, normal[1]), value(r, normal[2]));
                if (uvs) uvs_[v] = Vec2(value(r, uv[0]), value(r, uv[1]));
                for (size_t a = 0; a < attributes.size(); ++a) {
                    const std::vector<int>& props = attributes[a].properties;
                    for (size_t c = 0; c < props.size(); ++c) {
                        const size_t k = size_t(props[c]);
                        attributes_[first_attribute + a].values[v * props.size() + c] =
                            to_float(attribute_value(decode(r + offset[k], e.properties[k].type, swap), e.properties[k].type));
                    }
                }
            }
        });
        return true;
    }

    void append_attributes(const PlyElement& e, const std::vector<PlyAttribute>& attributes, const std::vector<double>& values,
                           size_t first_attribute) {
        for (size_t a = 0; a < attributes.size(); ++a)
            for (int k : attributes[a].properties)
                attributes_[first_attribute + a].values.push_back(
                    to_float(attribute_value(values[size_t(k)], e.properties[size_t(k)].type)));
    }

    void read_faces(const PlyElement& e, PlyBodyReader& body) {
        int list = -1;
        for (size_t i = 0; i < e.properties.size(); ++i)
            if (e.properties[i].is_list && (e.properties[i].name == "vertex_indices" || e.properties[i].name == "vertex_index"))
                list = int(i);
        if (list < 0) throw PlyError("face element lacks a vertex_indices list");
        if (!is_integer_type(e.properties[size_t(list)].type)) throw PlyError("vertex_indices must have an integer type");
        std::vector<PlyAttribute> attributes = group_attributes(e, "face_", {}, ignored_);
        size_t first_attribute = attributes_.size();
        for (const PlyAttribute& a : attributes) attributes_.push_back(MeshAttribute{a.name, true, int(a.properties.size()), {}});
        std::vector<double> values(e.properties.size(), 0.0);
        std::vector<unsigned> corner;
        const PlyType index_type = e.properties[size_t(list)].type;
        // Binary triangles, the common case, take their three indices at once.
        const bool binary_triangles = body.binary() && type_size(index_type) == 4;
        triangles_.reserve(triangles_.size() + e.count);
        const PlyType count_type = e.properties[size_t(list)].count_type;
        // The most common layout of all, a face element of nothing but binary triangles with a
        // one-byte count, is read in parallel; any other element, or one with a bad face, is read
        // face by face below.
        const bool only_list = e.properties.size() == 1 && binary_triangles && type_size(count_type) == 1;
        if (only_list && read_triangle_records(e, body, index_type)) return;
        for (size_t i = 0; i < e.count; ++i) {
            corner.clear();
            for (size_t k = 0; k < e.properties.size(); ++k) {
                const PlyProperty& p = e.properties[k];
                if (!p.is_list) {
                    values[k] = body.read(p.type);
                    continue;
                }
                size_t n = read_count(p, body);
                if (int(k) != list) {  // another per-face list (texture coordinates, ...): skipped
                    for (size_t j = 0; j < n; ++j) body.read(p.type);
                    continue;
                }
                if (n > 1000000) throw PlyError("face " + std::to_string(i) + " has " + std::to_string(n) + " corners");
                corner.resize(n);
                const unsigned char* three = binary_triangles && n == 3 ? body.take(12) : nullptr;
                for (size_t j = 0; j < corner.size(); ++j) {
                    // An integer: the type is checked above.
                    double idx = three ? decode(three + 4 * j, index_type, body.swap()) : body.read(p.type);
                    if (idx < 0 || idx >= double(positions_.size()))
                        throw PlyError("face " + std::to_string(i) + " refers to vertex " + std::to_string(int64_t(idx)) +
                                       ", which does not exist (vertices must come before faces)");
                    corner[j] = unsigned(idx);
                }
            }
            body.end_element();
            size_t before = triangles_.size();
            if (corner.size() == 3) {
                triangles_.push_back({corner[0], corner[1], corner[2]});
            } else if (corner.size() > 3) {
                std::vector<Vec3> pts(corner.size());
                for (size_t j = 0; j < corner.size(); ++j) pts[j] = positions_[corner[j]];
                for (auto& t : triangulate_polygon_3d(pts)) triangles_.push_back({corner[t[0]], corner[t[1]], corner[t[2]]});
            }
            // Face attributes: one row per triangle of the polygon.
            if (!attributes.empty())
                for (size_t t = before; t < triangles_.size(); ++t) append_attributes(e, attributes, values, first_attribute);
        }
    }

    // A face element of nothing but triangles, 13-byte records of a count of 3 and three 4-byte
    // indices, as most binary files are: checked and decoded in parallel chunks. False, with
    // nothing read, when some face is not a triangle or names a missing vertex (the face-by-face
    // loop then reads them and names the first such face).
    bool read_triangle_records(const PlyElement& e, PlyBodyReader& body, PlyType index_type) {
        constexpr size_t Record = 13;
        if (body.left() / Record < e.count) return false;
        const unsigned char* data = body.peek(e.count * Record);
        const uint64_t vertices = positions_.size();
        const bool swap = body.swap(), signed_index = index_type == PlyType::Int32;
        const size_t base = triangles_.size();
        triangles_.resize(base + e.count);
        populate_pages_in_parallel(data, e.count * Record, false);
        populate_pages_in_parallel(triangles_.data() + base, e.count * sizeof(glm::uvec3), true);
        // The count is one byte (int8 or uint8), so a triangle's is the byte 3. The checks are
        // gathered per chunk without branching: a bad record is rare, and the element is then
        // read again face by face, which names the problem.
        const uint32_t index_limit =
            signed_index ? uint32_t(std::min<uint64_t>(vertices, 0x80000000ull)) : uint32_t(std::min<uint64_t>(vertices, 0xFFFFFFFFull));
        const bool all_indices_fit = vertices > 0xFFFFFFFFull && !signed_index;  // every uint32 index is below the count
        std::atomic<bool> valid{true};
        parallel_chunks(e.count, 1 << 16, [&](size_t begin, size_t end) {
            if (!valid.load(std::memory_order_relaxed)) return;
            bool chunk_valid = true;
            for (size_t i = begin; i < end; ++i) {
                const unsigned char* r = data + i * Record;
                uint32_t v[3];
                std::memcpy(v, r + 1, 12);
                if (swap)
                    for (uint32_t& x : v) x = __builtin_bswap32(x);
                const uint32_t largest = std::max({v[0], v[1], v[2]});
                chunk_valid &= (r[0] == 3) & (all_indices_fit | (largest < index_limit));
                triangles_[base + i] = glm::uvec3(v[0], v[1], v[2]);
            }
            if (!chunk_valid) valid = false;
        });
        if (!valid) {
            triangles_.resize(base);
            return false;
        }
        body.take(e.count * Record);
        return true;
    }

    // A list's length: its count type is an integer type (checked in the header), so only a
    // negative count is left to refuse.
    static size_t read_count(const PlyProperty& p, PlyBodyReader& body) {
        double n = body.read(p.count_type);
        if (n < 0) throw PlyError("list \"" + p.name + "\" has a negative length");
        return size_t(n);
    }

    // float() of a double beyond float's range is undefined; such values become infinities,
    // which the mesh refuses as non-finite.
    static float to_float(double v) {
        if (std::abs(v) > double(std::numeric_limits<float>::max()) && std::isfinite(v))
            return v > 0 ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity();
        return float(v);
    }

    static void skip(const PlyElement& e, PlyBodyReader& body) {
        // An element without properties holds no data, however many it counts (fuzz_ply in CI:
        // 444444444444444 of them took minutes to skip one by one).
        if (e.properties.empty()) return;
        for (size_t i = 0; i < e.count; ++i) {
            for (const PlyProperty& p : e.properties) {
                size_t n = p.is_list ? read_count(p, body) : 1;
                for (size_t j = 0; j < n; ++j) body.read(p.type);
            }
            body.end_element();
        }
    }
};

CANDELA_REGISTER(PlyMesh, ObjectKind::Shape, "ply");

}  // namespace candela
