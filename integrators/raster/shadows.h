#pragma once
// Shadows for the rasterizer, per light:
//  - ShadowMap: depth rendered from the light (one 2D map for spot and directional lights, a
//    cube of six for point and area lights), looked up with a slope-scaled bias (the allowance
//    grows with the angle between normal and light, in texel units) and percentage-closer
//    filtering over k x k texels. Each face is rendered only over the window of it that the
//    camera's samples look up (fitting the light's view to the visible receivers, as sample
//    distribution shadow maps do, Lauritzen et al. 2011): a texel keeps the size the view asks
//    for, and the texels nothing looks up are neither cleared nor rasterized.
//  - Shadow volumes (Crow 1977; z-fail counting of Carmack / Everitt & Kilgard 2002): occluders
//    are extruded away from the light to infinity (silhouette edges and caps for closed meshes,
//    one prism per triangle for open ones); a sample is in shadow when the volume faces behind
//    it, counted +1 back-facing and -1 front-facing, do not cancel.

#include "integrators/raster/raster_scene.h"
#include "integrators/raster/rasterizer.h"

#include <array>
#include <vector>

namespace candela::raster {

// What the camera's samples ask of one face of a shadow map: the finest resolution any of them
// needs (texels per side of the whole face; 0 when none looks the face up) and the rectangle of
// the face they look up, in its normalised coordinates [-1, 1]^2 (x / w, y / w of its clip space).
struct FaceNeeds {
    float resolution = 0.0f;
    Vec2 lo{1.0f}, hi{-1.0f};  // empty until a sample is added
    // Both: what two sets of samples need together (exact in any order).
    void merge(const FaceNeeds& other) {
        resolution = std::max(resolution, other.resolution);
        lo = glm::min(lo, other.lo);
        hi = glm::max(hi, other.hi);
    }
    // Adds a sample that needs `sample_resolution` at normalised position `at`.
    void add(float sample_resolution, const Vec2& at) { merge(FaceNeeds{sample_resolution, at, at}); }
};

// Per face of a shadow map (a cube has six).
using ShadowMapNeeds = std::array<FaceNeeds, 6>;

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
    // Where p lies on face `face`, in its normalised coordinates (within [-1, 1]^2 when the face
    // sees p; clamped there otherwise).
    Vec2 face_position(int face, const Vec3& p) const;
    // Renders the depth of every triangle except those of the light's own shape into each face,
    // at `resolution[face]` texels per side, over the window of it that needs[face] asks for
    // (with a margin for a pcf x pcf filter and the normal offset); a face of resolution 0 (no
    // sample looks it up) is left out. Reuses the storage of earlier frames.
    void render(const RasterGeometry& geometry, const std::vector<int>& resolution, const FaceNeeds* needs, int pcf);
    // Fraction of the light that reaches p (normal n) unoccluded, PCF over pcf x pcf texels.
    float visibility(const Vec3& p, const Vec3& n, int pcf) const;

private:
    struct Face {
        RasterCamera camera;
        float extent = 0.0f;                    // world size of the face's side per unit view depth (or constant, ortho)
        int resolution = 0;                     // texels per side of the whole face; 0 when left out
        float texel_scale = 0.0f;               // extent / resolution: a texel's world size per unit depth (or constant)
        Vec2i window_min{0}, window_size{0};    // the texels rendered: [min, min + size) of the face's
        std::vector<float> depth;               // view depth (camera z) per texel of the window; +inf where nothing
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
