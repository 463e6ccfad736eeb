#pragma once
// Shadows for the rasterizer, per light:
//  - ShadowMap: depth rendered from the light (one 2D map for spot and directional lights, a
//    cube of six for point and area lights), looked up with a slope-scaled bias (the allowance
//    grows with the angle between normal and light, in texel units) and percentage-closer
//    filtering over k x k texels.
//  - Shadow volumes (Crow 1977; z-fail counting of Carmack / Everitt & Kilgard 2002): occluders
//    are extruded away from the light to infinity (silhouette edges and caps for closed meshes,
//    one prism per triangle for open ones); a sample is in shadow when the volume faces behind
//    it, counted +1 back-facing and -1 front-facing, do not cancel.

#include "integrators/raster/raster_scene.h"
#include "integrators/raster/rasterizer.h"

#include <vector>

namespace candela::raster {

class ShadowMap {
public:
    // Places the faces around the light: one for a spot or directional light, a cube of six for
    // point and area lights. Storage of an earlier frame is kept for reuse.
    void place(const LocalLight& light, const RasterGeometry& geometry);
    size_t face_count() const { return faces_.size(); }
    // The face that point p looks up.
    int face_of(const Vec3& p) const;
    // Texels per side that face `face` needs so that one of its texels spans no more than
    // `footprint` (world units) at p.
    float resolution_needed(int face, const Vec3& p, float footprint) const;
    // Renders the depth of every triangle except those of the light's own shape into each face,
    // at `resolution[face]` texels per side; a face of resolution 0 (no sample looks it up) is
    // left out. Reuses the storage of earlier frames.
    void render(const RasterGeometry& geometry, const std::vector<int>& resolution);
    // Fraction of the light that reaches p (normal n) unoccluded, PCF over pcf x pcf texels.
    float visibility(const Vec3& p, const Vec3& n, int pcf) const;

private:
    struct Face {
        RasterCamera camera;
        float extent = 0.0f;  // world size of the face's side per unit view depth (or constant, ortho)
        int resolution = 0;   // texels per side; 0 when left out
        float texel_scale = 0.0f;  // extent / resolution: a texel's world size per unit depth (or constant)
        std::vector<float> depth;  // view depth (camera z) per texel; +inf where nothing
        std::vector<std::array<Vec4, 3>> clip;  // scratch: the triangles in the face's clip space
        Rasterizer rasterizer;                  // scratch, one sample per texel
        // World size of a texel at view depth d.
        float texel(float d) const { return camera.orthographic ? texel_scale : texel_scale * d; }
    };
    float face_visibility(const Face& f, const Vec3& p, const Vec3& n, float cos_theta, int pcf) const;
    void render_depth(Face& f, const RasterGeometry& geometry, int skip_shape);
    LocalLight light_;
    std::vector<Face> faces_;
};

// Per camera sample, whether each sample is lit by the light (stencil count zero). `depths` are
// the camera samples' view depths (+inf for background), in Rasterizer sample order.
void shadow_volume_mask(const LocalLight& light, const RasterGeometry& geometry, const RasterCamera& camera, const Rasterizer& layout,
                        const std::vector<float>& view_depths, std::vector<uint8_t>& lit);

// The shape whose emitter is this light (its own geometry does not shadow it), or -1.
int light_shape(const LocalLight& light, const RasterGeometry& geometry);

}  // namespace candela::raster
