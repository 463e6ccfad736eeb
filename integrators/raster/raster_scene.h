#pragma once
// The scene as the rasterizer sees it: every shape as triangles with per-vertex normals and
// uvs, each with its local-model material; the camera as view and projection matrices that
// reproduce the path tracer's pinhole exactly; and the lights of the local model.

#include "core/bsdf.h"
#include "core/emitter.h"
#include "core/local_model.h"
#include "core/scene.h"

#include <vector>

namespace candela {
struct RadiosityMesh;
}

namespace candela::raster {

struct RasterShape {
    const Shape* shape = nullptr;
    const BSDF* bsdf = nullptr;
    LocalShading material;
    Spectrum emission{0.0f};  // radiance of an area emitter on the front side
    bool closed = false;
    uint32_t first_triangle = 0, triangle_count = 0;
};

// A triangle's own frame: its unit face normal (the counter-clockwise side) and the tangents
// dp/du, dp/dv of its uvs (triangle_tangents).
struct TriangleFrame {
    Vec3 n, dpdu, dpdv;
};

struct RasterGeometry {
    std::vector<Vec3> positions, normals;
    std::vector<Vec2> uvs;
    std::vector<glm::uvec3> triangles;
    std::vector<TriangleFrame> triangle_frames;  // per triangle, computed once with the geometry
    std::vector<uint32_t> triangle_shape;        // index into shapes
    std::vector<uint32_t> vertex_shape;          // index into shapes: every vertex belongs to one shape
    std::vector<RasterShape> shapes;
    BoundingBox bbox;
    // Baked lighting (empty unless the geometry was built from a bake): the irradiance (W m^-2)
    // arriving at every vertex on its front side, and on its back side (zero for one-sided
    // materials).
    std::vector<Spectrum> baked_front, baked_back;
};

// Tessellates every shape (`detail` segments per turn for analytic shapes). With displacement,
// shapes whose material has a height field are subdivided `subdivisions` times (each triangle
// into four) and their vertices moved along the normal by height * scale, normals recomputed.
RasterGeometry build_geometry(const Scene& scene, int detail, bool displacement, int subdivisions);
// The scene as baked lighting draws it: every shape's radiosity patches (bake_radiosity,
// bake_path_irradiance in integrators/radiosity.h) with the irradiance at their vertices.
RasterGeometry build_baked_geometry(const std::vector<RadiosityMesh>& meshes);

// A view and projection. Camera space has +z forward, +y up, +x toward the image's left; clip
// space x, y in [-w, w] and z in [0, w] (0 at the near plane). Perspective or orthographic.
struct RasterCamera {
    Mat4 view{1.0f}, projection{1.0f}, view_projection{1.0f};
    Vec3 eye{0.0f};
    bool orthographic = false;
    float near_clip = 0.01f, far_clip = 1e4f;

    // The scene camera: matches Sensor::sample_ray pixel for pixel.
    static RasterCamera from_pinhole(const PinholeProjection& p);
    // A light's view: perspective with horizontal and vertical half-angle tangents, or an
    // orthographic box of half-extent `half_size` looking along +z of `to_world`.
    static RasterCamera perspective(const Transform& to_world, float tan_half_x, float tan_half_y, float near_clip, float far_clip);
    static RasterCamera orthographic_box(const Transform& to_world, float half_x, float half_y, float near_clip, float far_clip);

    Vec4 clip(const Vec3& world) const { return view_projection * Vec4(world, 1.0f); }
    // Distance along the view axis (camera-space z) of a world point.
    float view_depth(const Vec3& world) const { return (view * Vec4(world, 1.0f)).z; }
};

// The lights of the local model: delta lights exactly (through sample_direction), area lights
// as points (their local approximation), environments as ambient radiance.
struct LocalLight {
    enum class Kind { Point, Spot, Directional, AreaPoint };
    Kind kind = Kind::Point;
    const Emitter* emitter = nullptr;
    Vec3 position{0.0f};
    Vec3 direction{0.0f, 0.0f, 1.0f};  // spot axis, directional travel direction, area normal
    float cos_cutoff = -1.0f;          // spot
    float cutoff = Pi;                 // spot, radians
    LocalApproximation area;           // AreaPoint

    // Direction toward the light from p (unit), distance (inf for directional) and the
    // irradiance on a surface facing the light.
    void illuminate(const Vec3& p, Vec3& to_light, float& distance, Spectrum& irradiance) const;
};

struct LocalLights {
    std::vector<LocalLight> lights;
    Spectrum ambient{0.0f};  // ambient radiance (environments)
};
LocalLights collect_lights(const Scene& scene);

}  // namespace candela::raster
