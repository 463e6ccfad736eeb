#pragma once
// One rasterized frame, pass by pass. RasterIntegrator::render runs them in this order:
//   geometry   clip-space triangles, then at every camera sample the nearest triangle, its view
//              depth and perspective-correct barycentrics (a G-buffer)     pass_geometry.cpp
//   surfaces   position, normals, uv and texture lookup at every sample, and the radiance that
//              needs no light: emission, mirror and refraction of the environment (glossy
//              ones prefiltered), the environment itself where no surface is  pass_surfaces.cpp
//   ambient    the diffuse light that is not from the local lights: the environment's SH
//              irradiance (or its average) and the `ambient` setting, times ambient occlusion;
//              or the baked irradiance                                    pass_ambient.cpp
//   lights     per light, its shadow (map or volume) and its direct lighting added to every
//              sample (Gouraud: lit at the vertices, interpolated)        pass_lights.cpp
//   fog        the medium around the camera as exponential fog              pass_fog.cpp
//   resolve    the supersamples filtered into pixels                       pass_resolve.cpp
//   overlays   wireframe and light gizmos drawn over the pixels            pass_overlays.cpp
// The passes share FrameBuffers: each reads what earlier passes wrote and fills its own part.

#include "core/image.h"
#include "integrators/raster/image_lighting.h"
#include "integrators/raster/raster.h"
#include "integrators/raster/raster_scene.h"
#include "integrators/raster/rasterizer.h"
#include "integrators/raster/shadows.h"

#include <array>
#include <vector>

namespace candela::raster {

constexpr uint32_t NoTriangle = 0xffffffffu;

// What stays the same during a frame: scene, settings, geometry, camera, lights, sample layout.
struct FrameSetup {
    FrameSetup(const Scene& scene, const RasterSettings& settings, const RasterGeometry& geometry, const PinholeProjection& pinhole,
               const ImageBasedLighting* image_lighting);

    const Scene& scene;
    const RasterSettings& settings;
    const RasterGeometry& geometry;
    RasterCamera camera;
    LocalLights lights;
    Spectrum ambient;  // of the environments plus the `ambient` setting
    // The environment as image-based light, null without an environment or when the settings
    // ask for its average (`ambient` then holds it).
    const ImageBasedLighting* image_lighting;
    Vec2i full, offset;         // the film's size and the crop window's corner in it
    int width, height;          // the crop window: the image rendered
    std::vector<Vec2> pattern;  // sample positions within a pixel

    int samples_per_pixel() const { return int(pattern.size()); }
    size_t sample_count() const { return size_t(width) * size_t(height) * pattern.size(); }
    // Sample s of pixel (x, y) in the per-sample buffers (the Rasterizer's order).
    size_t sample_index(int x, int y, int s) const { return (size_t(y) * size_t(width) + size_t(x)) * pattern.size() + size_t(s); }
    // Where sample s of pixel (x, y) lies in the crop window, in pixels.
    Vec2 sample_position(int x, int y, int s) const { return Vec2(float(x) + pattern[size_t(s)].x, float(y) + pattern[size_t(s)].y); }
    // The spacing of the camera's samples (world units) on a surface facing the camera at this
    // view depth.
    float sample_spacing(float view_depth) const;
    // Points `r` at the camera's samples (triangles not yet set up), keeping its storage.
    void aim_camera_rasterizer(Rasterizer& r) const {
        r.set_samples(pattern);
        r.set_target(width, height, full, offset);
    }
};

// The visible surface at one camera sample, as the shading passes need it.
struct SurfaceSample {
    Vec3 p{0.0f};      // position
    Vec3 n{0.0f};      // shading normal (interpolated or face, bump-mapped; toward the viewer when two-sided)
    Vec3 n_geo{0.0f};  // face normal (toward the viewer when two-sided)
    Vec3 v{0.0f};      // unit direction toward the eye
    Vec2 uv{0.0f};
    Spectrum kd{0.0f};      // diffuse albedo, filtered over the sample's footprint
    bool front = false;     // the face's front (counter-clockwise) side is seen
    bool lit_side = false;  // seen from a side the material reflects on
};

// Screen-space derivatives of the perspective-correct barycentrics of a triangle at a pixel
// position, from its homogeneous 2D setup (Olano & Greer 1997): (b / w) is linear in (x, y).
struct HomogeneousSetup {
    Mat3 inverse{1.0f};
    bool valid = false;
    Vec3 at(float x, float y) const {
        Vec3 u = inverse * Vec3(x, y, 1.0f);
        float s = u.x + u.y + u.z;
        return s != 0.0f ? u / s : Vec3(1.0f / 3.0f);
    }
};

// Kept by the integrator from frame to frame: the passes resize them, so a frame like the last
// one reuses their storage and allocates nothing per sample or per triangle.
struct FrameBuffers {
    // Per triangle (geometry): clip-space vertices; culled back faces lie behind the eye.
    std::vector<std::array<Vec4, 3>> clip;
    std::vector<HomogeneousSetup> setups;  // per triangle (surfaces): for texture footprints
    Rasterizer camera_rasterizer;          // geometry: the camera's samples; shadow volumes: their layout
    // Per camera sample (geometry): the nearest surface.
    std::vector<float> depth;        // its view depth (w); +inf where there is none
    std::vector<uint32_t> triangle;  // its triangle, NoTriangle where there is none
    std::vector<Vec3> bary;          // its barycentrics within that triangle
    // Per camera sample (surfaces, then lights).
    std::vector<SurfaceSample> surface;
    std::vector<Spectrum> color;  // the radiance so far
    // Per light (lights): its shadow map, when shadows are mapped.
    std::vector<ShadowMap> shadow_maps;
    // Scratch of the lights pass: per chunk of samples, what each shadow-map face needs
    // (resolution and window); the resolution chosen per face; per sample, the view depth and
    // the shadow-volume mask; per vertex, Gouraud's lighting.
    std::vector<ShadowMapNeeds> shadow_map_needs;
    std::vector<int> shadow_map_resolution;
    std::vector<float> view_depth;
    std::vector<uint8_t> lit;
    std::vector<Spectrum> vertex_light;
    // Per pixel (resolve, then overlays).
    Image image;
    std::vector<float> coverage;  // the filtered fraction of samples that found a surface
};

void geometry_pass(const FrameSetup& frame, FrameBuffers& buffers);
void surface_pass(const FrameSetup& frame, FrameBuffers& buffers);
void ambient_pass(const FrameSetup& frame, FrameBuffers& buffers);
void lights_pass(const FrameSetup& frame, FrameBuffers& buffers);
void fog_pass(const FrameSetup& frame, FrameBuffers& buffers);
void resolve_pass(const FrameSetup& frame, FrameBuffers& buffers);
void overlay_pass(const FrameSetup& frame, FrameBuffers& buffers);

// View depth of the surface at sample i (from its reconstructed position), +inf where none.
float surface_view_depth(const FrameSetup& frame, const FrameBuffers& buffers, size_t i);

}  // namespace candela::raster
