// The lights pass: one light after another, its visibility at every camera sample (a shadow map,
// a shadow-volume mask, or none) times its direct lighting, added to the sample's radiance.
// Flat shading lights each triangle at its centroid with the face normal, Gouraud lights each
// vertex once and interpolates, Phong lights every sample with its own normal. Under baked
// lighting the lights add their highlights only (the bake holds their diffuse light).

#include "core/parallel.h"
#include "integrators/raster/frame.h"
#include "integrators/raster/shadows.h"

#include <array>

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

// With baked lighting the bake holds every light's diffuse light: the lights add highlights only.
bool baked_diffuse(const FrameSetup& f) {
    return f.settings.lighting == RasterSettings::Lighting::Baked && !f.geometry.baked_front.empty();
}

// Whether any surface has a highlight.
bool has_highlights(const RasterGeometry& g) {
    for (const RasterShape& rs : g.shapes)
        if (rs.material.shininess > 0.0f && !is_black(rs.material.specular)) return true;
    return false;
}

// Gouraud: the light at every vertex, with the material of the one shape the vertex belongs
// to and its texture at the vertex (through the texture's mapping). One evaluation per vertex, each written by one task.
void light_vertices(const FrameSetup& f, const LocalLight& light, std::vector<Spectrum>& vertex_light) {
    const RasterGeometry& g = f.geometry;
    vertex_light.resize(g.positions.size());
    parallel_for(g.positions.size(), [&](size_t i) {
        const LocalShading& m = g.shapes[g.vertex_shape[i]].material;
        Vec3 n = g.normals[i], v = glm::normalize(f.camera.eye - g.positions[i]);
        if (m.two_sided && glm::dot(n, v) < 0.0f) n = -n;
        Spectrum kd = m.diffuse && !baked_diffuse(f) ? m.diffuse->eval(m.diffuse->mapping().map(g.uvs[i], g.positions[i])) : Spectrum(0.0f);
        vertex_light[i] = direct_light(light, m, kd, g.positions[i], n, v, f.settings.reflection);
    });
}

// The light's direct lighting at camera sample i on triangle t, by the shading mode.
Spectrum sample_light(const FrameSetup& f, const FrameBuffers& b, size_t i, const LocalLight& light) {
    const RasterGeometry& g = f.geometry;
    const uint32_t t = b.triangle[i];
    const SurfaceSample& ss = b.surface[i];
    const LocalShading& m = g.shapes[g.triangle_shape[t]].material;
    const glm::uvec3& v = g.triangles[t];
    switch (f.settings.shading) {
        case RasterSettings::Shading::Gouraud: {
            const Vec3& w = b.bary[i];
            return w.x * b.vertex_light[v.x] + w.y * b.vertex_light[v.y] + w.z * b.vertex_light[v.z];
        }
        case RasterSettings::Shading::Flat: {
            Vec3 c = (g.positions[v.x] + g.positions[v.y] + g.positions[v.z]) / 3.0f;
            Vec2 uvc = (g.uvs[v.x] + g.uvs[v.y] + g.uvs[v.z]) / 3.0f;
            Spectrum kd = m.diffuse && !baked_diffuse(f) ? m.diffuse->eval(m.diffuse->mapping().map(uvc, c)) : Spectrum(0.0f);
            return direct_light(light, m, kd, c, ss.n_geo, glm::normalize(f.camera.eye - c), f.settings.reflection);
        }
        case RasterSettings::Shading::Phong: break;
    }
    return direct_light(light, m, baked_diffuse(f) ? Spectrum(0.0f) : ss.kd, ss.p, ss.n, ss.v, f.settings.reflection);
}

// Whether camera sample i receives direct light (a surface seen from a side that reflects).
bool receives_light(const FrameBuffers& b, size_t i) { return b.triangle[i] != NoTriangle && b.surface[i].lit_side; }

