// The geometry pass: every triangle into clip space (back faces culled on request), then the
// nearest one at every camera sample by a z-buffer of view depth (w, exact for a perspective
// camera), with its barycentrics: the G-buffer the later passes shade from.

#include "core/parallel.h"
#include "integrators/raster/frame.h"

namespace candela::raster {

namespace {

// Clip-space vertices of every triangle; a culled triangle gets w < 0 everywhere, which the
// rasterizer's clipping removes.
void clip_triangles(const FrameSetup& f, std::vector<std::array<Vec4, 3>>& clip) {
    const RasterGeometry& g = f.geometry;
    clip.resize(g.triangles.size());
    parallel_for(g.triangles.size(), [&](size_t i) {
        const glm::uvec3& t = g.triangles[i];
        clip[i] = {f.camera.clip(g.positions[t.x]), f.camera.clip(g.positions[t.y]), f.camera.clip(g.positions[t.z])};
        if (f.settings.backface_culling && !g.shapes[g.triangle_shape[i]].material.two_sided) {
            Vec3 n = glm::cross(g.positions[t.y] - g.positions[t.x], g.positions[t.z] - g.positions[t.x]);
            if (glm::dot(n, f.camera.eye - g.positions[t.x]) <= 0.0f) clip[i] = {Vec4(0, 0, 0, -1), Vec4(0, 0, 0, -1), Vec4(0, 0, 0, -1)};
        }
    });
}

}  // namespace

void geometry_pass(const FrameSetup& f, FrameBuffers& b) {
    clip_triangles(f, b.clip);
    Rasterizer& rasterizer = b.camera_rasterizer;
    f.aim_camera_rasterizer(rasterizer);
    rasterizer.setup(b.clip, !f.settings.affine);
    const size_t count = f.sample_count();
    b.depth.assign(count, Infinity);
    b.triangle.assign(count, NoTriangle);
    b.bary.assign(count, Vec3(0.0f));
    rasterizer.run([&](const Fragment& frag) {
        size_t i = f.sample_index(frag.x, frag.y, frag.sample);
        if (frag.w < b.depth[i]) {
            b.depth[i] = float(frag.w);
            b.triangle[i] = frag.triangle->id;
            b.bary[i] = frag.bary;
        }
    });
}

}  // namespace candela::raster
