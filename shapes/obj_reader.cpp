#include "shapes/obj_reader.h"

#include "core/parallel.h"
#include "geometry2d/polygon.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

namespace candela {

namespace {

constexpr uint32_t None = 0xFFFFFFFFu;  // a corner without uv or normal; a vertex not yet numbered
// More elements of one kind than this cannot be indexed by the mesh's 32-bit triangles.
constexpr uint64_t MaxElements = 0xFFFFFFF0u;

inline bool is_blank(char c) { return c == ' ' || c == '\t'; }
inline bool is_line_end(char c) { return c == '\n' || c == '\r'; }
inline bool is_digit(char c) { return static_cast<unsigned char>(c - '0') < 10; }
// Where a value's text stops: a blank, the line's end, a comment or the end of the text.
inline bool ends_value(const char* p, const char* end) { return p == end || is_blank(*p) || is_line_end(*p) || *p == '#'; }
inline const char* skip_blanks(const char* p, const char* end) {
    while (p != end && is_blank(*p)) ++p;
    return p;
}
// The end of the line at `p` and the start of the next. Lines end in \n, \r\n or \r; in a
// chunk without a lone \r (`lf`, nearly every file) a line's end is its \n, found by memchr, and
// a \r before it ends the line's data like a blank.
template <bool lf>
inline const char* find_line_end(const char* p, const char* end) {
    if (lf) {
        const void* nl = std::memchr(p, '\n', size_t(end - p));
        return nl ? static_cast<const char*>(nl) : end;
    }
    while (p != end && !is_line_end(*p)) ++p;
    return p;
}
template <bool lf>
inline const char* past_line_end(const char* p, const char* end) {
    if (p == end) return p;
    if (lf) return p + 1;
    if (*p++ == '\r' && p != end && *p == '\n') ++p;
    return p;
}
bool has_lone_cr(const char* p, const char* end) {
    while (const void* cr = std::memchr(p, '\r', size_t(end - p))) {
        p = static_cast<const char*>(cr) + 1;
        if (p == end || *p != '\n') return true;
    }
    return false;
}
// Whether a line starts at `p` (0 < p <= size): after a \n, or after a \r that no \n follows.
inline bool starts_line(const char* text, size_t p, size_t size) {
    return p == size || text[p - 1] == '\n' || (text[p - 1] == '\r' && text[p] != '\n');
}

enum class LineKind { Other, Position, TexCoord, Normal, Face };

// The kind of the line at `p`, moving `p` past its leading blanks and its keyword.
inline LineKind classify(const char*& p, const char* end) {
    p = skip_blanks(p, end);
    if (end - p < 2) return LineKind::Other;
    if (p[0] == 'v') {
        if (is_blank(p[1])) {
            p += 2;
            return LineKind::Position;
        }
        if ((p[1] == 't' || p[1] == 'n') && end - p >= 3 && is_blank(p[2])) {
            LineKind kind = p[1] == 't' ? LineKind::TexCoord : LineKind::Normal;
            p += 3;
            return kind;
        }
        return LineKind::Other;
    }
    if (p[0] == 'f' && is_blank(p[1])) {
        p += 2;
        return LineKind::Face;
    }
    return LineKind::Other;
}

struct Corner {
    uint32_t v, vt, vn;  // 0-based; None for a missing uv or normal
};

// A part of the text, from a line start to a line start, with what the passes find in it.
struct Chunk {
    const char* begin = nullptr;
    const char* end = nullptr;
    // Pass 1: line ends, lines of each kind, and the faces of three or more corners.
    uint64_t line_ends = 0, positions = 0, texcoords = 0, normals = 0, faces = 0, corners = 0, triangles = 0;
    bool slashes = false;  // some corner names a uv or a normal
    bool lone_cr = false;  // some line ends in a \r alone (find_line_end)
    // Everything before the chunk (prefix sums of the above); first_line counts from 1.
    uint64_t first_line = 1, position0 = 0, texcoord0 = 0, normal0 = 0, face0 = 0, corner0 = 0, triangle0 = 0;
    // Pass 2: the chunk's first error.
    bool failed = false;
    uint64_t error_line = 0;
    std::string error;
    // Pass 2 without hash table: the polygons (more than three corners), as (first triangle slot,
    // corner count), whose corners wait in their triangle slots until the positions are known;
    // and whether the faces use positions first in file order (see first_use_is_file_order).
    std::vector<std::pair<uint64_t, uint32_t>> polygons;
    int64_t largest_index = -1, needs_before = -1;
    // Pass 3: a polygon gave fewer than corners - 2 triangles (a degenerate one); its spare
    // slots hold Unused.
    bool short_polygons = false;
};

const glm::uvec3 Unused(None, None, None);

// Pass 1's classes of characters in face lines (one table look-up per character).
enum : unsigned { Blank = 1, DataEnd = 2, Slash = 4 };  // DataEnd: a line end or '#'
struct CharClassTable {
    unsigned char of[256] = {};
    constexpr CharClassTable() {
        of[int(' ')] = of[int('\t')] = Blank;
        of[int('\n')] = of[int('\r')] = of[int('#')] = DataEnd;
        of[int('/')] = Slash;
    }
};
constexpr CharClassTable CharClasses;

// Counts the lines of a chunk (pass 1). Never fails: pass 2 checks what it reads.
template <bool lf>
void count_lines(Chunk& c) {
    const char* p = c.begin;
    const char* end = c.end;
    while (p != end) {
        switch (classify(p, end)) {
            case LineKind::Position: ++c.positions; break;
            case LineKind::TexCoord: ++c.texcoords; break;
            case LineKind::Normal: ++c.normals; break;
            case LineKind::Face: {
                // A corner starts at every non-blank after a blank (the keyword's blank first).
                uint64_t corners = 0;
                unsigned previous = Blank, seen = 0;
                for (; p != end; ++p) {
                    const unsigned k = CharClasses.of[static_cast<unsigned char>(*p)];
                    if (k & DataEnd) break;
                    corners += previous & ~k & Blank;
                    previous = k;
                    seen |= k;
                }
                if (seen & Slash) c.slashes = true;
                if (corners >= 3) {
                    ++c.faces;
                    c.corners += corners;
                    c.triangles += corners - 2;
                }
                break;
            }
            case LineKind::Other: break;
        }
        p = find_line_end<lf>(p, end);
        if (p != end) {
            p = past_line_end<lf>(p, end);
            ++c.line_ends;
        }
    }
}

// The text of a malformed value for a message: up to its end, at most 40 characters, with
// anything unprintable as '?'.
std::string quote_value(const char* p, const char* end) {
    std::string s;
    for (; !ends_value(p, end) && s.size() < 40; ++p) s += (*p >= 0x20 && *p < 0x7F) ? *p : '?';
    if (!ends_value(p, end)) s += "...";
    return "\"" + s + "\"";
}

// Where pass 2 writes. Without the hash table, positions go straight to the mesh and faces to
// its triangles (a polygon's corners first, in its slots); with it, the file's arrays and the
// corners and corner counts of the faces are kept for the merge.
struct Outputs {
    bool merging = false;
    bool keep_normals = false;  // merging, and the normals used
    Vec3* positions = nullptr;
    Vec2* texcoords = nullptr;
    Vec3* normals = nullptr;
    glm::uvec3* triangles = nullptr;  // without merging
    Corner* corners = nullptr;        // with merging
    uint32_t* face_sizes = nullptr;   // with merging
    uint64_t total_positions = 0, total_texcoords = 0, total_normals = 0;
    bool flip_tex_coords = true;
};

// Parses one chunk (pass 2). Throws ObjError at the chunk's first problem.
class ChunkParser {
public:
    ChunkParser(Chunk& chunk, const Outputs& out) : c_(chunk), out_(out), line_(chunk.first_line) {}

