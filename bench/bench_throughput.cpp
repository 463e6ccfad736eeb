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
// rate at which Embree traces the path tracer's own rays. Last, (5) raw Embree on the same rays
// in packets of 8 and 16 (rtcIntersect8/16, consecutive rays, as a wavefront path tracer's batch
// of incoherent secondary rays would be) and as one stream per chunk (rtcIntersect1M), each
// against single rays in the same round: what batching could gain inside Embree (issue 34's
// "measure before you choose"). Then (6) the same single rays and packets with the scene rebuilt
// without RTC_SCENE_FLAG_ROBUST (Mitsuba 3's setting): what Candela's watertight traversal costs.
// Each round also renders one path at a time (RenderOptions::wavefront off; the same image), so
// that the wavefront's gain is a ratio measured side by side.
// It prints figures and asserts nothing.

#include "bench/bench_args.h"
#include "core/parallel.h"
#include "core/profiling.h"
#include "core/rng.h"
#include "core/warp.h"
#include "core/xml.h"

#include <embree3/rtcore.h>
#include <tbb/task_arena.h>

#include <sys/time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
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

// Closest hits of one packet of consecutive rays (RTCRayHit8 or RTCRayHit16 with its
// rtcIntersect8/16); how many hit.
template <typename Packet, typename Intersect>
int intersect_packet(RTCScene scene, const Ray* rays, Packet& packet, Intersect intersect) {
    constexpr int width = int(sizeof(packet.ray.org_x) / sizeof(float));
    alignas(64) int valid[width];
    for (int k = 0; k < width; ++k) {
        const Ray& r = rays[k];
        valid[k] = -1;
        packet.ray.org_x[k] = r.o.x, packet.ray.org_y[k] = r.o.y, packet.ray.org_z[k] = r.o.z;
        packet.ray.dir_x[k] = r.d.x, packet.ray.dir_y[k] = r.d.y, packet.ray.dir_z[k] = r.d.z;
        packet.ray.tnear[k] = r.tmin, packet.ray.tfar[k] = r.tmax, packet.ray.time[k] = 0.0f;
        packet.ray.mask[k] = 0xFFFFFFFFu, packet.ray.id[k] = 0, packet.ray.flags[k] = 0;
        packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    intersect(valid, scene, &context, &packet);
    int hits = 0;
    for (int k = 0; k < width; ++k) hits += packet.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
    return hits;
}

const char* const usage =
    "usage: bench_throughput [SCENE.xml] [--threads N] [--spp N] [--rays N] [--rounds N]\n"
    "  SCENE.xml     the scene (default " CANDELA_SOURCE_DIR
    "/scenes/cbox.xml)\n"
    "  --threads N   threads of the render and the Embree rounds (default 0: all cores)\n"
    "  --spp N       samples per pixel of the path tracer's render (default 64; 0: the scene's sample_count)\n"
    "  --rays N      incoherent Embree rays per round, rounded down to whole packets of 16 (default 20000000)\n"
    "  --rounds N    rounds of Embree rays against the path tracer, and of packets (default 5)\n";

int run(int argc, char** argv) {
    std::string scene_path = std::string(CANDELA_SOURCE_DIR) + "/scenes/cbox.xml";
    int threads = 0, spp = 64, rounds = 5;
    long long ray_count = 20000000;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--threads")
            threads = bench::int_option(argc, argv, i, 0);
        else if (a == "--spp")
            spp = bench::int_option(argc, argv, i, 0);
        else if (a == "--rays")
            ray_count = bench::parse_whole(a, bench::option_value(argc, argv, i), 16, LLONG_MAX);
        else if (a == "--rounds")
            rounds = bench::int_option(argc, argv, i, 1);
        else if (bench::is_option(a))
            bench::reject_argument(a);
        else
            scene_path = a;
    }
    ray_count -= ray_count % 16;  // whole packets of 16 (and of 8) in the batched rounds
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
    std::printf("round  embree Mrays/s  path Mrays/s  path samples/s  ratio path/embree  one-at-a-time Mrays/s  its ratio/embree\n");
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
    std::vector<double> ratios, scalar_ratios, wave_gains;
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
        RenderOptions one_at_a_time = options;
        one_at_a_time.wavefront = false;
        const RenderResult scalar = scene->integrator().render(*scene, one_at_a_time);
        const double scalar_mrays = double(scalar.stats.rays) / scalar.stats.seconds * 1e-6;
        scalar_ratios.push_back(scalar_mrays / embree_mrays);
        wave_gains.push_back(path_mrays / scalar_mrays);
        std::printf("%5d  %14.2f  %12.2f  %14.0f  %17.3f  %21.2f  %16.3f\n", round + 1, embree_mrays, path_mrays, samples_per_s,
                    ratios.back(), scalar_mrays, scalar_ratios.back());
    }
    std::printf("embree closest-hit rays   %lld incoherent per round, %.1f%% hit\n", ray_count, 100.0 * double(hits) / double(ray_count));
    std::printf("path tracer               %d spp, %llu rays per round (%.2f per sample)\n", result.stats.spp,
                (unsigned long long)result.stats.rays, double(result.stats.rays) / double(result.stats.samples));
    const auto [lowest, highest] = std::minmax_element(ratios.begin(), ratios.end());
    std::printf("ratio path/embree Mrays   median %.3f of %d rounds (lowest %.3f, highest %.3f)\n", bench::median(ratios), rounds, *lowest,
                *highest);
    std::printf("one path at a time        median ratio to embree %.3f; path's Mrays/s over it: median %.3f\n",
                bench::median(scalar_ratios), bench::median(wave_gains));
    // Packets and streams: the ray records are filled per packet (a wavefront tracer keeps its
    // batch in this layout), hits counted as in trace().
    RTCScene embree = scene->accel().scene();
    auto trace_packets = [&](int width) {
        std::atomic<long long> packet_hits{0};
        arena.execute([&] {
            parallel_chunks(rays.size() / 16, 256, [&](size_t begin, size_t end) {
                long long local = 0;
                for (size_t p = begin * 16; p != end * 16; p += size_t(width)) {
                    if (width == 8) {
                        alignas(32) RTCRayHit8 packet;
                        local += intersect_packet(embree, &rays[p], packet, rtcIntersect8);
                    } else {
                        alignas(64) RTCRayHit16 packet;
                        local += intersect_packet(embree, &rays[p], packet, rtcIntersect16);
                    }
                }
                packet_hits += local;
            });
        });
        return packet_hits.load();
    };
    auto trace_stream = [&]() {
        std::atomic<long long> stream_hits{0};
        arena.execute([&] {
            parallel_chunks(rays.size(), 4096, [&](size_t begin, size_t end) {
                std::vector<RTCRayHit> stream(end - begin);
                for (size_t i = begin; i != end; ++i) {
                    RTCRayHit& rh = stream[i - begin];
                    const Ray& r = rays[i];
                    rh.ray.org_x = r.o.x, rh.ray.org_y = r.o.y, rh.ray.org_z = r.o.z;
                    rh.ray.dir_x = r.d.x, rh.ray.dir_y = r.d.y, rh.ray.dir_z = r.d.z;
                    rh.ray.tnear = r.tmin, rh.ray.tfar = r.tmax, rh.ray.time = 0.0f;
                    rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                }
                RTCIntersectContext context;
                rtcInitIntersectContext(&context);
                context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
                rtcIntersect1M(embree, &context, stream.data(), unsigned(stream.size()), sizeof(RTCRayHit));
                long long local = 0;
                for (const RTCRayHit& rh : stream) local += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
                stream_hits += local;
            });
        });
        return stream_hits.load();
    };
    auto mrays_of = [&](auto&& run) {
        auto t0 = std::chrono::steady_clock::now();
        long long h = run();
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (h != hits) std::printf("(a batched trace found %lld hits, single rays %lld)\n", h, hits);
        return double(rays.size()) / s * 1e-6;
    };
    // `rounds` rounds of single rays, packets and (with_stream) streams, as ratios to single rays.
    auto batched_rounds = [&](const char* title, bool with_stream) {
        std::printf("%-25s single Mrays/s  x8 packets  x16 packets%s  (ratios to single)\n", title, with_stream ? "  1M stream" : "");
        for (int round = 0; round < rounds; ++round) {
            double single = mrays_of([&] { return trace(rays.size()); });
            double x8 = mrays_of([&] { return trace_packets(8); });
            double x16 = mrays_of([&] { return trace_packets(16); });
            std::printf("%5d  %24.2f  %10.3f  %11.3f", round + 1, single, x8 / single, x16 / single);
            if (with_stream) std::printf("  %9.3f", mrays_of(trace_stream) / single);
            std::printf("\n");
        }
    };
    batched_rounds("batched embree", true);
    rtcSetSceneFlags(embree, RTC_SCENE_FLAG_NONE);
    rtcCommitScene(embree);
    batched_rounds("without ROBUST", false);
    rtcSetSceneFlags(embree, RTC_SCENE_FLAG_ROBUST);
    rtcCommitScene(embree);
    double share = embree_share(*scene, options);
    std::printf("share of time inside Embree %.1f%% (%ld profiler ticks)\n", 100.0 * share, g_samples_total.load());
    std::printf("embree Mrays/s on its rays  %.2f (path tracer rays / time inside Embree)\n", path_mrays / share);
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
