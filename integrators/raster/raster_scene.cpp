#include "integrators/raster/raster_scene.h"

#include "core/mesh.h"
#include "core/texture.h"
#include "integrators/radiosity.h"

#include <map>

namespace candela::raster {

namespace {

// Splits every triangle into four (edge midpoints shared between neighbours).
void subdivide(RasterGeometry& g, uint32_t first, uint32_t count, std::vector<glm::uvec3>& out) {
    std::map<std::pair<unsigned, unsigned>, unsigned> midpoints;
    auto mid = [&](unsigned a, unsigned b) {
        auto key = std::minmax(a, b);
        auto it = midpoints.find(key);
        if (it != midpoints.end()) return it->second;
        unsigned m = unsigned(g.positions.size());
        g.positions.push_back(0.5f * (g.positions[a] + g.positions[b]));
        g.normals.push_back(glm::normalize(g.normals[a] + g.normals[b]));
        g.uvs.push_back(0.5f * (g.uvs[a] + g.uvs[b]));
        midpoints.emplace(key, m);
        return m;
    };
    for (uint32_t i = first; i < first + count; ++i) {
        glm::uvec3 t = g.triangles[i];
        unsigned ab = mid(t.x, t.y), bc = mid(t.y, t.z), ca = mid(t.z, t.x);
        out.push_back({t.x, ab, ca});
        out.push_back({ab, t.y, bc});
        out.push_back({ca, bc, t.z});
        out.push_back({ab, bc, ca});
    }
}

// Displacement mapping of the shape's triangles (its vertices from first_vertex on): refine
// `subdivisions` times, move every vertex along its normal by the height field, recompute the
// normals (area-weighted face normals). The height field is then geometry: no longer a bump.
void displace(RasterGeometry& g, RasterShape& rs, unsigned first_vertex, int subdivisions) {
    for (int level = 0; level < subdivisions; ++level) {
        std::vector<glm::uvec3> refined;
        subdivide(g, rs.first_triangle, rs.triangle_count, refined);
        g.triangles.resize(rs.first_triangle);
        g.triangles.insert(g.triangles.end(), refined.begin(), refined.end());
        rs.triangle_count = uint32_t(refined.size());
    }
    for (unsigned v = first_vertex; v < g.positions.size(); ++v)
        g.positions[v] += g.normals[v] * (rs.material.height->eval_1(rs.material.height->mapping().map(g.uvs[v], g.positions[v])) *
                                          rs.material.height_scale);
    std::vector<Vec3> n(g.positions.size() - first_vertex, Vec3(0.0f));
    for (uint32_t i = rs.first_triangle; i < rs.first_triangle + rs.triangle_count; ++i) {
        const glm::uvec3& t = g.triangles[i];
        Vec3 f = glm::cross(g.positions[t.y] - g.positions[t.x], g.positions[t.z] - g.positions[t.x]);
        n[t.x - first_vertex] += f;
        n[t.y - first_vertex] += f;
        n[t.z - first_vertex] += f;
    }
    for (size_t v = 0; v < n.size(); ++v)
        if (squared_length(n[v]) > 0.0f) g.normals[first_vertex + v] = glm::normalize(n[v]);
    rs.material.height = nullptr;
}

// Appends one shape's triangles with its material (displaced when asked).
void add_shape(RasterGeometry& g, const Shape* shape, const TriangleSoup& soup, bool displacement, int subdivisions) {
    RasterShape rs;
    rs.shape = shape;
    rs.bsdf = shape->bsdf();
    rs.material = rs.bsdf->local_shading();
    rs.closed = soup.closed;
    if (const Emitter* e = shape->emitter()) {
        auto a = e->local_approximation();
        if (a && a->kind == LocalApproximation::Kind::AreaPoint) rs.emission = a->radiance;
    }
    unsigned base = unsigned(g.positions.size());
    g.positions.insert(g.positions.end(), soup.positions.begin(), soup.positions.end());
    g.normals.insert(g.normals.end(), soup.normals.begin(), soup.normals.end());
    g.uvs.insert(g.uvs.end(), soup.uvs.begin(), soup.uvs.end());
    rs.first_triangle = uint32_t(g.triangles.size());
    for (const auto& t : soup.triangles) g.triangles.push_back(t + glm::uvec3(base));
    rs.triangle_count = uint32_t(soup.triangles.size());
    if (displacement && rs.material.height) displace(g, rs, base, subdivisions);
    g.triangle_shape.resize(g.triangles.size(), uint32_t(g.shapes.size()));
    g.vertex_shape.resize(g.positions.size(), uint32_t(g.shapes.size()));
    g.shapes.push_back(rs);
}

// What both builders finish with: the bounding box and every triangle's frame.
void finish(RasterGeometry& g) {
    for (const Vec3& p : g.positions) g.bbox.expand(p);
    g.triangle_frames.resize(g.triangles.size());
    for (size_t i = 0; i < g.triangles.size(); ++i) {
        const glm::uvec3& t = g.triangles[i];
        const Vec3 &p0 = g.positions[t.x], &p1 = g.positions[t.y], &p2 = g.positions[t.z];
        TriangleFrame& frame = g.triangle_frames[i];
        frame.n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
        triangle_tangents(p0, p1, p2, g.uvs[t.x], g.uvs[t.y], g.uvs[t.z], frame.n, frame.dpdu, frame.dpdv);
    }
}

}  // namespace

RasterGeometry build_geometry(const Scene& scene, int detail, bool displacement, int subdivisions) {
    RasterGeometry g;
    std::vector<TessellatedPart> parts;  // one scene shape's parts at a time (an instance has several)
    for (const auto& shape : scene.shapes()) {
        parts.clear();
        shape->tessellate_parts(parts, detail);
        for (const TessellatedPart& part : parts) add_shape(g, part.shape, part.triangles, displacement, subdivisions);
    }
    finish(g);
    return g;
}

RasterGeometry build_baked_geometry(const std::vector<RadiosityMesh>& meshes) {
    RasterGeometry g;
    for (const RadiosityMesh& m : meshes) {
        if (!m.shape || m.patches.triangles.empty()) continue;
        add_shape(g, m.shape, m.patches, false, 0);
        g.baked_front.insert(g.baked_front.end(), m.irradiance.begin(), m.irradiance.end());
        if (m.irradiance_back.empty())
            g.baked_back.resize(g.baked_front.size(), Spectrum(0.0f));
        else
            g.baked_back.insert(g.baked_back.end(), m.irradiance_back.begin(), m.irradiance_back.end());
    }
    finish(g);
    return g;
}

RasterCamera RasterCamera::perspective(const Transform& to_world, float tx, float ty, float n, float f) {
    RasterCamera c;
    c.view = to_world.inverse_matrix();
    c.eye = to_world.apply_point(Vec3(0.0f));
    c.near_clip = n;
    c.far_clip = f;
    // Camera +x maps to the image's left and +y to its top, hence the negated x and y rows:
    // x_ndc = -x / (z tan_x), y_ndc = -y / (z tan_y); z_ndc = f (z - n) / ((f - n) z).
    Mat4 p(0.0f);  // column-major: p[col][row]
    p[0][0] = -1.0f / tx;
    p[1][1] = -1.0f / ty;
    p[2][2] = f / (f - n);
    p[3][2] = -f * n / (f - n);
    p[2][3] = 1.0f;
    c.projection = p;
    c.view_projection = c.projection * c.view;
    return c;
}

RasterCamera RasterCamera::orthographic_box(const Transform& to_world, float hx, float hy, float n, float f) {
    RasterCamera c;
    c.view = to_world.inverse_matrix();
    c.eye = to_world.apply_point(Vec3(0.0f));
    c.orthographic = true;
    c.near_clip = n;
    c.far_clip = f;
    Mat4 p(1.0f);
    p[0][0] = -1.0f / hx;
    p[1][1] = -1.0f / hy;
    p[2][2] = 1.0f / (f - n);
    p[3][2] = -n / (f - n);
    c.projection = p;
    c.view_projection = c.projection * c.view;
    return c;
}

RasterCamera RasterCamera::from_pinhole(const PinholeProjection& p) {
    RasterCamera c = perspective(p.to_world, p.tan_half_x, p.tan_half_x / p.aspect, p.near_clip, p.far_clip);
    // A principal point offset o shifts the image: x_ndc = 2 s - 1 becomes 2 (s + o) - 1 - 2 o,
    // i.e. x_clip -= 2 o w with w = z (Mitsuba's principal_point_offset, see PinholeProjection).
    c.projection[2][0] -= 2.0f * p.principal_point_offset.x;
    c.projection[2][1] -= 2.0f * p.principal_point_offset.y;
    c.view_projection = c.projection * c.view;
    return c;
}

void LocalLight::illuminate(const Vec3& p, Vec3& to_light, float& distance, Spectrum& irradiance) const {
    if (emitter) {
        // Delta lights: exactly what next-event estimation sees (falloff, attenuation, texture).
        SurfaceInteraction ref;
        ref.p = p;
        Spectrum weight;
        DirectionSample ds = emitter->sample_direction(ref, Vec2(0.5f), weight);
        to_light = ds.d;
        distance = ds.dist;
        irradiance = weight;
        return;
    }
    Vec3 d = area.position - p;
    distance = glm::length(d);
    to_light = distance > 0.0f ? d / distance : Vec3(0, 0, 1);
    float cos_e = area.planar ? std::max(0.0f, glm::dot(area.normal, -to_light)) : 1.0f;
    irradiance = distance > 0.0f ? area.intensity * (cos_e / (distance * distance)) : Spectrum(0.0f);
}

LocalLights collect_lights(const Scene& scene) {
    LocalLights out;
    for (const auto& e : scene.emitters()) {
        LocalLight l;
        if (e->is_delta()) {
            l.emitter = e.get();
            SurfaceInteraction ref;
            ref.p = scene.bbox().valid() ? scene.bbox().center() : Vec3(0.0f);
            Spectrum w;
            DirectionSample ds = e->sample_direction(ref, Vec2(0.5f), w);
            if (e->type() == EmitterType::DeltaDirection) {
                l.kind = LocalLight::Kind::Directional;
                l.direction = -ds.d;
            } else {
                l.position = ds.p;
                auto b = e->bounds();
                if (b && b->cos_theta_o > -1.0f) {
                    l.kind = LocalLight::Kind::Spot;
                    l.direction = b->axis;
                    l.cos_cutoff = b->cos_theta_o;
                    l.cutoff = safe_acos(b->cos_theta_o);
                } else {
                    l.kind = LocalLight::Kind::Point;
                }
            }
            out.lights.push_back(l);
            continue;
        }
        auto a = e->local_approximation();
        if (!a) continue;
        if (a->kind == LocalApproximation::Kind::Ambient) {
            out.ambient += a->radiance;
            continue;
        }
        l.kind = LocalLight::Kind::AreaPoint;
        l.area = *a;
        l.position = a->position;
        l.direction = a->normal;
        out.lights.push_back(l);
    }
    return out;
}

}  // namespace candela::raster
