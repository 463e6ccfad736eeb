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

#include "core/byte_order.h"
#include "core/mapped_file.h"
#include "core/memory_budget.h"
#include "core/mesh.h"
#include "core/parallel.h"
#include "core/registry.h"

#include <isa-l/igzip_lib.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <string_view>
#include <system_error>
#include <thread>

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

// What ISA-L's inflate says of a stream it cannot read.
std::string inflate_error(int status) {
    switch (status) {
        case ISAL_INVALID_BLOCK: return "an invalid block";
        case ISAL_INVALID_SYMBOL: return "an invalid code";
        case ISAL_INVALID_LOOKBACK: return "a distance too far back";
        case ISAL_INVALID_WRAPPER: return "an invalid zlib header";
        case ISAL_UNSUPPORTED_METHOD: return "an unsupported compression method";
        case ISAL_INCORRECT_CHECKSUM: return "an incorrect Adler-32 check value";
        case ISAL_NEED_DICT: return "a preset dictionary";
        default: return "error " + std::to_string(status);
    }
}

// Inflates a zlib stream field by field, straight into the caller's arrays: a mesh's data is
// never held twice (decompressed buffer and parsed copy). ISA-L's inflate (Intel's
// Intelligent Storage Acceleration Library, igzip) reads the zlib wrapper and verifies the
// Adler-32 check value as zlib does, and is faster on one core: the 10^7-triangle stream of
// bench_scale inflated in 0.34 s against zlib 1.2.13's 0.46 s. One stream cannot be split
// across threads, so that is the serialized reader's critical path.
class StreamInflater {
public:
    StreamInflater(std::string_view file, size_t offset) : state_(std::make_unique<inflate_state>()) {
        isal_inflate_init(state_.get());
        state_->crc_flag = ISAL_ZLIB;
        state_->next_in = reinterpret_cast<uint8_t*>(const_cast<char*>(file.data() + offset));
        state_->avail_in = uint32_t(std::min<size_t>(file.size() - offset, std::numeric_limits<uint32_t>::max()));
        rest_in_ = file.size() - offset - state_->avail_in;
    }
    StreamInflater(const StreamInflater&) = delete;
    StreamInflater& operator=(const StreamInflater&) = delete;

    // Exactly `bytes` bytes into `out`, or an error naming `what`.
    void read(void* out, size_t bytes, const char* what) {
        auto* dst = static_cast<uint8_t*>(out);
        while (bytes > 0) {
            if (ended()) throw SerializedError(std::string("the data ends inside the ") + what);
            const size_t got = inflate_some(dst, std::min<size_t>(bytes, size_t(1) << 30));
            dst += got;
            bytes -= got;
        }
    }
    template <class T>
    T value(const char* what) {
        unsigned char b[sizeof(T)];
        read(b, sizeof(T), what);
        return T(read_little_endian(b, sizeof(T)));
    }
    // Whether the stream ends here: its last block and check value come with no more data.
    bool ends_here() {
        uint8_t extra;
        while (!ended())
            if (inflate_some(&extra, 1) > 0) return false;
        return true;
    }

private:
    bool ended() const { return state_->block_state == ISAL_BLOCK_FINISH; }
    // Inflates into up to `capacity` bytes at `dst`; how many it wrote. Throws when the data is
    // corrupt, or ends (or stops giving anything) before the stream does.
    size_t inflate_some(uint8_t* dst, size_t capacity) {
        // ISA-L counts its input in 32-bit lengths: larger files are fed in pieces.
        if (state_->avail_in == 0 && rest_in_ > 0) {
            state_->avail_in = uint32_t(std::min<size_t>(rest_in_, std::numeric_limits<uint32_t>::max()));
            rest_in_ -= state_->avail_in;
        }
        state_->next_out = dst;
        state_->avail_out = uint32_t(capacity);
        const uint32_t input_before = state_->avail_in;
        const int status = isal_inflate(state_.get());
        if (status < 0 || status == ISAL_NEED_DICT) throw SerializedError("the compressed data is corrupt (" + inflate_error(status) + ")");
        const size_t got = capacity - state_->avail_out;
        if (got == 0 && !ended() && state_->avail_in == input_before && rest_in_ == 0)
            throw SerializedError("the compressed data is truncated");
        return got;
    }

    std::unique_ptr<inflate_state> state_;  // large (its window and tables): not on the stack
    size_t rest_in_ = 0;
};

