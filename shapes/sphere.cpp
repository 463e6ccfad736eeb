// sphere: an exact (analytic) sphere.
//
// Parameters:
//   center         point       centre in object space (default 0, 0, 0)
//   radius         float       radius (default 1)
//   to_world       transform   applied after center and radius; must scale uniformly
//   flip_normals   boolean     make the inside the front side (default false)
// uv: u = phi / 2pi around the object z axis from +x, v = theta / pi from the +z pole.
// As an area light it is sampled by the cone it subtends (uniform solid angle) when seen from
// outside, and by area from inside.

#include "core/registry.h"
#include "core/warp.h"
#include "shapes/analytic_shape.h"

namespace candela {

class Sphere final : public AnalyticShape {
public:
    explicit Sphere(const Properties& props) : AnalyticShape(props) {
        Vec3 c = props.get_point("center", Vec3(0.0f));
        float r = props.get_float("radius", 1.0f);
        if (!(r > 0.0f)) props.fail("radius", "sphere radius must be positive");
        object_to_world_ = to_world_ * Transform::translate(c) * Transform::scale(Vec3(r));
        if (!object_to_world_.all_finite()) props.fail("to_world", "sphere transform is not finite");
        center_ = object_to_world_.apply_point(Vec3(0.0f));
        Vec3 ax = object_to_world_.apply_vector(Vec3(1, 0, 0)), ay = object_to_world_.apply_vector(Vec3(0, 1, 0)),
             az = object_to_world_.apply_vector(Vec3(0, 0, 1));
        radius_ = glm::length(ax);
        float tol = 1e-4f * radius_;
        if (std::abs(glm::length(ay) - radius_) > tol || std::abs(glm::length(az) - radius_) > tol)
            props.fail("to_world", "a sphere's to_world must scale uniformly (use a mesh for ellipsoids)");
        // A mirroring transform turns the sphere inside out.
        if (object_to_world_.determinant3() < 0.0f) flip_normals_ = !flip_normals_;
        world_to_object_ = object_to_world_.inverse();
    }

    BoundingBox bbox() const override {
        BoundingBox b;
        b.expand(center_ - Vec3(radius_));
        b.expand(center_ + Vec3(radius_));
        return b;
    }
    float surface_area() const override { return FourPi * radius_ * radius_; }

    bool intersect_t(const Vec3& of, const Vec3& df, float tmin, float tmax, float& t) const override {
        // Double precision and the numerically stable discriminant of "Precision Improvements
        // for Ray/Sphere Intersection" (Haines et al., Ray Tracing Gems, 2019): the silhouette
        // stays exact even for large spheres far from the origin.
        Vec3d o = Vec3d(of) - Vec3d(center_), d(df);
        double a = glm::dot(d, d), b = glm::dot(o, d), r = radius_;
        Vec3d f = o - (b / a) * d;
        double disc = a * (r * r - glm::dot(f, f));
        if (disc < 0.0) return false;
        double c = glm::dot(o, o) - r * r;
        double q = -(b + std::copysign(std::sqrt(disc), b));
        double t0 = q / a, t1 = q != 0.0 ? c / q : t0;
        if (t0 > t1) std::swap(t0, t1);
        return root_in_segment(t0, tmin, tmax, t) || root_in_segment(t1, tmin, tmax, t);
    }

    void fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const override {
        Vec3 p = ray(hit.t);
        Vec3 n = glm::normalize(p - center_);
        // Re-project onto the surface: removes the error of o + t d.
        fill_at(center_ + radius_ * n, n, si);
    }

    PositionSample sample_position(const Vec2& u) const override {
        Vec3 n = warp::square_to_uniform_sphere(u);
        PositionSample ps;
        ps.p = center_ + radius_ * n;
        ps.p_error = error_bound();
        ps.n = flip_normals_ ? -n : n;
        ps.uv = uv_of(ps.p);
        ps.pdf = 1.0f / surface_area();
        return ps;
    }

    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2& u) const override {
        Vec3 to_center = center_ - ref.p;
        float dc2 = squared_length(to_center);
        if (dc2 <= radius_ * radius_ * (1.0f + 1e-4f)) return Shape::sample_direction(ref, u);  // inside: by area
        // Uniform over the subtended cone (pbrt-v4, Sphere::Sample with a reference point).
        float dc = std::sqrt(dc2);
        float sin2_max = radius_ * radius_ / dc2;
        float cos_max = safe_sqrt(1.0f - sin2_max);
        float one_minus_cos_max = 1.0f - cos_max;
        float cos_theta = (cos_max - 1.0f) * u.x + 1.0f;
        float sin2_theta = 1.0f - cos_theta * cos_theta;
        if (sin2_max < 0.00068523f) {
            // Small cones (under 1.5 degrees): Taylor expansions avoid cancellation.
            sin2_theta = sin2_max * u.x;
            cos_theta = std::sqrt(1.0f - sin2_theta);
            one_minus_cos_max = sin2_max / 2.0f;
        }
        // Angle at the sphere's centre between the axis and the sampled point.
        float cos_alpha = sin2_theta / std::sqrt(sin2_max) + cos_theta * safe_sqrt(1.0f - sin2_theta / sin2_max);
        float sin_alpha = safe_sqrt(1.0f - cos_alpha * cos_alpha);
        float phi = TwoPi * u.y;
        Frame frame(-to_center / dc);  // +z points from the centre toward the reference
        Vec3 n = frame.to_world(Vec3(sin_alpha * std::cos(phi), sin_alpha * std::sin(phi), cos_alpha));
        DirectionSample ds;
        ds.p = center_ + radius_ * n;
        ds.p_error = error_bound();
        ds.n = flip_normals_ ? -n : n;
        ds.uv = uv_of(ds.p);
        Vec3 to = ds.p - ref.p;
        ds.dist = glm::length(to);
        ds.d = to / ds.dist;
        ds.pdf = 1.0f / (TwoPi * one_minus_cos_max);
        return ds;
    }

