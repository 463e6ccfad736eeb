// The lights pass: one light after another, its visibility at every camera sample (a shadow map,
// a shadow-volume mask, or none) times its direct lighting, added to the sample's radiance.
// Flat shading lights each triangle at its centroid with the face normal, Gouraud lights each
// vertex once and interpolates, Phong lights every sample with its own normal.

#include "integrators/raster/frame.h"
#include "integrators/raster/shadows.h"

#include <tbb/parallel_for.h>

#include <memory>

namespace candela::raster {

namespace {

// The lighting of one light at one point (no visibility): OpenGL's diffuse and specular terms
// with physically scaled coefficients (see raster.cpp).
Spectrum direct_light(const LocalLight& light, const LocalShading& m, const Spectrum& kd, const Vec3& p, const Vec3& n, const Vec3& v,
                      RasterSettings::Reflection reflection) {
    Vec3 l;
    float dist;
    Spectrum E;
    light.illuminate(p, l, dist, E);
    float ndl = glm::dot(n, l);
    if (ndl <= 0.0f || is_black(E)) return Spectrum(0.0f);
    Spectrum out = kd * (InvPi * ndl);
    if (m.shininess > 0.0f && !is_black(m.specular)) {
        float lobe, norm;
        if (reflection == RasterSettings::Reflection::Blinn) {
            Vec3 h = glm::normalize(l + v);
            lobe = std::pow(std::max(glm::dot(n, h), 0.0f), m.shininess);
            norm = (m.shininess + 8.0f) / (8.0f * Pi);
        } else {
            Vec3 r = 2.0f * ndl * n - l;
            lobe = std::pow(std::max(glm::dot(r, v), 0.0f), m.shininess);
            norm = (m.shininess + 2.0f) * InvTwoPi;
        }
        out += m.specular * (norm * lobe);
    }
    return out * E;
}

// Gouraud: the light at every vertex, with the material of the one shape the vertex belongs
// to and its texture at the vertex uv. One evaluation per vertex, each written by one task.
void light_vertices(const FrameSetup& f, const LocalLight& light, std::vector<Spectrum>& vertex_light) {
    const RasterGeometry& g = f.geometry;
    vertex_light.resize(g.positions.size());
    tbb::parallel_for(size_t(0), g.positions.size(), [&](size_t i) {
        const LocalShading& m = g.shapes[g.vertex_shape[i]].material;
        Vec3 n = g.normals[i], v = glm::normalize(f.camera.eye - g.positions[i]);
        if (m.two_sided && glm::dot(n, v) < 0.0f) n = -n;
        Spectrum kd = m.diffuse ? m.diffuse->eval(g.uvs[i]) : Spectrum(0.0f);
        vertex_light[i] = direct_light(light, m, kd, g.positions[i], n, v, f.settings.reflection);
    });
}

// The light's direct lighting at camera sample i on triangle t, by the shading mode.
Spectrum sample_light(const FrameSetup& f, const FrameBuffers& b, size_t i, const LocalLight& light, const std::vector<Spectrum>& vertex_light) {
    const RasterGeometry& g = f.geometry;
    const uint32_t t = b.triangle[i];
    const SurfaceSample& ss = b.surface[i];
    const LocalShading& m = g.shapes[g.triangle_shape[t]].material;
    const glm::uvec3& v = g.triangles[t];
    switch (f.settings.shading) {
    case RasterSettings::Shading::Gouraud: {
        const Vec3& w = b.bary[i];
        return w.x * vertex_light[v.x] + w.y * vertex_light[v.y] + w.z * vertex_light[v.z];
    }
    case RasterSettings::Shading::Flat: {
        Vec3 c = (g.positions[v.x] + g.positions[v.y] + g.positions[v.z]) / 3.0f;
        Vec2 uvc = (g.uvs[v.x] + g.uvs[v.y] + g.uvs[v.z]) / 3.0f;
        Spectrum kd = m.diffuse ? m.diffuse->eval(uvc) : Spectrum(0.0f);
        return direct_light(light, m, kd, c, ss.n_geo, glm::normalize(f.camera.eye - c), f.settings.reflection);
    }
    case RasterSettings::Shading::Phong: break;
    }
    return direct_light(light, m, ss.kd, ss.p, ss.n, ss.v, f.settings.reflection);
}

// One light: its shadow, then visibility times lighting added to every lit sample.
void add_light(const FrameSetup& f, FrameBuffers& b, const LocalLight& light, const std::vector<float>& view_depth, std::vector<uint8_t>& lit,
               std::vector<Spectrum>& vertex_light) {
    const RasterSettings& s = f.settings;
    std::unique_ptr<ShadowMap> map;
    if (s.shadows == RasterSettings::Shadows::Map) map = std::make_unique<ShadowMap>(light, f.geometry, s.shadow_map_resolution);
    if (s.shadows == RasterSettings::Shadows::Volume) shadow_volume_mask(light, f.geometry, f.camera, f.camera_rasterizer(), view_depth, lit);
    if (s.shading == RasterSettings::Shading::Gouraud) light_vertices(f, light, vertex_light);
    tbb::parallel_for(size_t(0), f.sample_count(), [&](size_t i) {
        const SurfaceSample& ss = b.surface[i];
        if (b.triangle[i] == NoTriangle || !ss.lit_side) return;
        float visibility = 1.0f;
        if (map) visibility = map->visibility(ss.p, ss.n_geo, s.pcf);
        if (s.shadows == RasterSettings::Shadows::Volume) visibility = lit[i] ? 1.0f : 0.0f;
        if (visibility == 0.0f) return;
        b.color[i] += visibility * sample_light(f, b, i, light, vertex_light);
    });
}

}  // namespace

void lights_pass(const FrameSetup& f, FrameBuffers& b) {
    std::vector<float> view_depth;  // of every sample, for shadow volumes
    if (f.settings.shadows == RasterSettings::Shadows::Volume) {
        view_depth.resize(f.sample_count());
        for (size_t i = 0; i < view_depth.size(); ++i) view_depth[i] = surface_view_depth(f, b, i);
    }
    std::vector<uint8_t> lit;
    std::vector<Spectrum> vertex_light;
    for (const LocalLight& light : f.lights.lights) add_light(f, b, light, view_depth, lit, vertex_light);
}

}  // namespace candela::raster
