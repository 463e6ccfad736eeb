#include "integrators/raster/shadows.h"

#include <map>

namespace candela::raster {

int light_shape(const LocalLight& light, const RasterGeometry& g) {
    if (light.kind != LocalLight::Kind::AreaPoint) return -1;
    for (size_t i = 0; i < g.shapes.size(); ++i)
        if (g.shapes[i].shape == light.area.shape) return int(i);
    return -1;
}

namespace {

// Builds a view looking from `origin` along `dir` with any up vector.
Transform view_along(const Vec3& origin, const Vec3& dir) {
    Vec3 up = std::abs(dir.y) < 0.9f ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
    return Transform::look_at(origin, origin + dir, up);
}

float linear_depth(const RasterCamera& c, float z_ndc) {
    if (c.orthographic) return c.near_clip + z_ndc * (c.far_clip - c.near_clip);
    return c.far_clip * c.near_clip / (c.far_clip - z_ndc * (c.far_clip - c.near_clip));
}

}  // namespace

void ShadowMap::place(const LocalLight& light, const RasterGeometry& g) {
    light_ = light;
    float radius = std::max(g.bbox.bounding_radius(), 1e-3f);
    Vec3 center = g.bbox.center();
    float far_clip = 4.0f * radius + glm::length(light.position - center);
    float near_clip = far_clip * 1e-5f;
    switch (light.kind) {
        case LocalLight::Kind::Directional:
            faces_.resize(1);
            faces_[0].camera = RasterCamera::orthographic_box(view_along(center - light.direction * (2.0f * radius), light.direction),
                                                              radius, radius, 0.0f, 4.0f * radius);
            faces_[0].extent = 2.0f * radius;
            break;
        case LocalLight::Kind::Spot: {
            faces_.resize(1);
            float t = std::tan(std::min(light.cutoff, radians(85.0f)));
            faces_[0].camera = RasterCamera::perspective(view_along(light.position, light.direction), t, t, near_clip, far_clip);
            faces_[0].extent = 2.0f * t;
            break;
        }
        default: {
            // In the order face_of() numbers them.
            const Vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
            faces_.resize(6);
            for (int i = 0; i < 6; ++i) {
                faces_[size_t(i)].camera = RasterCamera::perspective(view_along(light.position, axes[i]), 1.0f, 1.0f, near_clip, far_clip);
                faces_[size_t(i)].extent = 2.0f;
            }
        }
    }
}

int ShadowMap::face_of(const Vec3& p) const {
    if (faces_.size() == 1) return 0;
    // Cube map: the face of the dominant axis of the direction from the light.
    Vec3 d = p - light_.position, a = glm::abs(d);
    return a.x >= a.y && a.x >= a.z ? (d.x > 0 ? 0 : 1) : (a.y >= a.z ? (d.y > 0 ? 2 : 3) : (d.z > 0 ? 4 : 5));
}

float ShadowMap::resolution_needed(int face, const Vec3& p, float footprint) const {
    const Face& f = faces_[size_t(face)];
    float side = f.camera.orthographic ? f.extent : f.extent * std::max(f.camera.view_depth(p), 0.0f);
    return side / footprint;
}

Vec2 ShadowMap::face_position(int face, const Vec3& p) const {
    Vec4 c = faces_[size_t(face)].camera.clip(p);
    if (!(c.w > 0.0f)) return Vec2(0.0f);  // behind the face: visibility() does not look it up
    return glm::clamp(Vec2(c.x, c.y) / c.w, Vec2(-1.0f), Vec2(1.0f));
}

void ShadowMap::render(const RasterGeometry& g, const std::vector<int>& resolution, const FaceNeeds* needs, int pcf) {
    int skip = light_shape(light_, g);
    for (size_t i = 0; i < faces_.size(); ++i) {
        Face& f = faces_[i];
        f.resolution = resolution[i];
        f.texel_scale = f.extent / float(std::max(resolution[i], 1));
        if (resolution[i] <= 0) continue;
        // The window the samples look up, widened by the filter's half width and two texels for
        // the normal offset, which moves a lookup by about one texel (face_visibility).
        const int res = resolution[i], margin = std::max(pcf, 1) / 2 + 2;
        auto texels = [&](const Vec2& ndc) { return (ndc + 1.0f) * 0.5f * float(res); };  // as face_visibility maps
        Vec2i lo = glm::clamp(Vec2i(glm::floor(texels(needs[i].lo))) - margin, Vec2i(0), Vec2i(res));
        Vec2i hi = glm::clamp(Vec2i(glm::ceil(texels(needs[i].hi))) + margin, Vec2i(0), Vec2i(res));
        f.window_min = lo;
        f.window_size = glm::max(hi - lo, Vec2i(1));
        render_depth(f, g, skip);
    }
}

void ShadowMap::render_depth(Face& f, const RasterGeometry& g, int skip_shape) {
    f.clip.clear();
    for (size_t i = 0; i < g.triangles.size(); ++i) {
        if (int(g.triangle_shape[i]) == skip_shape) continue;
        const glm::uvec3& t = g.triangles[i];
        f.clip.push_back({f.camera.clip(g.positions[t.x]), f.camera.clip(g.positions[t.y]), f.camera.clip(g.positions[t.z])});
    }
    // The window is a crop of the whole face (the rasterizer's offset): texel (x, y) of the
    // window is texel window_min + (x, y) of the face.
    const int width = f.window_size.x;
    f.rasterizer.set_target(width, f.window_size.y, Vec2i(f.resolution), f.window_min);
    f.rasterizer.setup(f.clip, true);
    f.depth.assign(size_t(width) * size_t(f.window_size.y), Infinity);
    bool ortho = f.camera.orthographic;
    f.rasterizer.run([&](const Fragment& frag) {
        float& d = f.depth[size_t(frag.y) * width + frag.x];
        float view = float(ortho ? linear_depth(f.camera, float(frag.depth)) : frag.w);
        if (view < d) d = view;
    });
}

float ShadowMap::face_visibility(const Face& f, const Vec3& p_surface, const Vec3& n, float cos_theta, int pcf) const {
    // Normal offset: look the map up a texel's width off the surface, which keeps grazing
    // surfaces (where the depth slope is steep) out of their own shadow.
    Vec3 p = p_surface + n * f.texel(std::max(f.camera.view_depth(p_surface), 0.0f));
    Vec4 c = f.camera.clip(p);
    if (!(c.w > 0.0f)) return 1.0f;
    const int res = f.resolution;
    float px = (c.x / c.w + 1.0f) * 0.5f * float(res), py = (c.y / c.w + 1.0f) * 0.5f * float(res);
    float depth = f.camera.view_depth(p);
    // Slope-scaled bias: a texel spans texel(depth) in the world; a surface tilted by theta
    // against the light changes depth by that much times tan(theta) across it.
    float tan_theta = std::min(safe_sqrt(1.0f - cos_theta * cos_theta) / std::max(cos_theta, 1e-3f), 10.0f);
    float bias = f.texel(depth) * (1.5f + 2.0f * tan_theta);
    int k = std::max(pcf, 1), half = k / 2;
    // In the window's texels; a lookup beyond it (a larger filter than the margin allows for)
    // reads its edge, as one beyond the face reads the face's edge.
    int cx = int(std::floor(px)) - f.window_min.x, cy = int(std::floor(py)) - f.window_min.y;
    const int width = f.window_size.x, height = f.window_size.y;
    int lit = 0, total = 0;
    for (int dy = -half; dy < k - half; ++dy)
        for (int dx = -half; dx < k - half; ++dx) {
            int x = std::clamp(cx + dx, 0, width - 1), y = std::clamp(cy + dy, 0, height - 1);
            ++total;
            if (depth - bias <= f.depth[size_t(y) * width + x]) ++lit;
        }
    return float(lit) / float(total);
}

float ShadowMap::visibility(const Vec3& p, const Vec3& n, int pcf) const {
    Vec3 to_light;
    float dist;
    Spectrum e;
    light_.illuminate(p, to_light, dist, e);
    float cos_theta = std::abs(glm::dot(n, to_light));
    Vec3 n_lit = glm::dot(n, to_light) >= 0.0f ? n : -n;
    const Face& face = faces_[size_t(face_of(p))];
    if (face.resolution == 0) return 1.0f;  // left out: no sample was expected to look it up
    return face_visibility(face, p, n_lit, cos_theta, pcf);
}

// ---- shadow volumes ------------------------------------------------------------------------

namespace {

// Builds shadow volumes as closed, consistently oriented polyhedra in homogeneous coordinates:
// every volume is a near cap facing the light, its copy at infinity reversed (the far cap), and
// one quad per boundary edge traversing that edge opposite to the cap. The orientation is thus
// exact even for faces at infinity (w = 0), where finite stand-in points would mislead.
struct VolumeBuilder {
    const LocalLight& light;
    std::vector<std::array<Vec4, 3>> world;
    float push;  // relative offset of the near cap away from the light (avoids self-shadowing)