    float pdf_direction(const SurfaceInteraction& ref, const DirectionSample& ds) const override {
        float dc2 = squared_length(center_ - ref.p);
        if (dc2 <= radius_ * radius_ * (1.0f + 1e-4f)) return Shape::pdf_direction(ref, ds);
        float sin2_max = radius_ * radius_ / dc2;
        float one_minus_cos_max = sin2_max < 0.00068523f ? sin2_max / 2.0f : 1.0f - safe_sqrt(1.0f - sin2_max);
        return 1.0f / (TwoPi * one_minus_cos_max);
    }

    // A latitude-longitude grid; the seam repeats the first column exactly, the poles are rings
    // of coincident vertices (so that uvs stay continuous).
    void tessellate(TriangleSoup& out, int detail) const override {
        int nphi = std::max(detail, 8), ntheta = std::max(detail / 2, 4);
        unsigned base = unsigned(out.positions.size());
        for (int i = 0; i <= ntheta; ++i) {
            float theta = Pi * float(i) / float(ntheta);
            for (int j = 0; j <= nphi; ++j) {
                float phi = TwoPi * float(j % nphi) / float(nphi);
                Vec3 local(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
                Vec3 p = object_to_world_.apply_point(local);
                Vec3 n = glm::normalize(p - center_);
                out.positions.push_back(p);
                out.normals.push_back(flip_normals_ ? -n : n);
                out.uvs.emplace_back(float(j) / float(nphi), float(i) / float(ntheta));
            }
        }
        for (int i = 0; i < ntheta; ++i)
            for (int j = 0; j < nphi; ++j) {
                unsigned a = base + unsigned(i * (nphi + 1) + j), b = a + 1, c = a + unsigned(nphi + 1), d = c + 1;
                // Counter-clockwise seen from outside (theta grows toward -z, phi toward +y).
                glm::uvec3 t0(a, c, d), t1(a, d, b);
                // At the poles one of the two collapses (two corners on the pole): skip it.
                if (i + 1 < ntheta) out.triangles.push_back(flip_normals_ ? glm::uvec3(t0.x, t0.z, t0.y) : t0);
                if (i > 0) out.triangles.push_back(flip_normals_ ? glm::uvec3(t1.x, t1.z, t1.y) : t1);
            }
        out.closed = true;
    }

    std::string to_string() const override { return "sphere"; }

private:
    Vec2 uv_of(const Vec3& p) const {
        Vec3 local = world_to_object_.apply_point(p);
        float phi = std::atan2(local.y, local.x);
        if (phi < 0.0f) phi += TwoPi;
        return Vec2(phi * InvTwoPi, safe_acos(local.z) * InvPi);
    }

    // A point computed as centre + radius * (unit normal): a few roundings of |centre| + radius.
    float error_bound() const { return gamma_bound(6) * (max_abs_component(center_) + radius_); }

    void fill_at(const Vec3& p, const Vec3& n_out, SurfaceInteraction& si) const {
        si.p = p;
        si.p_error = error_bound();
        Vec3 local = world_to_object_.apply_point(p);
        float phi = std::atan2(local.y, local.x);
        if (phi < 0.0f) phi += TwoPi;
        si.uv = Vec2(phi * InvTwoPi, safe_acos(local.z) * InvPi);
        float rxy = std::sqrt(local.x * local.x + local.y * local.y);
        si.dpdu = object_to_world_.apply_vector(Vec3(-local.y, local.x, 0.0f) * TwoPi);
        si.dpdv = rxy > 0.0f ? object_to_world_.apply_vector(Vec3(local.z * local.x / rxy, local.z * local.y / rxy, -rxy) * Pi)
                             : object_to_world_.apply_vector(Vec3(1, 0, 0));
        Vec3 n = flip_normals_ ? -n_out : n_out;
        si.n = n;
        si.shading = Frame::from_normal_tangent(n, si.dpdu);
    }

    Transform object_to_world_, world_to_object_;
    Vec3 center_;
    float radius_;
};

CANDELA_REGISTER(Sphere, ObjectKind::Shape, "sphere");

}  // namespace candela