    void run() {
        if (c_.lone_cr)
            run<false>();
        else
            run<true>();
    }

private:
    template <bool lf>
    void run() {
        p_ = c_.begin;
        end_ = c_.end;
        uint64_t position = c_.position0, texcoord = c_.texcoord0, normal = c_.normal0;
        uint64_t face = c_.face0, corner = c_.corner0, triangle = c_.triangle0;
        const uint64_t position_end = position + c_.positions, texcoord_end = texcoord + c_.texcoords, normal_end = normal + c_.normals;
        const uint64_t face_end = face + c_.faces, corner_end = corner + c_.corners, triangle_end = triangle + c_.triangles;
        while (p_ != end_) {
            switch (classify(p_, end_)) {
                case LineKind::Position: {
                    if (position == position_end) inconsistent();
                    float x = number(), y = number(), z = number();
                    ignore_numbers();  // w, or r g b
                    if (out_.positions) out_.positions[position] = Vec3(x, y, z);
                    ++position;
                    break;
                }
                case LineKind::TexCoord: {
                    if (texcoord == texcoord_end) inconsistent();
                    float u = number(), v = 0.0f;
                    if (!at_data_end()) v = number();
                    ignore_numbers();  // w
                    if (out_.texcoords) out_.texcoords[texcoord] = Vec2(u, out_.flip_tex_coords ? 1.0f - v : v);
                    ++texcoord;
                    break;
                }
                case LineKind::Normal: {
                    if (normal == normal_end) inconsistent();
                    float x = number(), y = number(), z = number();
                    ignore_numbers();
                    if (out_.normals) out_.normals[normal] = Vec3(x, y, z);
                    ++normal;
                    break;
                }
                case LineKind::Face: {
                    face_corners_.clear();
                    while (!at_data_end()) face_corners_.push_back(read_corner(position, texcoord, normal));
                    const size_t k = face_corners_.size();
                    if (k < 3) break;  // not a face: dropped
                    if (face == face_end || corner_end - corner < k || triangle_end - triangle < k - 2) inconsistent();
                    if (out_.merging) {
                        for (const Corner& fc : face_corners_) out_.corners[corner++] = fc;
                        out_.face_sizes[face] = uint32_t(k);
                    } else {
                        for (size_t i = 0; i < k; ++i) {
                            const uint32_t v = face_corners_[i].v;
                            out_.triangles[triangle + i / 3][glm::length_t(i % 3)] = v;
                            note_first_use(v);
                        }
                        if (k > 3) c_.polygons.emplace_back(triangle, uint32_t(k));
                        corner += k;
                    }
                    ++face;
                    triangle += k - 2;
                    break;
                }
                case LineKind::Other: break;
            }
            // Past a comment or an ignored line (a value line's data already ends here).
            p_ = find_line_end<lf>(p_, end_);
            if (p_ != end_) {
                p_ = past_line_end<lf>(p_, end_);
                ++line_;
            }
        }
        if (position != position_end || texcoord != texcoord_end || normal != normal_end || face != face_end || corner != corner_end ||
            triangle != triangle_end)
            inconsistent();
    }

