#pragma once
// The base of the curve shapes (linearcurve, bsplinecurve): tubes around polylines or cubic
// B-splines with a radius per control point, intersected by Embree's round curve primitives.
// Loads Mitsuba's curve files: one control point "x y z radius" per line, curves separated by
// blank lines. Positions are moved by to_world; radii are not (as in Mitsuba).

#include "core/shape.h"

namespace candela {

class CurveShape : public Shape {
public:
    // `points_per_segment`: 2 for linear segments, 4 for cubic B-spline segments.
    CurveShape(const Properties& props, int points_per_segment, const char* type_name);

    RTCGeometry create_embree_geometry(RTCDevice device) const override;
    void fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const override;
    BoundingBox bbox() const override { return bbox_; }
    // A tube of rings around the centre line; `detail` sets the segments around.
    void tessellate(TriangleSoup& out, int detail) const override;

    // Curves cannot carry emitters (Mitsuba cannot sample them either): never called.
    float surface_area() const override;
    PositionSample sample_position(const Vec2&) const override;

    size_t segment_count() const { return first_point_.size(); }

protected:
    // The centre line on segment `segment` at parameter v in [0, 1]: point, derivative, second
    // derivative, radius and d radius / dv.
    struct CurvePoint {
        Vec3 c, dc, ddc;
        float radius = 0.0f, dradius = 0.0f;
    };
    virtual CurvePoint evaluate(size_t segment, float v) const = 0;
    // The unit normal at p, a point on the surface above centre point `cp`.
    virtual Vec3 surface_normal(const Vec3& p, const CurvePoint& cp) const = 0;

    std::vector<Vec4> points_;           // x, y, z (world), radius
    std::vector<unsigned> first_point_;  // per segment: the index of its first control point

private:
    RTCGeometryType embree_type_;
    int points_per_segment_;
    BoundingBox bbox_;
};

}  // namespace candela
