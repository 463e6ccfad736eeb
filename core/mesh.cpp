#include "core/mesh.h"

#include "core/error.h"
#include "core/mapped_file.h"
#include "core/parameters.h"

#include "core/memory_budget.h"
#include "core/parallel.h"
#include "core/warp.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <limits>
#include <map>
#include <tuple>

namespace candela {

void Mesh::check_mesh_memory(uint64_t vertices, uint64_t triangles, uint64_t file_bytes, const SourceLocation& where) {
    // Per vertex: position, normal and uv (32 bytes), rounded up to 64 for the readers'
    // temporaries (the OBJ reader's corner indices). Per triangle: the indices (Embree reads them
    // and the positions in place), Embree's BVH with its build's working memory (about 95 bytes
    // per triangle at high quality, measured by bench_scale), and an emitter's area table (12
    // bytes); a small flat mesh's cached triangle frames come on top and are not counted.
    const uint64_t per_vertex = 64, per_triangle = 12 + 96 + 12;
    uint64_t bytes =
        saturating_add(saturating_add(saturating_mul(vertices, per_vertex), saturating_mul(triangles, per_triangle)), file_bytes);
    check_memory(bytes, "mesh of " + std::to_string(vertices) + " vertices and " + std::to_string(triangles) + " triangles", where);
}
namespace {

// Errors in a mesh's data name the mesh file (at the filename property's line) when there is one.
[[noreturn]] void fail_mesh(const Properties& props, const std::string& message) {
    if (props.has("filename")) props.fail("filename", "mesh file \"" + props.get_string("filename") + "\": " + message);
    props.fail(message);
}
}  // namespace

void Mesh::finalize(const Properties& props, bool smooth_if_missing) {
    // Large meshes (10^7 triangles) spend seconds here when done on one core: the per-vertex
    // and per-triangle passes run in parallel chunks, each writing only its own elements, so the
    // results are the same whatever the thread count. What a reader prepared ahead is not done
    // again: a preparation that stopped at the end of an area chunk is continued, one that
    // stopped elsewhere (at an error) is done here in full.
    Prepared prepared = std::move(prepared_);
    prepared_ = Prepared();
    // The triangles [0, done) were prepared: all of them, or (a reader that handed the rest over
    // when its data ended) a whole number of area chunks, which the passes below continue.
    const size_t done =
        prepared.positions && (prepared.triangles == triangles_.size() || prepared.triangles % AreaChunk == 0) ? prepared.triangles : 0;
    const bool triangles_prepared = done == triangles_.size() && prepared.positions;
    std::atomic<bool> indices_valid{true};
    if (!triangles_prepared && !prepared.indices_checked)
        parallel_chunks(triangles_.size() - done, 1 << 16, [&](size_t begin, size_t end) {
            if (!indices_in_range(done + begin, done + end)) indices_valid = false;
        });
    if (!indices_valid) fail_mesh(props, "a face refers to a vertex that does not exist");
    if (!uvs_.empty() && uvs_.size() != positions_.size()) fail_mesh(props, "the uv count differs from the vertex count");
    if (!normals_.empty() && normals_.size() != positions_.size()) fail_mesh(props, "the normal count differs from the vertex count");
    for (const MeshAttribute& a : attributes_) {
        size_t rows = a.per_face ? triangles_.size() : positions_.size();
        if (a.channels < 1 || a.channels > 4 || a.values.size() != rows * size_t(a.channels))
            fail_mesh(props, "attribute \"" + a.name + "\" does not have one value per " + (a.per_face ? "face" : "vertex"));
    }

    std::atomic<bool> finite{prepared.finite};
    if (!prepared.positions)
        parallel_chunks(positions_.size(), 1 << 16, [&](size_t begin, size_t end) {
            if (!positions_to_world(begin, end, nullptr)) finite = false;
        });
    if (!finite) fail_mesh(props, "a vertex is not a finite number");
    for (const Vec2& uv : uvs_)
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) fail_mesh(props, "a texture coordinate is not a finite number");
    const size_t file_normals = prepared.normals ? 0 : normals_.size();
    for (size_t i = 0; i < file_normals; ++i)
        if (!all_finite(normals_[i])) fail_mesh(props, "a normal is not a finite number");
    parallel_chunks(file_normals, 1 << 16, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            Vec3 n = to_world_.apply_normal(normals_[i]);
            float len = glm::length(n);
            normals_[i] = len > 0.0f && std::isfinite(len) ? n / len : Vec3(0.0f, 0.0f, 1.0f);
        }
    });

    // Zero-area triangles cannot be hit or sampled: dropped, with their face attribute rows. A
    // parallel pass looks for one; only a mesh that has some is compacted, in place and in order
    // (a copy of the index array would double it when memory peaks for large meshes).
    // The same pass sums the areas of its chunks, which update_derived() then need not compute
    // again when there is nothing to drop.
    auto degenerate = [&](size_t i) {
        const float a = triangle_area(triangles_[i]);
        return !(a > 0.0f && std::isfinite(a));
    };
    std::atomic<bool> any_degenerate{done > 0 && prepared.degenerate};
    std::vector<double> chunk_areas((triangles_.size() + AreaChunk - 1) / AreaChunk);
    if (triangles_prepared) {
        if (triangles_.size() % AreaChunk != 0) prepared.chunk_areas.push_back(prepared.open_chunk_area);
        chunk_areas = std::move(prepared.chunk_areas);
    } else {
        const size_t first_chunk = done / AreaChunk;
        std::copy_n(prepared.chunk_areas.begin(), first_chunk, chunk_areas.begin());
        parallel_for(chunk_areas.size() - first_chunk, [&](size_t item) {
            const size_t c = first_chunk + item;
            double sum = 0.0;
            for (size_t i = c * AreaChunk; i < std::min(triangles_.size(), (c + 1) * AreaChunk); ++i) {
                const float a = triangle_area(triangles_[i]);
                if (!(a > 0.0f && std::isfinite(a)) || any_degenerate.load(std::memory_order_relaxed)) {
                    any_degenerate = true;
                    return;
                }
                sum += a;
            }
            chunk_areas[c] = sum;
        });
    }
    if (any_degenerate) {
        chunk_areas.clear();
        size_t kept = 0;
        for (size_t i = 0; i < triangles_.size(); ++i) {
            if (degenerate(i)) continue;
            if (kept != i) {
                triangles_[kept] = triangles_[i];
                for (MeshAttribute& attr : attributes_) {
                    if (!attr.per_face) continue;
                    const size_t c = size_t(attr.channels);
                    std::copy_n(attr.values.begin() + std::ptrdiff_t(i * c), c, attr.values.begin() + std::ptrdiff_t(kept * c));
                }
            }
            ++kept;
        }
        if (kept == 0) fail_mesh(props, "no triangle has a non-zero area");
        triangles_.resize(kept);
        triangles_.shrink_to_fit();
        for (MeshAttribute& attr : attributes_)
            if (attr.per_face) attr.values.resize(kept * size_t(attr.channels));
    }
    // Smooth normals summed ahead for [0, done): the rest of the triangles' terms added in order,
    // then normalized. Sums of a preparation that is not continued, or whose later triangles
    // have moved in a compaction, are dropped, and update_derived() computes them afresh.
    if (prepared.normals) {
        if (prepared.triangles != done || (any_degenerate && !triangles_prepared)) {
            normals_.clear();
        } else {
            if (!triangles_prepared) add_vertex_normal_terms(done);
            normalize_vertex_normals();
        }
    }
    update_derived(normals_.empty() && smooth_if_missing, chunk_areas.empty() ? nullptr : &chunk_areas,
                   prepared.positions ? &prepared.bounds : nullptr);
}

