#include "core/parameters.h"

#include "core/error.h"
#include "core/scene.h"

#include <cmath>
#include <map>
#include <set>

namespace candela {

void expose_float(ParameterVisitor& visitor, const std::string& name, float& value) {
    visitor.value(name, ParameterAccess{ParameterType::Float, [&value] { return std::vector<float>{value}; },
                                        [&value](const std::vector<float>& v) { value = v.at(0); }});
}

void expose_int(ParameterVisitor& visitor, const std::string& name, int& value) {
    visitor.value(name, ParameterAccess{ParameterType::Float, [&value] { return std::vector<float>{float(value)}; },
                                        [&value, name](const std::vector<float>& v) {
                                            if (v.size() != 1 || !(v[0] == std::round(v[0])) || std::abs(v[0]) > 1e9f)
                                                throw InputError(name + " must be a whole number");
                                            value = int(v[0]);
                                        }});
}

void expose_color(ParameterVisitor& visitor, const std::string& name, Spectrum& value) {
    visitor.value(name, ParameterAccess{ParameterType::Color,
                                        [&value] {
                                            return std::vector<float>{value.x, value.y, value.z};
                                        },
                                        [&value](const std::vector<float>& v) { value = Spectrum(v.at(0), v.at(1), v.at(2)); }});
}

void expose_transform(ParameterVisitor& visitor, const std::string& name, Transform& value) {
    visitor.value(name, ParameterAccess{ParameterType::Transform,
                                        [&value] {
                                            std::vector<float> v(16);
                                            const Mat4& m = value.matrix();  // column-major: m[col][row]
                                            for (int r = 0; r < 4; ++r)
                                                for (int c = 0; c < 4; ++c) v[size_t(r * 4 + c)] = m[c][r];
                                            return v;
                                        },
                                        [&value](const std::vector<float>& v) {
                                            if (v.size() != 16) throw InputError("a transform takes 16 numbers (4 x 4)");
                                            Mat4 m(1.0f);
                                            for (int r = 0; r < 4; ++r)
                                                for (int c = 0; c < 4; ++c) m[c][r] = v[size_t(r * 4 + c)];
                                            const Transform t(m);
                                            if (!t.all_finite()) throw InputError("the transform is singular or not finite");
                                            value = t;
                                        }});
}

namespace {

// Mitsuba's names of the objects a scene file leaves without an id (its class names), for the
// top level of traverse(); other plugins go by their type name.
std::string unnamed_object_name(const Object& object) {
    static const std::map<std::string, std::string> names = {{"perspective", "PerspectiveCamera"},
                                                             {"thinlens", "ThinLensCamera"},
                                                             {"orthographic", "OrthographicCamera"},
                                                             {"obj", "OBJMesh"},
                                                             {"ply", "PLYMesh"},
                                                             {"serialized", "SerializedMesh"},
                                                             {"rectangle", "Rectangle"},
                                                             {"cube", "Cube"},
                                                             {"sphere", "Sphere"},
                                                             {"disk", "Disk"},
                                                             {"cylinder", "Cylinder"},
                                                             {"constant", "ConstantBackgroundEmitter"},
                                                             {"envmap", "EnvironmentMapEmitter"},
                                                             {"point", "PointLight"},
                                                             {"spot", "SpotLight"},
                                                             {"directional", "DirectionalEmitter"},
                                                             {"projector", "Projector"},
                                                             {"directionalarea", "DirectionalArea"}};
    const std::string type = object.to_string();
    auto it = names.find(type);
    return it != names.end() ? it->second : type;
}

class Collector final : public ParameterVisitor {
public:
    Collector(std::vector<SceneParameter>& out, std::set<const Object*>& seen, std::string prefix, Object* owner)
        : out_(out), seen_(seen), prefix_(std::move(prefix)), owner_(owner) {}

    void value(const std::string& name, ParameterAccess access) override {
        out_.push_back(SceneParameter{prefix_ + "." + name, name, std::move(access), owner_});
    }
    void object(const std::string& name, Object* child) override {
        visit(child, child && !child->id.empty() ? child->id : prefix_ + "." + name);
    }

    // Visits `object` under `name`, each object once.
    void visit(Object* object, const std::string& name) {
        if (!object || !seen_.insert(object).second) return;
        Collector nested(out_, seen_, name, object);
        object->traverse(nested);
    }

private:
    std::vector<SceneParameter>& out_;
    std::set<const Object*>& seen_;
    std::string prefix_;
    Object* owner_;
};

}  // namespace

std::vector<SceneParameter> scene_parameters(Scene& scene) {
    std::vector<SceneParameter> out;
    std::set<const Object*> seen;
    std::map<std::string, int> used;  // top-level names, made unique with _1, _2, ...
    Collector top(out, seen, "", nullptr);
    auto top_level = [&](Object* object) {
        if (!object || seen.count(object)) return;
        std::string name = !object->id.empty() ? object->id : unnamed_object_name(*object);
        const int n = used[name]++;
        if (n > 0) name += "_" + std::to_string(n);
        top.visit(object, name);
    };
    for (const Ref<Shape>& shape : scene.shapes()) top_level(shape.get());
    for (const Ref<Emitter>& emitter : scene.emitters()) top_level(emitter.get());
    top_level(&scene.sensor());
    return out;
}

void apply_parameter_changes(Scene& scene, const std::vector<const SceneParameter*>& changed) {
    std::map<Object*, std::vector<std::string>> by_owner;
    std::vector<Object*> order;
    for (const SceneParameter* p : changed) {
        if (!p->owner) continue;
        auto [it, inserted] = by_owner.try_emplace(p->owner);
        if (inserted) order.push_back(p->owner);
        it->second.push_back(p->key);
    }
    bool geometry = false;
    for (Object* owner : order) {
        owner->parameters_changed(by_owner[owner]);
        geometry = geometry || owner->kind() == ObjectKind::Shape;
    }
    if (geometry) scene.update_geometry();
}

}  // namespace candela
