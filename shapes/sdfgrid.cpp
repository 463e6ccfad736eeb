// sdfgrid: the zero level set of a signed distance function sampled on a grid (positive
// outside), intersected exactly as the trilinear interpolant of the samples.
//
// Parameters:
//   filename       string      the grid: Mitsuba's volume format (.vol), one channel
//   normals        string      shading normals: smooth (default; interpolated between the
//                              gradients of neighbouring voxels, Hansson-Soederlund, Evans and
//                              Akenine-Moeller, JCGT 2022) or analytic (the gradient of the
//                              trilinear interpolant, discontinuous across voxel faces)
//   to_world       transform   object to world (default identity); any affine map
//   flip_normals   boolean     swap front and back (default false)
//
// As in Mitsuba 3: the grid spans the object-space cube [0, 1]^3 with its samples at the voxel
// corners (sample i of n at i / (n - 1)), the bounding box stored in the file is ignored, the
// geometric normal is the interpolant's gradient, there are no uvs (0, 0), and an sdfgrid cannot
// be an area emitter. Each voxel whose corners do not all have one strict sign is an Embree user
// primitive; a ray's hit is the first root of the cubic the interpolant becomes along it
// (Marmitt et al. 2004: split at the roots of its derivative, then regula falsi).
//
// Volume format (little endian): "VOL", version byte 3, int32 encoding (1: float32), int32
// xres, yres, zres, int32 channels, 6 float32 bounding box, then float32 values with x fastest.

#include "core/accel.h"
#include "core/registry.h"
#include "core/shape.h"
#include "shapes/analytic_shape.h"

#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace candela {

namespace {

class GridError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The first root in [t0, t1] of c3 t^3 + c2 t^2 + c1 t + c0 where it changes sign, if any.
bool first_cubic_root(double c3, double c2, double c1, double c0, double t0, double t1, double& t) {
    auto f = [&](double x) { return ((c3 * x + c2) * x + c1) * x + c0; };
    // The derivative's roots split [t0, t1] into pieces on which the cubic is monotonic.
    double cuts[4] = {t0, t1, t1, t1};
    int n = 1;
    double a = 3.0 * c3, b = 2.0 * c2, c = c1;
    if (a != 0.0) {
        double disc = b * b - 4.0 * a * c;
        if (disc >= 0.0) {
            double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
            double r0 = q / a, r1 = q != 0.0 ? c / q : r0;
            if (r0 > r1) std::swap(r0, r1);
            for (double r : {r0, r1})
                if (r > t0 && r < t1) cuts[n++] = r;
        }
    } else if (b != 0.0) {
        double r = -c / b;
        if (r > t0 && r < t1) cuts[n++] = r;
    }
    cuts[n] = t1;
    for (int i = 0; i < n; ++i) {
        double lo = cuts[i], hi = cuts[i + 1], flo = f(lo), fhi = f(hi);
        if (flo == 0.0) {
            t = lo;
            return true;
        }
        if (flo * fhi > 0.0) continue;
        // Regula falsi with the Illinois modification (the stale end's value is halved).
        int side = 0;
        for (int it = 0; it < 60 && hi - lo > 1e-7 * (1.0 + std::abs(hi)); ++it) {
            double m = (lo * fhi - hi * flo) / (fhi - flo);
            double fm = f(m);
            if (fm == 0.0) {
                lo = hi = m;
                break;
            }
            if (fm * flo < 0.0) {
                hi = m;
                fhi = fm;
                if (side == -1) flo *= 0.5;
                side = -1;
            } else {
                lo = m;
                flo = fm;
                if (side == 1) fhi *= 0.5;
                side = 1;
            }
        }
        t = 0.5 * (lo + hi);
        return true;
    }
    return false;
}

}  // namespace

class SdfGrid final : public Shape {
public:
    explicit SdfGrid(const Properties& props) : Shape(props) {
        std::string path = props.get_file_path("filename");
        std::string normals = props.get_string("normals", "smooth");
        if (normals != "smooth" && normals != "analytic")
            props.fail("normals", "normals must be smooth or analytic, not \"" + normals + "\"");
        smooth_ = normals == "smooth";
        if (emitter()) props.fail("an sdfgrid cannot be an area emitter (nor can it in Mitsuba)");
        if (!to_world_.all_finite() || to_world_.determinant3() == 0.0f) props.fail("to_world", "sdfgrid transform is degenerate");
        try {
            read(path);
        } catch (const GridError& e) {
            props.fail("filename", "cannot read SDF grid \"" + path + "\": " + e.what());
        }
        world_to_object_ = glm::inverse(glm::dmat4(to_world_.matrix()));
        find_surface_voxels();
        if (voxels_.empty()) props.fail("filename", "SDF grid \"" + path + "\" has no voxel where the function changes sign (no surface)");
    }