    [[noreturn]] void fail(const std::string& message) const { throw ObjError(line_, message); }
    // The two passes disagree about the text: a bug, not a property of the file.
    [[noreturn]] void inconsistent() const { fail("internal error: the OBJ reader's passes disagree about this line"); }

    // Whether the line's data ends here (after blanks): its end, a comment, or the text's end.
    bool at_data_end() {
        p_ = skip_blanks(p_, end_);
        return ends_value(p_, end_);
    }

    // A required number.
    float number() {
        if (at_data_end()) fail("a number is missing");
        const char* start = p_;
        const char* q = p_;
        // std::from_chars takes no '+'; a '+' before a sign is not a number.
        if (*q == '+' && q + 1 != end_ && (is_digit(q[1]) || q[1] == '.')) ++q;
        float value = 0.0f;
        auto [next, ec] = std::from_chars(q, end_, value);
        if (ec == std::errc::result_out_of_range && ends_value(next, end_)) {
            // Too small for a float: its nearest float (a subnormal or zero) through double;
            // too large: an error.
            double d = 0.0;
            auto r = std::from_chars(q, end_, d);
            if (r.ec == std::errc() && std::abs(d) < 1.0) {
                value = float(d);
                ec = std::errc();
            } else if (r.ec == std::errc::result_out_of_range && underflows(q, next)) {
                value = *q == '-' ? -0.0f : 0.0f;
                ec = std::errc();
            } else {
                fail("number out of range " + quote_value(start, end_));
            }
        }
        if (ec != std::errc() || !ends_value(next, end_)) fail("malformed number " + quote_value(start, end_));
        if (!std::isfinite(value)) fail("not a finite number " + quote_value(start, end_));
        p_ = next;
        return value;
    }
    // Whether a number out of even double's range is tiny: its exponent is negative.
    static bool underflows(const char* p, const char* end) {
        for (; p != end; ++p)
            if (*p == 'e' || *p == 'E') return p + 1 != end && p[1] == '-';
        return false;
    }
    // The rest of a value line: numbers, checked and ignored.
    void ignore_numbers() {
        while (!at_data_end()) number();
    }

