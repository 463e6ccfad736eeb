// disk: the unit disk in the z = 0 plane with normal +z, placed by to_world (an ellipse under a
// non-uniform scale). Intersected exactly.
//
// Parameters:
//   to_world       transform   object to world (default identity)
//   flip_normals   boolean     make -z the front side (default false)
// uv = (r, phi / 2pi) with r the object-space radius and phi measured from +x (Mitsuba 3).

#include "core/registry.h"
#include "core/warp.h"
#include "shapes/analytic_shape.h"

namespace candela {

class Disk final : public AnalyticShape {
public:
    explicit Disk(const Properties& props) : AnalyticShape(props) {
        if (!to_world_.all_finite()) props.fail("to_world", "disk transform is not finite");
        world_to_object_ = to_world_.inverse();
        Vec3 n = to_world_.apply_normal(Vec3(0, 0, 1));
        if (!(squared_length(n) > 0.0f)) props.fail("to_world", "disk transform is degenerate");
        normal_ = glm::normalize(n);
        if (flip_normals_) normal_ = -normal_;
        Vec3 ex = to_world_.apply_vector(Vec3(1, 0, 0)), ey = to_world_.apply_vector(Vec3(0, 1, 0));
        area_ = Pi * glm::length(glm::cross(ex, ey));
        if (!(area_ > 0.0f)) props.fail("to_world", "disk transform is degenerate");
        // The ellipse's bounding box: centre +- the per-axis extent of the two semi-axes.
        Vec3 c = to_world_.apply_point(Vec3(0.0f));
        Vec3 ext = glm::sqrt(ex * ex + ey * ey);
        bbox_.expand(c - ext);
        bbox_.expand(c + ext);
    }

    BoundingBox bbox() const override { return bbox_; }
    void normal_cone(Vec3& axis, float& cos_theta) const override {
        axis = normal_;
        cos_theta = 1.0f;
    }
    float surface_area() const override { return area_; }

    bool intersect_t(const Vec3& of, const Vec3& df, float tmin, float tmax, float& t) const override {
        // An affine map keeps the ray parameter, so intersect in object space.
        Vec3d o(world_to_object_.apply_point(of)), d(world_to_object_.apply_vector(df));
        if (d.z == 0.0) return false;
        double th = -o.z / d.z;
        // A ray leaving the disk's exact centre (an untransformed disk's point there has no
        // rounding error, so it is not offset) starts on the plane, at t = 0: strictly beyond tmin.
        float hit_t;
        if (!root_in_segment(th, tmin, tmax, hit_t)) return false;
        double x = o.x + th * d.x, y = o.y + th * d.y;
        if (x * x + y * y > 1.0) return false;
        t = hit_t;
        return true;
    }

    void fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const override {
        Vec3 local = world_to_object_.apply_point(ray(hit.t));
        local.z = 0.0f;
        fill_at(local, si);
    }

    PositionSample sample_position(const Vec2& u) const override {
        Vec2 d = warp::square_to_uniform_disk_concentric(u);
        SurfaceInteraction si;
        fill_at(Vec3(d, 0.0f), si);
        PositionSample ps;
        ps.p = si.p;
        ps.p_error = si.p_error;
        ps.n = normal_;
        ps.uv = si.uv;
        ps.pdf = 1.0f / area_;
        return ps;
    }

    // A fan of `detail` triangles around the centre.
    void tessellate(TriangleSoup& out, int detail) const override {
        int n = std::max(detail, 8);
        unsigned base = unsigned(out.positions.size());
        SurfaceInteraction si;
        fill_at(Vec3(0.0f), si);
        out.positions.push_back(si.p);
        out.normals.push_back(normal_);
        out.uvs.push_back(Vec2(0.0f));
        for (int j = 0; j <= n; ++j) {
            float phi = TwoPi * float(j % n) / float(n);
            fill_at(Vec3(std::cos(phi), std::sin(phi), 0.0f), si);
            out.positions.push_back(si.p);
            out.normals.push_back(normal_);
            out.uvs.emplace_back(1.0f, float(j) / float(n));
        }
        for (int j = 0; j < n; ++j) {
            unsigned a = base + 1 + unsigned(j), b = a + 1;
            // Counter-clockwise around the front normal.
            Vec3 face = glm::cross(out.positions[a] - out.positions[base], out.positions[b] - out.positions[base]);
            out.triangles.push_back(glm::dot(face, normal_) >= 0.0f ? glm::uvec3(base, a, b) : glm::uvec3(base, b, a));
        }
        out.closed = false;
    }

    std::string to_string() const override { return "disk"; }

private:
    void fill_at(const Vec3& local, SurfaceInteraction& si) const {
        si.p = to_world_.apply_point(local);
        // Error of the affine map: a few roundings of sum_j |M_ij local_j| + |t_i|.
        const Mat4& m = to_world_.matrix();
        Vec3 magnitude = glm::abs(Vec3(m[0]) * local.x) + glm::abs(Vec3(m[1]) * local.y) + glm::abs(Vec3(m[3]));
        si.p_error = gamma_bound(6) * max_component(magnitude);
        float r = std::sqrt(local.x * local.x + local.y * local.y);
        float phi = std::atan2(local.y, local.x);
        if (phi < 0.0f) phi += TwoPi;
        si.uv = Vec2(r, phi * InvTwoPi);
        float c = r > 0.0f ? local.x / r : 1.0f, s = r > 0.0f ? local.y / r : 0.0f;
        si.dpdu = to_world_.apply_vector(Vec3(c, s, 0.0f));
        si.dpdv = to_world_.apply_vector(Vec3(-s, c, 0.0f));
        si.n = normal_;
        si.shading = Frame::from_normal_tangent(normal_, si.dpdu);
    }

    Transform world_to_object_;
    Vec3 normal_;
    float area_ = 0.0f;
    BoundingBox bbox_;
};

CANDELA_REGISTER(Disk, ObjectKind::Shape, "disk");

}  // namespace candela
