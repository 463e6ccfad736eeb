#pragma once
// The plugin registry. Concrete BSDFs, emitters, shapes, ... register themselves by their Mitsuba
// type name; the scene loader builds them from a Properties bag. Nothing in core/ knows a
// concrete plugin.

#include "core/object.h"
#include "core/properties.h"

#include <functional>
#include <string>
#include <vector>

namespace candela {

using PluginFactory = std::function<Ref<Object>(const Properties&)>;

// `spectral`: the plugin also renders in the spectral variant (core/variant.h). Plugins of the
// kinds that carry colour (BSDFs, emitters, textures, integrators, media, phase functions,
// volumes) are refused in that variant unless they say so; shapes, sensors, films, filters and
// samplers carry none and render in every variant.
void register_plugin(ObjectKind kind, const std::string& type, PluginFactory factory, bool spectral = false);
bool plugin_exists(ObjectKind kind, const std::string& type);
std::vector<std::string> plugin_names(ObjectKind kind);

// Builds the plugin named by props.plugin_type(), then checks that it read every property.
// An unknown type is a SceneError at the object's location naming the nearest supported type;
// Mitsuba plugins that Candela deliberately lacks (differentiable ones) say why.
Ref<Object> create_plugin(ObjectKind kind, const Properties& props);

template <typename T>
Ref<T> create_plugin_as(ObjectKind kind, const Properties& props) {
    return std::static_pointer_cast<T>(create_plugin(kind, props));
}

template <typename T>
struct PluginRegistration {
    PluginRegistration(ObjectKind kind, const char* type, bool spectral = false) {
        register_plugin(
            kind, type, [](const Properties& p) -> Ref<Object> { return std::make_shared<T>(p); }, spectral);
    }
};

#define CANDELA_CONCAT_INNER(a, b) a##b
#define CANDELA_CONCAT(a, b) CANDELA_CONCAT_INNER(a, b)
// Registers class `Class` (constructible from `const Properties&`) under a Mitsuba type name.
#define CANDELA_REGISTER(Class, kind, type_name) \
    static ::candela::PluginRegistration<Class> CANDELA_CONCAT(candela_registration_, __LINE__)(kind, type_name)
// The same for a plugin that renders in the spectral variant too (its values at the path's
// wavelengths: core/wavelengths.h).
#define CANDELA_REGISTER_SPECTRAL(Class, kind, type_name) \
    static ::candela::PluginRegistration<Class> CANDELA_CONCAT(candela_registration_, __LINE__)(kind, type_name, true)

}  // namespace candela
