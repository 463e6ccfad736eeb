#include "shapes/curve.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace candela {

namespace {

// Mitsuba's frame around a curve's tangent: v_rot is the part of +z orthogonal to the tangent
// (+y where the tangent is along z), v_rad = v_rot x tangent. The angle u is measured from
// v_rad toward v_rot.
void curve_frame(const Vec3& tangent, Vec3& v_rot, Vec3& v_rad) {
    const Vec3 guide(0.0f, 0.0f, 1.0f);
    if (std::abs(glm::dot(guide, tangent)) >= 1.0f)
        v_rot = Vec3(0.0f, 1.0f, 0.0f);
    else
        v_rot = glm::normalize(guide - tangent * glm::dot(tangent, guide));
    v_rad = glm::cross(v_rot, tangent);
}

// Mitsuba's curves are not hit from inside: its Embree is built with back-face culling for
// curves, Debian's is not, so a filter rejects hits whose geometric normal faces along the ray.
void cull_back_faces(const RTCFilterFunctionNArguments* args) {
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] == 0) continue;
        float cos_d = RTCRayN_dir_x(args->ray, args->N, i) * RTCHitN_Ng_x(args->hit, args->N, i) +
                      RTCRayN_dir_y(args->ray, args->N, i) * RTCHitN_Ng_y(args->hit, args->N, i) +
                      RTCRayN_dir_z(args->ray, args->N, i) * RTCHitN_Ng_z(args->hit, args->N, i);
        if (cos_d > 0.0f) args->valid[i] = 0;
    }
}

}  // namespace

CurveShape::CurveShape(const Properties& props, int points_per_segment, const char* type_name)
    : Shape(props), points_per_segment_(points_per_segment) {
    embree_type_ = points_per_segment == 2 ? RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE : RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE;
    std::string path = props.get_file_path("filename");
    if (emitter()) props.fail(std::string("area emitters on a ") + type_name + " are not supported (Mitsuba cannot sample curves either)");
    std::ifstream in(path);
    if (!in) props.fail("filename", "cannot open curve file \"" + path + "\"");
    std::string context = std::string(" (in the ") + type_name + " at " + props.location().str() + ")";
    auto fail = [&](int line, const std::string& message) { throw SceneError(SourceLocation{path, line}, message + context); };

    std::string line;
    int line_no = 0, curve_start_line = 0;
    size_t curve_start = 0;
    // Closes the curve that started at point index curve_start: its segments start at every
    // control point but the last points_per_segment - 1.
    auto end_curve = [&]() {
        size_t count = points_.size() - curve_start;
        if (count == 0) return;
        if (count < size_t(points_per_segment))
            fail(curve_start_line, std::string("a ") + type_name + " needs at least " + std::to_string(points_per_segment) +
                                       " control points per curve, this one has " + std::to_string(count));
        for (size_t i = curve_start; i + size_t(points_per_segment) <= points_.size(); ++i) first_point_.push_back(unsigned(i));
        curve_start = points_.size();
    };
    while (std::getline(in, line)) {
        ++line_no;
        std::istringstream ss(line);
        std::vector<double> v;
        std::string token;
        while (ss >> token) {
            char* end = nullptr;
            double x = std::strtod(token.c_str(), &end);
            if (end == token.c_str() || *end != '\0') fail(line_no, "\"" + token + "\" is not a number");
            v.push_back(x);
        }
        if (v.empty()) {
            end_curve();
            continue;
        }
        if (v.size() != 4) fail(line_no, "a control point is 4 numbers, x y z radius; this line has " + std::to_string(v.size()));
        if (points_.size() == curve_start) curve_start_line = line_no;
        Vec3 p = to_world_.apply_point(Vec3(float(v[0]), float(v[1]), float(v[2])));
        float r = float(v[3]);
        if (!all_finite(p) || !std::isfinite(r)) fail(line_no, "a control point is not a finite number");
        if (r < 0.0f) fail(line_no, "a control point has a negative radius");
        points_.emplace_back(p, r);
        bbox_.expand(p - Vec3(r));
        bbox_.expand(p + Vec3(r));
    }
    end_curve();
    if (first_point_.empty()) props.fail("filename", "curve file \"" + path + "\" holds no control points");
}

