// The ambient pass: the diffuse light that does not come from the local model's lights, added
// to every lit sample:
//   local lighting:  kd / pi * AO * (E_env(n) + pi * ambient)
//                    E_env: the environment's irradiance from its nine SH coefficients
//                    (image-based lighting), or pi times its average radiance
//                    (environment_lighting average)
//   baked lighting:  kd / pi * E_baked, the irradiance baked at the patch vertices (the side the
//                    camera sees), interpolated; it holds every light's diffuse contribution
//                    with its shadows and interreflections, so neither AO nor the lights' diffuse
//                    terms apply (the lights pass adds only highlights)
// AO (ao > 0 rays): ray-cast ambient occlusion. From the sample's G-buffer position, `ao`
// cosine-weighted directions around its shading normal are traced through the scene's Embree
// BVH (the exact geometry, as the `ao` integrator traces it) up to ao_ray_length; AO is the
// fraction that meet nothing (directions below the face count as blocked). The rays leave the
// tessellated surface by its tessellation_gap, so a sphere does not occlude itself. The random
// numbers of sample k of pixel (x, y) depend only on (x, y, k) of the full film: deterministic,
// independent of threads and crop.

#include "core/mesh.h"
#include "core/parallel.h"
#include "core/rng.h"
#include "core/sampler.h"
#include "core/warp.h"
#include "integrators/raster/frame.h"

namespace candela::raster {

namespace {

constexpr uint64_t OcclusionSeed = 0x616d6269656e74ULL;  // "ambient"

// The fraction of `rays` cosine-weighted directions around the sample's shading normal that
// meet nothing within `reach`.
float ambient_occlusion(const FrameSetup& f, const FrameBuffers& b, size_t i, const Vec2i& pixel, int k, float reach) {
    const RasterGeometry& g = f.geometry;
    const SurfaceSample& ss = b.surface[i];
    const glm::uvec3& t = g.triangles[b.triangle[i]];
    const Vec3 &p0 = g.positions[t.x], &p1 = g.positions[t.y], &p2 = g.positions[t.z];
    float gap = tessellation_gap(p0, p1, p2, g.normals[t.x], g.normals[t.y], g.normals[t.z]);
    // The float error of the interpolated position (as for a ray hit), or the gap when larger.
    float scale = std::max({max_abs_component(p0), max_abs_component(p1), max_abs_component(p2)});
    float p_error = std::max(gamma_bound(16) * scale, gap / OffsetSafety);
    PCG32 rng;
    seed_for_sample(rng, OcclusionSeed, Vec2i(pixel.x + f.offset.x, pixel.y + f.offset.y), uint32_t(k));
    const Frame frame(ss.n);
    int open = 0;
    for (int r = 0; r < f.settings.ao; ++r) {
        float u1 = rng.next_float(), u2 = rng.next_float();
        Vec3 d = frame.to_world(warp::square_to_cosine_hemisphere(Vec2(u1, u2)));
        if (glm::dot(d, ss.n_geo) <= 0.0f) continue;
        Ray ray(offset_ray_origin(ss.p, p_error, ss.n_geo, d), d);
        ray.tmax = reach;
        ray.time = f.scene.sensor().shutter_open();  // the instant the frame draws
        if (!f.scene.occluded(ray)) ++open;
    }
    return float(open) / float(f.settings.ao);
}

// The baked irradiance at sample i, on the side the camera sees.
Spectrum baked_irradiance(const FrameSetup& f, const FrameBuffers& b, size_t i) {
    const RasterGeometry& g = f.geometry;
    const std::vector<Spectrum>& side = b.surface[i].front ? g.baked_front : g.baked_back;
    const glm::uvec3& t = g.triangles[b.triangle[i]];
    const Vec3& w = b.bary[i];
    return w.x * side[t.x] + w.y * side[t.y] + w.z * side[t.z];
}

}  // namespace

void ambient_pass(const FrameSetup& f, FrameBuffers& b) {
    const RasterSettings& s = f.settings;
    const bool baked = s.lighting == RasterSettings::Lighting::Baked && !f.geometry.baked_front.empty();
    const float reach = s.ao_ray_length > 0.0f ? s.ao_ray_length : 0.5f * f.scene.bbox().bounding_radius();
    const Spectrum extra = Pi * s.ambient;
    if (!baked && !f.image_lighting && is_black(f.ambient)) return;  // no ambient light to add
    parallel_for(size_t(f.height), [&](int y) {
        for (int x = 0; x < f.width; ++x)
            for (int k = 0; k < f.samples_per_pixel(); ++k) {
                size_t i = f.sample_index(x, y, k);
                const SurfaceSample& ss = b.surface[i];
                if (b.triangle[i] == NoTriangle || !ss.lit_side || is_black(ss.kd)) continue;
                Spectrum E;
                if (baked) {
                    E = baked_irradiance(f, b, i);
                } else {
                    E = f.image_lighting ? f.image_lighting->irradiance(ss.n) + extra : Pi * f.ambient;
                    if (s.ao > 0 && !is_black(E)) E *= ambient_occlusion(f, b, i, Vec2i(x, y), k, reach);
                }
                b.color[i] += ss.kd * InvPi * E;
            }
    });
}

}  // namespace candela::raster
