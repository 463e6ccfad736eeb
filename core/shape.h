#pragma once
// Shapes: geometry that Embree intersects, and that area lights sample. Every shape reads
// `to_world` and `flip_normals` and may hold one BSDF and one area emitter (nested or by ref).

#include "core/animated_transform.h"
#include "core/mesh_array.h"
#include "core/object.h"
#include "core/properties.h"
#include "core/ray.h"
#include "core/spectrum.h"

#include <embree3/rtcore.h>

#include <string>
#include <vector>

namespace candela {

class BSDF;
class Emitter;
class Sensor;
class Medium;

// A point sampled on a surface; `pdf` is per unit area.
struct PositionSample {
    Vec3 p{0.0f}, n{0.0f, 0.0f, 1.0f};
    float p_error = 0.0f;  // bound on the absolute error of each coordinate of p
    Vec2 uv{0.0f};
    float pdf = 0.0f;
    bool delta = false;
};
// Shape::direction_from_position copies these fields one by one.
static_assert(sizeof(PositionSample) == 44, "a new PositionSample field must be copied in direction_from_position");

// A point sampled as seen from a reference point: `d` is the unit direction from the reference
// to `p`, `dist` the distance, and `pdf` per unit solid angle (or the probability of a delta).
struct DirectionSample : PositionSample {
    Vec3 d{0.0f, 0.0f, 1.0f};
    float dist = 0.0f;
    const Emitter* emitter = nullptr;
};

// Triangles in world space with per-vertex normals and uvs (for the rasterizer).
struct TriangleSoup {
    MeshArray<Vec3> positions, normals;  // normals: shading normals, front side
    MeshArray<Vec2> uvs;
    MeshArray<glm::uvec3> triangles;
    bool closed = false;  // every edge shared by exactly two triangles (a watertight surface)

    // Adds another soup's triangles (the result is not known to be closed).
    void append(const TriangleSoup& other) {
        unsigned base = unsigned(positions.size());
        positions.insert(positions.end(), other.positions.begin(), other.positions.end());
        normals.insert(normals.end(), other.normals.begin(), other.normals.end());
        uvs.insert(uvs.end(), other.uvs.begin(), other.uvs.end());
        for (const auto& t : other.triangles) triangles.push_back(t + glm::uvec3(base));
        closed = false;
    }
};

class Shape;

// Triangles of one shape, for the rasterizer, with the shape whose BSDF and emitter they have.
struct TessellatedPart {
    const Shape* shape = nullptr;
    TriangleSoup triangles;
};

// What Embree reports for a closest hit; shapes turn it into a SurfaceInteraction.
// The fields are not in RTCRayHit's order on purpose: Embree stores its hit fields one by one,
// and where two neighbours there were neighbours here too, the copy read them back as one 8-byte
// load that had to wait for both stores to reach the cache (store forwarding cannot merge them).
struct RayHit {
    float t = Infinity;
    unsigned prim_index = 0;
    float u = 0.0f;                    // barycentrics (u, v) for triangles, shape-defined otherwise
    unsigned instance_geometry = ~0u;  // for a hit on an instance: the geometry hit inside its group
    float v = 0.0f;
};

class Shape : public Object {
public:
    // `may_move`: the shape accepts an animated to_world (instances); for the others an
    // <animation> is an error at its line.
    explicit Shape(const Properties& props, bool may_move = false);
    ObjectKind kind() const override { return ObjectKind::Shape; }

    // Builds the Embree geometry for this shape (the caller commits, attaches and releases it).
    virtual RTCGeometry create_embree_geometry(RTCDevice device) const = 0;
    // Fills position, normals, shading frame and uv for a hit on this shape.
    virtual void fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const = 0;

    virtual BoundingBox bbox() const = 0;
    virtual float surface_area() const = 0;
    // A point uniform by area.
    virtual PositionSample sample_position(const Vec2& u) const = 0;
    // A point as seen from `ref`, with pdf per unit solid angle. By default: uniform by area,
    // converted; shapes that can do better (sphere: the visible cone) override both functions.
    virtual DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2& u) const;
    virtual float pdf_direction(const SurfaceInteraction& ref, const DirectionSample& ds) const;

    // Appends this shape as triangles; analytic shapes are tessellated finely enough that their
    // silhouettes stay within about a pixel at `detail` segments per full turn.
    virtual void tessellate(TriangleSoup& out, int detail = 64) const = 0;
    // What the rasterizer draws for this shape: by default one part, this shape's tessellation;
    // an instance gives one part per shape of its group (each with its own BSDF).
    virtual void tessellate_parts(std::vector<TessellatedPart>& parts, int detail = 64) const;

