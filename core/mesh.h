#pragma once
// Triangle meshes in world space, intersected by Embree's triangle geometry. The mesh plugins
// (obj, ply, rectangle, cube) fill the arrays in object space and call finalize().

#include "core/distribution.h"
#include "core/shape.h"

#include <algorithm>
#include <vector>

namespace candela {

// dp/du and dp/dv of a triangle from its uv parametrisation (any tangents around n when the uvs
// are degenerate).
void triangle_tangents(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec2& uv0, const Vec2& uv1, const Vec2& uv2, const Vec3& n,
                       Vec3& dpdu, Vec3& dpdv);

// How far the surface a triangle approximates may lie from the triangle's plane, from how much
// its vertex normals turn away from the face normal: a chord of length l across a surface whose
// normals turn by theta lies l theta / 8 below it (the sagitta, l^2 / 8R with l = R theta); with
// the vertex normals turned by about theta / 2, l max|n_i x n_face| / 4 covers it, and twice
// that leaves a margin. Zero for flat meshes. Rays leaving a tessellated surface toward the
// exact one (the raster mode's ambient occlusion, baking) start this far off it.
inline float tessellation_gap(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& n0, const Vec3& n1, const Vec3& n2) {
    Vec3 face = glm::cross(p1 - p0, p2 - p0);
    float len = glm::length(face);
    if (!(len > 0.0f)) return 0.0f;
    face /= len;
    float turn = std::max({glm::length(glm::cross(n0, face)), glm::length(glm::cross(n1, face)), glm::length(glm::cross(n2, face))});
    float edge = std::sqrt(std::max({squared_length(p1 - p0), squared_length(p2 - p1), squared_length(p0 - p2)}));
    return 0.5f * edge * turn;
}

// Data attached to a mesh's vertices or faces, named as in Mitsuba ("vertex_color",
// "face_normal_x", ...), with 1 to 4 channels per element.
struct MeshAttribute {
    std::string name;
    bool per_face = false;
    int channels = 1;
    std::vector<float> values;  // channels per vertex (or per triangle of triangles_)
};

class Mesh : public Shape {
public:
    explicit Mesh(const Properties& props) : Shape(props) {}

    RTCGeometry create_embree_geometry(RTCDevice device) const override;
    void fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const override;
    BoundingBox bbox() const override { return bbox_; }
    float surface_area() const override { return area_; }
    PositionSample sample_position(const Vec2& u) const override;
    // Appends the mesh to `out` (expected empty: `closed` describes this mesh alone).
    void tessellate(TriangleSoup& out, int detail) const override;
    void normal_cone(Vec3& axis, float& cos_theta) const override {
        axis = cone_axis_;
        cos_theta = cone_cos_;
    }

    bool eval_attribute(const std::string& name, const SurfaceInteraction& si, Spectrum& value) const override;
    const std::vector<MeshAttribute>& attributes() const { return attributes_; }

    size_t triangle_count() const { return triangles_.size(); }
    const MeshArray<Vec3>& positions() const { return positions_; }
    const MeshArray<Vec3>& normals() const { return normals_; }
    const MeshArray<Vec2>& uvs() const { return uvs_; }
    const MeshArray<glm::uvec3>& triangles() const { return triangles_; }
    // Its BSDF and emitter, and vertex_positions (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override;
    void parameters_changed(const std::vector<std::string>& keys) override;

protected:
    // Stops the load (memory_budget.h) before a reader allocates a mesh of `vertices` and
    // `triangles`, with `file_bytes` more for the reader's own buffers: an estimate of the
    // arrays here with finalize()'s temporaries, the area table and Embree's buffers and BVH.
    static void check_mesh_memory(uint64_t vertices, uint64_t triangles, uint64_t file_bytes, const SourceLocation& where);
    // Moves the object-space data to world space, drops degenerate triangles, and builds the
    // area table. With `smooth_if_missing`, a mesh without vertex normals gets angle-weighted
    // smooth normals (Thürmer & Wüthrich 1998), as Mitsuba does for OBJ and PLY files.
    void finalize(const Properties& props, bool smooth_if_missing);
    // What finalize() derives from the positions: bounds, area table, normal cone, flat frames,
    // and the vertex normals when `recompute_normals`. `known_chunk_areas`: the area sums of
    // consecutive chunks of AreaChunk triangles (finalize() has them), and `known_bounds`, else
    // computed here.
    void update_derived(bool recompute_normals, const std::vector<double>* known_chunk_areas = nullptr,
                        const BoundingBox* known_bounds = nullptr);
    void recompute_vertex_normals();
    // Triangles per chunk of the area sums: fixed, so that the sums are the same whatever the
    // thread count (finalize() and update_derived() chunk alike, and a reader's preparation
    // hands the rest over at a chunk's end).
    static constexpr size_t AreaChunk = size_t(1) << 16;
    // finalize()'s passes done ahead, while the data still arrives, by a reader that reads on one
    // thread and has another to spare (serialized: one zlib stream). prepare_normal_sums(), for
    // a mesh that gets smooth normals, zeroes their sums (once positions_ is sized). Once every
    // position is in, prepare_positions() moves them to world space, checks that they are finite
    // (false when one is not) and takes their bounds. Then prepare_triangles() for consecutive
    // ranges of triangles from the first checks their indices, sums their areas as finalize()
    // does and adds their smooth normals' terms to the sums (false at an index out of range: the
    // rest is left undone). finalize() then does only what was not done, with the same results
    // bit for bit: degenerate triangles are skipped as it drops them, and every sum is made in
    // the same order.
    void prepare_normal_sums();
    bool prepare_positions();
    bool prepare_triangles(size_t first, size_t last);
    // The reader has checked every triangle's indices itself (serialized, whose message names
    // the index): finalize() does not check those it did not prepare again.
    void indices_checked_by_reader() { prepared_.indices_checked = true; }
    float triangle_area(const glm::uvec3& t) const {
        return 0.5f * glm::length(glm::cross(positions_[t.y] - positions_[t.x], positions_[t.z] - positions_[t.x]));
    }