    bool directional() const { return light.kind == LocalLight::Kind::Directional; }
    Vec3 away(const Vec3& p) const { return directional() ? light.direction : glm::normalize(p - light.position); }
    Vec4 near_point(const Vec3& p) const {
        float scale = directional() ? push : push * glm::length(p - light.position);
        return Vec4(p + away(p) * scale, 1.0f);
    }
    Vec4 far_point(const Vec3& p) const { return Vec4(away(p), 0.0f); }
    // True when (a, b, c), counter-clockwise, faces the light.
    bool faces_light(const Vec3& a, const Vec3& b, const Vec3& c) const {
        Vec3 n = glm::cross(b - a, c - a);
        return glm::dot(n, away((a + b + c) / 3.0f)) < 0.0f;
    }
    // The caps of a near-cap triangle (u, v, w), which must face the light.
    void caps(const Vec3& u, const Vec3& v, const Vec3& w) {
        world.push_back({near_point(u), near_point(v), near_point(w)});
        if (!directional()) world.push_back({far_point(u), far_point(w), far_point(v)});
    }
    // The side quad of near-cap edge u -> v: traversed v -> u, then out to infinity.
    void side(const Vec3& u, const Vec3& v) {
        world.push_back({near_point(v), near_point(u), far_point(u)});
        if (!directional()) world.push_back({near_point(v), far_point(u), far_point(v)});
    }
    // A whole prism: the triangle (either winding) extruded away from the light.
    void prism(Vec3 a, Vec3 b, Vec3 c) {
        if (!faces_light(a, b, c)) std::swap(b, c);
        caps(a, b, c);
        side(a, b);
        side(b, c);
        side(c, a);
    }
};

}  // namespace

namespace {

// The volumes of a closed mesh: the near caps are the triangles facing away from the light,
// reversed (so that they face it); the sides stand on the silhouette edges between those and the
// lit triangles (vertices welded by position to find neighbours).
void closed_mesh_volumes(VolumeBuilder& vb, const RasterGeometry& g, const RasterShape& rs) {
    std::map<std::tuple<float, float, float>, unsigned> weld;
    auto id = [&](unsigned v) {
        const Vec3& p = g.positions[v];
        return weld.emplace(std::make_tuple(p.x, p.y, p.z), unsigned(weld.size())).first->second;
    };
    struct Edge {
        bool dark;
        Vec3 from, to;
    };
    std::map<std::pair<unsigned, unsigned>, Edge> edges;  // directed, as wound in the mesh
    for (uint32_t i = rs.first_triangle; i < rs.first_triangle + rs.triangle_count; ++i) {
        const glm::uvec3& t = g.triangles[i];
        Vec3 a = g.positions[t.x], b = g.positions[t.y], c = g.positions[t.z];
        bool dark = !vb.faces_light(a, b, c);
        unsigned ia = id(t.x), ib = id(t.y), ic = id(t.z);
        edges[{ia, ib}] = {dark, a, b};
        edges[{ib, ic}] = {dark, b, c};
        edges[{ic, ia}] = {dark, c, a};
        if (dark) vb.caps(a, c, b);
    }
    for (const auto& [key, e] : edges) {
        if (!e.dark) continue;
        auto twin = edges.find({key.second, key.first});
        if (twin != edges.end() && twin->second.dark) continue;  // interior to the dark side
        // In the reversed cap this edge runs to -> from.
        vb.side(e.to, e.from);
    }
}

// Rasterizes the volumes with an infinitely far projection (z_ndc = 1 - n / z), so that the
// caps at infinity are not clipped away, and counts them against the camera samples (z-fail).
std::vector<int16_t> count_volumes(const std::vector<std::array<Vec4, 3>>& world, const RasterCamera& camera, const Rasterizer& layout,
                                   const std::vector<float>& view_depths) {
    Mat4 infinite = camera.projection;
    if (!camera.orthographic) {
        infinite[2][2] = 1.0f;
        infinite[3][2] = -camera.near_clip;
    }
    Mat4 vp = infinite * camera.view;
    std::vector<std::array<Vec4, 3>> clip;
    clip.reserve(world.size());
    for (const auto& t : world) clip.push_back({vp * t[0], vp * t[1], vp * t[2]});
    Rasterizer r(layout.width(), layout.height(), layout.sample_offsets(), layout.full_size(), layout.offset());
    r.setup(clip, true);
    std::vector<int16_t> count(view_depths.size(), 0);
    const int ns = layout.samples_per_pixel(), w = layout.width();
    float n = camera.near_clip;
    r.run([&](const Fragment& f) {
        size_t i = (size_t(f.y) * w + f.x) * ns + f.sample;
        // Infinitely far projection: z / w = 1 - n / z, so z = n / (1 - z / w); 1 at infinity.
        double depth = f.depth >= 1.0 ? double(Infinity) : double(n) / (1.0 - f.depth);
        if (depth >= view_depths[i]) count[i] += f.triangle->front ? -1 : 1;  // z-fail
    });
    return count;
}

}  // namespace

void shadow_volume_mask(const LocalLight& light, const RasterGeometry& g, const RasterCamera& camera, const Rasterizer& layout,
                        const std::vector<float>& view_depths, std::vector<uint8_t>& lit) {
    float reach = 4.0f * std::max(g.bbox.bounding_radius(), 1e-3f);
    VolumeBuilder vb{light, {}, 1e-3f * (light.kind == LocalLight::Kind::Directional ? reach : 1.0f)};
    int skip = light_shape(light, g);
    for (size_t s = 0; s < g.shapes.size(); ++s) {
        if (int(s) == skip) continue;
        const RasterShape& rs = g.shapes[s];
        if (rs.closed) {
            closed_mesh_volumes(vb, g, rs);
            continue;
        }
        for (uint32_t i = rs.first_triangle; i < rs.first_triangle + rs.triangle_count; ++i) {
            const glm::uvec3& t = g.triangles[i];
            vb.prism(g.positions[t.x], g.positions[t.y], g.positions[t.z]);
        }
    }
    std::vector<int16_t> count = count_volumes(vb.world, camera, layout, view_depths);
    lit.resize(view_depths.size());
    for (size_t i = 0; i < count.size(); ++i) lit[i] = count[i] == 0;
}

}  // namespace candela::raster