void Mesh::update_derived(bool recompute_normals, const std::vector<double>* known_chunk_areas, const BoundingBox* known_bounds) {
    // Embree reads vertices with 16-byte loads, so the buffer it shares with positions_ must be
    // readable 4 bytes past its last vertex: one element of spare capacity (readers reserve it
    // up front so that this reserve does not copy a large array).
    if (positions_.capacity() == positions_.size()) positions_.reserve(positions_.size() + 1);
    // The bounds of fixed chunks, then of them (the same box whatever the thread count).
    const size_t vertex_chunk = size_t(1) << 16;
    bbox_ = known_bounds ? *known_bounds : BoundingBox();
    if (!known_bounds) {
        std::vector<BoundingBox> boxes((positions_.size() + vertex_chunk - 1) / vertex_chunk);
        parallel_for(boxes.size(), [&](size_t c) {
            for (size_t i = c * vertex_chunk; i < std::min(positions_.size(), (c + 1) * vertex_chunk); ++i) boxes[c].expand(positions_[i]);
        });
        for (const BoundingBox& b : boxes) bbox_.expand(b);
    }
    // The total area in double, summed over fixed chunks in order: the same whatever the thread
    // count. The per-triangle areas are kept only for an emitter's area table (below).
    const size_t chunks = (triangles_.size() + AreaChunk - 1) / AreaChunk;
    std::vector<float> areas(emitter() ? triangles_.size() : 0);
    std::vector<double> partial;
    if (known_chunk_areas && areas.empty()) {
        partial = *known_chunk_areas;
    } else {
        partial.assign(chunks, 0.0);
        parallel_for(chunks, [&](size_t c) {
            double sum = 0.0;
            for (size_t i = c * AreaChunk; i < std::min(triangles_.size(), (c + 1) * AreaChunk); ++i) {
                float a = triangle_area(triangles_[i]);
                a = std::isfinite(a) ? a : 0.0f;
                sum += a;
                if (!areas.empty()) areas[i] = a;
            }
            partial[c] = sum;
        });
    }
    double total = 0.0;
    for (double p : partial) total += p;
    area_ = float(total);
    cone_axis_ = Vec3(0.0f, 0.0f, 1.0f);
    cone_cos_ = -1.0f;
    // What only light sampling reads (Shape::normal_cone, sample_position): built for the
    // meshes that carry an emitter, which is known from the constructor on. Other meshes, the
    // large ones in practice, do not hold an area table (12 bytes per triangle).
    area_distribution_ = Distribution1D();
    if (emitter()) {
        // Normal cone: the area-weighted mean normal and the widest deviation from it.
        Vec3 sum(0.0f);
        for (const auto& t : triangles_) sum += glm::cross(positions_[t.y] - positions_[t.x], positions_[t.z] - positions_[t.x]);
        if (squared_length(sum) > 0.0f) {
            cone_axis_ = glm::normalize(flip_normals_ ? -sum : sum);
            cone_cos_ = 1.0f;
            for (const auto& t : triangles_) {
                Vec3 n = glm::normalize(glm::cross(positions_[t.y] - positions_[t.x], positions_[t.z] - positions_[t.x]));
                cone_cos_ = std::min(cone_cos_, glm::dot(flip_normals_ ? -n : n, cone_axis_));
            }
            if (cone_cos_ < 1e-4f)
                cone_cos_ = -1.0f;  // beyond a hemisphere: treat as all directions
            else
                cone_cos_ = std::max(-1.0f, cone_cos_ - 1e-5f);
        }
        area_distribution_ = Distribution1D(std::move(areas));
    }
    if (recompute_normals) recompute_vertex_normals();
    // A flat triangle's frame is the same at every point of it: computed here once, not per hit,
    // up to a size where the 72 bytes per triangle would outweigh the mesh itself (larger flat
    // meshes compute it at each hit, as smooth ones do).
    flat_.clear();
    flat_.shrink_to_fit();
    if (normals_.empty() && triangles_.size() <= MaxCachedFlatTriangles) {
        flat_.resize(triangles_.size());
        parallel_chunks(triangles_.size(), 1 << 14, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) flat_[i] = flat_triangle_with_frame(triangles_[i]);
        });
    }
}