    RTCGeometry create_embree_geometry(RTCDevice device) const override;
    void fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const override;
    BoundingBox bbox() const override { return bbox_; }
    void tessellate(TriangleSoup& out, int detail) const override;
    std::string to_string() const override { return "sdfgrid"; }

    // Cannot carry an emitter: never called.
    float surface_area() const override { throw std::logic_error("an sdfgrid carries no emitter"); }
    PositionSample sample_position(const Vec2&) const override { throw std::logic_error("an sdfgrid carries no emitter"); }

    // The nearest hit of the world-space ray on surface voxel `slot`, within (tmin, tmax].
    bool intersect_voxel(unsigned slot, const Vec3& of, const Vec3& df, float tmin, float tmax, float& t) const;
    BoundingBox voxel_bounds(unsigned slot) const;

private:
    void read(const std::string& path);
    void find_surface_voxels();
    float value(int x, int y, int z) const { return values_[(size_t(z) * size_t(res_.y) + size_t(y)) * size_t(res_.x) + size_t(x)]; }
    // The interpolant at an object-space point, coordinates clamped to the grid.
    double sample(const glm::dvec3& p) const;
    // The gradient of voxel v's interpolant (extended linearly) at object-space point p.
    glm::dvec3 voxel_gradient(const glm::dvec3& p, const glm::ivec3& v) const;
    glm::ivec3 voxel_of(const glm::dvec3& p) const;
    glm::dvec3 smooth_normal(const glm::dvec3& p) const;

    glm::ivec3 res_{0};  // samples per axis
    std::vector<float> values_;
    std::vector<glm::ivec3> voxels_;  // the voxels that hold surface, by Embree primitive id
    glm::dmat4 world_to_object_{1.0};
    BoundingBox bbox_;
    bool smooth_ = true;
};

void SdfGrid::read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw GridError("cannot open the file");
    char header[48];
    if (!in.read(header, 48)) throw GridError("the file is too short for a volume header");
    if (std::memcmp(header, "VOL", 3) != 0) throw GridError("not a volume file (no \"VOL\" header)");
    if (header[3] != 3) throw GridError("unsupported volume format version " + std::to_string(int(header[3])) + " (3 is read)");
    int32_t fields[5];
    std::memcpy(fields, header + 4, sizeof(fields));  // encoding, xres, yres, zres, channels
    if (fields[0] != 1) throw GridError("unsupported encoding " + std::to_string(fields[0]) + " (1, float32, is read)");
    if (fields[4] != 1) throw GridError("an SDF grid has one channel, this file has " + std::to_string(fields[4]));
    res_ = glm::ivec3(fields[1], fields[2], fields[3]);
    if (res_.x < 2 || res_.y < 2 || res_.z < 2 || res_.x > 4096 || res_.y > 4096 || res_.z > 4096)
        throw GridError("grid resolution " + std::to_string(res_.x) + "x" + std::to_string(res_.y) + "x" + std::to_string(res_.z) +
                        " is not between 2 and 4096 per axis");
    values_.resize(size_t(res_.x) * size_t(res_.y) * size_t(res_.z));
    if (!in.read(reinterpret_cast<char*>(values_.data()), std::streamsize(values_.size() * sizeof(float))))
        throw GridError("the data ends before " + std::to_string(values_.size()) + " values");
    for (float v : values_)
        if (!std::isfinite(v)) throw GridError("the grid holds a value that is not a finite number");
}

void SdfGrid::find_surface_voxels() {
    for (int z = 0; z + 1 < res_.z; ++z)
        for (int y = 0; y + 1 < res_.y; ++y)
            for (int x = 0; x + 1 < res_.x; ++x) {
                bool positive = true, negative = true;
                for (int c = 0; c < 8; ++c) {
                    float v = value(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1));
                    positive = positive && v > 0.0f;
                    negative = negative && v < 0.0f;
                }
                if (positive || negative) continue;
                voxels_.emplace_back(x, y, z);
                bbox_.expand(voxel_bounds(unsigned(voxels_.size() - 1)));
            }
}

