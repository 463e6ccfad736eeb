// linearcurve: tubes along polylines, with a radius per control point (cones between control
// points, joined and ended by spheres), as Embree's round linear curves.
//
// Parameters:
//   filename       string      the curve file: one control point "x y z radius" per line,
//                              curves separated by blank lines, at least 2 points per curve
//   to_world       transform   moves the control points; radii stay as given (as in Mitsuba)
//   flip_normals   boolean     swap front and back (default false)
//
// As in Mitsuba 3: the normal at a hit is the direction from the axis point at Embree's curve
// parameter to the hit; uv = (angle around the segment / 2pi, (parameter + segment index) /
// segment count), the angle measured in Mitsuba's frame (from v_rot x tangent toward the part of
// +z orthogonal to the tangent). Rays starting inside a tube do not hit it. Curves cannot be
// area emitters.

#include "core/registry.h"
#include "shapes/curve.h"

namespace candela {

class LinearCurve final : public CurveShape {
public:
    explicit LinearCurve(const Properties& props) : CurveShape(props, 2, "linearcurve") {}
    std::string to_string() const override { return "linearcurve"; }

protected:
    CurvePoint evaluate(size_t segment, float v) const override {
        const Vec4 &a = points_[first_point_[segment]], &b = points_[first_point_[segment] + 1];
        CurvePoint cp;
        cp.c = Vec3(a) + v * (Vec3(b) - Vec3(a));
        cp.dc = Vec3(b) - Vec3(a);
        cp.ddc = Vec3(0.0f);
        cp.radius = a.w + v * (b.w - a.w);
        cp.dradius = b.w - a.w;
        return cp;
    }
    // Embree's parameter already accounts for a changing radius: the normal is radial from it.
    Vec3 surface_normal(const Vec3& p, const CurvePoint& cp) const override {
        Vec3 r = p - cp.c;
        return squared_length(r) > 0.0f ? glm::normalize(r) : Vec3(0.0f, 0.0f, 1.0f);
    }
};

CANDELA_REGISTER(LinearCurve, ObjectKind::Shape, "linearcurve");

}  // namespace candela
