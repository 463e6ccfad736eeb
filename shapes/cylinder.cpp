// cylinder: an open tube (no end caps), intersected exactly.
//
// Parameters:
//   p0             point       start of the axis in object space (default 0, 0, 0)
//   p1             point       end of the axis in object space (default 0, 0, 1)
//   radius         float       radius in object space (default 1)
//   flip_normals   boolean     make the inside the front side (default false: normals point out)
//   to_world       transform   object to world, applied after p0, p1 and radius; it may rotate,
//                              translate and scale, but not shear or scale the cross-section
//                              unevenly (an elliptic tube is an error; use a mesh)
//
// As in Mitsuba 3: the tube's own frame has z along p1 - p0 and x, y from coordinate_system of
// that direction; uv = (phi / 2pi, z / length) with phi measured from x toward y, dp/du =
// 2pi (-y, x, 0) and dp/dv = (0, 0, length) in that frame, and the geometric normal is
// dp/du x dp/dv (a mirroring to_world turns the tube inside out). As an area light it is sampled
// uniformly by area. With the default one-sided BSDFs the inside is black; wrap the BSDF in
// `twosided` to see it.

#include "core/registry.h"
#include "shapes/analytic_shape.h"

namespace candela {

class Cylinder final : public AnalyticShape {
public:
    explicit Cylinder(const Properties& props) : AnalyticShape(props) {
        Vec3 p0 = props.get_point("p0", Vec3(0.0f)), p1 = props.get_point("p1", Vec3(0, 0, 1));
        float radius = props.get_float("radius", 1.0f);
        if (!(radius > 0.0f) || !std::isfinite(radius)) props.fail("radius", "cylinder radius must be positive");
        Vec3 axis = p1 - p0;
        float length = glm::length(axis);
        if (!(length > 0.0f) || !std::isfinite(length)) props.fail("p1", "cylinder p0 and p1 must differ");
        Frame frame(axis / length);
        Mat4 local(1.0f);  // the unit tube x^2 + y^2 = 1, 0 <= z <= 1, onto the object-space one
        local[0] = Vec4(frame.s * radius, 0.0f);
        local[1] = Vec4(frame.t * radius, 0.0f);
        local[2] = Vec4(axis, 0.0f);
        local[3] = Vec4(p0, 1.0f);
        object_to_world_ = to_world_ * Transform(local);
        if (!object_to_world_.all_finite()) props.fail("to_world", "cylinder transform is not finite");
        const Mat4& m = object_to_world_.matrix();
        Vec3 a0(m[0]), a1(m[1]), a2(m[2]);
        radius_ = glm::length(a0);
        length_ = glm::length(a2);
        float tol = 1e-4f;
        if (std::abs(glm::length(a1) - radius_) > tol * radius_ || std::abs(glm::dot(a0, a1)) > tol * radius_ * radius_ ||
            std::abs(glm::dot(a0, a2)) > tol * radius_ * length_ || std::abs(glm::dot(a1, a2)) > tol * radius_ * length_ ||
            !(radius_ > 0.0f) || !(length_ > 0.0f))
            props.fail("to_world",
                       "a cylinder's to_world must not shear it or scale its cross-section unevenly (use a mesh for elliptic tubes)");
        world_to_object_ = glm::inverse(glm::dmat4(m));
        // The two end circles bound the tube.
        Vec3 c0(m[3]), c1 = c0 + a2, ext = glm::sqrt(a0 * a0 + a1 * a1);
        bbox_.expand(c0 - ext);
        bbox_.expand(c0 + ext);
        bbox_.expand(c1 - ext);
        bbox_.expand(c1 + ext);
    }

    BoundingBox bbox() const override { return bbox_; }
    float surface_area() const override { return TwoPi * radius_ * length_; }

    bool intersect_t(const Vec3& of, const Vec3& df, float tmin, float tmax, float& t) const override {
        // In the unit tube's space (an affine map keeps the ray parameter), in double precision:
        // (ox + t dx)^2 + (oy + t dy)^2 = 1 with 0 <= z <= 1.
        glm::dvec3 o(world_to_object_ * glm::dvec4(Vec3d(of), 1.0)), d(world_to_object_ * glm::dvec4(Vec3d(df), 0.0));
        double a = d.x * d.x + d.y * d.y;
        if (a == 0.0) return false;  // parallel to the axis
        double b = o.x * d.x + o.y * d.y, c = o.x * o.x + o.y * o.y - 1.0;
        double disc = b * b - a * c;
        if (disc < 0.0) return false;
        // The stable pair of roots (Numerical Recipes 5.6).
        double q = -(b + std::copysign(std::sqrt(disc), b));
        double t0 = q / a, t1 = q != 0.0 ? c / q : t0;
        if (t0 > t1) std::swap(t0, t1);
        for (double th : {t0, t1}) {
            double z = o.z + th * d.z;
            if (z >= 0.0 && z <= 1.0 && root_in_segment(th, tmin, tmax, t)) return true;
        }
        return false;
    }

