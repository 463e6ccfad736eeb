// instance: a shape group placed in the scene; many instances share the group's geometry and
// BVH (Embree instancing), so each costs a transform, not a copy.
//
// Parameters:
//   (nested or referenced shapegroup)   the group to draw, usually <ref id="..."/>
//   to_world                            object (group) to world (default identity), or an
//                                       <animation name="to_world"> of keyframes (motion blur,
//                                       resampled to equal steps if they are not; Embree's instance motion:
//                                       translation and scale/shear interpolated linearly, the
//                                       rotation by slerp; see core/animated_transform.h)
//
// As in Mitsuba 3, the materials are those of the group's shapes (an instance takes no BSDF, no
// emitter and no flip_normals). A hit is computed in the group's space and moved to world space:
// the position and tangents by to_world, the normals by its inverse transpose.

#include "core/error.h"
#include "core/registry.h"
#include "shapes/shapegroup.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace candela {

Instance::Instance(const Properties& props) : Shape(props, true) {
    if (props.has("flip_normals")) props.fail("flip_normals", "an instance takes no flip_normals (set it on the group's shapes)");
    if (!props.get_objects(ObjectKind::BSDF).empty()) props.fail("an instance takes no BSDF: its group's shapes carry theirs");
    if (emitter()) props.fail("instancing of emitters is not supported (as in Mitsuba)");
    auto shapes = props.get_objects(ObjectKind::Shape);
    if (shapes.size() != 1) props.fail("an instance references exactly one shapegroup");
    group_ = std::dynamic_pointer_cast<ShapeGroup>(shapes[0]);
    if (!group_) props.fail("an instance references a shapegroup, not a " + shapes[0]->to_string());
    for (const auto& key : motion_.keyframes())
        if (!key.transform.all_finite()) props.fail("to_world", "instance transform is not finite");
    // Embree's motion takes equal time steps: other keyframe times are resampled onto a step that
    // divides all their intervals (the same motion), if one within MaxKeyframes exists.
    const int MaxKeyframes = 1025;
    AnimatedTransform equal;
    if (!motion_.equally_spaced()) {
        if (!motion_.resampled_equally(MaxKeyframes, equal))
            props.fail("to_world",
                       "keyframe times too unevenly spaced: Embree's motion blur takes equal time steps, and a step that divides "
                       "every interval would need more than " +
                           std::to_string(MaxKeyframes) + " keyframes");
        motion_ = equal;
    }
    identity_ = !motion_.is_animated() && to_world_.is_identity();
    bbox_ = motion_.bounds(group_->bbox());
}

void Instance::collect_emitters(std::vector<Ref<Emitter>>& out) const {
    for (const Ref<Shape>& member : group_->members())
        if (member->emitter()) out.push_back(member->emitter_ref());
}

void Instance::set_shutter(float open, float close) {
    shutter_open_ = open;
    shutter_close_ = close;
    if (motion_.is_animated()) to_world_ = motion_.eval(open);
}

RTCGeometry Instance::create_embree_geometry(RTCDevice device) const {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(g, group_->embree_scene(device));
    if (motion_.is_animated()) {
        set_embree_motion(g);
        return g;
    }
    rtcSetGeometryTimeStepCount(g, 1);
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &to_world_.matrix()[0][0]);
    return g;
}

void Instance::set_embree_motion(RTCGeometry g) const {
    const auto& keys = motion_.keyframes();
    const float step = (motion_.end_time() - motion_.begin_time()) / float(keys.size() - 1);
    // Steps of copies before the first and after the last keyframe so the range covers the shutter.
    const int MaxPadding = 1024;
    float before = std::ceil((motion_.begin_time() - shutter_open_) / step),
          after = std::ceil((shutter_close_ - motion_.end_time()) / step);
    int pad_before = int(std::max(before, 0.0f)), pad_after = int(std::max(after, 0.0f));
    if (!(before <= MaxPadding && after <= MaxPadding))
        throw SceneError(motion_location(), "the shutter lies too far outside an instance's keyframes: give keyframes nearer the shutter");
    const unsigned count = unsigned(pad_before + int(keys.size()) + pad_after);
    const EmbreeTime time(shutter_open_, shutter_close_);
    rtcSetGeometryTimeStepCount(g, count);
    rtcSetGeometryTimeRange(g, time(motion_.begin_time() - float(pad_before) * step), time(motion_.end_time() + float(pad_after) * step));
    for (unsigned i = 0; i < count; ++i) {
        const AnimatedTransform::Keyframe& k = keys[size_t(std::clamp(int(i) - pad_before, 0, int(keys.size()) - 1))];
        RTCQuaternionDecomposition q;
        rtcInitQuaternionDecomposition(&q);
        // Embree's p' = T R S p with S upper triangular (scale, skew, shift); the shift stays 0.
        rtcQuaternionDecompositionSetScale(&q, k.scale_shear[0][0], k.scale_shear[1][1], k.scale_shear[2][2]);
        rtcQuaternionDecompositionSetSkew(&q, k.scale_shear[1][0], k.scale_shear[2][0], k.scale_shear[2][1]);
        rtcQuaternionDecompositionSetQuaternion(&q, k.rotation.w, k.rotation.x, k.rotation.y, k.rotation.z);
        rtcQuaternionDecompositionSetTranslation(&q, k.translation.x, k.translation.y, k.translation.z);
        rtcSetGeometryTransformQuaternion(g, i, &q);
    }
}

void Instance::fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const {
    const Shape* member = group_->member(hit.instance_geometry);
    if (!member) throw std::logic_error("an instance hit names no shape of its group");
    si.shape = member;
    if (identity_) {  // exactly what the group's shape gives in world space
        member->fill_interaction(ray, hit, si);
        return;
    }
    // Embree intersected the ray mapped by the inverse transform (at the ray's time), with the
    // same parameter t.
    const Transform to_world = motion_.is_animated() ? motion_.eval(ray.time) : to_world_;
    Ray local = ray;
    local.o = to_world.inverse().apply_point(ray.o);
    local.d = to_world.inverse().apply_vector(ray.d);
    member->fill_interaction(local, hit, si);
    to_world_space(to_world, si);
    // Embree interpolates its own copy of the decomposition: its pose and ours differ by a few
    // roundings of the coordinates, which the offset of the next ray must also clear.
    if (motion_.is_animated()) si.p_error += gamma_bound(16) * max_abs_component(si.p);
}

void Instance::to_world_space(const Transform& to_world, SurfaceInteraction& si) const {
    si.p_error = transformed_point_error(to_world, si.p, si.p_error);
    si.p = to_world.apply_point(si.p);
    si.n = glm::normalize(to_world.apply_normal(si.n));
    Vec3 ns = glm::normalize(to_world.apply_normal(si.shading.n));
    Vec3 tangent = to_world.apply_vector(si.shading.s);
    si.shading = Frame::from_normal_tangent(ns, tangent);
    si.dpdu = to_world.apply_vector(si.dpdu);
    si.dpdv = to_world.apply_vector(si.dpdv);
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
