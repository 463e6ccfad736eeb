// bench_throughput: how close the path tracer comes to Embree's raw ray throughput.
//
//   bench_throughput [SCENE.xml] [--threads N] [--spp N] [--rays N] [--rounds N]
//
// On one scene and one thread count it reports (1) raw Embree closest-hit throughput on
// incoherent rays (random points inside the scene's bounds, uniformly random directions),
// (2) the path tracer's rays per second and samples per second on the same scene, and (3) the
// ratio of the two. It measures the two in turn, `rounds` times (default 5), and prints every
// round's ratio and their median: on a shared machine a neighbour's load that lands on one half
// of a single pair moves its ratio by 10% and more either way, while each pair is side by side.
// A second render of the same scene is sampled by a profiling timer (SIGPROF every millisecond of
// CPU time) to give (4) the share of the path tracer's time spent inside Embree, and from it the
// rate at which Embree traces the path tracer's own rays. It prints figures and asserts nothing.

#include "core/parallel.h"
#include "core/profiling.h"
#include "core/rng.h"
#include "core/warp.h"
#include "core/xml.h"

#include <tbb/task_arena.h>

#include <sys/time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>

using namespace candela;

namespace {

std::atomic<long> g_samples_inside{0}, g_samples_total{0};

void on_profile_tick(int) {
    if (thread_inside_embree()) g_samples_inside.fetch_add(1, std::memory_order_relaxed);
    g_samples_total.fetch_add(1, std::memory_order_relaxed);
}

// Renders with a profiling timer running; the fraction of its ticks that found the interrupted
// thread inside an Embree query. A separate render, so the timer does not slow the timed one.
double embree_share(const Scene& scene, const RenderOptions& options) {
    struct sigaction action = {};
    action.sa_handler = on_profile_tick;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    sigaction(SIGPROF, &action, nullptr);
    itimerval tick = {{0, 1000}, {0, 1000}}, off = {};
    setitimer(ITIMER_PROF, &tick, nullptr);
    scene.integrator().render(scene, options);
    setitimer(ITIMER_PROF, &off, nullptr);
    return double(g_samples_inside.load()) / double(std::max(1L, g_samples_total.load()));
}

}  // namespace

int main(int argc, char** argv) {
    std::string scene_path = std::string(CANDELA_SOURCE_DIR) + "/scenes/cbox.xml";
    int threads = 0, spp = 64, rounds = 5;
    long long ray_count = 20000000;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--threads" && i + 1 < argc)
            threads = std::atoi(argv[++i]);
        else if (a == "--spp" && i + 1 < argc)
            spp = std::atoi(argv[++i]);
        else if (a == "--rays" && i + 1 < argc)
            ray_count = std::atoll(argv[++i]);
        else if (a == "--rounds" && i + 1 < argc)
            rounds = std::max(1, std::atoi(argv[++i]));
        else
            scene_path = a;
    }
    Ref<Scene> scene = load_scene(scene_path);
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    int used_threads = arena.max_concurrency();

    // Incoherent closest-hit rays, generated up front so that only tracing is timed.
    BoundingBox b = scene->bbox();
    std::vector<Ray> rays(static_cast<size_t>(ray_count));
    const size_t batch = 65536;  // rays per random stream
    parallel_for((rays.size() + batch - 1) / batch, [&](size_t c) {
        size_t start = c * batch, end = std::min(rays.size(), start + batch);
        PCG32 rng(start, 3);
        for (size_t i = start; i < end; ++i) {
            Vec3 u(rng.next_float(), rng.next_float(), rng.next_float());
            Vec3 o = b.min + u * (b.max - b.min);
            float a = rng.next_float();
            rays[i] = Ray(o, warp::square_to_uniform_sphere(Vec2(a, rng.next_float())));
        }
    });
    RenderOptions options;
    options.spp = spp;
    options.threads = threads;
    std::printf("scene                     %s\n", scene_path.c_str());
    std::printf("threads                   %d\n", used_threads);
    std::printf("round  embree Mrays/s  path Mrays/s  path samples/s  ratio path/embree\n");
    // Closest hits for the first `count` rays, traced by the arena's threads; how many hit.
    auto trace = [&](size_t count) {
        std::atomic<long long> hits{0};
        arena.execute([&] {
            parallel_chunks(count, 4096, [&](size_t begin, size_t end) {
                long long local = 0;
                RayHit hit;
                for (size_t i = begin; i != end; ++i) local += scene->accel().intersect(rays[i], hit) != nullptr;
                hits += local;
            });
        });
        return hits.load();
    };
    // One untimed pass over a slice of the rays and a small render first: the first timed round
    // otherwise caught the arena's threads and Embree's data cold (9.45 Mrays/s against 14.8 in
    // the rounds after it, 2026-12-02).
    trace(std::min<size_t>(rays.size(), 1000000));
    RenderOptions warm_up = options;
    warm_up.spp = 1;
    scene->integrator().render(*scene, warm_up);
    std::vector<double> ratios;
    long long hits = 0;
    double path_mrays = 0.0;  // the last round's, for the Embree-share line
    RenderResult result;
    for (int round = 0; round < rounds; ++round) {
        auto t0 = std::chrono::steady_clock::now();
        hits = trace(rays.size());
        double embree_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        double embree_mrays = double(ray_count) / embree_s * 1e-6;

        result = scene->integrator().render(*scene, options);
        path_mrays = double(result.stats.rays) / result.stats.seconds * 1e-6;
        double samples_per_s = double(result.stats.samples) / result.stats.seconds;
        ratios.push_back(path_mrays / embree_mrays);
        std::printf("%5d  %14.2f  %12.2f  %14.0f  %17.3f\n", round + 1, embree_mrays, path_mrays, samples_per_s, ratios.back());
    }
    std::printf("embree closest-hit rays   %lld incoherent per round, %.1f%% hit\n", ray_count, 100.0 * double(hits) / double(ray_count));
    std::printf("path tracer               %d spp, %llu rays per round (%.2f per sample)\n", result.stats.spp,
                (unsigned long long)result.stats.rays, double(result.stats.rays) / double(result.stats.samples));
    std::vector<double> sorted = ratios;
    std::sort(sorted.begin(), sorted.end());
    double median = sorted.size() % 2 ? sorted[sorted.size() / 2] : 0.5 * (sorted[sorted.size() / 2 - 1] + sorted[sorted.size() / 2]);
    std::printf("ratio path/embree Mrays   median %.3f of %d rounds (lowest %.3f, highest %.3f)\n", median, rounds, sorted.front(),
                sorted.back());
    double share = embree_share(*scene, options);
    std::printf("share of time inside Embree %.1f%% (%ld profiler ticks)\n", 100.0 * share, g_samples_total.load());
    std::printf("embree Mrays/s on its rays  %.2f (path tracer rays / time inside Embree)\n", path_mrays / share);
    return 0;
}
