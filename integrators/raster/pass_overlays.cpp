// The overlays pass: drawn over the resolved pixels with the classic 2D algorithms
// (geometry2d/raster2d.h): the visible triangle edges (--wireframe, Bresenham lines depth-tested
// against the surface at each pixel) and the lights (--light-gizmos: a circle at every point,
// spot and area light, a line along a spot's axis or an area light's normal, an arrow for a
// directional light).

#include "geometry2d/raster2d.h"
#include "integrators/raster/frame.h"

namespace candela::raster {

namespace {

// Pixel position (in the crop window) and view depth of a world point; false behind the eye.
bool project(const FrameSetup& f, const Vec3& p, Vec2& px, float& view_z) {
    Vec4 c = f.camera.clip(p);
    view_z = f.camera.view_depth(p);
    if (!(c.w > f.camera.near_clip * 0.5f)) return false;
    px = Vec2((c.x / c.w + 1.0f) * 0.5f * float(f.full.x) - float(f.offset.x),
              (c.y / c.w + 1.0f) * 0.5f * float(f.full.y) - float(f.offset.y));
    return true;
}

void put(Image& img, int x, int y, const Spectrum& c) {
    if (x >= 0 && y >= 0 && x < img.width() && y < img.height()) img.set_rgb(x, y, c);
}

// Visible edges: depth-tested against the nearest surface at the pixel (its first sample), with
// a tolerance relative to the depth; 1 / z is linear along the projected edge.
void draw_wireframe(const FrameSetup& f, FrameBuffers& b) {
    const int W = f.width, H = f.height;
    std::vector<float> pixel_depth(size_t(W) * H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) pixel_depth[size_t(y) * W + x] = surface_view_depth(f, b, f.sample_index(x, y, 0));
    const Spectrum ink(1.0f, 0.85f, 0.2f);
    for (const glm::uvec3& t : f.geometry.triangles)
        for (int k = 0; k < 3; ++k) {
            Vec2 a, e;
            float za, ze;
            if (!project(f, f.geometry.positions[t[k]], a, za) || !project(f, f.geometry.positions[t[(k + 1) % 3]], e, ze)) continue;
            int x0 = int(std::floor(a.x)), y0 = int(std::floor(a.y)), x1 = int(std::floor(e.x)), y1 = int(std::floor(e.y));
            int steps = std::max({std::abs(x1 - x0), std::abs(y1 - y0), 1}), step = 0;
            raster2d::line_bresenham(x0, y0, x1, y1, [&](int x, int y) {
                float s = float(step++) / float(steps);
                float z = 1.0f / ((1.0f - s) / za + s / ze);
                if (x < 0 || y < 0 || x >= W || y >= H) return;
                if (z <= pixel_depth[size_t(y) * W + x] * 1.002f + 1e-4f) b.image.set_rgb(x, y, ink);
            });
        }
}

void draw_light_gizmos(const FrameSetup& f, FrameBuffers& b) {
    const Spectrum gizmo(1.0f, 1.0f, 0.0f);
    auto dot = [&](int x, int y) { put(b.image, x, y, gizmo); };
    const float radius = std::max(f.geometry.bbox.bounding_radius(), 1e-3f);
    for (const LocalLight& light : f.lights.lights) {
        Vec2 a, e;
        float za, ze;
        if (light.kind == LocalLight::Kind::Directional) {
            Vec3 start = f.geometry.bbox.center() - light.direction * radius, end = start + light.direction * (0.4f * radius);
            if (project(f, start, a, za) && project(f, end, e, ze)) {
                raster2d::line_bresenham(int(a.x), int(a.y), int(e.x), int(e.y), dot);
                raster2d::circle_midpoint(int(a.x), int(a.y), 3, dot);
            }
            continue;
        }
        if (!project(f, light.position, a, za)) continue;
        raster2d::circle_midpoint(int(a.x), int(a.y), 6, dot);
        bool axis = light.kind == LocalLight::Kind::Spot || light.kind == LocalLight::Kind::AreaPoint;
        if (axis && project(f, light.position + light.direction * (0.25f * radius), e, ze))
            raster2d::line_bresenham(int(a.x), int(a.y), int(e.x), int(e.y), dot);
    }
}

}  // namespace

void overlay_pass(const FrameSetup& f, FrameBuffers& b) {
    if (f.settings.wireframe) draw_wireframe(f, b);
    if (f.settings.light_gizmos) draw_light_gizmos(f, b);
}

}  // namespace candela::raster
