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
    // Renders the depth of every triangle except those of the light's own shape.
    ShadowMap(const LocalLight& light, const RasterGeometry& geometry, int resolution);
    // Fraction of the light that reaches p (normal n) unoccluded, PCF over pcf x pcf texels.
    float visibility(const Vec3& p, const Vec3& n, int pcf) const;

private:
    struct Face {
        RasterCamera camera;
        float texel_scale = 0.0f;  // world size of a texel per unit view depth (or constant, ortho)
        std::vector<float> depth;  // view depth (camera z) per texel; +inf where nothing
    };
    float face_visibility(const Face& f, const Vec3& p, const Vec3& n, float cos_theta, int pcf) const;
    // The face's depth map of every triangle except those of shape `skip_shape`.
    void render_depth(Face& f, const RasterGeometry& geometry, int skip_shape) const;
    LocalLight light_;
    int resolution_;
    std::vector<Face> faces_;
};

// Per camera sample, whether each sample is lit by the light (stencil count zero). `depths` are
// the camera samples' view depths (+inf for background), in Rasterizer sample order.
void shadow_volume_mask(const LocalLight& light, const RasterGeometry& geometry, const RasterCamera& camera, const Rasterizer& layout,
                        const std::vector<float>& view_depths, std::vector<uint8_t>& lit);

// The shape whose emitter is this light (its own geometry does not shadow it), or -1.
int light_shape(const LocalLight& light, const RasterGeometry& geometry);

}  // namespace candela::raster
