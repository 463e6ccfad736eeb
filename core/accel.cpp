#include "core/accel.h"

#include "core/error.h"
#include "core/integrator.h"
#include "core/parallel.h"
#include "core/profiling.h"

#include <algorithm>
#include <csignal>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace candela {

namespace {
thread_local uint64_t g_rays_traced = 0;
// Set around each Embree query; volatile so that a signal handler on this thread sees it.
thread_local volatile sig_atomic_t g_inside_embree = 0;

// The hand-off from a thread that commits geometry or a scene to Embree's build threads.
ParallelHandOff& embree_build_hand_off() {
    static ParallelHandOff hand_off;
    return hand_off;
}

void embree_error(void*, RTCError code, const char* message) {
    if (code != RTC_ERROR_NONE) std::fprintf(stderr, "embree error %d: %s\n", int(code), message ? message : "");
}
}  // namespace

EmbreeCallbackScope::EmbreeCallbackScope() { embree_build_hand_off().chunk_begins(); }
EmbreeCallbackScope::~EmbreeCallbackScope() { embree_build_hand_off().chunk_ends(); }

uint64_t thread_ray_count() { return g_rays_traced; }
bool thread_inside_embree() { return g_inside_embree != 0; }

Accel::Accel() : owns_device_(true) {
    // CANDELA_EMBREE_CONFIG, when set, is Embree's device configuration ("isa=avx2",
    // "verbose=1"...): how the kernels of a machine without AVX-512 are tested on one with it.
    const char* config = std::getenv("CANDELA_EMBREE_CONFIG");
    device_ = rtcNewDevice(config);
    if (!device_) {
        const int code = int(rtcGetDeviceError(nullptr));
        if (config)
            throw InputError("CANDELA_EMBREE_CONFIG=\"" + std::string(config) + "\": Embree refused this device configuration (error " +
                             std::to_string(code) + ")");
        throw InternalError("could not create the Embree device (error " + std::to_string(code) + ")");
    }
    rtcSetDeviceErrorFunction(device_, embree_error, nullptr);
    rtcSetDeviceMemoryMonitorFunction(device_, memory_monitor, this);
    native_packet16_ = rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0;
}

Accel::Accel(RTCDevice shared_device) : device_(shared_device) {
    rtcRetainDevice(device_);
    native_packet16_ = rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0;
}