    void fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const override {
        glm::dvec3 o(world_to_object_ * glm::dvec4(Vec3d(ray.o), 1.0)), d(world_to_object_ * glm::dvec4(Vec3d(ray.d), 0.0));
        glm::dvec3 local = o + double(hit.t) * d;
        fill_at(std::atan2(local.y, local.x), float(std::clamp(local.z, 0.0, 1.0)), si);
    }

    PositionSample sample_position(const Vec2& u) const override {
        SurfaceInteraction si;
        fill_at(TwoPi * u.y, u.x, si);
        PositionSample ps;
        ps.p = si.p;
        ps.p_error = si.p_error;
        ps.n = si.n;
        ps.uv = si.uv;
        ps.pdf = 1.0f / surface_area();
        return ps;
    }

    // A ring of `detail` quads; the seam repeats its first column so that uvs stay continuous.
    void tessellate(TriangleSoup& out, int detail) const override {
        int n = std::max(detail, 8);
        unsigned base = unsigned(out.positions.size());
        SurfaceInteraction si;
        for (int j = 0; j <= n; ++j)
            for (int k = 0; k < 2; ++k) {
                fill_at(TwoPi * float(j % n) / float(n), float(k), si);
                out.positions.push_back(si.p);
                out.normals.push_back(si.n);
                out.uvs.emplace_back(float(j) / float(n), float(k));
            }
        for (int j = 0; j < n; ++j) {
            unsigned a = base + 2 * unsigned(j), b = a + 1, c = a + 2, d = a + 3;  // a, c at z = 0
            // Counter-clockwise around the front normal.
            Vec3 face = glm::cross(out.positions[c] - out.positions[a], out.positions[d] - out.positions[a]);
            bool ccw = glm::dot(face, out.normals[a] + out.normals[c]) >= 0.0f;
            out.triangles.push_back(ccw ? glm::uvec3(a, c, d) : glm::uvec3(a, d, c));
            out.triangles.push_back(ccw ? glm::uvec3(a, d, b) : glm::uvec3(a, b, d));
        }
        out.closed = false;
    }

    std::string to_string() const override { return "cylinder"; }

private:
    // The surface point at angle phi and height z in [0, 1] of the unit tube.
    void fill_at(double phi, float z, SurfaceInteraction& si) const {
        if (phi < 0.0) phi += 2.0 * double(Pi);
        float c = float(std::cos(phi)), s = float(std::sin(phi));
        Vec3 local(c, s, z);
        si.p = object_to_world_.apply_point(local);
        // Error of the affine map: a few roundings of sum_j |M_ij local_j| + |t_i|.
        const Mat4& m = object_to_world_.matrix();
        Vec3 magnitude = glm::abs(Vec3(m[0]) * c) + glm::abs(Vec3(m[1]) * s) + glm::abs(Vec3(m[2]) * z) + glm::abs(Vec3(m[3]));
        si.p_error = gamma_bound(6) * max_component(magnitude);
        si.uv = Vec2(float(phi / (2.0 * double(Pi))), z);
        si.dpdu = object_to_world_.apply_vector(Vec3(-s, c, 0.0f) * TwoPi);
        si.dpdv = object_to_world_.apply_vector(Vec3(0.0f, 0.0f, 1.0f));
        Vec3 n = glm::normalize(glm::cross(si.dpdu, si.dpdv));
        if (flip_normals_) n = -n;
        si.n = n;
        si.shading = Frame::from_normal_tangent(n, si.dpdu);
    }

    Transform object_to_world_;
    glm::dmat4 world_to_object_{1.0};
    float radius_ = 1.0f, length_ = 1.0f;
    BoundingBox bbox_;
};

CANDELA_REGISTER(Cylinder, ObjectKind::Shape, "cylinder");

}  // namespace candela