void Mesh::traverse(ParameterVisitor& visitor) {
    Shape::traverse(visitor);
    // World-space positions, x y z per vertex (Mitsuba's vertex_positions); the count is fixed.
    visitor.value("vertex_positions", ParameterAccess{ParameterType::Floats,
                                                      [this] {
                                                          std::vector<float> v(positions_.size() * 3);
                                                          if (!v.empty())
                                                              std::memcpy(v.data(), positions_.data(), v.size() * sizeof(float));
                                                          return v;
                                                      },
                                                      [this](const std::vector<float>& v) {
                                                          if (v.size() != positions_.size() * 3)
                                                              throw InputError("vertex_positions holds " +
                                                                               std::to_string(positions_.size() * 3) + " numbers, not " +
                                                                               std::to_string(v.size()));
                                                          for (float x : v)
                                                              if (!std::isfinite(x)) throw InputError("vertex_positions must be finite");
                                                          if (!v.empty())
                                                              std::memcpy(positions_.data(), v.data(), v.size() * sizeof(float));
                                                      }});
}

void Mesh::parameters_changed(const std::vector<std::string>& keys) {
    // Moved vertices: the bounds, areas, frames and (when the mesh has them) the vertex normals
    // follow, as in Mitsuba; the scene then rebuilds its BVH.
    if (std::find(keys.begin(), keys.end(), "vertex_positions") != keys.end()) update_derived(!normals_.empty());
}