    MeshArray<Vec3> positions_, normals_;
    MeshArray<Vec2> uvs_;
    MeshArray<glm::uvec3> triangles_;
    // Face attributes hold one row per entry of triangles_ (a polygon's row repeated for each of
    // its triangles); finalize() drops the rows of degenerate triangles with them.
    std::vector<MeshAttribute> attributes_;

private:
    // What a hit on a triangle needs beyond its point and uv, when the mesh has no vertex normals
    // (rectangles, cubes, faceted meshes): the same everywhere on the triangle, so finalize()
    // stores it per triangle instead of fill_interaction() recomputing it at every hit.
    struct FlatTriangle {
        Vec3 n, dpdu, dpdv;  // n on the front side (flip_normals applied)
        Frame shading;
    };
    FlatTriangle flat_triangle(const glm::uvec3& t) const;
    FlatTriangle flat_triangle_with_frame(const glm::uvec3& t) const;
    // Up to this many triangles, a mesh without vertex normals keeps its FlatTriangles (72 MB).
    static constexpr size_t MaxCachedFlatTriangles = size_t(1) << 20;
    // fill_interaction()'s normals and frames for a mesh with vertex normals: triangle t hit at
    // barycentrics (b0, b1, b2).
    void fill_smooth_frame(const glm::uvec3& t, float b0, float b1, float b2, SurfaceInteraction& si) const;
    // The smooth normals' pieces (the corners' terms are computed in mesh.cpp): their addition to
    // the vertices in order, and the normalization of the sums.
    void add_corner_terms(const glm::uvec3* triangles, size_t count, const Vec3* corners);
    // Adds the corner terms of triangles [first_triangle, end) to normals_ in triangle order, the
    // terms computed in parallel (recompute_vertex_normals from 0 on zeroed sums, finalize() after
    // a partial preparation).
    void add_vertex_normal_terms(size_t first_triangle);
    void normalize_vertex_normals();
    // finalize()'s and the preparation's shared steps over [begin, end): whether the triangles'
    // indices name existing vertices; the positions moved to world space, whether all are finite
    // (expanding `bounds` when given).
    bool indices_in_range(size_t begin, size_t end) const;
    bool positions_to_world(size_t begin, size_t end, BoundingBox* bounds);
    // What prepare_positions() and prepare_triangles() have done, until finalize() takes it.
    struct Prepared {
        bool positions = false;           // in world space
        bool finite = true;               // ... and all of them finite
        BoundingBox bounds;               // ... and their bounds
        size_t triangles = 0;             // the first `triangles` have valid indices, their areas summed
        bool indices_checked = false;     // every triangle's indices are valid (the reader checked them)
        bool degenerate = false;          // one of them has no positive finite area
        bool normals = false;             // normals_ holds their smooth normals' sums (not normalized)
        std::vector<double> chunk_areas;  // area sums of their complete chunks of AreaChunk
        double open_chunk_area = 0.0;     // and of the chunk they end inside
    };
    Prepared prepared_;
    std::vector<FlatTriangle> flat_;  // per entry of triangles_; empty with vertex normals

    Distribution1D area_distribution_;  // by triangle area; only in meshes that carry an emitter
    float area_ = 0.0f;
    BoundingBox bbox_;
    Vec3 cone_axis_{0.0f, 0.0f, 1.0f};
    float cone_cos_ = -1.0f;
};

}  // namespace candela