    // One index of a corner, from `corner_start`, resolved to 0-based against `seen` elements of
    // its kind before this line and `total` in the file.
    uint32_t index(const char* corner_start, uint64_t seen, uint64_t total, const char* what) {
        bool negative = false;
        if (p_ != end_ && *p_ == '-') {
            negative = true;
            ++p_;
        }
        if (p_ == end_ || !is_digit(*p_)) fail("malformed face corner " + quote_value(corner_start, end_));
        uint64_t value = 0;
        for (; p_ != end_ && is_digit(*p_); ++p_) {
            value = value * 10 + uint64_t(*p_ - '0');
            if (value > MaxElements)
                fail("a face refers to " + std::string(what) + " " + quote_value(corner_start, end_) + ", out of range");
        }
        if (value == 0) fail("a face refers to " + std::string(what) + " 0 (indices start at 1) in " + quote_value(corner_start, end_));
        if (negative) {
            if (value > seen)
                fail("a face refers to " + std::string(what) + " -" + std::to_string(value) + ", before the first (" +
                     std::to_string(seen) + " defined before this line)");
            return uint32_t(seen - value);
        }
        if (value > total)
            fail("a face refers to " + std::string(what) + " " + std::to_string(value) + ", which does not exist (the file has " +
                 std::to_string(total) + ")");
        return uint32_t(value - 1);
    }

    Corner read_corner(uint64_t positions_seen, uint64_t texcoords_seen, uint64_t normals_seen) {
        const char* start = p_;
        Corner corner{None, None, None};
        corner.v = index(start, positions_seen, out_.total_positions, "vertex");
        if (p_ != end_ && *p_ == '/') {
            ++p_;
            if (p_ == end_ || *p_ != '/') corner.vt = index(start, texcoords_seen, out_.total_texcoords, "texture coordinate");
            if (p_ != end_ && *p_ == '/') {
                ++p_;
                corner.vn = index(start, normals_seen, out_.total_normals, "normal");
            }
        }
        if (!ends_value(p_, end_)) fail("malformed face corner " + quote_value(start, end_));
        if (!out_.keep_normals) corner.vn = None;
        return corner;
    }

    // Whether the faces use the positions first in file order (position 0 first, then each new
    // one the next): a corner needs, before the chunk, every position up to one less than it
    // unless the chunk itself used them (its largest index so far is at least one less).
    void note_first_use(uint32_t v) {
        const int64_t i = int64_t(v);
        if (i > c_.largest_index + 1) c_.needs_before = std::max(c_.needs_before, i - 1);
        c_.largest_index = std::max(c_.largest_index, i);
    }

