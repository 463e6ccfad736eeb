// rectangle: the square [-1, 1]^2 in the z = 0 plane with normal +z, placed by to_world.
//
// Parameters:
//   to_world       transform   object to world (default identity)
//   flip_normals   boolean     make -z the front side (default false)
// uv = ((x + 1) / 2, (y + 1) / 2) in object space, as in Mitsuba 3.
//
// As an area light it is sampled uniformly in the solid angle it subtends (Urena, Fajardo & King
// 2013, "An Area-Preserving Parametrization for Spherical Rectangles") when that angle is large
// (estimated above 0.1 sr, see kSphericalMinSolidAngle); seen from afar, or when to_world shears
// it, uniformly by area, which costs a fraction and varies little over a small solid angle.
// A mirroring to_world faces it along the transformed normal, as Mitsuba's rectangle.

#include "core/fast_trig.h"
#include "core/mesh.h"
#include "core/registry.h"

namespace candela {

class Rectangle final : public Mesh {
public:
    explicit Rectangle(const Properties& props) : Mesh(props) {
        positions_ = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
        uvs_ = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        triangles_ = {{0, 1, 2}, {0, 2, 3}};
        // Mitsuba's rectangle faces along to_world's transformed normal (inverse transpose), which
        // a mirroring to_world turns against the triangles' winding: flip the winding's normal
        // then, so that hits, sampling and emission agree on the front side. Before finalize(),
        // which stores the triangles' frames and the normal cone on the front side.
        if (to_world_.determinant3() < 0.0f) flip_normals_ = !flip_normals_;
        finalize(props, false);
        corner_ = to_world_.apply_point(Vec3(-1, -1, 0));
        centre_ = to_world_.apply_point(Vec3(0, 0, 0));
        Vec3 ex = to_world_.apply_vector(Vec3(2, 0, 0)), ey = to_world_.apply_vector(Vec3(0, 2, 0));
        len_x_ = glm::length(ex);
        len_y_ = glm::length(ey);
        x_ = ex / len_x_;
        y_ = ey / len_y_;
        z_ = glm::cross(x_, y_);
        normal_ = glm::normalize(glm::cross(ex, ey));
        if (flip_normals_) normal_ = -normal_;
        ex_ = ex;
        ey_ = ey;
        orthogonal_ = std::abs(glm::dot(x_, y_)) < 1e-4f;
        // The error bound of corner + u.x ex + u.y ey depends on the rectangle alone.
        position_error_ = gamma_bound(6) * (max_abs_component(corner_) + max_abs_component(ex_) + max_abs_component(ey_));
    }
    std::string to_string() const override { return "rectangle"; }

    // Uniform by area: the affine image of the unit square, whose uv is the square's point itself.
    PositionSample sample_position(const Vec2& u) const override {
        PositionSample ps;
        ps.p = corner_ + u.x * ex_ + u.y * ey_;
        ps.p_error = position_error_;
        ps.n = normal_;
        ps.uv = u;
        ps.pdf = 1.0f / surface_area();
        return ps;
    }

    // Both returns build the result in the caller's storage (a named result returned on one path
    // only is copied, and the copy's reloads stalled store forwarding).
    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2& u) const override {
        SphericalRectangle sr;
        if (!spherical(ref.p, sr)) return direction_from_position(ref, sample_position(u));
        return sample_spherical(ref, sr, u);
    }

    float pdf_direction(const SurfaceInteraction& ref, const DirectionSample& ds) const override {
        SphericalRectangle sr;
        if (!spherical(ref.p, sr)) return Shape::pdf_direction(ref, ds);
        return 1.0f / sr.solid_angle;
    }

private:
    // The rectangle as seen from a point: its local frame (x along an edge, z away from the
    // point), corner coordinates, and the quantities the sampling needs.
    struct SphericalRectangle {
        Vec3 x, z;
        float x0, x1, y0, y1, z0;
        float b0, b1, one_minus_b0_squared, k, solid_angle;
    };

    DirectionSample sample_spherical(const SurfaceInteraction& ref, const SphericalRectangle& sr, const Vec2& u) const {
        // Invert the solid-angle CDF along x (u.x), then along y within the column (u.y).
        float au = u.x * sr.solid_angle + sr.k, sin_au, cos_au;
        sincos_any(au, sin_au, cos_au);
        float fu = (cos_au * sr.b0 - sr.b1) / sin_au;
        // Urena et al.'s cu = sign(fu) / sqrt(fu^2 + b0^2) and xu = -cu z0 / sqrt(1 - cu^2) in
        // one step: xu = -sign(fu) z0 / sqrt(fu^2 + b0^2 - 1), which is copysign(z0, fu) / ...
        // as z0 < 0, with 1 - b0^2 = z0^2 / r(y0)^2 computed without cancellation. One square
        // root and one division fewer on the sample's dependent chain.
        float xu = std::clamp(std::copysign(sr.z0, fu) / safe_sqrt(fu * fu - sr.one_minus_b0_squared), sr.x0, sr.x1);
        float d = std::sqrt(xu * xu + sr.z0 * sr.z0);
        float h0 = sr.y0 / std::sqrt(d * d + sr.y0 * sr.y0), h1 = sr.y1 / std::sqrt(d * d + sr.y1 * sr.y1);
        float hv = h0 + u.y * (h1 - h0), hv2 = hv * hv;
        float yv = hv2 < 1.0f - 1e-6f ? (hv * d) / std::sqrt(1.0f - hv2) : sr.y1;
        yv = std::clamp(yv, sr.y0, sr.y1);
        DirectionSample ds;
        ds.p = ref.p + xu * sr.x + yv * y_ + sr.z0 * sr.z;
        ds.n = normal_;
        ds.p_error = gamma_bound(8) * (max_abs_component(ref.p) + max_abs_component(corner_) + len_x_ + len_y_);
        Vec3 local = ds.p - corner_;
        ds.uv = Vec2(glm::dot(local, x_) / len_x_, glm::dot(local, y_) / len_y_);
        Vec3 to = ds.p - ref.p;
        ds.dist = glm::length(to);
        ds.d = to * (1.0f / ds.dist);
        ds.pdf = 1.0f / sr.solid_angle;
        return ds;
    }