Accel::~Accel() {
    // Scenes of shape groups may outlive this one on the same device: stop counting into *this.
    if (owns_device_) rtcSetDeviceMemoryMonitorFunction(device_, nullptr, nullptr);
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

bool Accel::memory_monitor(void* self, ssize_t bytes, bool) {
    EmbreeCallbackScope scope;
    static_cast<Accel*>(self)->bytes_ += int64_t(bytes);
    return true;
}

void Accel::build(const std::vector<Ref<Shape>>& shapes) {
    if (scene_) rtcReleaseScene(scene_);
    scene_ = rtcNewScene(device_);
    // ROBUST: no optimisations that trade arithmetic accuracy for speed (watertight hits).
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    shapes_.clear();
    for (const Ref<Shape>& shape : shapes) {
        RTCGeometry geometry = shape->create_embree_geometry(device_);
        embree_build_hand_off().before_loop();
        rtcCommitGeometry(geometry);
        embree_build_hand_off().after_loop();
        unsigned id = rtcAttachGeometry(scene_, geometry);
        rtcReleaseGeometry(geometry);
        if (shapes_.size() <= id) shapes_.resize(id + 1, nullptr);
        shapes_[id] = shape.get();
    }
    embree_build_hand_off().before_loop();
    rtcCommitScene(scene_);
    embree_build_hand_off().after_loop();
}

void write_padded_bounds(const BoundingBox& b, RTCBounds* out) {
    Vec3 pad = (Vec3(1.0f) + glm::abs(b.min) + glm::abs(b.max)) * 1e-6f;
    out->lower_x = b.min.x - pad.x;
    out->lower_y = b.min.y - pad.y;
    out->lower_z = b.min.z - pad.z;
    out->upper_x = b.max.x + pad.x;
    out->upper_y = b.max.y + pad.y;
    out->upper_z = b.max.z + pad.z;
}

const Shape* Accel::intersect(const Ray& ray, RayHit& hit) const {
    ++g_rays_traced;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x;
    rh.ray.org_y = ray.o.y;
    rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x;
    rh.ray.dir_y = ray.d.y;
    rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = ray.tmin;
    rh.ray.tfar = ray.tmax;
    rh.ray.time = embree_time(ray.time);
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    g_inside_embree = 1;
    rtcIntersect1(scene_, &context, &rh);
    g_inside_embree = 0;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return nullptr;
    hit.t = rh.ray.tfar;
    hit.v = rh.hit.v;
    hit.prim_index = rh.hit.primID;
    const bool instance = rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID;
    // u and instance_geometry in one 8-byte store: the shapes' fill_interaction may load u as
    // part of an 8-byte block (GCC does, to broadcast it), and a load that spans two separate
    // 4-byte stores waits for both to retire (store forwarding fails: a quarter of
    // Mesh::fill_interaction's time).
    // (Little-endian: the low half is the lower address.)
    uint32_t u_bits;
    std::memcpy(&u_bits, &rh.hit.u, sizeof(u_bits));
    const uint32_t inside = instance ? rh.hit.geomID : RTC_INVALID_GEOMETRY_ID;
    const uint64_t u_and_inside = uint64_t(u_bits) | (uint64_t(inside) << 32);
    static_assert(offsetof(RayHit, instance_geometry) == offsetof(RayHit, u) + 4, "u, then instance_geometry");
    std::memcpy(&hit.u, &u_and_inside, sizeof(u_and_inside));
    return shapes_[instance ? rh.hit.instID[0] : rh.hit.geomID];
}

bool Accel::occluded(const Ray& ray) const {
    ++g_rays_traced;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    r.org_x = ray.o.x;
    r.org_y = ray.o.y;
    r.org_z = ray.o.z;
    r.dir_x = ray.d.x;
    r.dir_y = ray.d.y;
    r.dir_z = ray.d.z;
    r.tnear = ray.tmin;
    r.tfar = ray.tmax;
    r.time = embree_time(ray.time);
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
    g_inside_embree = 1;
    rtcOccluded1(scene_, &context, &r);
    g_inside_embree = 0;
    return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

namespace {
// Embree reads a packet's valid mask with aligned vector loads.
template <int Width>
struct alignas(64) PacketMask {
    int lanes[Width];
};

// Embree's packet types and queries by width: 16 where the device's kernels are 16 wide
// (AVX-512), else 8. On AVX2 kernels Embree answers a 16-ray query as two 8-ray ones, and
// asking for the two measured 4% faster in raw Embree and 1% in the wave
// (bench/results/embree_isa_2026-12-07.txt).
template <int Width>
struct PacketQueries;
template <>
struct PacketQueries<8> {
    using RayHitPacket = RTCRayHit8;
    using RayPacket = RTCRay8;
    static void intersect(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHit8* rh) {
        rtcIntersect8(valid, scene, context, rh);
    }
    static void occluded(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay8* r) {
        rtcOccluded8(valid, scene, context, r);
    }
};
template <>
struct PacketQueries<16> {
    using RayHitPacket = RTCRayHit16;
    using RayPacket = RTCRay16;
    static void intersect(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHit16* rh) {
        rtcIntersect16(valid, scene, context, rh);
    }
    static void occluded(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay16* r) {
        rtcOccluded16(valid, scene, context, r);
    }
};

// Lanes [0, n) of `mask` on, with `rays` written into the packet's ray fields (times mapped by
// `time`); the lanes beyond n off.
template <int Width, class Packet, class TimeMap>
void fill_packet(const Ray* const rays[], size_t n, const TimeMap& time, PacketMask<Width>& mask, Packet& r) {
    for (size_t i = 0; i < size_t(Width); ++i) {
        mask.lanes[i] = i < n ? -1 : 0;
        if (i >= n) {
            // An off lane still holds a valid empty ray: Embree's kernels narrower than the
            // packet (an 8-ray query on SSE4.2) assert every lane's ray valid under the split's mask.
            r.org_x[i] = r.org_y[i] = r.org_z[i] = 0.0f;
            r.dir_x[i] = r.dir_y[i] = r.dir_z[i] = 1.0f;
            r.tnear[i] = 0.0f;
            r.tfar[i] = -Infinity;
            r.time[i] = 0.0f;
            r.mask[i] = 0u;
            r.id[i] = unsigned(i);
            r.flags[i] = 0;
            continue;
        }
        const Ray& ray = *rays[i];
        r.org_x[i] = ray.o.x;
        r.org_y[i] = ray.o.y;
        r.org_z[i] = ray.o.z;
        r.dir_x[i] = ray.d.x;
        r.dir_y[i] = ray.d.y;
        r.dir_z[i] = ray.d.z;
        r.tnear[i] = ray.tmin;
        r.tfar[i] = ray.tmax;
        r.time[i] = time(ray.time);
        r.mask[i] = 0xFFFFFFFFu;
        r.id[i] = unsigned(i);
        r.flags[i] = 0;
    }
}

// Fills `packet` with rays[0, n) (n <= Width) and runs `query(valid, context)` on it, counted as
// n rays and marked as inside Embree; `coherent` as Accel::intersect_packet's.
template <int Width, class Packet, class TimeMap, class Query>
void query_packet(const Ray* const rays[], size_t n, const TimeMap& time, Packet& packet, bool coherent, const Query& query) {
    g_rays_traced += n;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if (coherent) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    PacketMask<Width> mask;
    fill_packet<Width>(rays, n, time, mask, packet);
    g_inside_embree = 1;
    query(mask.lanes, &context);
    g_inside_embree = 0;
}
}  // namespace

template <int Width>
void Accel::intersect_lanes(const Ray* const rays[], size_t n, const Shape* shapes[], RayHit hits[], bool coherent) const {
    typename PacketQueries<Width>::RayHitPacket rh;
    for (size_t i = 0; i < size_t(Width); ++i) rh.hit.geomID[i] = rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    query_packet<Width>(
        rays, n, [this](float t) { return embree_time(t); }, rh.ray, coherent,
        [&](const int* valid, RTCIntersectContext* context) { PacketQueries<Width>::intersect(valid, scene_, context, &rh); });
    for (size_t i = 0; i < n; ++i) {
        if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) {
            shapes[i] = nullptr;
            continue;
        }
        const bool instance = rh.hit.instID[0][i] != RTC_INVALID_GEOMETRY_ID;
        hits[i].t = rh.ray.tfar[i];
        hits[i].prim_index = rh.hit.primID[i];
        hits[i].u = rh.hit.u[i];
        hits[i].v = rh.hit.v[i];
        hits[i].instance_geometry = instance ? rh.hit.geomID[i] : RTC_INVALID_GEOMETRY_ID;
        shapes[i] = shapes_[instance ? rh.hit.instID[0][i] : rh.hit.geomID[i]];
    }
}

template <int Width>
void Accel::occluded_lanes(const Ray* const rays[], size_t n, bool blocked[]) const {
    typename PacketQueries<Width>::RayPacket r;
    query_packet<Width>(
        rays, n, [this](float t) { return embree_time(t); }, r, false,
        [&](const int* valid, RTCIntersectContext* context) { PacketQueries<Width>::occluded(valid, scene_, context, &r); });
    for (size_t i = 0; i < n; ++i) blocked[i] = r.tfar[i] < 0.0f;  // Embree sets tfar to -inf on a hit
}

void Accel::intersect_packet(const Ray* const rays[], size_t n, const Shape* shapes[], RayHit hits[], bool coherent) const {
    n = std::min(n, PacketSize);
    if (native_packet16_) return intersect_lanes<16>(rays, n, shapes, hits, coherent);
    for (size_t first = 0; first < n; first += 8)
        intersect_lanes<8>(rays + first, std::min<size_t>(8, n - first), shapes + first, hits + first, coherent);
}

void Accel::occluded_packet(const Ray* const rays[], size_t n, bool blocked[]) const {
    n = std::min(n, PacketSize);
    if (native_packet16_) return occluded_lanes<16>(rays, n, blocked);
    for (size_t first = 0; first < n; first += 8) occluded_lanes<8>(rays + first, std::min<size_t>(8, n - first), blocked + first);
}

}  // namespace candela
