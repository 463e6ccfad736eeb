// mitsuba_ray_count: counts the rays Mitsuba 3's scalar variants trace, to compare Embree's cost
// per ray in Mitsuba and in Candela (bench/results/mitsuba_embree_2026-12-05.txt). A measuring
// tool beside the peer, not part of Candela; nothing builds it.
//
//   g++ -O2 -shared -fPIC bench/peers/mitsuba_ray_count.cpp -o /tmp/mitsuba_ray_count.so -ldl
//   export LD_LIBRARY_PATH=/tmp/mitsuba3 LD_PRELOAD=/tmp/mitsuba_ray_count.so
//   /tmp/mitsuba3/mitsuba -m scalar_rgb -t 2 -o /tmp/out.exr scene.xml
//
// prints, at exit, the closest-hit and shadow rays traced. Mitsuba's build puts Embree's API in
// namespace `mitsuba`, so the wrappers carry its names and forward to the next definition. The
// LLVM variants reach Embree through Dr.Jit without these entry points: they are not counted.

#include <dlfcn.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace {

std::atomic<long> g_closest_hit{0}, g_shadow{0};

struct ReportAtExit {
    ~ReportAtExit() {
        std::fprintf(stderr, "mitsuba_ray_count: %ld closest-hit rays, %ld shadow rays, %ld in all\n", g_closest_hit.load(),
                     g_shadow.load(), g_closest_hit.load() + g_shadow.load());
    }
} g_report;

void* next_definition(const char* mangled_name) {
    void* function = dlsym(RTLD_NEXT, mangled_name);
    if (!function) {
        std::fprintf(stderr, "mitsuba_ray_count: %s not found (is this Mitsuba's libembree3?)\n", mangled_name);
        std::abort();
    }
    return function;
}

}  // namespace

namespace mitsuba {

struct RTCSceneTy;
struct RTCIntersectContext;
struct RTCRayHit;
struct RTCRay;

void rtcIntersect1(RTCSceneTy* scene, RTCIntersectContext* context, RTCRayHit* ray) {
    using Function = void (*)(RTCSceneTy*, RTCIntersectContext*, RTCRayHit*);
    static const auto forward = reinterpret_cast<Function>(
        next_definition("_ZN7mitsuba13rtcIntersect1EPNS_10RTCSceneTyEPNS_19RTCIntersectContextEPNS_9RTCRayHitE"));
    g_closest_hit.fetch_add(1, std::memory_order_relaxed);
    forward(scene, context, ray);
}

void rtcOccluded1(RTCSceneTy* scene, RTCIntersectContext* context, RTCRay* ray) {
    using Function = void (*)(RTCSceneTy*, RTCIntersectContext*, RTCRay*);
    static const auto forward =
        reinterpret_cast<Function>(next_definition("_ZN7mitsuba12rtcOccluded1EPNS_10RTCSceneTyEPNS_19RTCIntersectContextEPNS_6RTCRayE"));
    g_shadow.fetch_add(1, std::memory_order_relaxed);
    forward(scene, context, ray);
}

}  // namespace mitsuba
