#pragma once
// Radiosity: diffuse light transport solved on patches (Goral, Torrance, Greenberg & Battaile
// 1984) by progressive refinement (Cohen, Chen, Wallace & Greenberg 1988). The `radiosity`
// integrator (radiosity.cpp, which lists the parameters) displays the solution; this header is
// what other code uses: the rasterizer's baked lighting reads the irradiance at the vertices of
// every shape's patches through bake_radiosity().

#include "core/integrator.h"
#include "core/shape.h"

#include <string>
#include <vector>

namespace candela {

class Scene;

struct RadiositySettings {
    // Patches: every tessellated triangle is split into n x n equal triangles, with n chosen so
    // that no patch is larger than max_patch_area (m^2), or n = subdivisions when that is set
    // (> 0). max_patch_area 0 and subdivisions 0: default_area_fraction (1/2000) of the scene's
    // surface area.
    float max_patch_area = 0.0f;
    int subdivisions = 0;
    float default_area_fraction = 1.0f / 2000.0f;
    float tolerance = 1e-3f;      // stop when the unshot power is this fraction of the emitted
    int max_iterations = 100000;  // most shots
    int visibility_rays = 16;     // rays per form factor
    uint64_t seed = 0;            // of the visibility samples
};

struct RadiosityStats {
    size_t patches = 0, elements = 0;  // triangles, and their lit sides
    int shots = 0;
    double unshot_fraction = 0.0;  // unshot / emitted power when the solve stopped
    bool converged = false;        // unshot_fraction <= tolerance
    bool interrupted = false;
    bool loaded = false;  // read from a solution file instead of solved
    uint64_t rays = 0;
    double seconds = 0.0;
    std::vector<std::string> approximated_bsdfs;  // non-diffuse BSDFs treated by their albedo
};

// One scene shape's patches with the solution at their vertices (area-weighted averages of the
// patches around each vertex). Back-side values exist only for two-sided BSDFs.
struct RadiosityMesh {
    const Shape* shape = nullptr;
    TriangleSoup patches;                   // world space; the front side is the shape's
    std::vector<Spectrum> irradiance;       // W m^-2 arriving at each vertex, front side
    std::vector<Spectrum> irradiance_back;  // the same on the back side (or empty)
    std::vector<Spectrum> radiosity;        // W m^-2 leaving the front side (pi x radiance)
};

// Solves the scene's radiosity with `settings` (threads, interruption and progress from
// `options`) and returns one RadiosityMesh per scene shape, in the order of scene.shapes().
std::vector<RadiosityMesh> bake_radiosity(const Scene& scene, const RadiositySettings& settings, const RenderOptions& options,
                                          RadiosityStats* stats = nullptr);

// The same patches and vertex values, with the irradiance at each element's centre estimated by
// the path tracer instead (`samples` paths each, every bounce: estimate_irradiance_at), seeded by
// settings.seed. Each centre moves off its patch along the side's normal by the patch's
// tessellation_gap (core/mesh.h), so that the exact surface of a curved shape cannot hide it.
std::vector<RadiosityMesh> bake_path_irradiance(const Scene& scene, const RadiositySettings& settings, int samples,
                                                const RenderOptions& options);

// The statistics of the last solve of a `radiosity` integrator (null for other integrators).
const RadiosityStats* radiosity_stats(const Integrator& integrator);

}  // namespace candela
