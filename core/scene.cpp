#include "core/scene.h"

#include "core/bsdf.h"
#include "core/registry.h"

namespace candela {

Scene::Scene(const Properties& props) {
    source_file = props.location().file;
    // Shape groups are not drawn themselves, only through the instances that reference them.
    for (auto& obj : props.get_objects(ObjectKind::Shape)) {
        auto shape = std::static_pointer_cast<Shape>(obj);
        if (!shape->is_shape_group()) shapes_.push_back(shape);
    }
    // Area emitters first (in shape order), then the scene's own emitters.
    for (auto& shape : shapes_)
        if (shape->emitter()) emitters_.push_back(shape->emitter_ref());
    for (auto& obj : props.get_objects(ObjectKind::Emitter)) {
        auto emitter = std::static_pointer_cast<Emitter>(obj);
        if (emitter->type() == EmitterType::Area)
            throw SceneError(props.location_of(emitter->id), "an area emitter must be nested inside a shape");
        emitters_.push_back(emitter);
    }
    auto sensors = props.get_objects(ObjectKind::Sensor);
    if (sensors.size() > 1) props.fail("only one sensor per scene is supported");
    sensor_ = sensors.empty() ? create_plugin_as<Sensor>(ObjectKind::Sensor, Properties("perspective", props.location()))
                              : std::static_pointer_cast<Sensor>(sensors[0]);
    auto integrators = props.get_objects(ObjectKind::Integrator);
    if (integrators.size() > 1) props.fail("only one integrator per scene is supported");
    integrator_ = integrators.empty() ? create_plugin_as<Integrator>(ObjectKind::Integrator, Properties("path", props.location()))
                                      : std::static_pointer_cast<Integrator>(integrators[0]);
    // Top-level BSDFs and textures exist to be referenced by id; they need no further use here.
    props.get_objects(ObjectKind::BSDF);
    props.get_objects(ObjectKind::Texture);

    for (auto& shape : shapes_) bbox_.expand(shape->bbox());
    accel_.build(shapes_);
    for (auto& emitter : emitters_) {
        emitter->set_scene(*this);
        if (emitter->is_infinite()) infinite_emitters_.push_back(emitter.get());
    }
}

bool Scene::intersect(const Ray& ray, SurfaceInteraction& si) const {
    RayHit hit;
    const Shape* shape = accel_.intersect(ray, hit);
    if (!shape) {
        si.shape = nullptr;
        si.t = Infinity;
        si.wi = -ray.d;
        return false;
    }
    // An instance replaces si.shape by the shape of its group that was hit (for its BSDF).
    si.shape = shape;
    shape->fill_interaction(ray, hit, si);
    si.prim_index = hit.prim_index;
    si.prim_uv = Vec2(hit.u, hit.v);
    si.t = hit.t;
    si.wi = si.to_local(-ray.d);
    return true;
}

Spectrum Scene::eval_environment(const Vec3& d) const {
    Spectrum L(0.0f);
    for (const Emitter* e : infinite_emitters_) L += e->eval_environment(d);
    return L;
}

}  // namespace candela