// `count` little-endian reals of 4 or 8 bytes into floats, `skip`ped when the caller does not
// want them (they must still be inflated to reach what follows).
// The floats of an array of glm vectors (packed: Vec3 is three floats, Vec2 two).
template <class V>
float* floats(MeshArray<V>& v) {
    return v.empty() ? nullptr : &v[0].x;
}

void read_reals(StreamInflater& in, float* out, size_t count, bool dbl, const char* what) {
    if (!dbl && out) {  // the file's floats are the machine's (core/byte_order.h)
        in.read(out, count * 4, what);
        return;
    }
    // Doubles narrowed to floats, or values read past (out null), a chunk at a time.
    const size_t size = dbl ? 8 : 4, chunk = size_t(1) << 16;
    std::vector<unsigned char> buffer(std::min(count, chunk) * size);
    for (size_t first = 0; first < count; first += chunk) {
        const size_t n = std::min(chunk, count - first);
        in.read(buffer.data(), n * size, what);
        if (!out) continue;
        for (size_t i = 0; i < n; ++i) {
            double d;
            std::memcpy(&d, buffer.data() + i * size, 8);
            out[first + i] = float(d);
        }
    }
}

}  // namespace

class SerializedMesh final : public Mesh {
public:
    // Meshes of fewer triangles are read on one thread: a second one would not pay for itself.
    static constexpr size_t FollowFromTriangles = size_t(1) << 10;
    // Triangles the follower is told of at a time.
    static constexpr size_t FollowSlice = size_t(1) << 14;

    // The thread that follows the inflating one. One zlib stream is inflated on one thread (the
    // reader's critical path: 0.34 s for bench_scale's 10^7 triangles), which would leave the
    // other cores idle, and then finalize() would check, transform and sum the mesh (0.2 s on
    // two cores). The follower populates the pages of the file and of every array ahead of the
    // inflater, then does finalize()'s work on the data read so far (Mesh::prepare_positions,
    // Mesh::prepare_triangles). It is a thread of its own, not a task: it waits on the
    // inflater, which is running (the caller), and the inflater never waits on it but to join.
    // The destructor (on every path, errors included) tells it that nothing more comes and
    // joins it.
    class Follower {
    public:
        Follower(SerializedMesh& mesh, std::string_view file, bool smooth_normals, bool wanted)
            : mesh_(mesh), file_(file), smooth_normals_(smooth_normals) {
            if (!wanted) return;
            try {
                thread_ = std::thread([this] { follow(); });
            } catch (const std::system_error&) {
                // No thread to be had: this one reads, and finalize() does the rest.
            }
        }
        Follower(const Follower&) = delete;
        Follower& operator=(const Follower&) = delete;
        ~Follower() {
            stop(true);
            if (thread_.joinable()) thread_.join();
        }
        void positions_read() {
            update([&] { positions_read_ = true; });
        }
        void triangles_read(size_t count) {
            update([&] { triangles_read_ = count; });
        }
        // Once the stream is read: waits for the follower to end; how many triangles it prepared
        // (and checked). It stops at the end of the area chunk it is in, and finalize()'s parallel
        // passes do the rest: on two cores the follower could end 0.18 s after the stream, with
        // the other core waiting.
        size_t finish() {
            stop(false);
            if (thread_.joinable()) thread_.join();
            if (error_) std::rethrow_exception(error_);
            return prepared_;
        }

