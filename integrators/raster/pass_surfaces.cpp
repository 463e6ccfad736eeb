// The surfaces pass: from the G-buffer, the visible surface at every camera sample (position,
// normals, uv, the BSDF's bump- or normal-mapped frame under Phong shading, the texture filtered
// over the sample's footprint) and the radiance that needs no light: emission and the
// environment seen by reflection and refraction; where no surface is, the environment itself.

#include "core/bsdf.h"
#include "core/parallel.h"
#include "integrators/raster/environment.h"
#include "integrators/raster/frame.h"

namespace candela::raster {

namespace {

HomogeneousSetup homogeneous_setup(const Vec4 c[3], Vec2i full, Vec2i offset) {
    HomogeneousSetup h;
    Mat3 m;  // columns: vertices; rows: X, Y, W in pixel-homogeneous coordinates
    for (int i = 0; i < 3; ++i)
        m[i] = Vec3((c[i].x + c[i].w) * 0.5f * float(full.x) - float(offset.x) * c[i].w,
                    (c[i].y + c[i].w) * 0.5f * float(full.y) - float(offset.y) * c[i].w, c[i].w);
    float det = glm::determinant(m);
    if (std::abs(det) > 1e-30f && std::isfinite(det)) {
        h.inverse = glm::inverse(m);
        h.valid = true;
    }
    return h;
}

// Refraction of the view ray into a surface of relative index eta (Snell); straight through
// for eta 1; total internal reflection gives the mirror direction.
Vec3 refracted(const Vec3& v, const Vec3& n, float eta) {
    if (eta == 1.0f) return -v;
    float cos_i = glm::dot(n, v), inv = 1.0f / eta;
    float k = 1.0f - inv * inv * (1.0f - cos_i * cos_i);
    if (k < 0.0f) return 2.0f * cos_i * n - v;
    return glm::normalize(-v * inv + n * (inv * cos_i - std::sqrt(k)));
}

// The surface of triangle t at barycentrics b: interpolated (Gouraud, Phong) or face (flat)
// normal, under Phong shading perturbed by the BSDF's own frame (bump and normal maps); both
// normals turned toward the viewer on two-sided materials. Written in place, every field (copying
// a returned one took 11% of the pass's profile); kd is the texture's, set by the caller.
void reconstruct(const FrameSetup& f, uint32_t t, const Vec3& b, SurfaceSample& ss) {
    const RasterGeometry& g = f.geometry;
    const glm::uvec3& v = g.triangles[t];
    const RasterShape& rs = g.shapes[g.triangle_shape[t]];
    const Vec3 &p0 = g.positions[v.x], &p1 = g.positions[v.y], &p2 = g.positions[v.z];
    const TriangleFrame& frame = g.triangle_frames[t];
    ss.p = b.x * p0 + b.y * p1 + b.z * p2;
    ss.n_geo = frame.n;
    ss.uv = b.x * g.uvs[v.x] + b.y * g.uvs[v.y] + b.z * g.uvs[v.z];
    ss.v = glm::normalize(f.camera.eye - ss.p);
    const RasterSettings::Shading shading = f.settings.shading;
    Vec3 n = shading == RasterSettings::Shading::Flat ? ss.n_geo
                                                      : glm::normalize(b.x * g.normals[v.x] + b.y * g.normals[v.y] + b.z * g.normals[v.z]);
    if (shading == RasterSettings::Shading::Phong) {
        SurfaceInteraction si;
        si.p = ss.p;
        si.n = ss.n_geo;
        si.uv = ss.uv;
        si.dpdu = frame.dpdu;
        si.dpdv = frame.dpdv;
        si.shading = Frame::from_normal_tangent(n, si.dpdu);
        n = rs.bsdf->shading_frame(si).n;
    }
    ss.front = glm::dot(ss.n_geo, ss.v) > 0.0f;
    if (!ss.front && rs.material.two_sided) {
        n = -n;
        ss.n_geo = -ss.n_geo;
    }
    ss.n = n;
    ss.lit_side = ss.front || rs.material.two_sided;
    ss.kd = Spectrum(0.0f);
}

// The diffuse texture at the surface point (uv, p), through the texture's mapping (uv or
// projected from the position), filtered over the footprint of the sample at `pos`: the
// derivatives per pixel come from the triangle's homogeneous setup.
Spectrum filtered_albedo(const FrameSetup& f, const Texture& texture, const HomogeneousSetup& h, uint32_t t, const Vec2& surface_uv,
                         const Vec3& p, const Vec2& pos) {
    // A constant texture is the same everywhere: no mapping, no footprint.
    if (texture.is_constant()) return texture.eval(surface_uv);
    const RasterGeometry& g = f.geometry;
    const glm::uvec3& v = g.triangles[t];
    const TextureMapping& mapping = texture.mapping();
    const Vec2 uv = mapping.map(surface_uv, p);
    Vec2 du(0.0f), dv(0.0f);
    if (h.valid) {
        Vec3 b0 = h.at(pos.x, pos.y), bx = h.at(pos.x + 1.0f, pos.y), by = h.at(pos.x, pos.y + 1.0f);
        auto uv_at = [&](const Vec3& bb) {
            return mapping.map(bb.x * g.uvs[v.x] + bb.y * g.uvs[v.y] + bb.z * g.uvs[v.z],
                               bb.x * g.positions[v.x] + bb.y * g.positions[v.y] + bb.z * g.positions[v.z]);
        };
        du = mapping.difference(uv_at(b0), uv_at(bx));
        dv = mapping.difference(uv_at(b0), uv_at(by));
    }
    return texture.eval_filtered(uv, du, dv, f.settings.texture_filter);
}

// The environment seen in direction d by a reflection or refraction of this roughness: a glossy
// one (lat-long mapping, roughness > 0) reads the image-based lighting's prefiltered maps, the
// others the environment or its cube map.
Spectrum environment_seen(const FrameSetup& f, const EnvironmentLookup& environment, const Vec3& d, float roughness) {
    if (f.image_lighting && roughness > 0.0f && !f.settings.cube_mapping) return f.image_lighting->glossy(d, roughness);
    return environment.lookup(d, roughness);
}

// What a surface shows without any light of the local model: its emission (front side) and the
// environment in the mirror and refraction directions. (Ambient light: the ambient pass.)
Spectrum unlit_radiance(const FrameSetup& f, const EnvironmentLookup& environment, const RasterShape& rs, const SurfaceSample& ss) {
    const LocalShading& m = rs.material;
    Spectrum L(0.0f);
    if (ss.front) L += rs.emission;
    if (!is_black(m.mirror)) L += m.mirror * environment_seen(f, environment, 2.0f * glm::dot(ss.n, ss.v) * ss.n - ss.v, m.roughness);
    if (!is_black(m.transmission))
        L += m.transmission * environment_seen(f, environment, refracted(ss.v, ss.n, ss.front ? m.eta : 1.0f / m.eta), m.roughness);
    return L;
}

// Where no surface is: the environment along the camera ray, as the path tracer sees it.
Spectrum background(const FrameSetup& f, const Vec2& pos) {
    Ray ray = f.scene.sensor().sample_ray(Vec2(pos.x + float(f.offset.x), pos.y + float(f.offset.y)), Vec2(0.5f));
    return f.scene.eval_environment(ray.d);
}

}  // namespace

void surface_pass(const FrameSetup& f, FrameBuffers& b) {
    const RasterGeometry& g = f.geometry;
    std::vector<HomogeneousSetup>& setups = b.setups;
    setups.resize(g.triangles.size());
    parallel_for(g.triangles.size(), [&](size_t i) { setups[i] = homogeneous_setup(b.clip[i].data(), f.full, f.offset); });
    const RasterSettings& s = f.settings;
    EnvironmentLookup environment(f.scene, s.cube_mapping ? EnvironmentLookup::Mode::Cube : EnvironmentLookup::Mode::LatLong,
                                  s.cube_resolution, s.cube_map);
    // Every sample's surface and colour is written below (in parallel, not cleared first).
    b.surface.resize(f.sample_count());
    b.color.resize(f.sample_count());
    parallel_for(size_t(f.height), [&](int y) {
        for (int x = 0; x < f.width; ++x)
            for (int k = 0; k < f.samples_per_pixel(); ++k) {
                size_t i = f.sample_index(x, y, k);
                Vec2 pos = f.sample_position(x, y, k);
                uint32_t t = b.triangle[i];
                if (t == NoTriangle) {
                    b.surface[i] = SurfaceSample{};
                    b.color[i] = background(f, pos);
                    continue;
                }
                SurfaceSample& ss = b.surface[i];
                reconstruct(f, t, b.bary[i], ss);
                b.color[i] = Spectrum(0.0f);
                if (!ss.lit_side) continue;  // one-sided materials are black from behind
                const RasterShape& rs = g.shapes[g.triangle_shape[t]];
                if (rs.material.diffuse) ss.kd = filtered_albedo(f, *rs.material.diffuse, setups[t], t, ss.uv, ss.p, pos);
                b.color[i] = unlit_radiance(f, environment, rs, ss);
            }
    });
}

float surface_view_depth(const FrameSetup& f, const FrameBuffers& b, size_t i) {
    return b.triangle[i] == NoTriangle ? Infinity : f.camera.view_depth(b.surface[i].p);
}

}  // namespace candela::raster