namespace {
// acos(x) for x in [-1, 1] to float precision: Abramowitz and Stegun 4.4.46, acos(x) =
// sqrt(1 - x) (a0 + a1 x + ... + a7 x^7) on [0, 1] (absolute error at most 2e-8), and
// acos(-x) = pi - acos(x). A third of the cost of the library's acosf where it runs 3 times per
// triangle of a large mesh.
float acos_fast(float x) {
    const float a = std::min(std::fabs(x), 1.0f);
    const float p = 1.5707963050f +
                    a * (-0.2145988016f +
                         a * (0.0889789874f +
                              a * (-0.0501743046f + a * (0.0308918810f + a * (-0.0170881256f + a * (0.0066700901f - a * 0.0012624911f))))));
    const float r = std::sqrt(1.0f - a) * p;
    return x < 0.0f ? Pi - r : r;
}

// Corner k of triangles[i] gets corners[3 i + k]: its face's unit normal times the corner's angle.
// Built twice by GCC on x86-64, for AVX2 and for the baseline (SSE2), and picked when the program
// loads: the arithmetic is IEEE additions, multiplications, divisions, square roots, minima and
// maxima, each rounded the same at any vector width (AVX2 does not bring FMA contraction), so
// both give the same terms bit for bit, the AVX2 one in about half the time.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void normal_corner_terms(const Vec3* positions, const glm::uvec3* triangles, size_t count, Vec3* corners) {
    // Batches of triangles as structures of arrays: the arithmetic loop below is plain float code
    // over arrays, which the compiler turns into SIMD (square roots and divisions dominate it).
    // Each triangle's terms depend on it alone, so any batching gives the same values.
    constexpr size_t Batch = 64;
    float e[3][3][Batch];  // e[edge][axis][triangle]: e0 = p1 - p0, e1 = p2 - p1, e2 = p0 - p2
    float angle[3][Batch], unit[3][Batch];
    for (size_t b = 0; b < count; b += Batch) {
        const size_t n = std::min(Batch, count - b);
        for (size_t j = 0; j < n; ++j) {
            const glm::uvec3& t = triangles[b + j];
            const Vec3 p0 = positions[t.x], p1 = positions[t.y], p2 = positions[t.z];
            const Vec3 edges[3] = {p1 - p0, p2 - p1, p0 - p2};
            for (int k = 0; k < 3; ++k)
                for (int axis = 0; axis < 3; ++axis) e[k][axis][j] = edges[k][axis];
        }
        for (size_t j = 0; j < n; ++j) {
            auto dot = [&](int k, int m) { return e[k][0][j] * e[m][0][j] + e[k][1][j] * e[m][1][j] + e[k][2][j] * e[m][2][j]; };
            const float s0 = dot(0, 0), s1 = dot(1, 1), s2 = dot(2, 2);  // squared edge lengths
            // The face normal e0 x (-e2) = e2 x e0.
            const float cx = e[2][1][j] * e[0][2][j] - e[2][2][j] * e[0][1][j];
            const float cy = e[2][2][j] * e[0][0][j] - e[2][0][j] * e[0][2][j];
            const float cz = e[2][0][j] * e[0][1][j] - e[2][1][j] * e[0][0][j];
            const float face = cx * cx + cy * cy + cz * cz;
            // Branch-free, so that the loop vectorizes: a degenerate triangle (excluded by
            // finalize(), but vertex_positions may move) gets weight 0 via `valid`, and its
            // divisions see safe denominators.
            const float valid = float((face > 0.0f) & (s0 > 0.0f) & (s1 > 0.0f) & (s2 > 0.0f));
            const float smallest = std::numeric_limits<float>::min();
            const float inverse = valid / std::sqrt(std::max(face, smallest));
            unit[0][j] = cx * inverse;
            unit[1][j] = cy * inverse;
            unit[2][j] = cz * inverse;
            // The angle at p0 lies between e0 and -e2, at p1 between e1 and -e0, at p2 between
            // e2 and -e1: cos = -(e_k . e_(k-1)) / (|e_k| |e_(k-1)|).
            auto corner_angle = [&](float edge_dot, float squared_a, float squared_b) {
                const float cosine = -edge_dot / std::sqrt(std::max(squared_a * squared_b, smallest));
                return acos_fast(std::min(1.0f, std::max(-1.0f, cosine)));
            };
            angle[0][j] = corner_angle(dot(0, 2), s0, s2);
            angle[1][j] = corner_angle(dot(1, 0), s1, s0);
            angle[2][j] = corner_angle(dot(2, 1), s2, s1);
        }
        for (size_t j = 0; j < n; ++j)
            for (int k = 0; k < 3; ++k) corners[3 * (b + j) + size_t(k)] = angle[k][j] * Vec3(unit[0][j], unit[1][j], unit[2][j]);
    }
}

}  // namespace

