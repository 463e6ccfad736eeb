#pragma once
// The machinery behind radiosity.h, shared by the `radiosity` integrator and bake_radiosity():
// the patches (radiosity_patches.cpp), the progressive-refinement solve (radiosity_solver.cpp)
// and the solution file (radiosity_file.cpp).
//
// Patches: every scene shape's tessellation (Shape::tessellate) cut into smaller triangles, in
// one Embree BVH of their own. An element is one lit side of one patch: the front side always,
// the back side too when the BSDF is two-sided. Radiosity renders and solves on the same
// triangles, so its rays never mix exact and tessellated surfaces.

#include "core/accel.h"
#include "integrators/radiosity.h"

#include <vector>

namespace candela {

class Scene;

struct RadiosityElement {
    uint32_t mesh = 0, triangle = 0;  // which PatchMesh and which of its triangles
    bool back = false;                // the back side of the patch
    float area = 0.0f;
    Vec3 centroid{0.0f}, normal{0.0f};  // normal: the side's own (away from the surface)
    float p_error = 0.0f;               // bound on the centroid's coordinate errors
    Spectrum reflectance{0.0f};         // the BSDF's albedo at the centroid, clamped to [0, 1]
    Spectrum emitted{0.0f};             // pi x emitted radiance (W m^-2), front side only
};

// Where a ray met the patches: the element on the side it arrived from (-1 for the unlit back
// of a one-sided surface), the vertices and barycentrics for interpolation.
struct PatchHit {
    int element = -1;
    glm::uvec3 vertices{0u};  // global vertex indices
    Vec3 bary{0.0f};
};

class RadiosityPatches {
public:
    RadiosityPatches(const Scene& scene, const RadiositySettings& settings);
    ~RadiosityPatches();

    // Closest patch along the ray. `si` is filled as Scene::intersect would (si.shape is the
    // scene's shape, so its BSDF and emitter answer; si.prim_index is the patch).
    bool intersect(const Ray& ray, SurfaceInteraction& si, PatchHit& hit) const;
    bool occluded(const Ray& ray) const { return accel_.occluded(ray); }
    // True when nothing but `light`'s own patches lies on the ray: a shadow ray toward a point
    // sampled on the exact surface of a curved light would otherwise hit its tessellation.
    bool occluded_except(const Ray& ray, const Shape* light) const;

    const std::vector<RadiosityElement>& elements() const { return elements_; }
    // The patch triangle of an element, in world space.
    void triangle(const RadiosityElement& e, Vec3& p0, Vec3& p1, Vec3& p2) const;
    size_t patch_count() const { return patch_count_; }
    size_t vertex_count() const { return vertex_count_; }

    // Per-element values averaged at the vertices (area-weighted over the elements of the same
    // side around each vertex; coincident vertices with equal normals are one vertex), for the
    // front (back = false) or back sides. Index: global vertex.
    std::vector<Spectrum> vertex_average(const std::vector<Spectrum>& element_values, bool back) const;
    // The interpolated value at a hit from per-vertex values.
    static Spectrum interpolate(const std::vector<Spectrum>& vertex_values, const PatchHit& hit) {
        return hit.bary.x * vertex_values[hit.vertices.x] + hit.bary.y * vertex_values[hit.vertices.y] +
               hit.bary.z * vertex_values[hit.vertices.z];
    }

    // Names of the BSDFs that are not purely diffuse (treated by their albedo).
    const std::vector<std::string>& approximated_bsdfs() const { return approximated_; }
    // A hash of the patches' geometry, reflectances and emission (FNV-1a over their bytes).
    uint64_t hash() const;
    // Each scene shape's patches with per-vertex values (see RadiosityMesh).
    std::vector<RadiosityMesh> meshes(const std::vector<Spectrum>& vertex_irradiance_front,
                                      const std::vector<Spectrum>& vertex_irradiance_back,
                                      const std::vector<Spectrum>& vertex_radiosity_front) const;

private:
    class PatchMesh;
    void build_elements(const Scene& scene);
    void build_welds();

    std::vector<Ref<Shape>> meshes_;  // PatchMesh, one per scene shape
    std::vector<uint32_t> vertex_offset_, triangle_offset_;
    std::vector<int32_t> front_element_, back_element_;  // by global triangle
    std::vector<uint32_t> weld_;                         // global vertex -> its welded representative
    std::vector<RadiosityElement> elements_;
    std::vector<std::string> approximated_;
    size_t patch_count_ = 0, vertex_count_ = 0;
    Accel accel_;
};

// Irradiance (W m^-2) at each element's centre from the emitters that are not area lights
// (point, spot, directional exactly; environments by 64 samples): the light these add before
// the first shot.
std::vector<Spectrum> direct_irradiance(const RadiosityPatches& patches, const Scene& scene, const RadiositySettings& settings,
                                        const RenderOptions& options);

// Progressive refinement (Cohen et al. 1988): repeatedly the element with the most unshot power
// shoots it to every other element, until the unshot power falls below `tolerance` times the
// emitted power, max_iterations shots were made, or options.interrupt is set. Returns each
// element's irradiance (W m^-2); its radiosity is emitted + reflectance x irradiance.
std::vector<Spectrum> shoot_radiosity(const RadiosityPatches& patches, const RadiositySettings& settings,
                                      const std::vector<Spectrum>& initial, const RenderOptions& options, RadiosityStats& stats);

// The whole solve: initial light, then the solution file when `solution_file` names one that
// matches (same patches, reflectances, emission, light and settings), else shooting, saving the
// result there when it was not interrupted. A stale or damaged file is refused with a warning
// at `where`, as are non-diffuse BSDFs.
std::vector<Spectrum> solve_radiosity(const RadiosityPatches& patches, const Scene& scene, const RadiositySettings& settings,
                                      const RenderOptions& options, const std::string& solution_file, const SourceLocation& where,
                                      RadiosityStats& stats);

// The solution file (little-endian): "CANDELA-RADIOSITY\0" (18 bytes), uint32 version 1,
// uint64 key (hash of the patches and the settings), uint64 element count, uint32 shots,
// float32 unshot fraction, then per element float32 R, G, B irradiance in W m^-2.
// read_radiosity_file returns false, with the reason, for a missing, damaged or stale file.
bool read_radiosity_file(const std::string& path, uint64_t key, size_t elements, std::vector<Spectrum>& irradiance, RadiosityStats& stats,
                         std::string& reason);
void write_radiosity_file(const std::string& path, uint64_t key, const std::vector<Spectrum>& irradiance, const RadiosityStats& stats);

}  // namespace candela
