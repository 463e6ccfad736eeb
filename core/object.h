#pragma once
// The base of every scene object that a plugin creates, and the kinds a scene file can name.

#include <memory>
#include <string>
#include <vector>

namespace candela {

enum class ObjectKind { Scene, Shape, BSDF, Emitter, Texture, Sensor, Film, Filter, Sampler, Integrator, Medium, Phase, Volume };

// The XML tag of each kind ("bsdf", "rfilter", ...).
const char* kind_tag(ObjectKind kind);

class ParameterVisitor;

class Object {
public:
    virtual ~Object() = default;
    virtual ObjectKind kind() const = 0;
    // A one-line description for logs and error messages.
    virtual std::string to_string() const { return kind_tag(kind()); }
    // The editable parameters and the child objects, by Mitsuba's names (core/parameters.h).
    virtual void traverse(ParameterVisitor& visitor) {}
    // Some parameters changed (`keys`: their names relative to this object): update what is
    // derived from them.
    virtual void parameters_changed(const std::vector<std::string>& keys) {}
    std::string id;  // the scene file's id attribute, if any
};

template <typename T>
using Ref = std::shared_ptr<T>;

}  // namespace candela