void Mesh::add_corner_terms(const glm::uvec3* triangles, size_t count, const Vec3* corners) {
    for (size_t i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k) normals_[triangles[i][k]] += corners[3 * i + size_t(k)];
}

void Mesh::normalize_vertex_normals() {
    parallel_chunks(normals_.size(), 1 << 16, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const float len = glm::length(normals_[i]);
            normals_[i] = len > 0.0f ? normals_[i] / len : Vec3(1.0f, 0.0f, 0.0f);
        }
    });
}

void Mesh::recompute_vertex_normals() {
    // Each corner adds its face's unit normal weighted by the corner's angle (Thürmer and
    // Wüthrich 1998), in float as Mitsuba does. The corners' terms are computed in parallel, a
    // block of triangles at a time, and added to the vertices in triangle order on one thread:
    // the same normals whatever the thread count. That addition of one block runs beside the
    // computation of the next block's terms (two buffers), so that it does not leave the other
    // cores idle. The normals are zeroed in parallel too (a serial fill of a 10^7-triangle mesh's
    // was 0.05 s).
    normals_.resize(positions_.size());
    populate_pages_in_parallel(normals_.data(), normals_.size() * sizeof(Vec3), true);
    parallel_chunks(normals_.size(), 1 << 16,
                    [&](size_t begin, size_t end) { std::fill(normals_.begin() + begin, normals_.begin() + end, Vec3(0.0f)); });
    add_vertex_normal_terms(0);
    normalize_vertex_normals();
}

void Mesh::add_vertex_normal_terms(size_t first_triangle) {
    const size_t total = triangles_.size() - first_triangle;
    const size_t block = size_t(1) << 18, blocks = (total + block - 1) / block;
    MeshArray<Vec3> corners[2];
    for (auto& c : corners) {
        c.resize(3 * std::min(block, total));
        populate_pages_in_parallel(c.data(), c.size() * sizeof(Vec3), true);
    }
    const glm::uvec3* triangles = triangles_.data() + first_triangle;
    // Step s computes block s's terms in chunks (items 1...) while item 0 adds block s - 1's.
    const size_t chunk = size_t(1) << 12;
    for (size_t step = 0; step <= blocks; ++step) {
        const size_t first = step * block, count = step < blocks ? std::min(block, total - first) : 0;
        parallel_for(1 + (count + chunk - 1) / chunk, [&](size_t item) {
            if (item == 0) {
                if (step > 0)
                    add_corner_terms(triangles + (first - block), std::min(block, total - (first - block)), corners[(step - 1) % 2].data());
                return;
            }
            const size_t begin = (item - 1) * chunk;
            normal_corner_terms(positions_.data(), triangles + first + begin, std::min(count, begin + chunk) - begin,
                                &corners[step % 2][3 * begin]);
        });
    }
}

void Mesh::prepare_normal_sums() {
    normals_.resize(positions_.size());  // a reader may have reserved (and populated) them
    if (!normals_.empty()) std::memset(static_cast<void*>(normals_.data()), 0, normals_.size() * sizeof(Vec3));  // +0.0f: zero bits
    prepared_.normals = true;
}

