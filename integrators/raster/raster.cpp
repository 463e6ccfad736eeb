// raster: renders the scene with a software rasterizer and the local illumination model of the
// lecture (what OpenGL's fixed-function pipeline computes), for side-by-side comparison with
// global illumination. Selected by <integrator type="raster"> or `candela render --mode raster`.
//
// Parameters (all optional; the command line's --shading, --reflection, ... set the same):
//   shading                string    flat, gouraud or phong (default phong)
//   reflection             string    phong (R.V lobe) or blinn (N.H lobe) (default blinn)
//   shadows                string    none, map (shadow maps) or volume (shadow volumes)
//                                    (default map)
//   aa                     integer   supersamples per pixel (default 1)
//   aa_filter              string    box (coverage average), tent or gaussian (default box)
//   texture_filter         string    nearest, bilinear or trilinear (MIP-mapped) (default trilinear)
//   wireframe              boolean   draw visible triangle edges over the image (default false)
//   light_gizmos           boolean   draw the lights: circles, spot axes, directional arrows
//   affine                 boolean   interpolate in screen space, not perspective-correct
//   backface_culling       boolean   skip triangles facing away (unless two-sided) (default false)
//   ambient                rgb       extra ambient radiance added to the environments' (default 0)
//   environment_mapping    string    latlong (look the environment up directly) or cube
//   cube_resolution        integer   faces built from the environment (default 256)
//   cube_map               string    six face images instead, "{face}" = px, nx, py, ny, pz, nz
//   shadow_map_resolution  integer   texels per side (default 1024)
//   pcf                    integer   percentage-closer filter width in texels (default 3)
//   displacement           boolean   move bump-mapped surfaces by their height field (default false)
//   subdivisions           integer   4^n refinement of displaced shapes (default 3)
//   tessellation           integer   segments per turn for spheres and disks (default 96)
//
// The lighting equation, per light with irradiance E (on a surface facing it), direction L,
// view V and normal N, is OpenGL's with physically scaled coefficients:
//   L_o = emission + kd L_ambient + mirror env(R) + transmission env(T)
//       + sum over lights of visibility * E * [ kd / pi max(N.L, 0)
//                                              + (N.L > 0) ks c_n lobe ]
// with lobe = max(N.H, 0)^n and c_n = (n + 8) / (8 pi) for Blinn-Phong, lobe = max(R.V, 0)^n and
// c_n = (n + 2) / (2 pi) for Phong. kd, ks, n, mirror and transmission come from each BSDF's
// local_shading() (documented in every BSDF file). Delta lights give E exactly as the path tracer
// computes it (falloff, attenuation); an area light acts as a point light at its centre with
// intensity L A cos(theta) (planar) or L A / 4 (other shapes); environments act as ambient
// radiance equal to their average, and are what mirrors and refractions look up.
// Flat shading lights each triangle once at its centroid with the face normal, Gouraud lights
// the vertices and interpolates, Phong lights every sample with the interpolated normal (and the
// bump- or normal-mapped frame).

#include "integrators/raster/raster.h"

#include "core/bsdf.h"
#include "core/error.h"
#include "core/mesh.h"
#include "geometry2d/raster2d.h"
#include "core/registry.h"
#include "core/scene.h"
#include "core/texture.h"
#include "integrators/raster/environment.h"
#include "integrators/raster/raster_scene.h"
#include "integrators/raster/rasterizer.h"
#include "integrators/raster/shadows.h"
#include "materials/fresnel.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <map>