// The shadow map of `light` for this frame. A face that no receiving sample looks up is left
// out, and of the others only the window that samples look up is rendered. Each face's
// resolution is the setting's, or, when the settings leave it to the view, the finest that a
// sample looking it up needs: a texel no larger than the spacing of the camera's samples there
// (at most AutoShadowMapLimit texels per side).
void render_shadow_map(const FrameSetup& f, FrameBuffers& b, const LocalLight& light, ShadowMap& map) {
    constexpr int AutoShadowMapLimit = 1024;
    map.place(light, f.geometry);
    // Per chunk of samples, then combined: max and min are exact in any order.
    const size_t chunk = 4096, chunks = (f.sample_count() + chunk - 1) / chunk;
    std::vector<ShadowMapNeeds>& chunk_needs = b.shadow_map_needs;
    chunk_needs.assign(chunks, ShadowMapNeeds{});
    const float spacing_per_depth = f.sample_spacing(1.0f);  // proportional to view depth
    parallel_for(chunks, [&](size_t c) {
        ShadowMapNeeds& acc = chunk_needs[c];
        for (size_t i = c * chunk; i != std::min(f.sample_count(), (c + 1) * chunk); ++i) {
            if (!receives_light(b, i)) continue;
            const Vec3& p = b.surface[i].p;
            int face = map.face_of(p);
            float need = map.resolution_needed(face, p, spacing_per_depth * b.depth[i]);
            acc[size_t(face)].add(std::isfinite(need) ? std::max(need, 1.0f) : float(AutoShadowMapLimit), map.face_position(face, p));
        }
    });
    ShadowMapNeeds needs{};
    for (const ShadowMapNeeds& c : chunk_needs)
        for (size_t k = 0; k < needs.size(); ++k) needs[k].merge(c[k]);
    std::vector<int>& resolution = b.shadow_map_resolution;
    resolution.assign(map.face_count(), 0);
    for (size_t k = 0; k < resolution.size(); ++k) {
        if (needs[k].resolution <= 0.0f) continue;
        int fixed = f.settings.shadow_map_resolution;
        // Rounded up to whole rasterizer tiles: the size changes only in steps as the view moves.
        int chosen = std::min(AutoShadowMapLimit, (int(std::ceil(needs[k].resolution)) + TileSize - 1) / TileSize * TileSize);
        resolution[k] = fixed > 0 ? fixed : chosen;
    }
    map.render(f.geometry, resolution, needs.data(), f.settings.pcf);
}

// One light: its shadow, then visibility times lighting added to every lit sample.
void add_light(const FrameSetup& f, FrameBuffers& b, size_t light_index) {
    const RasterSettings& s = f.settings;
    const LocalLight& light = f.lights.lights[light_index];
    const ShadowMap* map = nullptr;
    if (s.shadows == RasterSettings::Shadows::Map) {
        render_shadow_map(f, b, light, b.shadow_maps[light_index]);
        map = &b.shadow_maps[light_index];
    }
    if (s.shadows == RasterSettings::Shadows::Volume)
        shadow_volume_mask(light, f.geometry, f.camera, b.camera_rasterizer, b.view_depth, b.lit);
    if (s.shading == RasterSettings::Shading::Gouraud) light_vertices(f, light, b.vertex_light);
    parallel_for(f.sample_count(), [&](size_t i) {
        if (!receives_light(b, i)) return;
        float visibility = 1.0f;
        if (map) visibility = map->visibility(b.surface[i].p, b.surface[i].n_geo, s.pcf);
        if (s.shadows == RasterSettings::Shadows::Volume) visibility = b.lit[i] ? 1.0f : 0.0f;
        if (visibility == 0.0f) return;
        b.color[i] += visibility * sample_light(f, b, i, light);
    });
}

}  // namespace

void lights_pass(const FrameSetup& f, FrameBuffers& b) {
    if (baked_diffuse(f) && !has_highlights(f.geometry)) return;  // nothing for the lights to add
    if (f.settings.shadows == RasterSettings::Shadows::Volume) {
        b.view_depth.resize(f.sample_count());
        for (size_t i = 0; i < b.view_depth.size(); ++i) b.view_depth[i] = surface_view_depth(f, b, i);
    }
    if (f.settings.shadows == RasterSettings::Shadows::Map) b.shadow_maps.resize(f.lights.lights.size());
    for (size_t k = 0; k < f.lights.lights.size(); ++k) add_light(f, b, k);
}

}  // namespace candela::raster