    private:
        template <class Change>
        void update(const Change& change) {
            {
                std::lock_guard<std::mutex> lock(mutex_);
                change();
            }
            changed_.notify_one();
        }
        // Nothing more comes; `abandon`: what has come is not wanted either (an error).
        void stop(bool abandon) {
            update([&] {
                ended_ = true;
                abandoned_ = abandoned_ || abandon;
            });
        }
        // Waits until the inflater has read more than `have` triangles (or the positions, for
        // have = npos) or ends (`ended`); false when nothing more is wanted.
        bool wait_for_more(size_t have, size_t& read, bool& ended) {
            std::unique_lock<std::mutex> lock(mutex_);
            auto more = [&] { return have == npos ? positions_read_ : triangles_read_ > have; };
            changed_.wait(lock, [&] { return more() || ended_; });
            read = triangles_read_;
            ended = ended_;
            return !abandoned_ && more();
        }
        void follow() {
            try {
                // In the order the inflater writes.
                populate_pages(file_.data(), file_.size(), false);
                populate_pages(mesh_.positions_.data(), mesh_.positions_.size() * sizeof(Vec3), true);
                populate_pages(mesh_.normals_.data(), mesh_.normals_.size() * sizeof(Vec3), true);
                populate_pages(mesh_.uvs_.data(), mesh_.uvs_.size() * sizeof(Vec2), true);
                populate_pages(mesh_.triangles_.data(), mesh_.triangles_.size() * sizeof(glm::uvec3), true);
                if (smooth_normals_) {
                    populate_pages(mesh_.normals_.data(), mesh_.normals_.capacity() * sizeof(Vec3), true);
                    mesh_.prepare_normal_sums();
                }
                size_t read = 0;
                bool ended = false;
                if (!wait_for_more(npos, read, ended) || !mesh_.prepare_positions()) return;
                // A slice at a time, so that the end of the stream is seen soon; from then on only
                // to the end of the current area chunk (finish()).
                while (wait_for_more(prepared_, read, ended)) {
                    size_t until = std::min(read, prepared_ + FollowSlice);
                    if (ended) until = std::min(until, (prepared_ + Mesh::AreaChunk - 1) / Mesh::AreaChunk * Mesh::AreaChunk);
                    if (until == prepared_ || !mesh_.prepare_triangles(prepared_, until)) return;
                    prepared_ = until;
                }
            } catch (...) {
                error_ = std::current_exception();  // read by finish() after the join
            }
        }