namespace candela {

bool RasterSettings::set(const std::string& name, const std::string& value, std::string& error) {
    auto pick = [&](std::initializer_list<const char*> names, int& out) {
        int i = 0;
        for (const char* n : names) {
            if (value == n) {
                out = i;
                return true;
            }
            ++i;
        }
        error = name + " must be one of";
        for (const char* n : names) error += std::string(" ") + n;
        error += ", not \"" + value + "\"";
        return false;
    };
    auto integer = [&](int& out, int lo) {
        char* end = nullptr;
        long v = std::strtol(value.c_str(), &end, 10);
        if (value.empty() || *end || v < lo) {
            error = name + " must be an integer >= " + std::to_string(lo);
            return false;
        }
        out = int(v);
        return true;
    };
    auto boolean = [&](bool& out) {
        if (value != "true" && value != "false") {
            error = name + " must be true or false";
            return false;
        }
        out = value == "true";
        return true;
    };
    int e = 0;
    if (name == "shading") {
        if (!pick({"flat", "gouraud", "phong"}, e)) return false;
        shading = Shading(e);
    } else if (name == "reflection") {
        if (!pick({"phong", "blinn"}, e)) return false;
        reflection = Reflection(e);
    } else if (name == "shadows") {
        if (!pick({"none", "map", "volume"}, e)) return false;
        shadows = Shadows(e);
    } else if (name == "aa_filter") {
        if (!pick({"box", "tent", "gaussian"}, e)) return false;
        aa_filter = AAFilter(e);
    } else if (name == "texture_filter") {
        if (!pick({"nearest", "bilinear", "trilinear"}, e)) return false;
        texture_filter = TextureFilter(e);
    } else if (name == "environment_mapping") {
        if (!pick({"latlong", "cube"}, e)) return false;
        cube_mapping = e == 1;
    } else if (name == "aa") {
        return integer(aa, 1);
    } else if (name == "cube_resolution") {
        return integer(cube_resolution, 1);
    } else if (name == "shadow_map_resolution") {
        return integer(shadow_map_resolution, 16);
    } else if (name == "pcf") {
        return integer(pcf, 1);
    } else if (name == "subdivisions") {
        return integer(subdivisions, 0);
    } else if (name == "tessellation") {
        return integer(tessellation, 8);
    } else if (name == "wireframe") {
        return boolean(wireframe);
    } else if (name == "light_gizmos") {
        return boolean(light_gizmos);
    } else if (name == "affine") {
        return boolean(affine);
    } else if (name == "backface_culling") {
        return boolean(backface_culling);
    } else if (name == "displacement") {
        return boolean(displacement);
    } else if (name == "cube_map") {
        cube_map = value;
        cube_mapping = true;
    } else {
        error = "unknown raster option \"" + name + "\"";
        return false;
    }
    return true;
}

RasterIntegrator::RasterIntegrator(const Properties& props) {
    std::string error;
    auto apply = [&](const std::string& name, const std::string& value) {
        if (!settings_.set(name, value, error)) props.fail(name, error);
    };
    for (const char* name : {"shading", "reflection", "shadows", "aa_filter", "texture_filter", "environment_mapping", "cube_map"})
        if (props.has(name)) apply(name, props.get_string(name));
    for (const char* name : {"aa", "cube_resolution", "shadow_map_resolution", "pcf", "subdivisions", "tessellation"})
        if (props.has(name)) apply(name, std::to_string(props.get_int(name)));
    for (const char* name : {"wireframe", "light_gizmos", "affine", "backface_culling", "displacement"})
        if (props.has(name)) apply(name, props.get_bool(name, false) ? "true" : "false");
    if (props.has("cube_map")) settings_.cube_map = props.get_file_path("cube_map");
    settings_.ambient = props.get_rgb("ambient", Spectrum(0.0f));
}

namespace raster {
namespace {

constexpr uint32_t NoTriangle = 0xffffffffu;

// What the shading passes need at one camera sample.
struct SurfaceSample {
    uint32_t triangle = NoTriangle;
    Vec3 p{0.0f}, n{0.0f}, n_geo{0.0f}, v{0.0f};
    Vec3 bary{0.0f};
    Vec2 uv{0.0f};
    Spectrum kd{0.0f};
    bool lit_side = false;  // seen from the side the material reflects on
};

// The lighting of one light at one point (no visibility).
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

// Refraction of the view ray into a surface of relative index eta (Snell); straight through
// for eta 1; total internal reflection gives the mirror direction.
Vec3 refracted(const Vec3& v, const Vec3& n, float eta) {
    if (eta == 1.0f) return -v;
    float cos_i = glm::dot(n, v), inv = 1.0f / eta;
    float k = 1.0f - inv * inv * (1.0f - cos_i * cos_i);
    if (k < 0.0f) return 2.0f * cos_i * n - v;
    return glm::normalize(-v * inv + n * (inv * cos_i - std::sqrt(k)));
}

// Reconstruction filter weight for supersample resolve (per axis, in pixels).
float resolve_weight(RasterSettings::AAFilter f, float d) {
    d = std::abs(d);
    switch (f) {
    case RasterSettings::AAFilter::Box: return d < 0.5f ? 1.0f : 0.0f;
    case RasterSettings::AAFilter::Tent: return std::max(0.0f, 1.0f - d);
    case RasterSettings::AAFilter::Gaussian: return d < 1.5f ? std::exp(-d * d / (2.0f * 0.25f)) - std::exp(-1.5f * 1.5f / (2.0f * 0.25f)) : 0.0f;
    }
    return 0.0f;
}

// Screen-space derivatives of the perspective-correct barycentrics of a triangle at a pixel
// position, from its homogeneous 2D setup (Olano & Greer 1997): (b / w) is linear in (x, y).
struct HomogeneousSetup {
    Mat3 inverse{1.0f};
    bool valid = false;
    Vec3 at(float x, float y) const {
        Vec3 u = inverse * Vec3(x, y, 1.0f);
        float s = u.x + u.y + u.z;
        return s != 0.0f ? u / s : Vec3(1.0f / 3.0f);
    }
};

HomogeneousSetup homogeneous_setup(const Vec4 c[3], Vec2i full, Vec2i offset) {
    HomogeneousSetup h;
    Mat3 m;  // columns: vertices; rows: X, Y, W in pixel-homogeneous coordinates
    for (int i = 0; i < 3; ++i)
        m[i] = Vec3((c[i].x + c[i].w) * 0.5f * float(full.x) - float(offset.x) * c[i].w, (c[i].y + c[i].w) * 0.5f * float(full.y) - float(offset.y) * c[i].w,
                    c[i].w);
    float det = glm::determinant(m);
    if (std::abs(det) > 1e-30f && std::isfinite(det)) {
        h.inverse = glm::inverse(m);
        h.valid = true;
    }
    return h;
}

}  // namespace
}  // namespace raster

RasterIntegrator::~RasterIntegrator() = default;

RenderResult RasterIntegrator::render(const Scene& scene, const RenderOptions& options) {
    using namespace raster;
    auto t_start = std::chrono::steady_clock::now();
    if (!options.aovs.empty()) throw InputError("the raster mode renders no AOVs (albedo, normal, depth, variance come from sampling integrators)");
    auto pinhole = scene.sensor().pinhole();
    if (!pinhole) throw InputError("the raster mode needs a perspective (pinhole) camera");
    const RasterSettings& S = settings_;
    const Film& film = scene.sensor().film();
    const Vec2i full = film.full_size(), crop = film.crop_size(), offset = film.crop_offset();
    const int W = crop.x, H = crop.y;

    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    RenderResult result;
    arena.execute([&] {
        int key[3] = {S.tessellation, S.displacement ? 1 : 0, S.subdivisions};
        if (!geometry_ || geometry_scene_ != &scene || !std::equal(key, key + 3, geometry_key_)) {
            geometry_ = std::make_shared<RasterGeometry>(build_geometry(scene, S.tessellation, S.displacement, S.subdivisions));
            geometry_scene_ = &scene;
            std::copy(key, key + 3, geometry_key_);
        }
        const RasterGeometry& g = *geometry_;
        LocalLights lights = collect_lights(scene);
        const Spectrum ambient = lights.ambient + S.ambient;
        RasterCamera camera = RasterCamera::from_pinhole(*pinhole);
        std::vector<Vec2> pattern = sample_pattern(S.aa);
        const int ns = int(pattern.size());
        const size_t count = size_t(W) * H * ns;
        auto sample_index = [&](int x, int y, int s) { return (size_t(y) * W + x) * ns + s; };

        // ---- geometry pass: nearest triangle and barycentrics per sample (a G-buffer) ----
        std::vector<std::array<Vec4, 3>> clip(g.triangles.size());
        tbb::parallel_for(size_t(0), g.triangles.size(), [&](size_t i) {
            const glm::uvec3& t = g.triangles[i];
            clip[i] = {camera.clip(g.positions[t.x]), camera.clip(g.positions[t.y]), camera.clip(g.positions[t.z])};
            if (S.backface_culling && !g.shapes[g.triangle_shape[i]].material.two_sided) {
                Vec3 n = glm::cross(g.positions[t.y] - g.positions[t.x], g.positions[t.z] - g.positions[t.x]);
                if (glm::dot(n, camera.eye - g.positions[t.x]) <= 0.0f) clip[i] = {Vec4(0, 0, 0, -1), Vec4(0, 0, 0, -1), Vec4(0, 0, 0, -1)};
            }
        });
        Rasterizer rasterizer(W, H, pattern, full, offset);
        rasterizer.setup(clip, !S.affine);
        std::vector<float> depth(count, Infinity);
        std::vector<uint32_t> tri(count, NoTriangle);
        std::vector<Vec3> bary(count);
        // The z-buffer holds view depth (w), exact for a perspective camera.
        rasterizer.run([&](const Fragment& f) {
            size_t i = sample_index(f.x, f.y, f.sample);
            if (f.w < depth[i]) {
                depth[i] = float(f.w);
                tri[i] = f.triangle->id;
                bary[i] = f.bary;
            }
        });

        // ---- surface reconstruction per sample ----
        std::vector<HomogeneousSetup> setups(g.triangles.size());
        tbb::parallel_for(size_t(0), g.triangles.size(), [&](size_t i) { setups[i] = homogeneous_setup(clip[i].data(), full, offset); });
        std::vector<SurfaceSample> surf(count);
        std::vector<Spectrum> color(count, Spectrum(0.0f));
        EnvironmentLookup environment(scene, S.cube_mapping ? EnvironmentLookup::Mode::Cube : EnvironmentLookup::Mode::LatLong, S.cube_resolution,
                                      S.cube_map);
        tbb::parallel_for(0, H, [&](int y) {
            for (int x = 0; x < W; ++x)
                for (int s = 0; s < ns; ++s) {
                    size_t i = sample_index(x, y, s);
                    SurfaceSample& ss = surf[i];
                    float px = float(x) + pattern[size_t(s)].x, py = float(y) + pattern[size_t(s)].y;
                    if (tri[i] == NoTriangle) {
                        // Nothing here: the environment along the camera ray, as the path tracer sees it.
                        Ray ray = scene.sensor().sample_ray(Vec2(px + float(offset.x), py + float(offset.y)), Vec2(0.5f));
                        color[i] = scene.eval_environment(ray.d);
                        continue;
                    }
                    uint32_t t = tri[i];
                    const glm::uvec3& v = g.triangles[t];
                    const RasterShape& rs = g.shapes[g.triangle_shape[t]];
                    const Vec3& b = bary[i];
                    ss.triangle = t;
                    ss.bary = b;
                    const Vec3 &p0 = g.positions[v.x], &p1 = g.positions[v.y], &p2 = g.positions[v.z];
                    ss.p = b.x * p0 + b.y * p1 + b.z * p2;
                    ss.n_geo = glm::normalize(glm::cross(p1 - p0, p2 - p0));
                    ss.uv = b.x * g.uvs[v.x] + b.y * g.uvs[v.y] + b.z * g.uvs[v.z];
                    ss.v = glm::normalize(camera.eye - ss.p);
                    Vec3 n = S.shading == RasterSettings::Shading::Flat ? ss.n_geo : glm::normalize(b.x * g.normals[v.x] + b.y * g.normals[v.y] + b.z * g.normals[v.z]);
                    // Bump and normal maps: the BSDF's own shading frame.
                    if (S.shading == RasterSettings::Shading::Phong) {
                        SurfaceInteraction si;
                        si.p = ss.p;
                        si.n = ss.n_geo;
                        si.uv = ss.uv;
                        triangle_tangents(p0, p1, p2, g.uvs[v.x], g.uvs[v.y], g.uvs[v.z], ss.n_geo, si.dpdu, si.dpdv);
                        si.shading = Frame::from_normal_tangent(n, si.dpdu);
                        n = rs.bsdf->shading_frame(si).n;
                    }
                    bool front = glm::dot(ss.n_geo, ss.v) > 0.0f;
                    if (!front && rs.material.two_sided) {
                        n = -n;
                        ss.n_geo = -ss.n_geo;
                    }
                    ss.n = n;
                    ss.lit_side = front || rs.material.two_sided;
                    if (!ss.lit_side) continue;  // one-sided materials are black from behind
                    // Texture lookups over the sample's footprint (uv derivatives from the setup).
                    if (rs.material.diffuse) {
                        // Texture coordinates through the texture's mapping (uv or projected from the position).
                        const TextureMapping& mapping = rs.material.diffuse->mapping();
                        auto uv_at = [&](const Vec3& bb) {
                            return mapping.map(bb.x * g.uvs[v.x] + bb.y * g.uvs[v.y] + bb.z * g.uvs[v.z], bb.x * p0 + bb.y * p1 + bb.z * p2);
                        };
                        Vec2 uv = mapping.map(ss.uv, ss.p), du(0.0f), dv(0.0f);
                        if (setups[t].valid) {
                            Vec3 b0 = setups[t].at(px, py), bx = setups[t].at(px + 1.0f, py), by = setups[t].at(px, py + 1.0f);
                            du = mapping.difference(uv_at(b0), uv_at(bx));
                            dv = mapping.difference(uv_at(b0), uv_at(by));
                        }
                        ss.kd = rs.material.diffuse->eval_filtered(uv, du, dv, S.texture_filter);
                    }
                    Spectrum L(0.0f);
                    if (front) L += rs.emission;
                    L += ss.kd * ambient;
                    if (!is_black(rs.material.mirror)) L += rs.material.mirror * environment.lookup(2.0f * glm::dot(ss.n, ss.v) * ss.n - ss.v, rs.material.roughness);
                    if (!is_black(rs.material.transmission))
                        L += rs.material.transmission * environment.lookup(refracted(ss.v, ss.n, front ? rs.material.eta : 1.0f / rs.material.eta), rs.material.roughness);
                    color[i] = L;
                }
        });

        // ---- one pass per light: visibility times direct lighting ----
        std::vector<float> view_depth;
        if (S.shadows == RasterSettings::Shadows::Volume) {
            view_depth.resize(count);
            for (size_t i = 0; i < count; ++i) view_depth[i] = tri[i] == NoTriangle ? Infinity : camera.view_depth(surf[i].p);
        }
        std::vector<Spectrum> vertex_light;
        std::vector<uint8_t> lit;
        for (const LocalLight& light : lights.lights) {
            std::unique_ptr<ShadowMap> map;
            if (S.shadows == RasterSettings::Shadows::Map) map = std::make_unique<ShadowMap>(light, g, S.shadow_map_resolution);
            if (S.shadows == RasterSettings::Shadows::Volume) shadow_volume_mask(light, g, camera, rasterizer, view_depth, lit);
            if (S.shading == RasterSettings::Shading::Gouraud) {
                // Light the vertices (texture at the vertex uv), then interpolate.
                vertex_light.assign(g.positions.size(), Spectrum(0.0f));
                tbb::parallel_for(size_t(0), g.triangles.size(), [&](size_t t) {
                    const RasterShape& rs = g.shapes[g.triangle_shape[t]];
                    for (int k = 0; k < 3; ++k) {
                        unsigned vi = g.triangles[t][k];
                        Vec3 n = g.normals[vi], v = glm::normalize(camera.eye - g.positions[vi]);
                        if (rs.material.two_sided && glm::dot(n, v) < 0.0f) n = -n;
                        Spectrum kd = rs.material.diffuse ? rs.material.diffuse->eval(rs.material.diffuse->mapping().map(g.uvs[vi], g.positions[vi])) : Spectrum(0.0f);
                        vertex_light[vi] = direct_light(light, rs.material, kd, g.positions[vi], n, v, S.reflection);
                    }
                });
            }
            tbb::parallel_for(size_t(0), count, [&](size_t i) {
                const SurfaceSample& ss = surf[i];
                if (ss.triangle == NoTriangle || !ss.lit_side) return;
                float visibility = 1.0f;
                if (map) visibility = map->visibility(ss.p, ss.n_geo, S.pcf);
                if (S.shadows == RasterSettings::Shadows::Volume) visibility = lit[i] ? 1.0f : 0.0f;
                if (visibility == 0.0f) return;
                const RasterShape& rs = g.shapes[g.triangle_shape[ss.triangle]];
                Spectrum d;
                if (S.shading == RasterSettings::Shading::Gouraud) {
                    const glm::uvec3& v = g.triangles[ss.triangle];
                    d = ss.bary.x * vertex_light[v.x] + ss.bary.y * vertex_light[v.y] + ss.bary.z * vertex_light[v.z];
                } else if (S.shading == RasterSettings::Shading::Flat) {
                    const glm::uvec3& v = g.triangles[ss.triangle];
                    Vec3 c = (g.positions[v.x] + g.positions[v.y] + g.positions[v.z]) / 3.0f;
                    Vec2 uvc = (g.uvs[v.x] + g.uvs[v.y] + g.uvs[v.z]) / 3.0f;
                    Spectrum kd = rs.material.diffuse ? rs.material.diffuse->eval(rs.material.diffuse->mapping().map(uvc, c)) : Spectrum(0.0f);
                    d = direct_light(light, rs.material, kd, c, ss.n_geo, glm::normalize(camera.eye - c), S.reflection);
                } else {
                    d = direct_light(light, rs.material, ss.kd, ss.p, ss.n, ss.v, S.reflection);
                }
                color[i] += visibility * d;
            });
        }

        // ---- resolve the supersamples ----
        Image img = Image::rgb(W, H);
        const int reach = S.aa_filter == RasterSettings::AAFilter::Box ? 0 : (S.aa_filter == RasterSettings::AAFilter::Tent ? 1 : 2);
        tbb::parallel_for(0, H, [&](int y) {
            for (int x = 0; x < W; ++x) {
                Spectrum sum(0.0f);
                float wsum = 0.0f;
                for (int yy = std::max(0, y - reach); yy <= std::min(H - 1, y + reach); ++yy)
                    for (int xx = std::max(0, x - reach); xx <= std::min(W - 1, x + reach); ++xx)
                        for (int s = 0; s < ns; ++s) {
                            float dx = float(xx) + pattern[size_t(s)].x - (float(x) + 0.5f), dy = float(yy) + pattern[size_t(s)].y - (float(y) + 0.5f);
                            float w = resolve_weight(S.aa_filter, dx) * resolve_weight(S.aa_filter, dy);
                            if (w <= 0.0f) continue;
                            sum += w * color[sample_index(xx, yy, s)];
                            wsum += w;
                        }
                img.set_rgb(x, y, wsum > 0.0f ? sum / wsum : Spectrum(0.0f));
            }
        });

        // ---- overlays ----
        auto project = [&](const Vec3& p, Vec2& px, float& view_z) {
            Vec4 c = camera.clip(p);
            view_z = camera.view_depth(p);
            if (!(c.w > camera.near_clip * 0.5f)) return false;
            px = Vec2((c.x / c.w + 1.0f) * 0.5f * float(full.x) - float(offset.x), (c.y / c.w + 1.0f) * 0.5f * float(full.y) - float(offset.y));
            return true;
        };
        auto put = [&](int x, int y, const Spectrum& c) {
            if (x >= 0 && y >= 0 && x < W && y < H) img.set_rgb(x, y, c);
        };
        if (S.wireframe) {
            // Visible edges: depth-tested against the nearest surface at the pixel (its first
            // sample), with a tolerance relative to the depth.
            std::vector<float> pixel_depth(size_t(W) * H, Infinity);
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    size_t i = sample_index(x, y, 0);
                    if (tri[i] != NoTriangle) pixel_depth[size_t(y) * W + x] = camera.view_depth(surf[i].p);
                }
            const Spectrum ink(1.0f, 0.85f, 0.2f);
            for (const glm::uvec3& t : g.triangles)
                for (int k = 0; k < 3; ++k) {
                    Vec2 a, b;
                    float za, zb;
                    if (!project(g.positions[t[k]], a, za) || !project(g.positions[t[(k + 1) % 3]], b, zb)) continue;
                    int x0 = int(std::floor(a.x)), y0 = int(std::floor(a.y)), x1 = int(std::floor(b.x)), y1 = int(std::floor(b.y));
                    int steps = std::max({std::abs(x1 - x0), std::abs(y1 - y0), 1}), step = 0;
                    raster2d::line_bresenham(x0, y0, x1, y1, [&](int x, int y) {
                        // 1/z is linear in screen space.
                        float f = float(step++) / float(steps);
                        float z = 1.0f / ((1.0f - f) / za + f / zb);
                        if (x < 0 || y < 0 || x >= W || y >= H) return;
                        if (z <= pixel_depth[size_t(y) * W + x] * 1.002f + 1e-4f) put(x, y, ink);
                    });
                }
        }
        if (S.light_gizmos) {
            const Spectrum gizmo(1.0f, 1.0f, 0.0f);
            float radius = std::max(g.bbox.bounding_radius(), 1e-3f);
            for (const LocalLight& light : lights.lights) {
                Vec2 a, b;
                float za, zb;
                if (light.kind == LocalLight::Kind::Directional) {
                    Vec3 start = g.bbox.center() - light.direction * radius, end = start + light.direction * (0.4f * radius);
                    if (project(start, a, za) && project(end, b, zb)) {
                        raster2d::line_bresenham(int(a.x), int(a.y), int(b.x), int(b.y), [&](int x, int y) { put(x, y, gizmo); });
                        raster2d::circle_midpoint(int(a.x), int(a.y), 3, [&](int x, int y) { put(x, y, gizmo); });
                    }
                    continue;
                }
                if (!project(light.position, a, za)) continue;
                raster2d::circle_midpoint(int(a.x), int(a.y), 6, [&](int x, int y) { put(x, y, gizmo); });
                if (light.kind == LocalLight::Kind::Spot || light.kind == LocalLight::Kind::AreaPoint) {
                    if (project(light.position + light.direction * (0.25f * radius), b, zb))
                        raster2d::line_bresenham(int(a.x), int(a.y), int(b.x), int(b.y), [&](int x, int y) { put(x, y, gizmo); });
                }
            }
        }
        result.image = std::move(img);
        result.stats.samples = count;
    });
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    result.stats.spp = S.aa;
    return result;
}

CANDELA_REGISTER(RasterIntegrator, ObjectKind::Integrator, "raster");

}  // namespace candela