RTCGeometry CurveShape::create_embree_geometry(RTCDevice device) const {
    RTCGeometry g = rtcNewGeometry(device, embree_type_);
    auto* v = static_cast<Vec4*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, sizeof(Vec4), points_.size()));
    std::copy(points_.begin(), points_.end(), v);
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(unsigned), first_point_.size()));
    std::copy(first_point_.begin(), first_point_.end(), idx);
    rtcSetGeometryIntersectFilterFunction(g, cull_back_faces);
    rtcSetGeometryOccludedFilterFunction(g, cull_back_faces);
    return g;
}

void CurveShape::fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const {
    CurvePoint cp = evaluate(hit.prim_index, hit.u);
    si.p = ray(hit.t);
    // o + t d: a few roundings of |o| + |t d|. Curves are not hit from inside, so a point that
    // lands slightly inside cannot hit its own curve again.
    si.p_error = gamma_bound(8) * max_component(glm::abs(ray.o) + glm::abs(hit.t * ray.d));
    Vec3 n = surface_normal(si.p, cp);
    // uv as Mitsuba: u the angle around the curve, v the position along all segments.
    Vec3 tangent = glm::normalize(cp.dc), v_rot, v_rad;
    curve_frame(tangent, v_rot, v_rad);
    Vec3 radial = si.p - cp.c;
    float len = glm::length(radial);
    Vec3 r_hat = len > 0.0f ? radial / len : n;
    float phi = std::atan2(glm::dot(v_rot, r_hat), glm::dot(v_rad, r_hat));
    if (phi < 0.0f) phi += TwoPi;
    float segments = float(segment_count());
    si.uv = Vec2(phi * InvTwoPi, (hit.u + float(hit.prim_index)) / segments);
    si.dpdu = TwoPi * len * (std::cos(phi) * v_rot - std::sin(phi) * v_rad);
    si.dpdv = cp.dc * segments;
    if (flip_normals_) n = -n;
    si.n = n;
    // s around the fibre, t = n x s along it (the frame Mitsuba's hair model expects).
    si.shading = Frame::from_normal_tangent(n, si.dpdu);
}

void CurveShape::tessellate(TriangleSoup& out, int detail) const {
    int around = std::max(detail / 8, 6), along = points_per_segment_ == 2 ? 1 : 4;
    for (size_t s = 0; s < segment_count(); ++s) {
        unsigned base = unsigned(out.positions.size());
        for (int i = 0; i <= along; ++i) {
            float v = float(i) / float(along);
            CurvePoint cp = evaluate(s, v);
            Vec3 tangent = glm::length(cp.dc) > 0.0f ? glm::normalize(cp.dc) : Vec3(0, 0, 1), v_rot, v_rad;
            curve_frame(tangent, v_rot, v_rad);
            for (int j = 0; j <= around; ++j) {
                float phi = TwoPi * float(j % around) / float(around);
                Vec3 r_hat = std::cos(phi) * v_rad + std::sin(phi) * v_rot;
                out.positions.push_back(cp.c + cp.radius * r_hat);
                out.normals.push_back(flip_normals_ ? -r_hat : r_hat);
                out.uvs.emplace_back(float(j) / float(around), (v + float(s)) / float(segment_count()));
            }
        }
        for (int i = 0; i < along; ++i)
            for (int j = 0; j < around; ++j) {
                unsigned a = base + unsigned(i * (around + 1) + j), b = a + 1, c = a + unsigned(around + 1), d = c + 1;
                // (v_rad, v_rot, tangent) is right-handed, so (b - a) x (d - a) points outward:
                // (a, b, d) is counter-clockwise seen from outside.
                glm::uvec3 t0(a, b, d), t1(a, d, c);
                out.triangles.push_back(flip_normals_ ? glm::uvec3(t0.x, t0.z, t0.y) : t0);
                out.triangles.push_back(flip_normals_ ? glm::uvec3(t1.x, t1.z, t1.y) : t1);
            }
    }
    out.closed = false;
}

float CurveShape::surface_area() const { throw std::logic_error("curves carry no emitter"); }
PositionSample CurveShape::sample_position(const Vec2&) const { throw std::logic_error("curves carry no emitter"); }

}  // namespace candela
