// bsplinecurve: tubes along uniform cubic B-splines, with a radius per control point (itself a
// B-spline), open-ended (no caps: give the end points radius 0 to close them), as Embree's round
// B-spline curves.
//
// Parameters:
//   filename       string      the curve file: one control point "x y z radius" per line,
//                              curves separated by blank lines, at least 4 points per curve
//   to_world       transform   moves the control points; radii stay as given (as in Mitsuba)
//   flip_normals   boolean     swap front and back (default false)
//
// Each run of four consecutive control points is one segment. As in Mitsuba 3: the normal at a
// hit point p above centre c(v) is normalize((|c'|^2 - (p - c).c'') (p - c) - r r' c'), which
// accounts for the changing radius and the curve's bending; uv = (angle around the curve / 2pi,
// (v + segment index) / segment count), the angle measured in Mitsuba's frame (see
// linearcurve.cpp). Rays starting inside a tube do not hit it. Curves cannot be area emitters.

#include "core/registry.h"
#include "shapes/curve.h"

namespace candela {

class BSplineCurve final : public CurveShape {
public:
    explicit BSplineCurve(const Properties& props) : CurveShape(props, 4, "bsplinecurve") {}
    std::string to_string() const override { return "bsplinecurve"; }

protected:
    // The uniform cubic B-spline basis, its first and second derivatives (times 6).
    CurvePoint evaluate(size_t segment, float v) const override {
        float v2 = v * v, v3 = v2 * v;
        const float w[4] = {-v3 + 3 * v2 - 3 * v + 1, 3 * v3 - 6 * v2 + 4, -3 * v3 + 3 * v2 + 3 * v + 1, v3};
        const float dw[4] = {-3 * v2 + 6 * v - 3, 9 * v2 - 12 * v, -9 * v2 + 6 * v + 3, 3 * v2};
        const float ddw[4] = {6 * (1 - v), 6 * (3 * v - 2), 6 * (1 - 3 * v), 6 * v};
        CurvePoint cp;
        cp.c = cp.dc = cp.ddc = Vec3(0.0f);
        for (int k = 0; k < 4; ++k) {
            const Vec4& q = points_[first_point_[segment] + unsigned(k)];
            cp.c += w[k] * Vec3(q);
            cp.dc += dw[k] * Vec3(q);
            cp.ddc += ddw[k] * Vec3(q);
            cp.radius += w[k] * q.w;
            cp.dradius += dw[k] * q.w;
        }
        const float sixth = 1.0f / 6.0f;
        cp.c *= sixth;
        cp.dc *= sixth;
        cp.ddc *= sixth;
        cp.radius *= sixth;
        cp.dradius *= sixth;
        return cp;
    }
    Vec3 surface_normal(const Vec3& p, const CurvePoint& cp) const override {
        Vec3 r = p - cp.c;
        Vec3 n = (squared_length(cp.dc) - glm::dot(r, cp.ddc)) * r - (cp.dradius * cp.radius) * cp.dc;
        return squared_length(n) > 0.0f ? glm::normalize(n) : Vec3(0.0f, 0.0f, 1.0f);
    }
};

CANDELA_REGISTER(BSplineCurve, ObjectKind::Shape, "bsplinecurve");

}  // namespace candela