        static constexpr size_t npos = ~size_t(0);
        SerializedMesh& mesh_;
        const std::string_view file_;
        const bool smooth_normals_;
        std::thread thread_;
        std::mutex mutex_;  // guards what the inflater tells: the four below
        std::condition_variable changed_;
        bool positions_read_ = false, ended_ = false, abandoned_ = false;
        size_t triangles_read_ = 0;
        size_t prepared_ = 0;  // the follower's own until it is joined
        std::exception_ptr error_;
    };

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
    uint64_t stream_size(std::string_view file, size_t offset, int version, const SourceLocation& location) const {
        StreamInflater head(file, offset);
        uint32_t flags = head.value<uint32_t>("flags");
        uint64_t header = 4 + 16;
        if (version == 4) {
            while (head.value<uint8_t>("mesh name") != 0)
                if (++header > MaxHeaderBytes) throw SerializedError("the mesh name is not terminated");
            ++header;
        }
        uint64_t vertices = head.value<uint64_t>("vertex count"), triangles = head.value<uint64_t>("triangle count");
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

    // Triangles [first, first + count) from the stream.
    void read_triangles(StreamInflater& in, size_t first, size_t count, uint64_t vertex_count) {
        if (vertex_count <= 0xFFFFFFFFull) {
            in.read(triangles_.data() + first, count * sizeof(glm::uvec3), "triangle indices");
            return;
        }
        // More than 2^32 vertices: 64-bit indices, which must still name vertices the mesh has.
        for (size_t i = first; i < first + count; ++i) {
            glm::uvec3& t = triangles_[i];
            uint64_t v[3];
            in.read(v, sizeof v, "triangle indices");
            if (std::max({v[0], v[1], v[2]}) >= vertex_count)
                throw SerializedError("a triangle refers to vertex " + std::to_string(std::max({v[0], v[1], v[2]})) + " of " +
                                      std::to_string(vertex_count));
            t = glm::uvec3(unsigned(v[0]), unsigned(v[1]), unsigned(v[2]));
        }
    }

    // Loads mesh `index`.
    void read(const std::string& path, size_t index, bool skip_normals, const SourceLocation& location) {
        // The compressed file, memory-mapped (not copied).
        std::unique_ptr<MappedFile> mapped;
        try {
            mapped = std::make_unique<MappedFile>(path);
        } catch (const std::runtime_error& e) {
            throw SerializedError(e.what());
        }
        const std::string_view file(reinterpret_cast<const char*>(mapped->data()), mapped->size());
        auto bytes = [&](size_t at) { return reinterpret_cast<const unsigned char*>(file.data() + at); };
        if (file.size() < 4 || read_little_endian(bytes(0), 2) != FileMagic)
            throw SerializedError("not a serialized mesh (no 0x041C header)");
        int version = int(read_little_endian(bytes(2), 2));
        if (version != 3 && version != 4)
            throw SerializedError("unsupported format version " + std::to_string(version) + " (3 and 4 are read)");

        size_t offset = 0;
        if (index > 0) {
            // The dictionary at the end: the offsets of all meshes, then their count.
            if (file.size() < 8) throw SerializedError("the file is too short for its mesh dictionary");
            uint64_t count = read_little_endian(bytes(file.size() - 4), 4);
            size_t entry = version == 4 ? 8 : 4;
            if (count > (file.size() - 4) / entry) throw SerializedError("the mesh dictionary at the end of the file is corrupt");
            if (index >= count)
                throw SerializedError("the file holds " + std::to_string(count) + " meshes, so there is no index " + std::to_string(index));
            uint64_t at = read_little_endian(bytes(file.size() - 4 - entry * size_t(count - index)), entry);
            if (at + 4 > file.size() || read_little_endian(bytes(size_t(at)), 2) != FileMagic)
                throw SerializedError("the dictionary's offset of this mesh does not point at a mesh header");
            offset = size_t(at);
        }
        stream_size(file, offset + 4, version, location);
        StreamInflater in(file, offset + 4);
        const uint32_t flags = in.value<uint32_t>("flags");
        if (version == 4)
            while (in.value<uint8_t>("mesh name") != 0) {}
        const uint64_t vertex_count = in.value<uint64_t>("vertex count"), triangle_count = in.value<uint64_t>("triangle count");
        const bool dbl = (flags & DoublePrecision) != 0;
        const size_t vertices = size_t(vertex_count);
        // One spare element: Embree's padding (Mesh::update_derived). Every array is allocated
        // before the stream is inflated, on one thread (one zlib stream), while another populates
        // their pages and the rest of the compressed file's: for a 10^7-triangle mesh the page
        // faults were a third of that thread's time.
        positions_.reserve(vertices + 1);
        positions_.resize(vertices);
        if ((flags & HasNormals) && !skip_normals) normals_.resize(vertices);
        if (flags & HasTexcoords) uvs_.resize(vertices);
        if (flags & HasColors) attributes_.push_back(MeshAttribute{"vertex_color", false, 3, std::vector<float>(3 * vertices)});
        triangles_.resize(size_t(triangle_count));
        // Smooth normals (the file has none, and face_normals is off): their sums are reserved
        // here too, to be populated with the rest.
        const bool smooth_normals = !(flags & HasNormals) && !skip_normals;
        if (smooth_normals) normals_.reserve(vertices);
        // This thread inflates; a larger mesh's follower (below) populates the pages ahead of it
        // and then does finalize()'s work on what has been read.
        Follower follower(*this, file, smooth_normals, triangles_.size() >= FollowFromTriangles);
        read_reals(in, floats(positions_), 3 * vertices, dbl, "vertex positions");
        follower.positions_read();
        if (flags & HasNormals) read_reals(in, skip_normals ? nullptr : floats(normals_), 3 * vertices, dbl, "vertex normals");
        if (flags & HasTexcoords) read_reals(in, floats(uvs_), 2 * vertices, dbl, "texture coordinates");
        if (flags & HasColors) read_reals(in, attributes_.back().values.data(), 3 * vertices, dbl, "vertex colours");
        for (size_t first = 0; first < triangles_.size(); first += FollowSlice) {
            const size_t count = std::min(FollowSlice, triangles_.size() - first);
            read_triangles(in, first, count, vertex_count);
            follower.triangles_read(first + count);
        }
        // The follower checked the indices of the triangles it prepared.
        const size_t checked = follower.finish();
        // One byte more than declared shows a stream that holds more than its header says.
        if (!in.ends_here()) throw SerializedError("the compressed data holds more than its header declares");
        // The other indices, checked in parallel (each chunk its largest), here rather than in
        // finalize() so that the message names the index.
        std::atomic<uint64_t> largest{0};
        if (checked < triangles_.size())
            parallel_chunks(triangles_.size() - checked, 1 << 16, [&](size_t begin, size_t end) {
                uint64_t m = 0;
                for (size_t i = checked + begin; i < checked + end; ++i)
                    m = std::max({m, uint64_t(triangles_[i].x), uint64_t(triangles_[i].y), uint64_t(triangles_[i].z)});
                uint64_t seen = largest.load();
                while (m > seen && !largest.compare_exchange_weak(seen, m)) {}
            });
        if (!triangles_.empty() && largest.load() >= vertex_count)
            throw SerializedError("a triangle refers to vertex " + std::to_string(largest.load()) + " of " + std::to_string(vertex_count));
        if (triangles_.empty()) throw SerializedError("the mesh has no triangles");
        indices_checked_by_reader();
    }
};

CANDELA_REGISTER(SerializedMesh, ObjectKind::Shape, "serialized");

}  // namespace candela
