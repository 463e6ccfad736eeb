#pragma once
// Shapes intersected by their own exact formula (sphere, disk), wrapped as Embree user geometry
// so that they share the one BVH with the triangle meshes.

#include "core/shape.h"

namespace candela {

class AnalyticShape : public Shape {
public:
    explicit AnalyticShape(const Properties& props) : Shape(props) {}
    RTCGeometry create_embree_geometry(RTCDevice device) const override;
    // The nearest hit parameter in (tmin, tmax], if any: strictly beyond tmin, so that a ray
    // starting exactly on the surface does not hit its own origin at t = 0. Such rays are given
    // from outside (a radiancemeter's origin placed on a surface) or spawned from a point whose
    // error bound is zero, so that spawn_ray does not offset it (an untransformed disk's centre).
    // Embree's robust triangles take tnear <= t; whether a ray starting on a triangle's plane
    // finds t = 0 there is left to rounding, and spawn_ray always offsets mesh points.
    virtual bool intersect_t(const Vec3& o, const Vec3& d, float tmin, float tmax, float& t) const = 0;
};

// Whether a root found in double precision is a hit in (tmin, tmax] once rounded to the float the
// hit stores (a root just above tmin can round onto it); sets t when it is.
inline bool root_in_segment(double root, float tmin, float tmax, float& t) {
    const float rounded = float(root);
    if (!(rounded > tmin && rounded <= tmax)) return false;
    t = rounded;
    return true;
}
}  // namespace candela
