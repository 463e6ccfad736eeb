// shapegroup: shapes kept for instancing; they are not drawn themselves, only through
// `instance` shapes that reference the group by id.
//
// Parameters:
//   (nested shapes)   one or more shapes, each with its own BSDF
//
// As in Mitsuba 3, a group may not contain another group or an instance (Embree here instances
// one level deep), nor shapes with emitters; it takes no to_world (instances place it), no
// flip_normals and no BSDF of its own. Each instance shades with its group's BSDFs.

#include "shapes/shapegroup.h"
#include "core/emitter.h"
#include "core/registry.h"

#include <stdexcept>

namespace candela {

ShapeGroup::ShapeGroup(const Properties& props) : Shape(props) {
    for (const char* name : {"to_world", "flip_normals"})
        if (props.has(name)) props.fail(name, std::string("a shapegroup takes no ") + name + " (each instance has its own to_world)");
    for (const std::string& name : props.names()) {
        Properties::Type type;
        const Properties::Value& value = props.get_raw(name, &type);
        // (get_raw marks what it reads as used: a stray parameter must still be an error.)
        if (type != Properties::Type::Object) props.fail(name, "unused property \"" + name + "\" in shapegroup: no such parameter");
        const Ref<Object>& object = std::get<Ref<Object>>(value);
        SourceLocation where = props.location_of(name);
        if (object->kind() == ObjectKind::BSDF)
            throw SceneError(where, "a shapegroup has no BSDF of its own: put the bsdf inside the shapes it holds");
        if (object->kind() == ObjectKind::Emitter) throw SceneError(where, "instancing of emitters is not supported (as in Mitsuba)");
        if (object->kind() != ObjectKind::Shape)
            throw SceneError(where, std::string("a shapegroup holds shapes, not a ") + kind_tag(object->kind()));
        auto shape = std::static_pointer_cast<Shape>(object);
        if (shape->is_shape_group()) throw SceneError(where, "nested shapegroups are not permitted");
        if (dynamic_cast<const Instance*>(shape.get())) throw SceneError(where, "nested instancing is not permitted");
        // (A moving area light's still shape is let in: the loader's group of one, see
        // Emitter::move_with_instance.)
        if (shape->emitter() && !shape->emitter()->moves_with_instance())
            throw SceneError(where, "instancing of emitters is not supported (as in Mitsuba): this shape has an area emitter");
        members_.push_back(shape);
        bbox_.expand(shape->bbox());
    }
    if (members_.empty()) props.fail("a shapegroup needs at least one shape");
}

RTCScene ShapeGroup::embree_scene(RTCDevice device) const {
    std::lock_guard<std::mutex> lock(build_mutex_);
    if (!accel_ || accel_->device() != device) {
        accel_ = std::make_unique<Accel>(device);
        accel_->build(members_);
    }
    return accel_->scene();
}

void ShapeGroup::tessellate(TriangleSoup& out, int detail) const {
    for (const Ref<Shape>& shape : members_) {
        TriangleSoup soup;
        shape->tessellate(soup, detail);
        out.append(soup);
    }
}

RTCGeometry ShapeGroup::create_embree_geometry(RTCDevice) const { throw std::logic_error("a shapegroup is drawn only through instances"); }
void ShapeGroup::fill_interaction(const Ray&, const RayHit&, SurfaceInteraction&) const {
    throw std::logic_error("a shapegroup is drawn only through instances");
}
float ShapeGroup::surface_area() const { throw std::logic_error("a shapegroup carries no emitter"); }
PositionSample ShapeGroup::sample_position(const Vec2&) const { throw std::logic_error("a shapegroup carries no emitter"); }

CANDELA_REGISTER(ShapeGroup, ObjectKind::Shape, "shapegroup");

}  // namespace candela