bool Mesh::indices_in_range(size_t begin, size_t end) const {
    const size_t vertices = positions_.size();
    bool valid = true;
    for (size_t i = begin; i < end; ++i)
        valid = valid && triangles_[i].x < vertices && triangles_[i].y < vertices && triangles_[i].z < vertices;
    return valid;
}

bool Mesh::positions_to_world(size_t begin, size_t end, BoundingBox* bounds) {
    const bool identity = to_world_.is_identity();  // the common case: nothing to transform
    bool finite = true;
    for (size_t i = begin; i < end; ++i) {
        if (!identity) positions_[i] = to_world_.apply_point(positions_[i]);
        finite = finite && all_finite(positions_[i]);
        if (bounds) bounds->expand(positions_[i]);
    }
    return finite;
}

bool Mesh::prepare_positions() {
    // As finalize()'s pass does it, on this thread, with the bounds as update_derived() takes
    // them (a box's expansion gives the same box in any order).
    BoundingBox bounds;
    const bool finite = positions_to_world(0, positions_.size(), &bounds);
    prepared_.positions = true;
    prepared_.finite = finite;
    prepared_.bounds = bounds;
    return finite;
}

bool Mesh::prepare_triangles(size_t first, size_t last) {
    if (!prepared_.positions || first != prepared_.triangles || last > triangles_.size() || first > last)
        throw std::logic_error("prepare_triangles: consecutive ranges from the first, after prepare_positions");
    if (!prepared_.finite) return false;
    // A batch at a time: its indices checked, its areas summed in finalize()'s order (each chunk
    // of AreaChunk triangles in double, from its first), the triangles finalize() keeps (a
    // positive finite area) gathered, their smooth normals' terms computed and added in order.
    constexpr size_t Batch = 1 << 10;
    glm::uvec3 kept[Batch];
    Vec3 corners[3 * Batch];
    for (size_t begin = first; begin < last; begin += Batch) {
        const size_t end = std::min(last, begin + Batch);
        if (!indices_in_range(begin, end)) return false;
        size_t count = 0;
        for (size_t i = begin; i < end; ++i) {
            const float a = triangle_area(triangles_[i]);
            if (a > 0.0f && std::isfinite(a)) {
                prepared_.open_chunk_area += a;
                kept[count++] = triangles_[i];
            } else {
                prepared_.degenerate = true;
            }
            if ((i + 1) % AreaChunk == 0) {
                prepared_.chunk_areas.push_back(prepared_.open_chunk_area);
                prepared_.open_chunk_area = 0.0;
            }
        }
        if (prepared_.normals) {
            normal_corner_terms(positions_.data(), kept, count, corners);
            add_corner_terms(kept, count, corners);
        }
        prepared_.triangles = end;
    }
    return true;
}

void triangle_tangents(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec2& uv0, const Vec2& uv1, const Vec2& uv2, const Vec3& n,
                       Vec3& dpdu, Vec3& dpdv) {
    Vec2 duv1 = uv1 - uv0, duv2 = uv2 - uv0;
    Vec3 dp1 = p1 - p0, dp2 = p2 - p0;
    float det = duv1.x * duv2.y - duv1.y * duv2.x;
    if (std::abs(det) > 1e-12f) {
        float inv = 1.0f / det;
        dpdu = (duv2.y * dp1 - duv1.y * dp2) * inv;
        dpdv = (-duv2.x * dp1 + duv1.x * dp2) * inv;
    } else {
        coordinate_system(n, dpdu, dpdv);
    }
}

RTCGeometry Mesh::create_embree_geometry(RTCDevice device) const {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree reads the mesh's own arrays (shared buffers): a mesh is held once, not copied into
    // Embree. Vec3 and uvec3 are three packed 32-bit values; update_derived() keeps the spare
    // element of capacity that Embree's 16-byte vertex loads need.
    static_assert(sizeof(Vec3) == 12 && sizeof(glm::uvec3) == 12, "Embree reads packed float3 and uint3");
    if (positions_.capacity() <= positions_.size()) throw std::logic_error("mesh positions lack Embree's padding");
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, positions_.data(), 0, sizeof(Vec3), positions_.size());
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, triangles_.data(), 0, sizeof(glm::uvec3), triangles_.size());
    return g;
}

