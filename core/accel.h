#pragma once
// The Embree 3 acceleration structure: one BVH over every shape of the scene, answering
// closest-hit and shadow (any-hit) queries. A shape group builds its own BVH on the scene's
// device, which instances then reference (Embree's single-level instancing): the group's
// geometry is stored once however many instances there are.

#include "core/shape.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <vector>

namespace candela {

// Embree's motion blur works in times relative to the shutter, [0, 1] from open to close
// (rtcSetGeometryTimeRange): scene times map there linearly. A closed shutter (open == close)
// maps by a unit length, so that its one instant lands on 0.
struct EmbreeTime {
    float open = 0.0f, length = 1.0f;
    EmbreeTime() = default;
    EmbreeTime(float shutter_open, float shutter_close)
        : open(shutter_open), length(shutter_close > shutter_open ? shutter_close - shutter_open : 1.0f) {}
    float operator()(float time) const { return (time - open) / length; }
};

class Accel {
public:
    // A BVH with its own Embree device (the scene's).
    Accel();
    // A BVH on an existing device (a shape group's, for instances in the scene on that device).
    explicit Accel(RTCDevice shared_device);
    ~Accel();
    Accel(const Accel&) = delete;
    Accel& operator=(const Accel&) = delete;

    void build(const std::vector<Ref<Shape>>& shapes);
    // The shutter the rays' times are relative to (see EmbreeTime); before build().
    void set_shutter(float open, float close) { time_ = EmbreeTime(open, close); }

    // Closest hit within [ray.tmin, ray.tmax]; returns the shape hit (null for a miss). For a hit
    // on an instance, the instance is returned and hit.instance_geometry names the geometry of
    // the group that was hit (see shape(unsigned)).
    const Shape* intersect(const Ray& ray, RayHit& hit) const;
    // True when anything blocks the ray within [ray.tmin, ray.tmax].
    bool occluded(const Ray& ray) const;
    // The same for up to PacketSize rays at once (Embree's 16-ray packets, rtcIntersect16 and
    // rtcOccluded16, or two 8-ray ones where the device's kernels are 8 wide: a wavefront's
    // batches), answered as the calls above answer each ray. `coherent`: the rays leave from
    // about one place in about one direction (one pixel's camera rays), so Embree may trace them
    // as a frustum (RTC_INTERSECT_CONTEXT_FLAG_COHERENT; the same hits, found faster for such
    // rays and slower for scattered ones).
    static constexpr size_t PacketSize = 16;
    void intersect_packet(const Ray* const rays[], size_t n, const Shape* shapes[], RayHit hits[], bool coherent = false) const;
    void occluded_packet(const Ray* const rays[], size_t n, bool blocked[]) const;

    RTCDevice device() const { return device_; }
    RTCScene scene() const { return scene_; }
    // The shape of an Embree geometry id of this BVH.
    const Shape* shape(unsigned geometry_id) const { return geometry_id < shapes_.size() ? shapes_[geometry_id] : nullptr; }
    // Bytes the Embree device currently holds (BVHs and geometry buffers of every scene built on
    // it, shape groups included); counted only by the Accel that created the device.
    int64_t embree_bytes() const { return bytes_.load(); }

private:
    static bool memory_monitor(void* self, ssize_t bytes, bool post);
    // Embree takes ray times in [0, 1] only (its assertions stop the program otherwise). Rays of
    // camera and light paths carry times within the shutter; a ray made without one (time 0)
    // in a scene whose shutter opens later takes the nearest instant of the shutter.
    // Inline: every query asks it.
    float embree_time(float time) const { return std::clamp(time_(time), 0.0f, 1.0f); }
    // A packet query of `Width` (8 or 16) rays.
    template <int Width>
    void intersect_lanes(const Ray* const rays[], size_t n, const Shape* shapes[], RayHit hits[], bool coherent) const;
    template <int Width>
    void occluded_lanes(const Ray* const rays[], size_t n, bool blocked[]) const;

    RTCDevice device_ = nullptr;
    bool owns_device_ = false;
    bool native_packet16_ = true;  // the device's kernels answer 16-ray packets as one
    RTCScene scene_ = nullptr;
    std::vector<const Shape*> shapes_;  // by Embree geometry id
    EmbreeTime time_;
    std::atomic<int64_t> bytes_{0};
};

// A user geometry's bounds callback's answer: box b, padded by a relative epsilon so that hits
// exactly on the box survive Embree's culling.
void write_padded_bounds(const BoundingBox& b, RTCBounds* out);

// A user geometry's Embree callbacks (analytic shapes, SDF grids), for any packet width N
// (rtcIntersect1 calls them with N = 1, the wavefront's packets with 16): each valid lane's ray
// is answered by `hit_t(o, d, tnear, tfar, t)`, true with the hit's distance t; a hit records the
// shape's primitive with barycentrics 0 and a placeholder normal (fill_interaction computes the
// real one).
template <class HitDistance>
void intersect_user_geometry(const RTCIntersectFunctionNArguments* args, const HitDistance& hit_t) {
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
    const unsigned N = args->N;
    for (unsigned i = 0; i < N; ++i) {
        if (!args->valid[i]) continue;
        const Vec3 o(RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i), RTCRayN_org_z(ray, N, i));
        const Vec3 d(RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i));
        float t;
        if (!hit_t(o, d, RTCRayN_tnear(ray, N, i), RTCRayN_tfar(ray, N, i), t)) continue;
        RTCRayN_tfar(ray, N, i) = t;
        RTCHitN_u(hit, N, i) = RTCHitN_v(hit, N, i) = 0.0f;
        RTCHitN_Ng_x(hit, N, i) = RTCHitN_Ng_y(hit, N, i) = 0.0f;
        RTCHitN_Ng_z(hit, N, i) = 1.0f;
        RTCHitN_primID(hit, N, i) = args->primID;
        RTCHitN_geomID(hit, N, i) = args->geomID;
        RTCHitN_instID(hit, N, i, 0) = args->context->instID[0];
    }
}
template <class HitDistance>
void occluded_user_geometry(const RTCOccludedFunctionNArguments* args, const HitDistance& hit_t) {
    const unsigned N = args->N;
    for (unsigned i = 0; i < N; ++i) {
        if (!args->valid[i]) continue;
        const Vec3 o(RTCRayN_org_x(args->ray, N, i), RTCRayN_org_y(args->ray, N, i), RTCRayN_org_z(args->ray, N, i));
        const Vec3 d(RTCRayN_dir_x(args->ray, N, i), RTCRayN_dir_y(args->ray, N, i), RTCRayN_dir_z(args->ray, N, i));
        float t;
        if (hit_t(o, d, RTCRayN_tnear(args->ray, N, i), RTCRayN_tfar(args->ray, N, i), t)) RTCRayN_tfar(args->ray, N, i) = -Infinity;
    }
}

// Embree builds BVHs on threads of its own (TBB's workers) and calls Candela's callbacks there
// (shape bounds, the memory monitor). Each such callback holds one of these for its duration: in
// a ThreadSanitizer build it tells TSan that what the committing thread wrote before the build
// happens before the callback, and the callback before the commit returns (hand-offs inside the
// uninstrumented libraries that TSan cannot see; core/parallel.h). Nothing in other builds.
class EmbreeCallbackScope {
public:
    EmbreeCallbackScope();
    ~EmbreeCallbackScope();
    EmbreeCallbackScope(const EmbreeCallbackScope&) = delete;
    EmbreeCallbackScope& operator=(const EmbreeCallbackScope&) = delete;
};

}  // namespace candela