    // A cone containing every front-facing normal of the shape: axis and the cosine of its
    // half-angle (-1 when the normals point everywhere).
    virtual void normal_cone(Vec3& axis, float& cos_theta) const {
        axis = Vec3(0.0f, 0.0f, 1.0f);
        cos_theta = -1.0f;
    }

    // A shape group only holds shapes for instances to reference; it is not part of the scene's
    // BVH itself.
    virtual bool is_shape_group() const { return false; }

    // Whether the shape moves (an animated to_world: instances only, through Embree's instance
    // motion blur).
    bool is_animated() const { return motion_.is_animated(); }
    const SourceLocation& motion_location() const { return motion_.where; }
    const AnimatedTransform& motion() const { return motion_; }
    // Told by the scene before its BVH is built: the sensor's exposure [open, close]. A moving
    // shape shows its pose at `open` to the views that have no time (the rasterizer's
    // tessellation) and holds its first and last poses before and after its keyframes.
    virtual void set_shutter(float open, float close) {}

    // A per-vertex or per-face attribute of a mesh ("vertex_color", "face_id", ...) at a hit
    // point (si.prim_index, si.prim_uv), as the mesh_attribute texture reads it: vertex
    // attributes interpolated barycentrically, face attributes constant per face. One channel
    // comes back as grey. False when the shape has no attribute of that name.
    virtual bool eval_attribute(const std::string& name, const SurfaceInteraction& si, Spectrum& value) const { return false; }

    // Whether all front-facing normals agree (rectangle, disk, a flat mesh), within the margin
    // that meshes add to their cone; `normal` receives the common normal.
    bool is_planar(Vec3& normal) const {
        float cos_theta;
        normal_cone(normal, cos_theta);
        return cos_theta >= 1.0f - 1e-4f;
    }

    // Mitsuba's media on either side: a ray crossing the surface against the geometric normal
    // enters the interior, along it the exterior (null: vacuum). A shape with neither leaves the
    // medium a ray is in unchanged.
    const Medium* interior() const { return interior_.get(); }
    const Medium* exterior() const { return exterior_.get(); }
    bool is_medium_transition() const { return interior_ || exterior_; }
    // The medium a ray leaving si in world direction d travels through (a transition only).
    const Medium* target_medium(const SurfaceInteraction& si, const Vec3& d) const {
        return glm::dot(d, si.n) > 0.0f ? exterior() : interior();
    }

    const BSDF* bsdf() const { return bsdf_.get(); }
    // Its BSDF and emitter, as "bsdf" and "emitter" (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override;
    const Emitter* emitter() const { return emitter_.get(); }
    const Ref<Emitter>& emitter_ref() const { return emitter_; }
    // The sensor nested in the shape (an irradiancemeter measuring on it), or null.
    const Ref<Sensor>& attached_sensor() const { return sensor_; }
    // The emitters this shape brings to the scene: its own, and for an instance the moving
    // emitter of its group's shape (see Emitter::move_with_instance).
    virtual void collect_emitters(std::vector<Ref<Emitter>>& out) const {
        if (emitter_) out.push_back(emitter_);
    }
    bool flip_normals() const { return flip_normals_; }

    // A point sampled uniformly by area (`ps`, pdf per unit area) as seen from `ref`: its
    // direction, distance and pdf per unit solid angle (pdf_area * dist^2 / |cos| at the point).
    // What the default sample_direction does; shapes that fall back to area sampling call it with
    // their own sample_position, sparing a virtual call and a copy per light sample (and a moving
    // area light, with a sample it moved).
    // Inline: the sample's fields then stay in registers from sample_position to here; out of
    // line, the fields stored one by one and reloaded as a block stalled store forwarding, which
    // perf measured at 5% of a Cornell box render's time.
    static DirectionSample direction_from_position(const SurfaceInteraction& ref, const PositionSample& ps) {
        DirectionSample ds;
        // Field by field: a block copy of `ps` went through the stack with the same stall.
        ds.p = ps.p;
        ds.n = ps.n;
        ds.p_error = ps.p_error;
        ds.uv = ps.uv;
        ds.pdf = ps.pdf;
        ds.delta = ps.delta;
        Vec3 to = ds.p - ref.p;
        float dist2 = squared_length(to);
        ds.dist = std::sqrt(dist2);
        ds.d = to / ds.dist;
        float cos_light = std::abs(glm::dot(ds.n, ds.d));
        ds.pdf = (cos_light > 0.0f && dist2 > 0.0f) ? ds.pdf * dist2 / cos_light : 0.0f;
        return ds;
    }

protected:
    Transform to_world_;
    AnimatedTransform motion_;  // to_world_ at its keyframes (static unless constructed with may_move)
    bool flip_normals_ = false;

private:
    Ref<BSDF> bsdf_;
    Ref<Emitter> emitter_;
    Ref<Sensor> sensor_;
    Ref<Medium> interior_, exterior_;
};

}  // namespace candela