    Chunk& c_;
    const Outputs& out_;
    uint64_t line_;
    const char* p_ = nullptr;
    const char* end_ = nullptr;
    std::vector<Corner> face_corners_;
};

// The chunks of the text: about `chunk_bytes` each, cut at line starts (never inside \r\n).
std::vector<Chunk> cut_chunks(const char* text, size_t size, size_t chunk_bytes) {
    std::vector<Chunk> chunks;
    size_t begin = 0;
    while (begin < size) {
        size_t end = size - begin <= chunk_bytes ? size : begin + chunk_bytes;
        while (!starts_line(text, end, size)) ++end;
        Chunk c;
        c.begin = text + begin;
        c.end = text + end;
        chunks.push_back(std::move(c));
        begin = end;
    }
    return chunks;
}

// Writes the triangles of polygon `ids` (k mesh vertices) to out[0, k - 2), by ear clipping;
// false when a degenerate polygon gave fewer (the rest of the slots hold Unused).
bool triangulate(const uint32_t* ids, size_t k, const MeshArray<Vec3>& positions, std::vector<Vec3>& pts, glm::uvec3* out) {
    pts.resize(k);
    for (size_t i = 0; i < k; ++i) pts[i] = positions[ids[i]];
    const auto tris = triangulate_polygon_3d(pts);
    const size_t n = std::min(tris.size(), k - 2);
    for (size_t i = 0; i < n; ++i) out[i] = glm::uvec3(ids[tris[i][0]], ids[tris[i][1]], ids[tris[i][2]]);
    for (size_t i = n; i < k - 2; ++i) out[i] = Unused;
    return n == k - 2;
}

// Removes the Unused slots that short polygons left, keeping the order.
void drop_unused(const std::vector<Chunk>& chunks, MeshArray<glm::uvec3>& triangles) {
    bool any = false;
    for (const Chunk& c : chunks) any |= c.short_polygons;
    if (!any) return;
    triangles.erase(std::remove(triangles.begin(), triangles.end(), Unused), triangles.end());
}

// An open-addressing hash table from (v, vt, vn) to a vertex number.
class CornerTable {
public:
    explicit CornerTable(uint64_t expected) {
        size_t capacity = 16;
        while (capacity < 2 * expected) capacity *= 2;
        slots_.assign(capacity, Slot{None, None, None, None});
    }
    // The vertex of `c`: the one it had, or `next` (then the caller adds it).
    uint32_t find_or_insert(const Corner& c, uint32_t next, bool& inserted) {
        if (2 * (count_ + 1) > slots_.size()) grow();
        size_t mask = slots_.size() - 1;
        for (size_t i = hash(c) & mask;; i = (i + 1) & mask) {
            Slot& s = slots_[i];
            if (s.id == None) {
                s = Slot{c.v, c.vt, c.vn, next};
                ++count_;
                inserted = true;
                return next;
            }
            if (s.v == c.v && s.vt == c.vt && s.vn == c.vn) {
                inserted = false;
                return s.id;
            }
        }
    }

private:
    struct Slot {
        uint32_t v, vt, vn, id;
    };
    static size_t hash(const Corner& c) {
        uint64_t h =
            (uint64_t(c.v) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(c.vt) * 0xC2B2AE3D27D4EB4Full) ^ (uint64_t(c.vn) * 0x165667B19E3779F9ull);
        return size_t(h ^ (h >> 29));
    }
    void grow() {
        std::vector<Slot> old(slots_.size() * 2, Slot{None, None, None, None});
        old.swap(slots_);
        size_t mask = slots_.size() - 1;
        for (const Slot& s : old) {
            if (s.id == None) continue;
            size_t i = hash(Corner{s.v, s.vt, s.vn}) & mask;
            while (slots_[i].id != None) i = (i + 1) & mask;
            slots_[i] = s;
        }
    }
    std::vector<Slot> slots_;
    size_t count_ = 0;
};

// Without merging: numbers the used positions in the order the faces first use them (what the
// merge would give) when that is not the file's order, rewriting the faces' corners and moving
// the positions; unused positions go.
void renumber_by_first_use(const std::vector<Chunk>& chunks, MeshArray<Vec3>& positions, MeshArray<glm::uvec3>& triangles) {
    std::vector<uint32_t> number(positions.size(), None);
    uint32_t next = 0;
    auto renumber = [&](unsigned& v) {
        if (number[v] == None) number[v] = next++;
        v = number[v];
    };
    for (const Chunk& c : chunks) {
        size_t polygon = 0;
        for (uint64_t t = c.triangle0; t < c.triangle0 + c.triangles;) {
            if (polygon < c.polygons.size() && c.polygons[polygon].first == t) {
                const uint32_t k = c.polygons[polygon++].second;
                for (uint32_t i = 0; i < k; ++i) renumber(triangles[t + i / 3][glm::length_t(i % 3)]);
                t += k - 2;
            } else {
                for (int i = 0; i < 3; ++i) renumber(triangles[t][i]);
                ++t;
            }
        }
    }
    MeshArray<Vec3> moved;
    moved.reserve(size_t(next) + 1);
    moved.resize(next);
    for (size_t v = 0; v < positions.size(); ++v)
        if (number[v] != None) moved[number[v]] = positions[v];
    positions.swap(moved);
}

// Whether the faces use every position, first in the file's order (then the merge would number
// the vertices as the file does).
bool first_use_is_file_order(const std::vector<Chunk>& chunks, uint64_t positions) {
    int64_t largest = -1;
    for (const Chunk& c : chunks) {
        if (c.needs_before > largest) return false;
        largest = std::max(largest, c.largest_index);
    }
    return uint64_t(largest + 1) == positions;
}

template <typename T>
void allocate(T& v, uint64_t n, uint64_t spare = 0) {
    T().swap(v);
    v.reserve(size_t(n + spare));
    v.resize(size_t(n));
}

}  // namespace

void read_obj(const char* text, size_t size, const ObjReadOptions& options, MeshArray<Vec3>& positions, MeshArray<Vec2>& uvs,
              MeshArray<Vec3>& normals, MeshArray<glm::uvec3>& triangles) {
    MeshArray<Vec3>().swap(positions);
    MeshArray<Vec2>().swap(uvs);
    MeshArray<Vec3>().swap(normals);
    MeshArray<glm::uvec3>().swap(triangles);
    // 4 MB chunks: a few dozen per thread on large files, few enough that their bookkeeping costs
    // nothing; at least 64 kB, and about 64 of them on smaller files.
    size_t chunk_bytes = options.chunk_bytes ? options.chunk_bytes : std::clamp<size_t>(size / 64, size_t(64) << 10, size_t(4) << 20);
    std::vector<Chunk> chunks = cut_chunks(text, size, chunk_bytes);

    // Pass 1: count.
    parallel_chunks(chunks.size(), 1, [&](size_t begin, size_t end) {
        for (size_t i = begin; i != end; ++i) {
            Chunk& c = chunks[i];
            c.lone_cr = has_lone_cr(c.begin, c.end);
            if (c.lone_cr)
                count_lines<false>(c);
            else
                count_lines<true>(c);
        }
    });
    Chunk total;
    bool slashes = false;
    for (Chunk& c : chunks) {
        c.first_line = total.first_line;
        c.position0 = total.positions;
        c.texcoord0 = total.texcoords;
        c.normal0 = total.normals;
        c.face0 = total.faces;
        c.corner0 = total.corners;
        c.triangle0 = total.triangles;
        total.first_line += c.line_ends;
        total.positions += c.positions;
        total.texcoords += c.texcoords;
        total.normals += c.normals;
        total.faces += c.faces;
        total.corners += c.corners;
        total.triangles += c.triangles;
        slashes |= c.slashes;
    }
    for (uint64_t n : {total.positions, total.texcoords, total.normals, total.triangles})
        if (n > MaxElements) throw ObjError(0, "too many elements for a mesh (" + std::to_string(n) + ")");

    // The arrays, each at its final size (with merging, the file's arrays and the faces' corners
    // until the merge has numbered the vertices).
    Outputs out;
    out.merging = slashes;
    out.keep_normals = slashes && !options.ignore_normals && total.normals > 0;
    out.total_positions = total.positions;
    out.total_texcoords = total.texcoords;
    out.total_normals = total.normals;
    out.flip_tex_coords = options.flip_tex_coords;
    MeshArray<Vec3> file_positions, file_normals;
    MeshArray<Vec2> file_texcoords;
    MeshArray<Corner> corners;
    MeshArray<uint32_t> face_sizes;
    if (options.before_allocating) {
        if (out.merging) {
            uint64_t vertices = std::max({total.positions, total.texcoords, total.normals});
            uint64_t temporary = 12 * total.positions + 8 * total.texcoords + 12 * total.normals + 12 * total.corners + 4 * total.faces +
                                 32 * vertices;  // the hash table
            options.before_allocating(vertices, total.triangles, temporary);
        } else {
            options.before_allocating(total.positions, total.triangles, 0);
        }
    }
    if (out.merging) {
        allocate(file_positions, total.positions);
        allocate(file_texcoords, total.texcoords);
        if (out.keep_normals) allocate(file_normals, total.normals);
        allocate(corners, total.corners);
        allocate(face_sizes, total.faces);
        out.positions = file_positions.data();
        out.texcoords = file_texcoords.data();
        out.normals = out.keep_normals ? file_normals.data() : nullptr;
        out.corners = corners.data();
        out.face_sizes = face_sizes.data();
    } else {
        allocate(positions, total.positions, 1);
        allocate(triangles, total.triangles);
        out.positions = positions.data();
        out.triangles = triangles.data();
    }

    // Pass 2: parse, each chunk into its slices. The file's first error is the first chunk's
    // that has one.
    parallel_chunks(chunks.size(), 1, [&](size_t begin, size_t end) {
        for (size_t i = begin; i != end; ++i) {
            try {
                ChunkParser(chunks[i], out).run();
            } catch (const ObjError& e) {
                chunks[i].failed = true;
                chunks[i].error_line = e.line;
                chunks[i].error = e.what();
            }
        }
    });
    for (const Chunk& c : chunks) {
        if (!c.failed) continue;
        for (auto* v : {&positions, &normals}) MeshArray<Vec3>().swap(*v);
        MeshArray<glm::uvec3>().swap(triangles);
        throw ObjError(c.error_line, c.error);
    }

    if (!out.merging) {
        if (!first_use_is_file_order(chunks, total.positions)) renumber_by_first_use(chunks, positions, triangles);
        // Pass 3: the polygons, now that the positions are known.
        parallel_chunks(chunks.size(), 1, [&](size_t begin, size_t end) {
            std::vector<Vec3> pts;
            std::vector<uint32_t> ids;
            for (size_t i = begin; i != end; ++i) {
                for (const auto& [slot, k] : chunks[i].polygons) {
                    ids.resize(k);
                    for (uint32_t j = 0; j < k; ++j) ids[j] = triangles[slot + j / 3][glm::length_t(j % 3)];
                    if (!triangulate(ids.data(), k, positions, pts, &triangles[slot])) chunks[i].short_polygons = true;
                }
            }
        });
        drop_unused(chunks, triangles);
        return;
    }

    // The merge, in the order the faces use the corners: each corner's vertex number replaces
    // its position index, and `vertices` lists each vertex's (v, vt, vn).
    std::vector<Corner> vertices;
    vertices.reserve(size_t(std::max({total.positions, total.texcoords, total.normals})));
    {
        CornerTable table(vertices.capacity());
        for (Corner& c : corners) {
            bool inserted = false;
            uint32_t id = table.find_or_insert(c, uint32_t(vertices.size()), inserted);
            if (inserted) vertices.push_back(c);
            c.v = id;
        }
    }
    bool any_uv = false, every_normal = !vertices.empty();
    for (const Corner& v : vertices) {
        any_uv |= v.vt != None;
        every_normal &= v.vn != None;
    }
    const size_t n = vertices.size();
    allocate(positions, n, 1);
    if (any_uv) allocate(uvs, n);
    if (every_normal) allocate(normals, n);
    parallel_chunks(n, 1 << 16, [&](size_t begin, size_t end) {
        for (size_t i = begin; i != end; ++i) {
            const Corner& v = vertices[i];
            positions[i] = file_positions[v.v];
            if (any_uv) uvs[i] = v.vt != None ? file_texcoords[v.vt] : Vec2(0.0f);
            if (every_normal) normals[i] = file_normals[v.vn];
        }
    });
    MeshArray<Vec3>().swap(file_positions);
    MeshArray<Vec2>().swap(file_texcoords);
    MeshArray<Vec3>().swap(file_normals);
    std::vector<Corner>().swap(vertices);

    // Pass 3: the triangles, each chunk's faces into its slots.
    allocate(triangles, total.triangles);
    parallel_chunks(chunks.size(), 1, [&](size_t begin, size_t end) {
        std::vector<Vec3> pts;
        std::vector<uint32_t> ids;
        for (size_t i = begin; i != end; ++i) {
            Chunk& c = chunks[i];
            uint64_t corner = c.corner0, triangle = c.triangle0;
            for (uint64_t f = c.face0; f < c.face0 + c.faces; ++f) {
                const uint32_t k = face_sizes[f];
                ids.resize(k);
                for (uint32_t j = 0; j < k; ++j) ids[j] = corners[corner + j].v;
                if (k == 3)
                    triangles[triangle] = glm::uvec3(ids[0], ids[1], ids[2]);
                else if (!triangulate(ids.data(), k, positions, pts, &triangles[triangle]))
                    c.short_polygons = true;
                corner += k;
                triangle += k - 2;
            }
        }
    });
    drop_unused(chunks, triangles);
}

}  // namespace candela