BoundingBox SdfGrid::voxel_bounds(unsigned slot) const {
    Vec3 size = 1.0f / Vec3(res_ - 1), lo = Vec3(voxels_[slot]) * size;
    BoundingBox b;
    for (int c = 0; c < 8; ++c) b.expand(to_world_.apply_point(lo + size * Vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1))));
    return b;
}

double SdfGrid::sample(const glm::dvec3& p) const {
    glm::dvec3 g = glm::clamp(p, 0.0, 1.0) * glm::dvec3(res_ - 1);
    glm::ivec3 i = glm::min(glm::ivec3(g), res_ - 2);
    glm::dvec3 f = g - glm::dvec3(i);
    double r = 0.0;
    for (int c = 0; c < 8; ++c) {
        glm::ivec3 o(c & 1, (c >> 1) & 1, (c >> 2) & 1);
        double w = (o.x ? f.x : 1.0 - f.x) * (o.y ? f.y : 1.0 - f.y) * (o.z ? f.z : 1.0 - f.z);
        r += w * double(value(i.x + o.x, i.y + o.y, i.z + o.z));
    }
    return r;
}

// Per axis: the interpolant at the voxel's two faces through p, as Mitsuba differences them
// (lookups clamped to the grid).
glm::dvec3 SdfGrid::voxel_gradient(const glm::dvec3& p, const glm::ivec3& v) const {
    glm::dvec3 size = 1.0 / glm::dvec3(res_ - 1), lo = glm::dvec3(v) * size, g;
    for (int axis = 0; axis < 3; ++axis) {
        glm::dvec3 a = p, b = p;
        a[axis] = lo[axis] + size[axis];
        b[axis] = lo[axis];
        g[axis] = (sample(a) - sample(b)) / size[axis];
    }
    return g;
}

glm::ivec3 SdfGrid::voxel_of(const glm::dvec3& p) const {
    return glm::clamp(glm::ivec3(glm::floor(p * glm::dvec3(res_ - 1))), glm::ivec3(0), res_ - 2);
}

// The gradients of the 8 voxels whose centres surround p, each normalised and blended
// trilinearly by p's position between those centres; voxels before the grid's start drop out.
glm::dvec3 SdfGrid::smooth_normal(const glm::dvec3& p) const {
    glm::dvec3 scaled = p * glm::dvec3(res_ - 1);
    glm::ivec3 v000 = glm::ivec3(glm::round(scaled)) - 1;
    glm::dvec3 w = scaled - glm::dvec3(v000) - 0.5;
    bool valid[8];
    glm::dvec3 n[8];
    for (int c = 0; c < 8; ++c) {
        glm::ivec3 v = v000 + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
        valid[c] = v.x >= 0 && v.y >= 0 && v.z >= 0;
        glm::dvec3 g = valid[c] ? voxel_gradient(p, v) : glm::dvec3(0.0);
        double len = glm::length(g);
        n[c] = len > 0.0 ? g / len : glm::dvec3(0.0);
    }
    // Along an axis where one side has no valid voxel, all weight goes to the other side.
    for (int axis = 0; axis < 3; ++axis) {
        bool low = false, high = false;
        for (int c = 0; c < 8; ++c) {
            if ((c >> axis) & 1)
                high = high || valid[c];
            else
                low = low || valid[c];
        }
        if (!low) w[axis] = 1.0;
        if (!high) w[axis] = 0.0;
    }
    glm::dvec3 sum(0.0);
    for (int c = 0; c < 8; ++c)
        sum += ((c & 1) ? w.x : 1.0 - w.x) * (((c >> 1) & 1) ? w.y : 1.0 - w.y) * (((c >> 2) & 1) ? w.z : 1.0 - w.z) * n[c];
    return sum;
}

