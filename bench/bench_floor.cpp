// bench_floor: the floor under the path tracer's time per ray, and what each piece of
// Candela's generality adds to it.
//
//   bench_floor [SCENE.xml] [--threads N] [--spp N] [--rounds N] [--sampler NAME] [--vector-lights]
//               [--candela-shading]
//
// The floor is a minimal path tracer written for one kind of scene only: diffuse BSDFs of
// constant reflectance and one rectangle area light of constant radiance (the Cornell box). It
// traces the same camera rays with the same estimator as `path` (next-event estimation and BSDF
// sampling combined by the power heuristic, Russian roulette from depth 5 with q = min(max beta,
// 0.95)) on the same Embree scene, but with tables indexed by Embree's geometry id, a fixed ray
// offset, uniform area sampling of the light and Embree called directly. Three variants put one
// of Candela's own pieces back in at a time:
//   lights   the light's sample_direction/pdf_direction (solid-angle sampling of a rectangle
//            close by, area sampling far away)
//   hits     Scene::intersect (the hit's SurfaceInteraction: shading frame, uv, error bounds)
//   shadows  shadow rays through Scene::transmittance, offset by both ends' error bounds
// and a fourth puts all three in. A sixth, the wavefront floor (below), is the floor rebuilt as a
// wavefront: 16-ray packets and shading written for vectors. With --sampler a seventh, the generic
// wave, takes its numbers from Candela's sampler and its light sample from Candela's emitter, lane
// by lane (--vector-lights: the rectangle's sampling in vectors instead, in both waves;
// --candela-shading: every lane shaded through Candela's scalar interfaces). Each round renders
// the scene with Candela's integrator and then the floors, side by side; it prints rays per
// second, rays per sample and image means (the same estimand: they agree to the noise) and, last,
// the medians of each floor's Mrays/s over Candela's. Issue 34 asks the path tracer for 0.85 of raw Embree's rate (bench_throughput);
// the floor says how much of the rest is Embree and how much is shading.
// It prints figures and asserts nothing. Scenes of any other kind are refused, with the reason.

#include "bench/bench_args.h"
#include "core/bsdf.h"
#include "core/emitter.h"
#include "core/film.h"
#include "core/integrator.h"
#include "core/parallel.h"
#include "core/rng.h"
#include "core/scene.h"
#include "core/sensor.h"
#include "core/shape.h"
#include "core/warp.h"
#include "core/xml.h"
#include "integrators/direct_lighting.h"
#include "lights/light_sampler.h"

#include <embree3/rtcore.h>
#include <immintrin.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

using namespace candela;

