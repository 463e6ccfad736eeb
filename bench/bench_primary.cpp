// bench_primary: what tracing camera rays as Embree packets would gain over one ray at a time.
//
//   bench_primary [SCENE.xml] [--spp N] [--repeats N]
//
// Generates the camera rays of every pixel of the scene's film (N per pixel, jittered inside the
// pixel, pinhole aperture sample 1/2) and traces them on one thread, closest hit, three ways:
// one at a time through Accel::intersect (what the path tracer does), as 8-ray packets of one
// pixel's samples (rtcIntersect8, coherent context), and as 8-ray packets of 8 neighbouring
// pixels in a row (one sample each). Prints Mrays/s of each (best of the repeats) and how many
// packet rays find a hit distance that differs in any bit from the single ray's. It asserts nothing: issue 11's question is whether coherent
// primary rays pay enough to restructure the pixel loop around them.

#include "bench/bench_args.h"
#include "core/accel.h"
#include "core/film.h"
#include "core/rng.h"
#include "core/scene.h"
#include "core/sensor.h"
#include "core/xml.h"

#include <embree3/rtcore.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

using namespace candela;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Traces rays [0, n) in packets of 8 consecutive rays; returns the number of hits and stores
// each ray's hit distance (infinity for a miss).
long trace_packets(RTCScene scene, const std::vector<Ray>& rays, std::vector<float>& t) {
    long hits = 0;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(32) int valid[8];
    alignas(32) RTCRayHit8 rh;
    for (size_t start = 0; start < rays.size(); start += 8) {
        for (int k = 0; k < 8; ++k) {
            size_t i = start + size_t(k);
            valid[k] = i < rays.size() ? -1 : 0;
            const Ray& r = rays[i < rays.size() ? i : start];
            rh.ray.org_x[k] = r.o.x;
            rh.ray.org_y[k] = r.o.y;
            rh.ray.org_z[k] = r.o.z;
            rh.ray.dir_x[k] = r.d.x;
            rh.ray.dir_y[k] = r.d.y;
            rh.ray.dir_z[k] = r.d.z;
            rh.ray.tnear[k] = r.tmin;
            rh.ray.tfar[k] = r.tmax;
            rh.ray.time[k] = 0.0f;
            rh.ray.mask[k] = 0xFFFFFFFFu;
            rh.ray.id[k] = 0;
            rh.ray.flags[k] = 0;
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect8(valid, scene, &context, &rh);
        for (int k = 0; k < 8 && start + size_t(k) < rays.size(); ++k) {
            t[start + size_t(k)] = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID ? rh.ray.tfar[k] : Infinity;
            hits += rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
        }
    }
    return hits;
}

const char* const usage =
    "usage: bench_primary [SCENE.xml] [--spp N] [--repeats N]\n"
    "  SCENE.xml     the scene (default " CANDELA_SOURCE_DIR
    "/scenes/cbox.xml)\n"
    "  --spp N       camera rays per pixel (default 8)\n"
    "  --repeats N   timed passes of each way, the best one reported (default 3)\n";

int run(int argc, char** argv) {
    std::string scene_path = std::string(CANDELA_SOURCE_DIR) + "/scenes/cbox.xml";
    int spp = 8, repeats = 3;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--spp")
            spp = bench::int_option(argc, argv, i, 1);
        else if (a == "--repeats")
            repeats = bench::int_option(argc, argv, i, 1);
        else if (bench::is_option(a))
            bench::reject_argument(a);
        else
            scene_path = a;
    }
    Ref<Scene> scene = load_scene(scene_path);
    const Sensor& sensor = scene->sensor();
    const Vec2i size = sensor.film().crop_size();
    // Two orders of the same rays: a pixel's samples together, and pixel rows together.
    std::vector<Ray> by_pixel, by_row(size_t(size.x) * size.y * spp);
    PCG32 rng(7, 3);
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x)
            for (int s = 0; s < spp; ++s) {
                Vec2 pos = Vec2(float(x), float(y)) + Vec2(rng.next_float(), rng.next_float());
                Ray r = sensor.sample_ray(pos, Vec2(0.5f), sensor.shutter_open());
                by_pixel.push_back(r);
                by_row[(size_t(s) * size.y + y) * size.x + x] = r;
            }
    const size_t n = by_pixel.size();
    std::vector<float> single_t(n), packet_t(n), row_t(n);
    double best_single = 1e30, best_packet = 1e30, best_row = 1e30;
    for (int r = 0; r < repeats; ++r) {
        auto t0 = std::chrono::steady_clock::now();
        RayHit hit;
        for (size_t i = 0; i < n; ++i) single_t[i] = scene->accel().intersect(by_pixel[i], hit) ? hit.t : Infinity;
        best_single = std::min(best_single, seconds_since(t0));
        t0 = std::chrono::steady_clock::now();
        trace_packets(scene->accel().scene(), by_pixel, packet_t);
        best_packet = std::min(best_packet, seconds_since(t0));
        t0 = std::chrono::steady_clock::now();
        trace_packets(scene->accel().scene(), by_row, row_t);
        best_row = std::min(best_row, seconds_since(t0));
    }
    // Whether a packet finds bit for bit the distance a single ray finds (the image would then not
    // depend on how samples are grouped into packets).
    long differ = 0;
    for (size_t i = 0; i < n; ++i) differ += !(single_t[i] == packet_t[i]);
    std::printf("scene                         %s\n", scene_path.c_str());
    std::printf("camera rays                   %zu (%d x %d pixels, %d per pixel), 1 thread, best of %d\n", n, size.x, size.y, spp,
                repeats);
    std::printf("one at a time Mrays/s         %.2f\n", double(n) / best_single * 1e-6);
    std::printf("8-packets of a pixel Mrays/s  %.2f (%.2fx)\n", double(n) / best_packet * 1e-6, best_single / best_packet);
    std::printf("8-packets of a row Mrays/s    %.2f (%.2fx)\n", double(n) / best_row * 1e-6, best_single / best_row);
    std::printf("distances not bit-identical   %ld of %zu\n", differ, n);
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::run_main(argc, argv, usage, run); }
