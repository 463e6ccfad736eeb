#pragma once
// Shapes intersected by their own exact formula (sphere, disk), wrapped as Embree user geometry
// so that they share the one BVH with the triangle meshes.

#include "core/shape.h"

namespace candela {

class AnalyticShape : public Shape {
public:
    explicit AnalyticShape(const Properties& props) : Shape(props) {}
    RTCGeometry create_embree_geometry(RTCDevice device) const override;
    // The nearest hit parameter in [tmin, tmax], if any.
    virtual bool intersect_t(const Vec3& o, const Vec3& d, float tmin, float tmax, float& t) const = 0;
};

}  // namespace candela
