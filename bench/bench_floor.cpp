// bench_floor: the floor under the path tracer's time per ray, and what each piece of
// Candela's generality adds to it.
//
//   bench_floor [SCENE.xml] [--threads N] [--spp N] [--rounds N]
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
// and a fourth puts all three in. Each round renders the scene with Candela's integrator and then
// the five floors, side by side; it prints rays per second, rays per sample and image means (the
// same estimand: they agree to the noise) and, last, the medians of each floor's Mrays/s over
// Candela's. Issue 34 asks the path tracer for 0.85 of raw Embree's rate (bench_throughput);
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

#include <embree3/rtcore.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
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

FloorRun render_floor(const FloorScene& fs, unsigned pieces, int spp, tbb::task_arena& arena) {
    const Sensor& sensor = fs.scene->sensor();
    Vec2i size = sensor.film().full_size();
    std::atomic<long long> rays{0};
    std::vector<double> row_sums(size_t(size.y), 0.0);
    auto t0 = std::chrono::steady_clock::now();
    arena.execute([&] {
        parallel_chunks(size_t(size.y), 1, [&](size_t y0, size_t y1) {
            long long local_rays = 0;
            for (size_t y = y0; y < y1; ++y)
                for (int x = 0; x < size.x; ++x)
                    for (int s = 0; s < spp; ++s) {
                        PCG32 rng((y * size.x + x) * uint64_t(spp) + s, 7);
                        Vec2 film_pos(float(x) + rng.next_float(), float(y) + rng.next_float());
                        Spectrum L = trace(fs, pieces, sensor.sample_ray(film_pos, Vec2(0.5f)), rng, local_rays);
                        row_sums[y] += average(L);
                    }
            rays += local_rays;
        });
    });
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double samples = double(size.x) * size.y * spp, total = 0.0;
    for (double r : row_sums) total += r;
    return {double(rays.load()) / seconds * 1e-6, double(rays.load()) / samples, total / samples};
}

const char* const usage =
    "usage: bench_floor [SCENE.xml] [--threads N] [--spp N] [--rounds N]\n"
    "  SCENE.xml     diffuse shapes and one rectangle area light (default " CANDELA_SOURCE_DIR
    "/scenes/cbox.xml)\n"
    "  --threads N   threads (default 0: all cores)\n"
    "  --spp N       samples per pixel (default 32)\n"
    "  --rounds N    rounds of Candela's render and the floors side by side (default 3)\n";

int run(int argc, char** argv) {
    std::string scene_path = std::string(CANDELA_SOURCE_DIR) + "/scenes/cbox.xml";
    int threads = 0, spp = 32, rounds = 3;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--threads")
            threads = bench::int_option(argc, argv, i, 0);
        else if (a == "--spp")
            spp = bench::int_option(argc, argv, i, 1);
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
    const unsigned variants[] = {0u, Lights, Hits, Shadows, Lights | Hits | Shadows};
    const char* const names[] = {"floor", "+lights", "+hits", "+shadows", "+all three"};
    std::printf("scene %s, %d threads, %d spp\n", scene_path.c_str(), arena.max_concurrency(), spp);
    std::printf("round  %-12s %8s %10s %8s\n", "renderer", "Mrays/s", "rays/spl", "mean");
    render_floor(fs, 0, 1, arena);  // warm-up: threads and Embree's data
    std::vector<std::vector<double>> ratios(5);
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
    }
    std::printf("medians of Mrays/s over candela's:");
    for (int v = 0; v < 5; ++v) std::printf("  %s %.3f", names[v], bench::median(ratios[size_t(v)]));
    std::printf("\n");
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
