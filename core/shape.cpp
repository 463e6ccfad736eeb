#include "core/shape.h"

#include "core/bsdf.h"
#include "core/emitter.h"
#include "core/medium.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "core/sensor.h"

namespace candela {

Shape::Shape(const Properties& props, bool may_move) {
    motion_ = may_move ? props.get_animated_transform("to_world") : AnimatedTransform(props.get_transform("to_world", Transform()));
    to_world_ = motion_.first();
    flip_normals_ = props.get_bool("flip_normals", false);
    auto emitters = props.get_objects(ObjectKind::Emitter);
    if (emitters.size() > 1) props.fail("a shape can have only one emitter");
    if (!emitters.empty()) {
        emitter_ = std::static_pointer_cast<Emitter>(emitters[0]);
        if (emitter_->type() != EmitterType::Area) props.fail("only an area emitter can be nested in a shape");
        if (emitter_->shape()) props.fail("this emitter is already attached to another shape");
        emitter_->set_shape(this);
    }
    auto sensors = props.get_objects(ObjectKind::Sensor);
    if (sensors.size() > 1) props.fail("a shape can have only one sensor");
    if (!sensors.empty()) {
        sensor_ = std::static_pointer_cast<Sensor>(sensors[0]);
        sensor_->attach_to_shape(*this, props);
    }
    for (auto& [name, medium] : props.get_named_objects(ObjectKind::Medium)) {
        if (name == "interior")
            interior_ = std::static_pointer_cast<Medium>(medium);
        else if (name == "exterior")
            exterior_ = std::static_pointer_cast<Medium>(medium);
        else
            props.fail(name, "a shape's medium must be named \"interior\" or \"exterior\", not \"" + name + "\"");
    }
    auto bsdfs = props.get_objects(ObjectKind::BSDF);
    if (bsdfs.size() > 1) props.fail("a shape can have only one bsdf");
    if (bsdfs.empty()) {
        // Mitsuba's default material: diffuse with reflectance 0.5, or 0 on an emitter.
        Properties diffuse("diffuse", props.location());
        if (emitter_) diffuse.set_rgb("reflectance", Spectrum(0.0f));
        bsdf_ = create_plugin_as<BSDF>(ObjectKind::BSDF, diffuse);
    } else {
        bsdf_ = std::static_pointer_cast<BSDF>(bsdfs[0]);
    }
}

void Shape::tessellate_parts(std::vector<TessellatedPart>& parts, int detail) const {
    parts.push_back(TessellatedPart{this, TriangleSoup()});
    tessellate(parts.back().triangles, detail);
}

DirectionSample Shape::sample_direction(const SurfaceInteraction& ref, const Vec2& u) const {
    return direction_from_position(ref, sample_position(u));
}

float Shape::pdf_direction(const SurfaceInteraction& ref, const DirectionSample& ds) const {
    float cos_light = std::abs(glm::dot(ds.n, ds.d));
    if (cos_light == 0.0f) return 0.0f;
    return ds.dist * ds.dist / (cos_light * surface_area());
}

void Shape::traverse(ParameterVisitor& visitor) {
    visitor.object("bsdf", bsdf_.get());
    visitor.object("emitter", emitter_.get());
}

}  // namespace candela