// The geometric normal (on the front side) and the uv tangents of triangle `t`; the shading
// frame is left to the caller.
Mesh::FlatTriangle Mesh::flat_triangle(const glm::uvec3& t) const {
    const Vec3 &p0 = positions_[t.x], &p1 = positions_[t.y], &p2 = positions_[t.z];
    FlatTriangle f;
    f.n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    if (!uvs_.empty())
        triangle_tangents(p0, p1, p2, uvs_[t.x], uvs_[t.y], uvs_[t.z], f.n, f.dpdu, f.dpdv);
    else
        coordinate_system(f.n, f.dpdu, f.dpdv);
    if (flip_normals_) f.n = -f.n;
    return f;
}

Mesh::FlatTriangle Mesh::flat_triangle_with_frame(const glm::uvec3& t) const {
    FlatTriangle f = flat_triangle(t);
    f.shading = Frame::from_normal_tangent(f.n, f.dpdu);
    return f;
}

void Mesh::fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const {
    const glm::uvec3& t = triangles_[hit.prim_index];
    const Vec3 &p0 = positions_[t.x], &p1 = positions_[t.y], &p2 = positions_[t.z];
    float b1 = hit.u, b2 = hit.v, b0 = 1.0f - b1 - b2;
    // Barycentric interpolation is more accurate than o + t d far from the origin. The weighted
    // vertices are kept in locals: p and its error bound both use them, and once a store into si
    // has happened the compiler must assume it changed the vertices (si could alias them) and
    // would load and multiply them again.
    const Vec3 w0 = b0 * p0, w1 = b1 * p1, w2 = b2 * p2;
    si.p = w0 + w1 + w2;
    si.p_error = gamma_bound(7) * max_component(abs_components(w0) + abs_components(w1) + abs_components(w2));
    si.uv = uvs_.empty() ? Vec2(b1, b2) : b0 * uvs_[t.x] + b1 * uvs_[t.y] + b2 * uvs_[t.z];
    if (normals_.empty()) {
        // The cached frame, or for a flat mesh too large to cache them, this triangle's own.
        auto take = [&si](const FlatTriangle& f) {
            si.n = f.n;
            si.dpdu = f.dpdu;
            si.dpdv = f.dpdv;
            si.shading = f.shading;
        };
        if (!flat_.empty())
            take(flat_[hit.prim_index]);
        else
            take(flat_triangle_with_frame(t));
        return;
    }
    fill_smooth_frame(t, b0, b1, b2, si);
}

// Out of fill_interaction() so that hits on flat meshes, the common case, do not pay on entry
// for the registers and stack this part needs.
void Mesh::fill_smooth_frame(const glm::uvec3& t, float b0, float b1, float b2, SurfaceInteraction& si) const {
    FlatTriangle f = flat_triangle(t);
    // The shading normal interpolates the vertex normals (on the geometric normal's side, which
    // flip_normals turns).
    Vec3 ns = b0 * normals_[t.x] + b1 * normals_[t.y] + b2 * normals_[t.z];
    float len = glm::length(ns);
    ns = len > 0.0f ? ns / len : (flip_normals_ ? -f.n : f.n);
    if (flip_normals_) ns = -ns;
    si.n = f.n;
    si.dpdu = f.dpdu;
    si.dpdv = f.dpdv;
    si.shading = Frame::from_normal_tangent(ns, f.dpdu);
}

