// instance: a shape group placed in the scene; many instances share the group's geometry and
// BVH (Embree instancing), so each costs a transform, not a copy.
//
// Parameters:
//   (nested or referenced shapegroup)   the group to draw, usually <ref id="..."/>
//   to_world                            object (group) to world (default identity)
//
// As in Mitsuba 3, the materials are those of the group's shapes (an instance takes no BSDF, no
// emitter and no flip_normals). A hit is computed in the group's space and moved to world space:
// the position and tangents by to_world, the normals by its inverse transpose.

#include "shapes/shapegroup.h"
#include "core/registry.h"

#include <stdexcept>

namespace candela {

Instance::Instance(const Properties& props) : Shape(props) {
    if (props.has("flip_normals")) props.fail("flip_normals", "an instance takes no flip_normals (set it on the group's shapes)");
    if (!props.get_objects(ObjectKind::BSDF).empty()) props.fail("an instance takes no BSDF: its group's shapes carry theirs");
    if (emitter()) props.fail("instancing of emitters is not supported (as in Mitsuba)");
    auto shapes = props.get_objects(ObjectKind::Shape);
    if (shapes.size() != 1) props.fail("an instance references exactly one shapegroup");
    group_ = std::dynamic_pointer_cast<ShapeGroup>(shapes[0]);
    if (!group_) props.fail("an instance references a shapegroup, not a " + shapes[0]->to_string());
    if (!to_world_.all_finite()) props.fail("to_world", "instance transform is not finite");
    identity_ = to_world_.is_identity();
    BoundingBox b = group_->bbox();
    for (int corner = 0; corner < 8; ++corner)
        bbox_.expand(to_world_.apply_point(Vec3(corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y, corner & 4 ? b.max.z : b.min.z)));
}

RTCGeometry Instance::create_embree_geometry(RTCDevice device) const {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(g, group_->embree_scene(device));
    rtcSetGeometryTimeStepCount(g, 1);
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &to_world_.matrix()[0][0]);
    return g;
}

void Instance::fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const {
    const Shape* member = group_->member(hit.instance_geometry);
    if (!member) throw std::logic_error("an instance hit names no shape of its group");
    si.shape = member;
    if (identity_) {  // exactly what the group's shape gives in world space
        member->fill_interaction(ray, hit, si);
        return;
    }
    // Embree intersected the ray mapped by the inverse transform, with the same parameter t.
    Ray local = ray;
    local.o = to_world_.inverse().apply_point(ray.o);
    local.d = to_world_.inverse().apply_vector(ray.d);
    member->fill_interaction(local, hit, si);
    to_world_space(si);
}

void Instance::to_world_space(SurfaceInteraction& si) const {
    const Mat4& m = to_world_.matrix();
    // Error of the affine map applied to a point that already carries error e: a few roundings
    // of sum_j |M_ij p_j| + |t_i|, plus sum_j |M_ij| e.
    Mat3 abs_m(glm::abs(Vec3(m[0])), glm::abs(Vec3(m[1])), glm::abs(Vec3(m[2])));
    Vec3 magnitude = abs_m * glm::abs(si.p) + glm::abs(Vec3(m[3]));
    si.p_error = gamma_bound(4) * max_component(magnitude) + max_component(abs_m * Vec3(si.p_error)) * (1.0f + gamma_bound(4));
    si.p = to_world_.apply_point(si.p);
    si.n = glm::normalize(to_world_.apply_normal(si.n));
    Vec3 ns = glm::normalize(to_world_.apply_normal(si.shading.n));
    Vec3 tangent = to_world_.apply_vector(si.shading.s);
    si.shading = Frame::from_normal_tangent(ns, tangent);
    si.dpdu = to_world_.apply_vector(si.dpdu);
    si.dpdv = to_world_.apply_vector(si.dpdv);
}

void Instance::transform_soup(TriangleSoup& soup) const {
    for (Vec3& p : soup.positions) p = to_world_.apply_point(p);
    for (Vec3& n : soup.normals) n = glm::normalize(to_world_.apply_normal(n));
    // A mirroring transform reverses the winding; keep triangles counter-clockwise around the
    // (transformed) front normals.
    if (to_world_.determinant3() < 0.0f)
        for (auto& t : soup.triangles) std::swap(t.y, t.z);
}

void Instance::tessellate(TriangleSoup& out, int detail) const {
    TriangleSoup soup;
    group_->tessellate(soup, detail);
    transform_soup(soup);
    out.append(soup);
}

void Instance::tessellate_parts(std::vector<TessellatedPart>& parts, int detail) const {
    for (const Ref<Shape>& member : group_->members()) {
        parts.push_back(TessellatedPart{member.get(), TriangleSoup()});
        member->tessellate(parts.back().triangles, detail);
        transform_soup(parts.back().triangles);
    }
}

float Instance::surface_area() const { throw std::logic_error("an instance carries no emitter"); }
PositionSample Instance::sample_position(const Vec2&) const { throw std::logic_error("an instance carries no emitter"); }

CANDELA_REGISTER(Instance, ObjectKind::Shape, "instance");

}  // namespace candela