namespace {

enum Piece : unsigned { Lights = 1, Hits = 2, Shadows = 4 };

// What the floor knows about the scene, by Embree geometry id.
struct FloorScene {
    const Scene* scene = nullptr;
    RTCScene embree = nullptr;
    std::vector<Spectrum> albedo, emission;
    const Shape* light_shape = nullptr;
    unsigned light_geometry = 0;  // its Embree geometry id
    const Emitter* light = nullptr;
    Spectrum radiance{0.0f};
    Vec3 corner{0.0f}, edge_x{0.0f}, edge_y{0.0f}, light_normal{0.0f};
    float light_area = 0.0f;
};

FloorScene describe(const Scene& scene) {
    FloorScene fs;
    fs.scene = &scene;
    fs.embree = scene.accel().scene();
    SurfaceInteraction probe;
    probe.shading = Frame(Vec3(0.0f, 0.0f, 1.0f));
    for (unsigned id = 0; const Shape* shape = scene.accel().shape(id); ++id) {
        if (!shape->bsdf() || shape->bsdf()->to_string() != "diffuse")
            throw std::runtime_error("every shape needs a diffuse BSDF (" + shape->to_string() + " has another)");
        probe.shape = shape;
        probe.uv = Vec2(0.25f, 0.75f);
        Spectrum a = shape->bsdf()->albedo(probe);
        probe.uv = Vec2(0.75f, 0.25f);
        if (a != shape->bsdf()->albedo(probe)) throw std::runtime_error("a reflectance varies over its shape");
        fs.albedo.push_back(a);
        fs.emission.push_back(Spectrum(0.0f));
        if (!shape->emitter()) continue;
        if (fs.light || shape->to_string() != "rectangle" || shape->emitter()->to_string() != "area")
            throw std::runtime_error("the scene needs exactly one light, an area rectangle");
        fs.light_shape = shape;
        fs.light_geometry = id;
        fs.light = shape->emitter();
        fs.radiance = fs.emission.back() = shape->emitter()->eval(probe);
        probe.uv = Vec2(0.25f, 0.75f);
        if (fs.radiance != shape->emitter()->eval(probe)) throw std::runtime_error("the light's radiance varies over its surface");
        PositionSample c = shape->sample_position(Vec2(0.0f)), x = shape->sample_position(Vec2(1.0f, 0.0f)),
                       y = shape->sample_position(Vec2(0.0f, 1.0f));
        fs.corner = c.p, fs.edge_x = x.p - c.p, fs.edge_y = y.p - c.p, fs.light_normal = c.n;
        fs.light_area = shape->surface_area();
    }
    if (!fs.light || scene.emitters().size() != 1) throw std::runtime_error("the scene needs exactly one light, an area rectangle");
    return fs;
}

// An orthonormal basis around n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
void basis(const Vec3& n, Vec3& b1, Vec3& b2) {
    float sign = std::copysign(1.0f, n.z), a = -1.0f / (sign + n.z), b = n.x * n.y * a;
    b1 = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    b2 = Vec3(b, sign + n.y * n.y * a, -n.y);
}

// A fixed relative offset along the normal: enough for the box's planes, not a general rule.
Vec3 lift(const Vec3& p, const Vec3& n) { return p + n * (1e-4f * (1.0f + max_abs_component(p))); }

struct Hit {
    unsigned id = 0;
    Vec3 p{0.0f}, n{0.0f};
    float t = 0.0f;
};

bool closest_hit(const FloorScene& fs, unsigned pieces, const Ray& ray, Hit& hit) {
    if (pieces & Hits) {
        SurfaceInteraction si;
        if (!fs.scene->intersect(ray, si)) return false;
        while (fs.scene->accel().shape(hit.id) != si.shape) ++hit.id;
        hit.p = si.p, hit.n = si.n, hit.t = si.t;
        return true;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x, rh.ray.org_y = ray.o.y, rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x, rh.ray.dir_y = ray.d.y, rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = 0.0f, rh.ray.tfar = Infinity, rh.ray.time = 0.0f;
    rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(fs.embree, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.id = rh.hit.geomID;
    hit.n = glm::normalize(Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
    hit.t = rh.ray.tfar;
    hit.p = ray.o + hit.t * ray.d;
    return true;
}

// Whether the segment from `from` (lifted off its surface) to `target` on the light is clear.
bool visible(const FloorScene& fs, unsigned pieces, const Vec3& from, const Vec3& n, const Vec3& target) {
    if (pieces & Shadows) {
        SurfaceInteraction at;
        at.p = from, at.n = n, at.p_error = 1e-6f * (1.0f + max_abs_component(from));
        return !is_black(fs.scene->transmittance(at.spawn_ray_to(target, fs.light_normal, 1e-6f)));
    }
    Vec3 o = lift(from, n), d = target - o;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    r.org_x = o.x, r.org_y = o.y, r.org_z = o.z;
    r.dir_x = d.x, r.dir_y = d.y, r.dir_z = d.z;
    r.tnear = 0.0f, r.tfar = 1.0f - 1e-4f, r.time = 0.0f;
    r.mask = 0xFFFFFFFFu, r.id = 0, r.flags = 0;
    rtcOccluded1(fs.embree, &context, &r);
    return r.tfar >= 0.0f;
}

float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }

// The light's density in solid angle at `target` seen from `from`.
float light_pdf(const FloorScene& fs, unsigned pieces, const Vec3& from, const Vec3& n, const Vec3& target) {
    Vec3 to = target - from;
    float d2 = glm::dot(to, to), dist = std::sqrt(d2);
    if (pieces & Lights) {
        SurfaceInteraction ref;
        ref.p = from, ref.n = n;
        DirectionSample ds;
        ds.p = target, ds.n = fs.light_normal, ds.dist = dist, ds.d = to / dist;
        return fs.light->pdf_direction(ref, ds);
    }
    float cos_light = -glm::dot(fs.light_normal, to) / dist;
    return cos_light > 0.0f ? d2 / (cos_light * fs.light_area) : 0.0f;
}

// One camera path's radiance; counts the rays it traces.
Spectrum trace(const FloorScene& fs, unsigned pieces, Ray ray, PCG32& rng, long long& rays) {
    Spectrum beta(1.0f), L(0.0f);
    float bsdf_pdf = 0.0f;
    Vec3 from(0.0f), from_n(0.0f);
    for (int depth = 0;; ++depth) {
        Hit hit;
        ++rays;
        if (!closest_hit(fs, pieces, ray, hit)) break;
        Vec3 n = hit.n;
        if (!is_black(fs.emission[hit.id]) && glm::dot(n, ray.d) < 0.0f) {
            float w = depth == 0 ? 1.0f : power_heuristic(bsdf_pdf, light_pdf(fs, pieces, from, from_n, hit.p));
            L += beta * fs.emission[hit.id] * w;
        }
        if (glm::dot(n, ray.d) > 0.0f) n = -n;
        const Spectrum& albedo = fs.albedo[hit.id];
        // Next-event estimation.
        float u0 = rng.next_float(), u1 = rng.next_float();
        Vec3 target;
        float pdf;
        if (pieces & Lights) {
            SurfaceInteraction ref;
            ref.p = hit.p, ref.n = n;
            Spectrum weight;
            DirectionSample ds = fs.light->sample_direction(ref, Vec2(u0, u1), weight);
            target = ds.p, pdf = ds.pdf;
        } else {
            target = fs.corner + u0 * fs.edge_x + u1 * fs.edge_y;
            pdf = light_pdf(fs, 0u, hit.p, n, target);
        }
        Vec3 to = target - hit.p;
        float cos_surface = glm::dot(n, to);
        if (cos_surface > 0.0f && pdf > 0.0f) {
            cos_surface /= glm::length(to);
            ++rays;
            if (visible(fs, pieces, hit.p, n, target))
                L += beta * albedo * fs.radiance * (InvPi * cos_surface * power_heuristic(pdf, cos_surface * InvPi) / pdf);
        }
        // BSDF sampling.
        Vec3 local = warp::square_to_cosine_hemisphere(Vec2(rng.next_float(), rng.next_float())), b1, b2;
        basis(n, b1, b2);
        bsdf_pdf = local.z * InvPi;
        beta *= albedo;
        if (depth + 1 >= 5) {
            float q = std::min(max_component(beta), 0.95f);
            if (!(rng.next_float() < q)) break;
            beta /= q;
        }
        from = hit.p, from_n = n;
        ray = Ray(lift(hit.p, n), local.x * b1 + local.y * b2 + local.z * n);
    }
    return L;
}

struct FloorRun {
    double mrays = 0.0, rays_per_sample = 0.0, mean = 0.0;
};

// Times render_rows(y0, y1, row_sums, rays) over the film's rows in parallel: each call renders
// rows [y0, y1) at `spp`, adds each row's mean radiance times its sample count to row_sums[y] and
// counts the rays it traced.
template <class RenderRows>
FloorRun time_rows(const FloorScene& fs, int spp, tbb::task_arena& arena, const RenderRows& render_rows) {
    Vec2i size = fs.scene->sensor().film().full_size();
    std::atomic<long long> rays{0};
    std::vector<double> row_sums(size_t(size.y), 0.0);
    auto t0 = std::chrono::steady_clock::now();
    arena.execute([&] {
        parallel_chunks(size_t(size.y), 1, [&](size_t y0, size_t y1) {
            long long local_rays = 0;
            render_rows(y0, y1, row_sums, local_rays);
            rays += local_rays;
        });
    });
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double samples = double(size.x) * size.y * spp, total = 0.0;
    for (double r : row_sums) total += r;
    return {double(rays.load()) / seconds * 1e-6, double(rays.load()) / samples, total / samples};
}

FloorRun render_floor(const FloorScene& fs, unsigned pieces, int spp, tbb::task_arena& arena) {
    const Sensor& sensor = fs.scene->sensor();
    const int width = sensor.film().full_size().x;
    return time_rows(fs, spp, arena, [&](size_t y0, size_t y1, std::vector<double>& row_sums, long long& rays) {
        for (size_t y = y0; y < y1; ++y)
            for (int x = 0; x < width; ++x)
                for (int s = 0; s < spp; ++s) {
                    PCG32 rng((y * width + x) * uint64_t(spp) + s, 7);
                    Vec2 film_pos(float(x) + rng.next_float(), float(y) + rng.next_float());
                    Spectrum L = trace(fs, pieces, sensor.sample_ray(film_pos, Vec2(0.5f)), rng, rays);
                    row_sums[y] += average(L);
                }
    });
}

// ---- The wavefront floor ---------------------------------------------------------------------
// The floor's estimator again (area sampling of the light, fixed offsets, tables by geometry id),
// but the paths of a film row advance together, bounce by bounce, as pbrt-v4's wavefront
// integrator and Mitsuba's vectorized variants do:
//   - their state is structure of arrays, laid out so that Embree's 16-ray packets are the state
//     itself (nothing is copied into or out of a packet), and every ray of a bounce is traced by
//     rtcIntersect16 or rtcOccluded16;
//   - the shading is written for vectors (GCC's vector extensions, 4 lanes: the baseline
//     x86-64's SSE, so no other build flags), every branch a select;
//   - paths that end are compacted away after each bounce.
// Its random numbers are hashed from (path, dimension), so that a path's numbers do not depend on
// the batch it travels in; they are not the scalar floor's PCG32 streams, so the images agree in
// mean, not pixel by pixel. It answers issue 34's question of what a wavefront design gains on
// Debian's Embree before any of Candela's generality is put back.

// A 32-bit integer hash (Wellons' "lowbias32"), for one number (uint32_t) or a vector of them (VU).
// Not core/rng.h's 64-bit mixers: 64-bit multiplies have no SSE2 instruction, 32-bit ones do.
template <class U>
U hash32(U x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}
// The 24 bits of path `path`'s number in dimension `dim` (hashed_float and vhashed_float scale them
// to [0, 1)).
template <class U>
U hashed_bits(U path, U dim) {
    return hash32(path * 0x9e3779b9u + hash32(dim + 0x632be5abu)) >> 8;
}
inline float hashed_float(uint32_t path, uint32_t dim) { return float(hashed_bits(path, dim)) * 0x1p-24f; }

// Embree reads a packet's valid mask with aligned vector loads.
struct alignas(64) ValidMask16 {
    int lane[16];
};

// A row's paths: lane i is lane i % 16 of packet i / 16.
struct WaveState {
    std::vector<RTCRayHit16> rays;  // extension rays and their hits
    std::vector<RTCRay16> shadows;  // each path's shadow ray
    std::vector<ValidMask16> valid, shadow_valid;
    std::vector<float> beta_r, beta_g, beta_b, L_r, L_g, L_b, bsdf_pdf, nee_r, nee_g, nee_b;
    std::vector<float> from_x, from_y, from_z, from_nx, from_ny, from_nz;  // the vertex before
    // Between the passes of a bounce: the hit (normal on the side the ray came from), the
    // vertex's numbers, the light sample, and the light's density at the hit from the vertex before.
    std::vector<float> px, py, pz, nx, ny, nz, u0, u1, u2, u3, u4, tx, ty, tz, light_pdf, light_pdf_hit;
    std::vector<int32_t> hit, front;
    std::vector<uint32_t> path, depth;
    std::vector<uint8_t> alive;
    std::vector<SamplerState> sampler_state;  // the generic variant's: where each path's sample stands
    void resize(size_t n) {
        size_t packets = (n + 15) / 16, lanes = packets * 16;
        rays.resize(packets), shadows.resize(packets), valid.resize(packets), shadow_valid.resize(packets);
        for (auto* v : {&beta_r, &beta_g, &beta_b,  &L_r,     &L_g,     &L_b, &bsdf_pdf, &nee_r, &nee_g,     &nee_b,        &from_x,
                        &from_y, &from_z, &from_nx, &from_ny, &from_nz, &px,  &py,       &pz,    &nx,        &ny,           &nz,
                        &u0,     &u1,     &u2,      &u3,      &u4,      &tx,  &ty,       &tz,    &light_pdf, &light_pdf_hit})
            v->resize(lanes);
        hit.resize(lanes), front.resize(lanes), path.resize(lanes), depth.resize(lanes), alive.resize(lanes), sampler_state.resize(lanes);
    }
};

// Lane l of a packet takes `ray`'s origin and direction.
void put_ray(RTCRay16& packet, size_t l, const Ray& ray) {
    packet.org_x[l] = ray.o.x, packet.org_y[l] = ray.o.y, packet.org_z[l] = ray.o.z;
    packet.dir_x[l] = ray.d.x, packet.dir_y[l] = ray.d.y, packet.dir_z[l] = ray.d.z;
}

// Four lanes as one SSE vector; comparisons give lane masks, `mask ? a : b` selects.
typedef float VF __attribute__((vector_size(16)));
typedef int32_t VI __attribute__((vector_size(16)));
typedef uint32_t VU __attribute__((vector_size(16)));
constexpr int Width = 4;

inline VF load(const float* p) {
    VF v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline VU load(const uint32_t* p) {
    VU v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline VI load(const int32_t* p) {
    VI v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store(float* p, const VF& v) { std::memcpy(p, &v, sizeof v); }
inline void store(int32_t* p, const VI& v) { std::memcpy(p, &v, sizeof v); }
inline VF splat(float x) { return VF{} + x; }
inline VF vsqrt(const VF& v) {
    __m128 q;
    std::memcpy(&q, &v, sizeof q);
    q = _mm_sqrt_ps(q);
    VF r;
    std::memcpy(&r, &q, sizeof r);
    return r;
}
inline VF vmin(const VF& a, const VF& b) { return a < b ? a : b; }
inline VF vmax(const VF& a, const VF& b) { return a > b ? a : b; }
inline VF vabs(const VF& a) { return a < 0.0f ? -a : a; }
inline VF vhashed_float(const VU& path, const VU& dim) { return __builtin_convertvector(hashed_bits(path, dim), VF) * 0x1p-24f; }

// A bounce of lanes [0, n), after their extension rays were traced, in three passes:
//   hits     (vector) the hit point and the normal on the side the ray came from;
//   samples  the vertex's numbers, a point on the light and its density, and the light's density
//            at the hit seen from the vertex before (for the emission's MIS weight): by vectors
//            (hashed numbers, uniform area sampling) in the wavefront floor, or lane by lane
//            through Candela's Sampler and Emitter in its generic variant;
//   shade    (vector) the emission found, the light sample's contribution and shadow ray, the
//            cosine-weighted BSDF sample (the concentric disk with both of its cases computed and
//            one selected, Candela's polynomial sine and cosine) and the roulette.
// Vertex k draws its own dimensions: light point (2), direction (2), roulette.
// for_lanes calls pass(packet, first lane within it, first lane overall, mask of the Width lanes
// below n) for each group of Width lanes.
template <class Pass>
void for_lanes(size_t n, const Pass& pass) {
    for (size_t i0 = 0; i0 < n; i0 += Width) {
        VI lane;
        for (int l = 0; l < Width; ++l) lane[l] = int(i0) + l;
        pass(i0 / 16, int(i0 % 16), i0, lane < int(n));
    }
}

void wave_hits(const FloorScene& fs, WaveState& w, size_t n) {
    const uint32_t geometries = uint32_t(fs.albedo.size());
    for_lanes(n, [&](size_t b, int o, size_t i0, VI valid) {
        const RTCRayHit16& rh = w.rays[b];
        const VI hit = valid & (load(rh.hit.geomID + o) < geometries);
        const VF dx = load(rh.ray.dir_x + o), dy = load(rh.ray.dir_y + o), dz = load(rh.ray.dir_z + o);
        const VF t = hit ? load(rh.ray.tfar + o) : VF{};
        VF nx = load(rh.hit.Ng_x + o), ny = load(rh.hit.Ng_y + o), nz = load(rh.hit.Ng_z + o);
        const VF inv_n = 1.0f / vsqrt(vmax(nx * nx + ny * ny + nz * nz, splat(1e-30f)));
        nx *= inv_n, ny *= inv_n, nz *= inv_n;
        const VF cos_in = nx * dx + ny * dy + nz * dz, flip = cos_in > 0.0f ? splat(-1.0f) : splat(1.0f);
        store(&w.px[i0], load(rh.ray.org_x + o) + t * dx), store(&w.py[i0], load(rh.ray.org_y + o) + t * dy);
        store(&w.pz[i0], load(rh.ray.org_z + o) + t * dz);
        store(&w.nx[i0], nx * flip), store(&w.ny[i0], ny * flip), store(&w.nz[i0], nz * flip);
        store(&w.hit[i0], hit), store(&w.front[i0], hit & (cos_in < 0.0f));
    });
}

void wave_samples_floor(const FloorScene& fs, WaveState& w, size_t n) {
    const Vec3 corner = fs.corner, ex = fs.edge_x, ey = fs.edge_y, ln = fs.light_normal;
    const float area = fs.light_area;
    for_lanes(n, [&](size_t b, int o, size_t i0, VI) {
        const RTCRayHit16& rh = w.rays[b];
        const VU path = load(&w.path[i0]), dim = 2u + 5u * load(&w.depth[i0]);
        const VF u0 = vhashed_float(path, dim), u1 = vhashed_float(path, dim + 1u);
        store(&w.u0[i0], u0), store(&w.u1[i0], u1), store(&w.u2[i0], vhashed_float(path, dim + 2u));
        store(&w.u3[i0], vhashed_float(path, dim + 3u)), store(&w.u4[i0], vhashed_float(path, dim + 4u));
        // A uniform point on the light, and its density in solid angle.
        const VF tx = corner.x + u0 * ex.x + u1 * ey.x, ty = corner.y + u0 * ex.y + u1 * ey.y, tz = corner.z + u0 * ex.z + u1 * ey.z;
        const VF vx = tx - load(&w.px[i0]), vy = ty - load(&w.py[i0]), vz = tz - load(&w.pz[i0]);
        const VF d2 = vx * vx + vy * vy + vz * vz, cos_light = -(ln.x * vx + ln.y * vy + ln.z * vz) / vsqrt(d2);
        store(&w.tx[i0], tx), store(&w.ty[i0], ty), store(&w.tz[i0], tz);
        store(&w.light_pdf[i0], cos_light > 0.0f ? d2 / (cos_light * area) : VF{});
        // The same density at the hit, seen from the ray's origin (the lifted vertex before).
        const VF dx = load(rh.ray.dir_x + o), dy = load(rh.ray.dir_y + o), dz = load(rh.ray.dir_z + o), t = load(rh.ray.tfar + o);
        const VF cos_light_hit = -(ln.x * dx + ln.y * dy + ln.z * dz);
        store(&w.light_pdf_hit[i0], cos_light_hit > 0.0f ? t * t / (cos_light_hit * area) : VF{});
    });
}

// acos by Abramowitz and Stegun 4.4.46 (|error| <= 2e-8 on [0, 1]), reflected for x < 0.
inline VF vacos(VF x) {
    x = vmin(vmax(x, splat(-1.0f)), splat(1.0f));
    const VF a = vabs(x);
    const VF p = 1.5707963050f +
                 a * (-0.2145988016f +
                      a * (0.0889789874f +
                           a * (-0.0501743046f + a * (0.0308918810f + a * (-0.0170881256f + a * (0.0066700901f + a * -0.0012624911f))))));
    const VF r = vsqrt(vmax(1.0f - a, VF{})) * p;
    return x < 0.0f ? Pi - r : r;
}
// sin and cos of any x: the nearest multiple n of pi/2 taken out (two-part constant), the rest
// by the quarter-circle polynomials, the quadrant n mod 4 choosing and signing them.
inline void vsincos(const VF& x, VF& s, VF& c) {
    const VF nf = __builtin_convertvector(__builtin_convertvector(x * (2.0f / Pi) + (x < 0.0f ? splat(-0.5f) : splat(0.5f)), VI), VF);
    const VF r = (x - nf * 1.57079637050628662109375f) - nf * -4.37113900018624283e-8f, r2 = r * r;
    const VF sr = r + r * r2 * (-1.6666654611e-1f + r2 * (8.3321608736e-3f + r2 * -1.9515295891e-4f));
    const VF cr = 1.0f - 0.5f * r2 + r2 * r2 * (4.166664568298827e-2f + r2 * (-1.388731625493765e-3f + r2 * 2.443315711809948e-5f));
    const VI q = __builtin_convertvector(nf, VI) & 3;
    const VI swap = (q & 1) != 0;
    const VF ss = swap ? cr : sr, cc = swap ? sr : cr;
    s = (q >= 2) ? -ss : ss;
    c = ((q == 1) | (q == 2)) ? -cc : cc;
}

// The rectangle light's sample as Rectangle::sample_direction takes it, for 4 lanes at once:
// uniform in solid angle (Urena et al. 2013) where the estimated solid angle A |z0| / r^3 is at
// least 0.1 sr, uniform by area elsewhere (both computed, one selected), nothing for points behind
// it. Reads u0, u1 and the hit; writes the light point and its density. An orthogonal rectangle
// only (run() checks).
void wave_lights_vector(const FloorScene& fs, WaveState& w, size_t n) {
    const Vec3 corner = fs.corner, ex = fs.edge_x, ey = fs.edge_y;
    const float len_x = glm::length(ex), len_y = glm::length(ey);
    const Vec3 xa = ex / len_x, ya = ey / len_y, za = glm::cross(xa, ya), centre = corner + 0.5f * (ex + ey), ln = fs.light_normal;
    const float area = fs.light_area, k = 0.1f;
    for_lanes(n, [&](size_t, int, size_t i0, VI) {
        const VF px = load(&w.px[i0]), py = load(&w.py[i0]), pz = load(&w.pz[i0]), u0 = load(&w.u0[i0]), u1 = load(&w.u1[i0]);
        // Area sampling.
        const VF ax = corner.x + u0 * ex.x + u1 * ey.x, ay = corner.y + u0 * ex.y + u1 * ey.y, az = corner.z + u0 * ex.z + u1 * ey.z;
        const VF vx = ax - px, vy = ay - py, vz = az - pz, d2 = vx * vx + vy * vy + vz * vz;
        const VF cos_light = -(ln.x * vx + ln.y * vy + ln.z * vz) / vsqrt(d2);
        const VF area_pdf = cos_light > 0.0f ? d2 / (cos_light * area) : VF{};
        // The threshold on the estimated solid angle A |z0| / r^3 > k, squared.
        const VF cx = centre.x - px, cy = centre.y - py, cz = centre.z - pz;
        const VF zc = cx * za.x + cy * za.y + cz * za.z, r2 = cx * cx + cy * cy + cz * cz, aa = len_x * len_y * zc;
        VI spherical = (vabs(zc) >= 1e-4f * std::max(len_x, len_y)) & (aa * aa >= k * k * (r2 * r2 * r2));
        // Solid-angle sampling (Urena et al. 2013), in the rectangle's frame seen from p.
        const VF dx = corner.x - px, dy = corner.y - py, dz = corner.z - pz;
        VF z0 = dx * za.x + dy * za.y + dz * za.z;
        const VF zsign = z0 > 0.0f ? splat(-1.0f) : splat(1.0f);
        z0 = z0 * zsign;
        const VF x0 = dx * xa.x + dy * xa.y + dz * xa.z, y0 = dx * ya.x + dy * ya.y + dz * ya.z, x1 = x0 + len_x, y1 = y0 + len_y;
        const VF z2 = z0 * z0;
        const VF irx0 = 1.0f / vsqrt(z2 + x0 * x0), irx1 = 1.0f / vsqrt(z2 + x1 * x1), iry0 = 1.0f / vsqrt(z2 + y0 * y0),
                 iry1 = 1.0f / vsqrt(z2 + y1 * y1);
        const VF g0 = vacos(y0 * x1 * iry0 * irx1), g1 = vacos(-x1 * y1 * irx1 * iry1), g2 = vacos(x0 * y1 * iry1 * irx0),
                 g3 = vacos(-x0 * y0 * irx0 * iry0);
        const VF b0 = -y0 * iry0, b1 = y1 * iry1, kk = TwoPi - g2 - g3, solid_angle = g0 + g1 - kk;
        spherical &= solid_angle > 1e-3f;
        VF sn, cs;
        vsincos(u0 * solid_angle + kk, sn, cs);
        const VF fu = (cs * b0 - b1) / sn;
        const VF cu = vmin(vmax((fu < 0.0f ? splat(-1.0f) : splat(1.0f)) / vsqrt(fu * fu + b0 * b0), splat(-1.0f)), splat(1.0f));
        const VF xu = vmin(vmax(-(cu * z0) / vsqrt(vmax(1.0f - cu * cu, VF{})), x0), x1);
        const VF d = vsqrt(xu * xu + z2);
        const VF h0 = y0 / vsqrt(d * d + y0 * y0), h1 = y1 / vsqrt(d * d + y1 * y1), hv = h0 + u1 * (h1 - h0), hv2 = hv * hv;
        const VF yv = vmin(vmax(hv2 < 1.0f - 1e-6f ? (hv * d) / vsqrt(vmax(1.0f - hv2, splat(1e-30f))) : y1, y0), y1);
        // p + xu x + yv y + z0 z', where z' is -z when the corner lay at positive z (z0 <= 0 now).
        const VF zx = za.x * zsign, zy = za.y * zsign, zz = za.z * zsign;
        const VF qx = px + xu * xa.x + yv * ya.x + z0 * zx, qy = py + xu * xa.y + yv * ya.y + z0 * zy,
                 qz = pz + xu * xa.z + yv * ya.z + z0 * zz;
        store(&w.tx[i0], spherical ? qx : ax), store(&w.ty[i0], spherical ? qy : ay), store(&w.tz[i0], spherical ? qz : az);
        // A one-sided light: nothing for points behind it.
        const VI in_front = -(dx * ln.x + dy * ln.y + dz * ln.z) > 0.0f;
        store(&w.light_pdf[i0], in_front ? (spherical ? 1.0f / solid_angle : area_pdf) : VF{});
    });
}

// The generic variant's middle pass, one lane at a time: the numbers from Candela's sampler (the
// path's SampleDimensions), the light sample and its density from Candela's emitter.
// With `vector_lights` the light sample is left to wave_lights_vector.
void wave_samples_generic(const FloorScene& fs, Sampler& sampler, bool vector_lights, WaveState& w, size_t n) {
    for (size_t i = 0; i < n; ++i) {
        sampler.restore(w.sampler_state[i]);
        const uint32_t dims = SampleDimensions::bounce(w.depth[i]);
        sampler.set_dimension(dims + SampleDimensions::LightPosition);
        const Vec2 ul = sampler.next_2d();
        sampler.set_dimension(dims + SampleDimensions::Direction);
        const Vec2 ud = sampler.next_2d();
        sampler.set_dimension(dims + SampleDimensions::Roulette);
        w.u0[i] = ul.x, w.u1[i] = ul.y, w.u2[i] = ud.x, w.u3[i] = ud.y, w.u4[i] = sampler.next_1d();
        sampler.save(w.sampler_state[i]);
        if (!vector_lights) {
            SurfaceInteraction ref;
            ref.p = Vec3(w.px[i], w.py[i], w.pz[i]), ref.n = Vec3(w.nx[i], w.ny[i], w.nz[i]);
            Spectrum weight;
            const DirectionSample ds = fs.light->sample_direction(ref, ul, weight);
            w.tx[i] = ds.p.x, w.ty[i] = ds.p.y, w.tz[i] = ds.p.z, w.light_pdf[i] = ds.pdf;
        }
        w.light_pdf_hit[i] = 0.0f;
        if (w.front[i] && w.depth[i] > 0 && w.rays[i / 16].hit.geomID[i % 16] == fs.light_geometry) {
            SurfaceInteraction from;
            from.p = Vec3(w.from_x[i], w.from_y[i], w.from_z[i]), from.n = Vec3(w.from_nx[i], w.from_ny[i], w.from_nz[i]);
            DirectionSample at;
            at.p = Vec3(w.px[i], w.py[i], w.pz[i]), at.n = fs.light_normal;
            const Vec3 to = at.p - from.p;
            at.dist = glm::length(to), at.d = to / at.dist;
            w.light_pdf_hit[i] = fs.light->pdf_direction(from, at);
        }
    }
}

void wave_shade(const FloorScene& fs, const float* albedo, const float* emission, WaveState& w, size_t n) {
    for_lanes(n, [&](size_t b, int o, size_t i0, VI) {
        RTCRayHit16& rh = w.rays[b];
        RTCRay16& sh = w.shadows[b];
        const VI hit = load(&w.hit[i0]);
        const VU g = hit ? load(rh.hit.geomID + o) : VU{}, depth = load(&w.depth[i0]);
        const VF px = load(&w.px[i0]), py = load(&w.py[i0]), pz = load(&w.pz[i0]);
        const VF nx = load(&w.nx[i0]), ny = load(&w.ny[i0]), nz = load(&w.nz[i0]);
        VF e_r, e_g, e_b, a_r, a_g, a_b;
        for (int l = 0; l < Width; ++l) {
            const float *e = emission + 3 * g[l], *a = albedo + 3 * g[l];
            e_r[l] = e[0], e_g[l] = e[1], e_b[l] = e[2], a_r[l] = a[0], a_g[l] = a[1], a_b[l] = a[2];
        }
        // The emission found, weighted against the light sample of the vertex before (power heuristic).
        const VF prev = load(&w.bsdf_pdf[i0]), pdf_hit = load(&w.light_pdf_hit[i0]);
        const VF mis_hit = depth == 0u ? splat(1.0f) : prev * prev / (prev * prev + pdf_hit * pdf_hit);
        const VF emit = load(&w.front[i0]) ? mis_hit : VF{};
        VF br = load(&w.beta_r[i0]), bg = load(&w.beta_g[i0]), bb = load(&w.beta_b[i0]);
        store(&w.L_r[i0], load(&w.L_r[i0]) + br * e_r * emit);
        store(&w.L_g[i0], load(&w.L_g[i0]) + bg * e_g * emit);
        store(&w.L_b[i0], load(&w.L_b[i0]) + bb * e_b * emit);
        // The light sample: f cos / pdf_light times the power heuristic's weight.
        const VF tx = load(&w.tx[i0]), ty = load(&w.ty[i0]), tz = load(&w.tz[i0]), light_pdf = load(&w.light_pdf[i0]);
        const VF vx = tx - px, vy = ty - py, vz = tz - pz;
        const VF cos_surface = (nx * vx + ny * vy + nz * vz) / vsqrt(vx * vx + vy * vy + vz * vz);
        const VI nee = hit & (cos_surface > 0.0f) & (light_pdf > 0.0f);
        const VF bsdf_at_light = cos_surface * InvPi;
        const VF nee_weight = nee ? bsdf_at_light * light_pdf / (light_pdf * light_pdf + bsdf_at_light * bsdf_at_light) : VF{};
        store(&w.nee_r[i0], br * a_r * (fs.radiance.x * nee_weight));
        store(&w.nee_g[i0], bg * a_g * (fs.radiance.y * nee_weight));
        store(&w.nee_b[i0], bb * a_b * (fs.radiance.z * nee_weight));
        const VF lift = 1e-4f * (1.0f + vmax(vmax(vabs(px), vabs(py)), vabs(pz)));
        const VF qx = px + nx * lift, qy = py + ny * lift, qz = pz + nz * lift;
        store(sh.org_x + o, qx), store(sh.org_y + o, qy), store(sh.org_z + o, qz);
        store(sh.dir_x + o, tx - qx), store(sh.dir_y + o, ty - qy), store(sh.dir_z + o, tz - qz);
        store(sh.tnear + o, VF{}), store(sh.tfar + o, splat(1.0f - 1e-4f)), store(sh.time + o, VF{});
        for (int l = 0; l < Width; ++l)
            sh.mask[o + l] = 0xFFFFFFFFu, sh.id[o + l] = 0u, sh.flags[o + l] = 0u, w.shadow_valid[b].lane[o + l] = nee[l];
        // The BSDF sample.
        const VF sx = 2.0f * load(&w.u2[i0]) - 1.0f, sy = 2.0f * load(&w.u3[i0]) - 1.0f;
        const VI x_major = vabs(sx) > vabs(sy);
        const VF r = x_major ? sx : sy, across = x_major ? sy : sx;
        const VF phi = r == 0.0f ? VF{} : (Pi / 4.0f) * (across / r), p2 = phi * phi;
        const VF s = phi + phi * p2 * (-1.6666654611e-1f + p2 * (8.3321608736e-3f + p2 * -1.9515295891e-4f));
        const VF c = 1.0f - 0.5f * p2 + p2 * p2 * (4.166664568298827e-2f + p2 * (-1.388731625493765e-3f + p2 * 2.443315711809948e-5f));
        const VF lx = r * (x_major ? c : s), ly = r * (x_major ? s : c);
        const VF lz = vsqrt(vmax(1.0f - lx * lx - ly * ly, VF{}));
        // The frame of basis() above.
        const VF sign = nz < 0.0f ? splat(-1.0f) : splat(1.0f), ia = -1.0f / (sign + nz), ib = nx * ny * ia;
        const VF b1x = 1.0f + sign * nx * nx * ia, b1y = sign * ib, b1z = -sign * nx;
        const VF b2x = ib, b2y = sign + ny * ny * ia, b2z = -ny;
        store(rh.ray.org_x + o, qx), store(rh.ray.org_y + o, qy), store(rh.ray.org_z + o, qz);
        store(rh.ray.dir_x + o, lx * b1x + ly * b2x + lz * nx);
        store(rh.ray.dir_y + o, lx * b1y + ly * b2y + lz * ny);
        store(rh.ray.dir_z + o, lx * b1z + ly * b2z + lz * nz);
        store(&w.bsdf_pdf[i0], lz * InvPi);
        store(&w.from_x[i0], px), store(&w.from_y[i0], py), store(&w.from_z[i0], pz);
        store(&w.from_nx[i0], nx), store(&w.from_ny[i0], ny), store(&w.from_nz[i0], nz);
        br *= a_r, bg *= a_g, bb *= a_b;
        // Russian roulette from depth 5, as the floor.
        const VF q = depth + 1u >= 5u ? vmin(vmax(vmax(br, bg), bb), splat(0.95f)) : splat(1.0f);
        const VI survives = hit & (load(&w.u4[i0]) < q);
        const VF inv_q = 1.0f / q;
        store(&w.beta_r[i0], br * inv_q), store(&w.beta_g[i0], bg * inv_q), store(&w.beta_b[i0], bb * inv_q);
        const VU next_depth = depth + 1u;
        std::memcpy(&w.depth[i0], &next_depth, sizeof next_depth);
        for (int l = 0; l < Width; ++l) w.alive[i0 + l] = survives[l] != 0;
    });
}

// The generic wave with Candela's shading as well (--candela-shading), one lane at a time after the
// packets are traced: the hit record (Shape::fill_interaction), the emission found with its MIS
// weight from the emitter's density, the sampler's numbers, the light sample, the BSDF's eval_pdf
// and sample, and robust shadow and extension rays (shadow_ray, spawn_ray), all through their
// scalar interfaces (the emission's weight is the path tracer's own emitter_hit_weight, with the
// scene's default light sampler); only the rays stay packets. What a first wavefront `path` built on the scalar
// plugins would cost.
void wave_candela(const FloorScene& fs, const LightSampler& lights, Sampler& sampler, WaveState& w, size_t n) {
    for (size_t i = 0; i < n; ++i) {
        RTCRayHit16& rh = w.rays[i / 16];
        RTCRay16& sh = w.shadows[i / 16];
        const size_t l = i % 16;
        w.shadow_valid[i / 16].lane[l] = 0;
        w.nee_r[i] = w.nee_g[i] = w.nee_b[i] = 0.0f;
        w.alive[i] = 0;
        const Shape* shape = fs.scene->accel().shape(rh.hit.geomID[l]);
        if (!shape) continue;
        const Ray ray(Vec3(rh.ray.org_x[l], rh.ray.org_y[l], rh.ray.org_z[l]), Vec3(rh.ray.dir_x[l], rh.ray.dir_y[l], rh.ray.dir_z[l]));
        RayHit hit;
        hit.t = rh.ray.tfar[l], hit.prim_index = rh.hit.primID[l], hit.u = rh.hit.u[l], hit.v = rh.hit.v[l];
        SurfaceInteraction si;
        si.shape = shape;
        shape->fill_interaction(ray, hit, si);
        si.prim_index = hit.prim_index, si.prim_uv = Vec2(hit.u, hit.v), si.t = hit.t, si.wi = si.to_local(-ray.d);
        Spectrum beta(w.beta_r[i], w.beta_g[i], w.beta_b[i]), L(w.L_r[i], w.L_g[i], w.L_b[i]);
        const uint32_t depth = w.depth[i];
        if (const Emitter* emitter = shape->emitter()) {
            const Spectrum Le = emitter->eval(si);
            float mis = 1.0f;
            if (depth > 0 && !is_black(Le)) {
                SurfaceInteraction from;
                from.p = Vec3(w.from_x[i], w.from_y[i], w.from_z[i]), from.n = Vec3(w.from_nx[i], w.from_ny[i], w.from_nz[i]);
                mis = emitter_hit_weight(lights, from, w.bsdf_pdf[i], *emitter, si);
            }
            L += beta * Le * mis;
        }
        sampler.restore(w.sampler_state[i]);
        const uint32_t dims = SampleDimensions::bounce(depth);
        sampler.set_dimension(dims + SampleDimensions::LightPosition);
        const Vec2 u_light = sampler.next_2d();
        sampler.set_dimension(dims + SampleDimensions::Direction);
        const Vec2 u_direction = sampler.next_2d();
        sampler.set_dimension(dims + SampleDimensions::Roulette);
        const float u_roulette = sampler.next_1d();
        sampler.save(w.sampler_state[i]);
        const BSDF& bsdf = *shape->bsdf();
        Spectrum weight(0.0f);
        const DirectionSample ds = fs.light->sample_direction(si, u_light, weight);
        if (ds.pdf > 0.0f && !is_black(weight)) {
            const BSDFEvalPdf f = bsdf.eval_pdf(BSDFContext(), si, si.to_local(ds.d));
            if (!is_black(f.value)) {
                const Ray r = shadow_ray(si, ds);
                put_ray(sh, l, r);
                sh.tnear[l] = r.tmin, sh.tfar[l] = r.tmax, sh.time[l] = 0.0f, sh.mask[l] = 0xFFFFFFFFu, sh.id[l] = 0u, sh.flags[l] = 0u;
                w.shadow_valid[i / 16].lane[l] = -1;
                const Spectrum c = beta * f.value * weight * power_heuristic(ds.pdf, f.pdf);
                w.nee_r[i] = c.x, w.nee_g[i] = c.y, w.nee_b[i] = c.z;
            }
        }
        w.L_r[i] = L.x, w.L_g[i] = L.y, w.L_b[i] = L.z;
        const BSDFSample bs = bsdf.sample(BSDFContext(), si, 0.0f, u_direction);
        if (!bs.valid() || is_black(bs.weight)) continue;
        beta *= bs.weight;
        // Russian roulette from depth 5, as the floor.
        const float q = depth + 1 >= 5 ? std::min(max_component(beta), 0.95f) : 1.0f;
        if (!(u_roulette < q)) continue;
        beta /= q;
        put_ray(rh.ray, l, si.spawn_ray(si.to_world(bs.wo)));
        w.beta_r[i] = beta.x, w.beta_g[i] = beta.y, w.beta_b[i] = beta.z;
        w.bsdf_pdf[i] = bs.pdf, w.depth[i] = depth + 1;
        w.from_x[i] = si.p.x, w.from_y[i] = si.p.y, w.from_z[i] = si.p.z, w.from_nx[i] = si.n.x, w.from_ny[i] = si.n.y,
        w.from_nz[i] = si.n.z;
        w.alive[i] = 1;
    }
}

// Moves lane `from` to lane `to` (to <= from): what the next bounce reads.
void move_lane(WaveState& w, size_t from, size_t to) {
    RTCRay16 &a = w.rays[from / 16].ray, &b = w.rays[to / 16].ray;
    size_t i = from % 16, j = to % 16;
    b.org_x[j] = a.org_x[i], b.org_y[j] = a.org_y[i], b.org_z[j] = a.org_z[i];
    b.dir_x[j] = a.dir_x[i], b.dir_y[j] = a.dir_y[i], b.dir_z[j] = a.dir_z[i];
    w.beta_r[to] = w.beta_r[from], w.beta_g[to] = w.beta_g[from], w.beta_b[to] = w.beta_b[from];
    w.L_r[to] = w.L_r[from], w.L_g[to] = w.L_g[from], w.L_b[to] = w.L_b[from];
    w.bsdf_pdf[to] = w.bsdf_pdf[from], w.path[to] = w.path[from], w.depth[to] = w.depth[from], w.sampler_state[to] = w.sampler_state[from];
    w.from_x[to] = w.from_x[from], w.from_y[to] = w.from_y[from], w.from_z[to] = w.from_z[from];
    w.from_nx[to] = w.from_nx[from], w.from_ny[to] = w.from_ny[from], w.from_nz[to] = w.from_nz[from];
}

// With `sampler` (a prototype to clone), the generic variant: the numbers from that sampler and
// the light sample from Candela's emitter, lane by lane. One sampler serves a thread's lanes: each
// lane keeps where its sample stands (Sampler::save) and restores it before its next numbers.
// With `vector_lights`, the light sample of wave_lights_vector (the rectangle's own sampling).
// With `candela_shading` (and `generic`), the bounce is wave_candela's.
FloorRun render_wavefront(const FloorScene& fs, int spp, const Sampler* generic, bool vector_lights, bool candela_shading,
                          tbb::task_arena& arena) {
    const Sensor& sensor = fs.scene->sensor();
    const size_t width = size_t(sensor.film().full_size().x), count = width * size_t(spp);
    std::vector<float> albedo, emission;
    for (size_t g = 0; g < fs.albedo.size(); ++g)
        for (int c = 0; c < 3; ++c) albedo.push_back(fs.albedo[g][c]), emission.push_back(fs.emission[g][c]);
    const std::unique_ptr<LightSampler> lights = create_light_sampler(DefaultLightSampler, *fs.scene);
    return time_rows(fs, spp, arena, [&](size_t y0, size_t y1, std::vector<double>& row_sums, long long& rays) {
        static thread_local WaveState w;  // a row's worth, kept by each thread across rows
        if (w.path.size() < count) w.resize(count);
        Ref<Sampler> sampler = generic ? generic->clone() : nullptr;
        RTCIntersectContext context;
        for (size_t y = y0; y < y1; ++y) {
            // The camera rays, one path per pixel sample.
            for (size_t i = 0; i < count; ++i) {
                const uint32_t path = uint32_t(y * count + i);
                const float x = float(i / size_t(spp));
                Vec2 film(hashed_float(path, 0), hashed_float(path, 1));
                if (generic) {
                    sampler->start(Vec2i(int(x), int(y)), uint32_t(i % size_t(spp)));
                    film = sampler->next_2d();
                    sampler->save(w.sampler_state[i]);
                }
                put_ray(w.rays[i / 16].ray, i % 16, sensor.sample_ray(Vec2(x, float(y)) + film, Vec2(0.5f)));
                w.path[i] = path, w.depth[i] = 0, w.bsdf_pdf[i] = 0.0f;
                w.beta_r[i] = w.beta_g[i] = w.beta_b[i] = 1.0f;
                w.L_r[i] = w.L_g[i] = w.L_b[i] = 0.0f;
            }
            for (size_t n = count; n > 0;) {
                const size_t packets = (n + 15) / 16;
                for (size_t b = 0; b < packets; ++b) {
                    RTCRayHit16& rh = w.rays[b];
                    for (size_t l = 0; l < 16; ++l) {
                        w.valid[b].lane[l] = b * 16 + l < n ? -1 : 0;
                        w.shadow_valid[b].lane[l] = 0;  // the shading sets its lanes'; the last packet's tail stays off
                        rh.ray.tnear[l] = 0.0f, rh.ray.tfar[l] = Infinity, rh.ray.time[l] = 0.0f;
                        rh.ray.mask[l] = 0xFFFFFFFFu, rh.ray.id[l] = 0u, rh.ray.flags[l] = 0u;
                        rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
                    }
                    rtcInitIntersectContext(&context);
                    rtcIntersect16(w.valid[b].lane, fs.embree, &context, &rh);
                }
                rays += (long long)n;
                if (generic && candela_shading) {
                    wave_candela(fs, *lights, *sampler, w, n);
                } else {
                    wave_hits(fs, w, n);
                    if (generic)
                        wave_samples_generic(fs, *sampler, vector_lights, w, n);
                    else
                        wave_samples_floor(fs, w, n);
                    if (vector_lights) wave_lights_vector(fs, w, n);
                    wave_shade(fs, albedo.data(), emission.data(), w, n);
                }
                for (size_t b = 0; b < packets; ++b) {
                    rtcInitIntersectContext(&context);
                    rtcOccluded16(w.shadow_valid[b].lane, fs.embree, &context, &w.shadows[b]);
                }
                // Unoccluded light samples count; ended paths leave their radiance, the rest move up.
                size_t kept = 0;
                for (size_t i = 0; i < n; ++i) {
                    if (w.shadow_valid[i / 16].lane[i % 16]) {
                        ++rays;
                        if (w.shadows[i / 16].tfar[i % 16] >= 0.0f) w.L_r[i] += w.nee_r[i], w.L_g[i] += w.nee_g[i], w.L_b[i] += w.nee_b[i];
                    }
                    if (w.alive[i]) {
                        if (kept != i) move_lane(w, i, kept);
                        ++kept;
                    } else {
                        row_sums[y] += (double(w.L_r[i]) + w.L_g[i] + w.L_b[i]) / 3.0;
                    }
                }
                n = kept;
            }
        }
    });
}

const char* const usage =
    "usage: bench_floor [SCENE.xml] [--threads N] [--spp N] [--rounds N] [--sampler NAME] [--vector-lights]\n"
    "  SCENE.xml     diffuse shapes and one rectangle area light (default " CANDELA_SOURCE_DIR
    "/scenes/cbox.xml)\n"
    "  --threads N   threads (default 0: all cores)\n"
    "  --spp N       samples per pixel (default 32)\n"
    "  --rounds N    rounds of Candela's render and the floors side by side (default 3)\n"
    "  --sampler NAME  Candela's render with this sampler instead of the scene's, and the generic wavefront\n"
    "                (run only with it)\n"
    "  --vector-lights  the wavefronts sample the light as the rectangle does (solid angle close by), in vectors\n"
    "  --candela-shading  the generic wavefront shades with Candela's hit records, emitter, BSDF and rays, lane by lane\n";

int run(int argc, char** argv) {
    std::string scene_path = std::string(CANDELA_SOURCE_DIR) + "/scenes/cbox.xml";
    int threads = 0, spp = 32, rounds = 3;
    std::string sampler;
    bool vector_lights = false, candela_shading = false;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--threads")
            threads = bench::int_option(argc, argv, i, 0);
        else if (a == "--spp")
            spp = bench::int_option(argc, argv, i, 1);
        else if (a == "--vector-lights")
            vector_lights = true;
        else if (a == "--candela-shading")
            candela_shading = true;
        else if (a == "--sampler")
            sampler = bench::option_value(argc, argv, i);
        else if (a == "--rounds")
            rounds = bench::int_option(argc, argv, i, 1);
        else if (bench::is_option(a))
            bench::reject_argument(a);
        else
            scene_path = a;
    }
    Ref<Scene> scene = load_scene(scene_path);
    FloorScene fs = describe(*scene);
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    RenderOptions options;
    options.spp = spp;
    options.threads = threads;
    options.sampler = sampler;
    Ref<Sampler> generic = sampler.empty() ? nullptr : configured_sampler(*scene, options);
    if (vector_lights && std::abs(glm::dot(glm::normalize(fs.edge_x), glm::normalize(fs.edge_y))) >= 1e-4f)
        throw std::runtime_error("--vector-lights needs a rectangle light without shear");
    const unsigned variants[] = {0u, Lights, Hits, Shadows, Lights | Hits | Shadows};
    const char* const names[] = {"floor", "+lights", "+hits", "+shadows", "+all three"};
    std::printf("scene %s, %d threads, %d spp\n", scene_path.c_str(), arena.max_concurrency(), spp);
    std::printf("round  %-12s %8s %10s %8s\n", "renderer", "Mrays/s", "rays/spl", "mean");
    render_floor(fs, 0, 1, arena);  // warm-up: threads and Embree's data
    std::vector<std::vector<double>> ratios(7);
    for (int round = 1; round <= rounds; ++round) {
        RenderResult result = scene->integrator().render(*scene, options);
        double path_mrays = double(result.stats.rays) / result.stats.seconds * 1e-6, mean = 0.0;
        for (int y = 0; y < result.image.height(); ++y)
            for (int x = 0; x < result.image.width(); ++x) mean += average(result.image.rgb_at(x, y));
        mean /= double(result.image.width()) * result.image.height();
        std::printf("%5d  %-12s %8.2f %10.2f %8.4f\n", round, "candela", path_mrays,
                    double(result.stats.rays) / double(result.stats.samples), mean);
        for (int v = 0; v < 5; ++v) {
            FloorRun f = render_floor(fs, variants[v], spp, arena);
            ratios[size_t(v)].push_back(f.mrays / path_mrays);
            std::printf("%5d  %-12s %8.2f %10.2f %8.4f\n", round, names[v], f.mrays, f.rays_per_sample, f.mean);
        }
        for (const Sampler* with : {(const Sampler*)nullptr, (const Sampler*)generic.get()}) {
            FloorRun f = render_wavefront(fs, spp, with, vector_lights, candela_shading, arena);
            ratios[with ? 6 : 5].push_back(f.mrays / path_mrays);
            std::printf("%5d  %-12s %8.2f %10.2f %8.4f\n", round, with ? "wave generic" : "wavefront", f.mrays, f.rays_per_sample, f.mean);
            if (!generic) break;
        }
    }
    std::printf("medians of Mrays/s over candela's:");
    for (int v = 0; v < 5; ++v) std::printf("  %s %.3f", names[v], bench::median(ratios[size_t(v)]));
    std::printf("  wavefront %.3f", bench::median(ratios[5]));
    if (generic) std::printf("  wave generic %.3f", bench::median(ratios[6]));
    std::printf("\n");
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
