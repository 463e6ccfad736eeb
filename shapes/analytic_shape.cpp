#include "shapes/analytic_shape.h"

#include "core/accel.h"

namespace candela {

namespace {
void bounds_callback(const RTCBoundsFunctionArguments* args) {
    EmbreeCallbackScope scope;
    auto* shape = static_cast<const AnalyticShape*>(args->geometryUserPtr);
    write_padded_bounds(shape->bbox(), args->bounds_o);
}

void intersect_callback(const RTCIntersectFunctionNArguments* args) {
    if (!args->valid[0]) return;
    auto* shape = static_cast<const AnalyticShape*>(args->geometryUserPtr);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);  // N == 1 for rtcIntersect1
    Vec3 o(rh->ray.org_x, rh->ray.org_y, rh->ray.org_z), d(rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z);
    float t;
    if (!shape->intersect_t(o, d, rh->ray.tnear, rh->ray.tfar, t)) return;
    rh->ray.tfar = t;
    rh->hit.u = 0.0f;
    rh->hit.v = 0.0f;
    rh->hit.Ng_x = rh->hit.Ng_y = 0.0f;
    rh->hit.Ng_z = 1.0f;
    rh->hit.primID = args->primID;
    rh->hit.geomID = args->geomID;
    rh->hit.instID[0] = args->context->instID[0];
}

void occluded_callback(const RTCOccludedFunctionNArguments* args) {
    if (!args->valid[0]) return;
    auto* shape = static_cast<const AnalyticShape*>(args->geometryUserPtr);
    auto* ray = reinterpret_cast<RTCRay*>(args->ray);
    Vec3 o(ray->org_x, ray->org_y, ray->org_z), d(ray->dir_x, ray->dir_y, ray->dir_z);
    float t;
    if (shape->intersect_t(o, d, ray->tnear, ray->tfar, t)) ray->tfar = -Infinity;
}
}  // namespace

RTCGeometry AnalyticShape::create_embree_geometry(RTCDevice device) const {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, 1);
    rtcSetGeometryUserData(g, const_cast<AnalyticShape*>(this));
    rtcSetGeometryBoundsFunction(g, bounds_callback, nullptr);
    rtcSetGeometryIntersectFunction(g, intersect_callback);
    rtcSetGeometryOccludedFunction(g, occluded_callback);
    return g;
}

}  // namespace candela
