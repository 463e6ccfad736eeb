#pragma once
// A scene's editable parameters by Mitsuba 3's names (its traverse() and parameters_changed()):
// what the Python API's traverse() lists and SceneParameters.update() changes without reloading
// the scene. Each object names its own values and its children (Object::traverse); a child with
// an id is named by its id alone (Mitsuba's "red.reflectance.value" for <bsdf id="red">), one
// without by its parent's name and its own ("light.emitter.radiance.value").
//
// A value is read and written through the object's accessors, as floats: 1 for a Float, 3 for a
// Color, 16 (row-major) for a Transform, any count for Floats (e.g. a mesh's vertex_positions,
// x y z per vertex). After writes, the owner's parameters_changed() brings what it derives from
// them (inverses, sampling weights, areas, the BVH) up to date.

#include "core/object.h"
#include "core/spectrum.h"
#include "core/transform.h"

#include <functional>
#include <string>
#include <vector>

namespace candela {

class Scene;

enum class ParameterType { Float, Color, Transform, Floats };

// What an object hands the visitor for one value.
struct ParameterAccess {
    ParameterType type = ParameterType::Float;
    std::function<std::vector<float>()> get;
    // Writes the value (count floats as get() returns; null for a read-only value).
    std::function<void(const std::vector<float>&)> set;
};

class ParameterVisitor {
public:
    virtual ~ParameterVisitor() = default;
    virtual void value(const std::string& name, ParameterAccess access) = 0;
    virtual void object(const std::string& name, Object* child) = 0;
};

// Helpers for the common values kept as plain members (the member must outlive the visitor's
// use of it: the scene's parameters live as long as the scene).
void expose_float(ParameterVisitor& visitor, const std::string& name, float& value);
// An integer as one float, which a write must give as a whole number (Mitsuba's integer parameters).
void expose_int(ParameterVisitor& visitor, const std::string& name, int& value);
void expose_color(ParameterVisitor& visitor, const std::string& name, Spectrum& value);
// A transform as 16 numbers, row by row (Mitsuba's matrix order); singular ones are refused.
void expose_transform(ParameterVisitor& visitor, const std::string& name, Transform& value);

// One parameter of a scene: its full name, how to read and write it, and the object whose
// parameters_changed() an update calls (with `key`, the name relative to it).
struct SceneParameter {
    std::string name, key;
    ParameterAccess access;
    Object* owner = nullptr;
};

// Every parameter of the scene, in traversal order (shapes, their BSDFs and emitters, the other
// emitters, the sensor), each object once.
std::vector<SceneParameter> scene_parameters(Scene& scene);

// Calls parameters_changed() on the owners of `changed` (each owner once, with its keys), then
// brings the scene up to date (its bounds, its BVH when geometry moved).
void apply_parameter_changes(Scene& scene, const std::vector<const SceneParameter*>& changed);

}  // namespace candela