bool SdfGrid::intersect_voxel(unsigned slot, const Vec3& of, const Vec3& df, float tmin, float tmax, float& t) const {
    // In voxel space (the voxel is [0, 1]^3), where the interpolant is
    // f = k0 + k1 x + k2 y + k3 xy + (k4 + k5 x + k6 y + k7 xy) z, and along the ray a cubic in t
    // (an affine map keeps the ray parameter).
    const glm::ivec3& v = voxels_[slot];
    glm::dvec3 scale(res_ - 1);
    glm::dvec3 o = glm::dvec3(world_to_object_ * glm::dvec4(Vec3d(of), 1.0)) * scale - glm::dvec3(v);
    glm::dvec3 d = glm::dvec3(world_to_object_ * glm::dvec4(Vec3d(df), 0.0)) * scale;
    // Roots strictly beyond tmin (shapes/analytic_shape.h): the search starts at the next float.
    double t0 = std::nextafter(tmin, Infinity), t1 = tmax;
    for (int axis = 0; axis < 3; ++axis) {  // the slab test against the voxel
        if (d[axis] == 0.0) {
            if (o[axis] < 0.0 || o[axis] > 1.0) return false;
            continue;
        }
        double a = -o[axis] / d[axis], b = (1.0 - o[axis]) / d[axis];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    if (!(t0 <= t1)) return false;
    double s[8];
    for (int c = 0; c < 8; ++c) s[c] = value(v.x + (c & 1), v.y + ((c >> 1) & 1), v.z + ((c >> 2) & 1));
    double k0 = s[0], k1 = s[1] - s[0], k2 = s[2] - s[0], k3 = s[3] - s[2] - k1;
    double k4 = s[4] - k0, k5 = (s[5] - s[4]) - k1, k6 = (s[6] - s[4]) - k2, k7 = (s[7] - s[6] - (s[5] - s[4])) - k3;
    // x(t) y(t) = (ox + t dx)(oy + t dy) = m0 + m2 t + m1 t^2
    double m0 = o.x * o.y, m1 = d.x * d.y, m2 = o.x * d.y + o.y * d.x;
    double p0 = k0 + k1 * o.x + k2 * o.y + k3 * m0, p1 = k1 * d.x + k2 * d.y + k3 * m2, p2 = k3 * m1;
    double q0 = k4 + k5 * o.x + k6 * o.y + k7 * m0, q1 = k5 * d.x + k6 * d.y + k7 * m2, q2 = k7 * m1;
    // f(t) = p(t) + q(t) (oz + t dz)
    double c0 = p0 + q0 * o.z, c1 = p1 + q1 * o.z + q0 * d.z, c2 = p2 + q2 * o.z + q1 * d.z, c3 = q2 * d.z;
    double root;
    if (!first_cubic_root(c3, c2, c1, c0, t0, t1, root)) return false;
    return root_in_segment(root, tmin, tmax, t);
}

namespace {
void sdf_bounds(const RTCBoundsFunctionArguments* args) {
    EmbreeCallbackScope scope;
    auto* grid = static_cast<const SdfGrid*>(args->geometryUserPtr);
    write_padded_bounds(grid->voxel_bounds(args->primID), args->bounds_o);
}

void sdf_intersect(const RTCIntersectFunctionNArguments* args) {
    auto* grid = static_cast<const SdfGrid*>(args->geometryUserPtr);
    const unsigned voxel = args->primID;
    intersect_user_geometry(args, [grid, voxel](const Vec3& o, const Vec3& d, float tnear, float tfar, float& t) {
        return grid->intersect_voxel(voxel, o, d, tnear, tfar, t);
    });
}

void sdf_occluded(const RTCOccludedFunctionNArguments* args) {
    auto* grid = static_cast<const SdfGrid*>(args->geometryUserPtr);
    const unsigned voxel = args->primID;
    occluded_user_geometry(args, [grid, voxel](const Vec3& o, const Vec3& d, float tnear, float tfar, float& t) {
        return grid->intersect_voxel(voxel, o, d, tnear, tfar, t);
    });
}
}  // namespace

RTCGeometry SdfGrid::create_embree_geometry(RTCDevice device) const {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, unsigned(voxels_.size()));
    rtcSetGeometryUserData(g, const_cast<SdfGrid*>(this));
    rtcSetGeometryBoundsFunction(g, sdf_bounds, nullptr);
    rtcSetGeometryIntersectFunction(g, sdf_intersect);
    rtcSetGeometryOccludedFunction(g, sdf_occluded);
    return g;
}

