#include "core/registry.h"

#include <map>

namespace candela {

namespace {
std::map<std::pair<ObjectKind, std::string>, PluginFactory>& registry() {
    static std::map<std::pair<ObjectKind, std::string>, PluginFactory> instance;
    return instance;
}
}  // namespace

void register_plugin(ObjectKind kind, const std::string& type, PluginFactory factory) {
    registry()[{kind, type}] = std::move(factory);
}

bool plugin_exists(ObjectKind kind, const std::string& type) { return registry().count({kind, type}) != 0; }

std::vector<std::string> plugin_names(ObjectKind kind) {
    std::vector<std::string> out;
    for (auto& [key, f] : registry())
        if (key.first == kind) out.push_back(key.second);
    return out;
}

Ref<Object> create_plugin(ObjectKind kind, const Properties& props) {
    auto it = registry().find({kind, props.plugin_type()});
    if (it == registry().end()) {
        std::string known;
        for (auto& name : plugin_names(kind)) known += (known.empty() ? "" : ", ") + name;
        throw SceneError(props.location(), std::string("unknown ") + kind_tag(kind) + " type \"" + props.plugin_type() +
                                               "\" (known: " + known + ")");
    }
    Ref<Object> obj;
    try {
        obj = it->second(props);
    } catch (const SceneError&) {
        throw;
    } catch (const std::exception& e) {
        // Errors from libraries (image readers, ...) get the object's location.
        throw SceneError(props.location(), e.what());
    }
    obj->id = props.id;
    props.check_all_used();
    return obj;
}

}  // namespace candela