    bool spherical(const Vec3& o, SphericalRectangle& sr) const {
        if (!orthogonal_) return false;
        // Seen from afar the rectangle's solid angle is nearly A |cos| / r^2 everywhere on it and
        // area sampling is almost as good, at a fraction of the cost (no acos, sin, cos). The
        // choice must depend on the point only, as pdf_direction repeats it: the estimate
        // A |z0| / r^3 from the rectangle's centre is such a function. It is decided first, from
        // the centre alone, as most points of a scene sample by area.
        Vec3 to_centre = centre_ - o;
        float z0 = glm::dot(to_centre, z_), r2 = squared_length(to_centre);
        // Too close to the plane: the spherical rectangle degenerates.
        if (std::abs(z0) < 1e-4f * std::max(len_x_, len_y_)) return false;
        // Squared, A^2 z0^2 < k^2 r^6, to keep a square root's latency off every light sample
        // (beyond float range r^6 is infinite and the point, that far away, samples by area).
        float a = len_x_ * len_y_ * z0;
        if (a * a < kSphericalMinSolidAngle * kSphericalMinSolidAngle * (r2 * r2 * r2)) return false;
        Vec3 d = corner_ - o;
        sr.x = x_;
        sr.z = z_;
        sr.z0 = glm::dot(d, z_);
        if (sr.z0 > 0.0f) {  // the rectangle must lie at negative z (only the coordinates matter)
            sr.z = -z_;
            sr.z0 = -sr.z0;
        }
        sr.x0 = glm::dot(d, x_);
        sr.y0 = glm::dot(d, y_);
        sr.x1 = sr.x0 + len_x_;
        sr.y1 = sr.y0 + len_y_;
        // The normals of the four edge planes through the point, n_i = normalize(v_i x v_i+1),
        // have closed forms in these coordinates (Urena et al. 2013, section 3.1):
        //   n0 = (0, z0, -y0) / r(y0)   n1 = (-z0, 0, x1) / r(x1)
        //   n2 = (0, -z0, y1) / r(y1)   n3 = (z0, 0, -x0) / r(x0)    with r(a) = sqrt(z0^2 + a^2),
        // so the interior angles g_i = acos(-n_i . n_i+1) need no cross products.
        // The four 1 / r and the four angles each as one vector (four independent libm acos
        // calls and square roots had made this the costliest step of a light sample).
        const Float4 coordinates{sr.x0, sr.x1, sr.y0, sr.y1};
        const Float4 inv_r = splat4(1.0f) / sqrt4(splat4(sr.z0 * sr.z0) + coordinates * coordinates);
        const float inv_rx0 = inv_r[0], inv_rx1 = inv_r[1], inv_ry0 = inv_r[2], inv_ry1 = inv_r[3];
        const Float4 g = acos4(Float4{sr.y0 * sr.x1, -sr.x1 * sr.y1, sr.x0 * sr.y1, -sr.x0 * sr.y0} *
                               Float4{inv_ry0 * inv_rx1, inv_rx1 * inv_ry1, inv_ry1 * inv_rx0, inv_rx0 * inv_ry0});
        const float g0 = g[0], g1 = g[1], g2 = g[2], g3 = g[3];
        sr.b0 = -sr.y0 * inv_ry0;
        sr.one_minus_b0_squared = sqr(sr.z0 * inv_ry0);
        sr.b1 = sr.y1 * inv_ry1;
        sr.k = TwoPi - g2 - g3;
        sr.solid_angle = g0 + g1 - sr.k;
        // Tiny solid angles lose all precision in the angle sums; area sampling is exact enough.
        return std::isfinite(sr.solid_angle) && sr.solid_angle > 1e-3f;
    }

    // Below this estimated solid angle (sr) area sampling replaces solid-angle sampling: at 0.1 sr
    // (a square seen from about three times its side) 1 / d^2 varies by less than +-35% over
    // it. On the validation Cornell box, 64 spp, this threshold gave 5-8% more efficiency
    // (1 / (relMSE x CPU time)) than solid-angle sampling everywhere and 2% more than area
    // sampling everywhere (bench: the light's relMSE and time at 0, 0.02 ... 0.5 and "always").
    // Measured again in the wavefront path (bench/results/rectangle_light_2026-12-07.txt, by
    // the fastest of 5-6 runs): on that box 0.1, 0.3 and area everywhere within 1%; with the
    // light 2x wider area everywhere gained 7%, 3.2x wider it lost 20% (0.3 lost 15%). 0.1 stays.
    static constexpr float kSphericalMinSolidAngle = 0.1f;

    Vec3 corner_, centre_, ex_, ey_, x_, y_, z_, normal_;
    float len_x_ = 0.0f, len_y_ = 0.0f;
    float position_error_ = 0.0f;  // the error bound of every point sample_position() returns
    bool orthogonal_ = false;
};

CANDELA_REGISTER(Rectangle, ObjectKind::Shape, "rectangle");

}  // namespace candela
