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
    auto* shape = static_cast<const AnalyticShape*>(args->geometryUserPtr);
    intersect_user_geometry(args, [shape](const Vec3& o, const Vec3& d, float tnear, float tfar, float& t) {
        return shape->intersect_t(o, d, tnear, tfar, t);
    });
}

void occluded_callback(const RTCOccludedFunctionNArguments* args) {
    auto* shape = static_cast<const AnalyticShape*>(args->geometryUserPtr);
    occluded_user_geometry(args, [shape](const Vec3& o, const Vec3& d, float tnear, float tfar, float& t) {
        return shape->intersect_t(o, d, tnear, tfar, t);
    });
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
