#pragma once
// Shape groups and their instances (Embree's single-level instancing). A group's shapes are
// stored and put into a BVH once; each instance adds only a transform and a reference to that
// BVH, so memory grows with the number of distinct groups, not with the number of instances.

#include "core/accel.h"

#include <memory>
#include <mutex>

namespace candela {

class ShapeGroup final : public Shape {
public:
    explicit ShapeGroup(const Properties& props);
    bool is_shape_group() const override { return true; }
    std::string to_string() const override { return "shapegroup"; }

    // The group's BVH on `device`, built on first use; every instance on that device shares it.
    RTCScene embree_scene(RTCDevice device) const;
    // The member shape of an Embree geometry id of that BVH.
    const Shape* member(unsigned geometry_id) const { return accel_ ? accel_->shape(geometry_id) : nullptr; }
    const std::vector<Ref<Shape>>& members() const { return members_; }

    // In the group's own space (instances place it).
    BoundingBox bbox() const override { return bbox_; }
    void tessellate(TriangleSoup& out, int detail) const override;

    // A group is never in a scene's BVH and carries no emitter: these are never called.
    RTCGeometry create_embree_geometry(RTCDevice) const override;
    void fill_interaction(const Ray&, const RayHit&, SurfaceInteraction&) const override;
    float surface_area() const override;
    PositionSample sample_position(const Vec2&) const override;

private:
    std::vector<Ref<Shape>> members_;
    BoundingBox bbox_;
    mutable std::mutex build_mutex_;
    mutable std::unique_ptr<Accel> accel_;
};

class Instance final : public Shape {
public:
    explicit Instance(const Properties& props);
    std::string to_string() const override { return "instance"; }

    RTCGeometry create_embree_geometry(RTCDevice device) const override;
    // Fills the interaction of the group's shape that was hit, moved to world space; si.shape
    // becomes that shape (its BSDF is the one that shades).
    void fill_interaction(const Ray& ray, const RayHit& hit, SurfaceInteraction& si) const override;
    BoundingBox bbox() const override { return bbox_; }
    void tessellate(TriangleSoup& out, int detail) const override;
    void tessellate_parts(std::vector<TessellatedPart>& parts, int detail) const override;
    void set_shutter(float open, float close) override;
    // The area emitter of a moving shape (the group's only member; see Emitter::move_with_instance).
    void collect_emitters(std::vector<Ref<Emitter>>& out) const override;

    // Instances carry no emitter (Mitsuba forbids emitters in shape groups): never called.
    float surface_area() const override;
    PositionSample sample_position(const Vec2&) const override;

private:
    void to_world_space(const Transform& to_world, SurfaceInteraction& si) const;
    void transform_soup(TriangleSoup& soup) const;
    // Embree's instance motion: one quaternion decomposition per time step, equally spaced from
    // the first keyframe to the last, padded with copies of the first and last pose to cover the
    // shutter (Embree leaves a geometry out at times beyond its time range), in Embree's time
    // relative to the shutter (EmbreeTime).
    void set_embree_motion(RTCGeometry g) const;

    Ref<ShapeGroup> group_;
    bool identity_ = true;
    float shutter_open_ = 0.0f, shutter_close_ = 0.0f;
    BoundingBox bbox_;
};

}  // namespace candela