void Mesh::tessellate(TriangleSoup& out, int) const {
    unsigned base = unsigned(out.positions.size());
    for (size_t i = 0; i < positions_.size(); ++i) {
        out.positions.push_back(positions_[i]);
        out.uvs.push_back(uvs_.empty() ? Vec2(0.0f) : uvs_[i]);
    }
    // Vertex normals: the file's (or smoothed) ones, else each vertex takes the normal of the
    // faces around it only if they agree; flat meshes (rectangle, cube faces) keep face normals
    // because their vertices are not shared between faces.
    std::vector<Vec3> normals(normals_.begin(), normals_.end());
    if (normals.empty()) {
        normals.assign(positions_.size(), Vec3(0.0f));
        for (const auto& t : triangles_) {
            Vec3 n = glm::cross(positions_[t.y] - positions_[t.x], positions_[t.z] - positions_[t.x]);
            normals[t.x] += n;
            normals[t.y] += n;
            normals[t.z] += n;
        }
        for (auto& n : normals) n = squared_length(n) > 0.0f ? glm::normalize(n) : Vec3(0, 0, 1);
    }
    for (const Vec3& n : normals) out.normals.push_back(flip_normals_ ? -n : n);
    for (const auto& t : triangles_)
        out.triangles.push_back(flip_normals_ ? glm::uvec3(base + t.x, base + t.z, base + t.y) : t + glm::uvec3(base));
    // Closed when, with coincident vertices welded, every edge has exactly one opposite twin.
    std::map<std::tuple<float, float, float>, unsigned> weld;
    auto id = [&](unsigned v) {
        const Vec3& p = positions_[v];
        return weld.emplace(std::make_tuple(p.x, p.y, p.z), unsigned(weld.size())).first->second;
    };
    std::map<std::pair<unsigned, unsigned>, int> edges;
    for (const auto& t : triangles_) {
        unsigned a = id(t.x), b = id(t.y), c = id(t.z);
        ++edges[{a, b}];
        ++edges[{b, c}];
        ++edges[{c, a}];
    }
    bool closed = !edges.empty();
    for (const auto& [e, n] : edges) {
        auto twin = edges.find({e.second, e.first});
        if (n != 1 || twin == edges.end() || twin->second != 1) {
            closed = false;
            break;
        }
    }
    out.closed = closed;
}

bool Mesh::eval_attribute(const std::string& name, const SurfaceInteraction& si, Spectrum& value) const {
    for (const MeshAttribute& a : attributes_) {
        if (a.name != name) continue;
        size_t n = size_t(a.channels);
        float v[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        if (a.per_face) {
            for (size_t c = 0; c < n; ++c) v[c] = a.values[si.prim_index * n + c];
        } else {
            const glm::uvec3& t = triangles_[si.prim_index];
            float b1 = si.prim_uv.x, b2 = si.prim_uv.y, b0 = 1.0f - b1 - b2;
            for (size_t c = 0; c < n; ++c) v[c] = b0 * a.values[t.x * n + c] + b1 * a.values[t.y * n + c] + b2 * a.values[t.z * n + c];
        }
        // One channel is grey; two fill red and green; a fourth (alpha) is not a colour.
        value = a.channels == 1 ? Spectrum(v[0]) : Spectrum(v[0], v[1], v[2]);
        return true;
    }
    return false;
}

PositionSample Mesh::sample_position(const Vec2& u) const {
    if (area_distribution_.empty()) throw std::logic_error("a mesh without an emitter has no area table to sample");
    float ux = u.x;
    size_t i = area_distribution_.sample_discrete(ux);
    Vec2 b = warp::square_to_uniform_triangle(Vec2(ux, u.y));
    const glm::uvec3& t = triangles_[i];
    const Vec3 &p0 = positions_[t.x], &p1 = positions_[t.y], &p2 = positions_[t.z];
    PositionSample ps;
    float b0 = 1.0f - b.x - b.y;
    ps.p = b0 * p0 + b.x * p1 + b.y * p2;
    ps.p_error = gamma_bound(7) * max_component(abs_components(b0 * p0) + abs_components(b.x * p1) + abs_components(b.y * p2));
    // The shading normal where the mesh has vertex normals (the face normal otherwise), as
    // Mitsuba 3 does: an area light then decides its emitting side, and converts area to solid
    // angle, with the normal a path that hits the point sees (SurfaceInteraction::shading.n), so
    // that light sampling and emitter hits agree on both.
    Vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    if (!normals_.empty()) {
        const Vec3 ns = b0 * normals_[t.x] + b.x * normals_[t.y] + b.y * normals_[t.z];
        const float len = glm::length(ns);
        if (len > 0.0f) n = ns / len;
    }
    ps.n = flip_normals_ ? -n : n;
    ps.uv = uvs_.empty() ? b : b0 * uvs_[t.x] + b.x * uvs_[t.y] + b.y * uvs_[t.z];
    ps.pdf = 1.0f / area_;
    return ps;
}

}  // namespace candela