void SdfGrid::fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const {
    si.p = ray(hit.t);
    // o + t d, plus the root finder's tolerance (1e-7 of a voxel) and the float rounding of t.
    Vec3 voxel = to_world_.apply_vector(1.0f / Vec3(res_ - 1));
    si.p_error = gamma_bound(8) * max_component(glm::abs(ray.o) + glm::abs(hit.t * ray.d)) + 1e-6f * glm::length(voxel);
    glm::dvec3 local(world_to_object_ * glm::dvec4(Vec3d(si.p), 1.0));
    Vec3 n = glm::normalize(to_world_.apply_normal(Vec3(voxel_gradient(local, voxel_of(local)))));
    Vec3 ns = smooth_ ? glm::normalize(to_world_.apply_normal(Vec3(smooth_normal(local)))) : n;
    if (!all_finite(n)) n = Vec3(0.0f, 0.0f, 1.0f);
    if (!all_finite(ns)) ns = n;
    if (flip_normals_) {
        n = -n;
        ns = -ns;
    }
    si.n = n;
    si.uv = Vec2(0.0f);
    si.shading = Frame(ns);
    si.dpdu = si.shading.s;
    si.dpdv = si.shading.t;
}

// Marching tetrahedra over the surface voxels: each voxel is cut into six tetrahedra around its
// main diagonal, and each tetrahedron contributes one or two triangles where its corners change
// sign, oriented so that their normals point toward the positive side.
void SdfGrid::tessellate(TriangleSoup& out, int) const {
    static const int tets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
    glm::dvec3 size = 1.0 / glm::dvec3(res_ - 1);
    auto emit = [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& outward) {
        glm::dvec3 pts[3] = {a, b, c};
        if (glm::dot(glm::cross(b - a, c - a), outward) < 0.0) std::swap(pts[1], pts[2]);
        unsigned base = unsigned(out.positions.size());
        for (const glm::dvec3& p : pts) {
            Vec3 n = glm::normalize(to_world_.apply_normal(Vec3(smooth_ ? smooth_normal(p) : voxel_gradient(p, voxel_of(p)))));
            if (!all_finite(n)) n = glm::normalize(to_world_.apply_normal(Vec3(outward)));
            out.positions.push_back(to_world_.apply_point(Vec3(p)));
            out.normals.push_back(flip_normals_ ? -n : n);
            out.uvs.emplace_back(0.0f);
        }
        out.triangles.push_back(flip_normals_ ? glm::uvec3(base, base + 2, base + 1) : glm::uvec3(base, base + 1, base + 2));
    };
    for (const glm::ivec3& v : voxels_)
        for (const auto& tet : tets) {
            glm::dvec3 p[4];
            double f[4];
            std::vector<int> in, outside;
            for (int k = 0; k < 4; ++k) {
                glm::ivec3 c = v + glm::ivec3(tet[k] & 1, (tet[k] >> 1) & 1, (tet[k] >> 2) & 1);
                p[k] = glm::dvec3(c) * size;
                f[k] = value(c.x, c.y, c.z);
                (f[k] < 0.0 ? in : outside).push_back(k);
            }
            auto cross_point = [&](int a, int b) { return p[a] + (p[b] - p[a]) * (f[a] / (f[a] - f[b])); };
            if (in.size() == 1 || in.size() == 3) {
                bool single_in = in.size() == 1;
                int lone = single_in ? in[0] : outside[0];
                const std::vector<int>& rest = single_in ? outside : in;
                glm::dvec3 outward = single_in ? p[rest[0]] - p[lone] : p[lone] - p[rest[0]];
                emit(cross_point(lone, rest[0]), cross_point(lone, rest[1]), cross_point(lone, rest[2]), outward);
            } else if (in.size() == 2) {
                glm::dvec3 a = cross_point(in[0], outside[0]), b = cross_point(in[0], outside[1]);
                glm::dvec3 c = cross_point(in[1], outside[1]), d = cross_point(in[1], outside[0]);
                glm::dvec3 outward = p[outside[0]] + p[outside[1]] - p[in[0]] - p[in[1]];
                emit(a, b, c, outward);
                emit(a, c, d, outward);
            }
        }
    out.closed = false;
}

CANDELA_REGISTER(SdfGrid, ObjectKind::Shape, "sdfgrid");

}  // namespace candela
