#include "core/registry.h"

#include "core/text.h"

#include "core/warning.h"

#include <algorithm>
#include <cctype>
#include <map>

namespace candela {

namespace {
struct PluginEntry {
    PluginFactory factory;
    bool spectral = false;
};
std::map<std::pair<ObjectKind, std::string>, PluginEntry>& registry() {
    static std::map<std::pair<ObjectKind, std::string>, PluginEntry> instance;
    return instance;
}

bool carries_colour(ObjectKind kind) {
    switch (kind) {
        case ObjectKind::BSDF:
        case ObjectKind::Emitter:
        case ObjectKind::Texture:
        case ObjectKind::Integrator:
        case ObjectKind::Medium:
        case ObjectKind::Phase:
        case ObjectKind::Volume: return true;
        default: return false;
    }
}
}  // namespace

void register_plugin(ObjectKind kind, const std::string& type, PluginFactory factory, bool spectral) {
    registry()[{kind, type}] = PluginEntry{std::move(factory), spectral};
}

bool plugin_exists(ObjectKind kind, const std::string& type) { return registry().count({kind, type}) != 0; }

std::vector<std::string> plugin_names(ObjectKind kind) {
    std::vector<std::string> out;
    for (auto& [key, f] : registry())
        if (key.first == kind) out.push_back(key.second);
    return out;
}

namespace {

// Names that scenes from Mitsuba's development carry but Candela does not have, with the plugin
// to use instead: a hint in the error, never a silent substitute.
const char* instead_of(ObjectKind kind, const std::string& type) {
    static const std::map<std::pair<ObjectKind, std::string>, const char*> table = {
        {{ObjectKind::BSDF, "disney"}, "Mitsuba 3 calls the Disney BSDF \"principled\"; its parameters may differ from the scene's"},
        {{ObjectKind::Sampler, "bose"}, "an orthogonal-array sampler; Candela's is \"orthogonal\" (Bush's construction)"},
        {{ObjectKind::Sampler, "bush"}, "an orthogonal-array sampler; Candela's is \"orthogonal\" (Bush's construction)"},
        // Names a newcomer writes for the path tracer ("ptracer", the nearest by spelling, is
        // the particle tracer: another algorithm).
        {{ObjectKind::Integrator, "pathtracer"},
         "did you mean \"path\" (unidirectional path tracing)? \"ptracer\" is the particle (light) tracer"},
        {{ObjectKind::Integrator, "path_tracer"},
         "did you mean \"path\" (unidirectional path tracing)? \"ptracer\" is the particle (light) tracer"},
        {{ObjectKind::Integrator, "pt"}, "did you mean \"path\" (unidirectional path tracing)? \"ptracer\" is the particle (light) tracer"},
        {{ObjectKind::Integrator, "pathtracing"}, "did you mean \"path\" (unidirectional path tracing)?"},
        {{ObjectKind::Integrator, "volumetric"}, "did you mean \"volpath\" (volumetric path tracing)?"},
        {{ObjectKind::Integrator, "photonmapping"}, "did you mean \"photonmapper\" (or \"sppm\", progressive photon mapping)?"},
        {{ObjectKind::Integrator, "bdpt"}, "bidirectional path tracing is not in Candela: render with \"path\" (or \"sppm\" for caustics)"},
        {{ObjectKind::Integrator, "mlt"}, "Metropolis light transport is not in Candela: render with \"path\" (or \"sppm\" for caustics)"},
        {{ObjectKind::BSDF, "lambert"}, "did you mean \"diffuse\" (Lambertian)?"},
        {{ObjectKind::BSDF, "lambertian"}, "did you mean \"diffuse\" (Lambertian)?"},
        {{ObjectKind::BSDF, "glass"}, "did you mean \"dielectric\" (smooth glass) or \"roughdielectric\"?"},
        {{ObjectKind::BSDF, "metal"}, "did you mean \"conductor\" (smooth metal) or \"roughconductor\"?"},
        {{ObjectKind::BSDF, "mirror"}, "did you mean \"conductor\" with material \"none\" (a perfect mirror)?"},
        {{ObjectKind::Emitter, "light"},
         "did you mean \"area\" (nested in a shape), \"point\", \"spot\", \"directional\", \"constant\" or \"envmap\"?"},
        {{ObjectKind::Sensor, "camera"}, "did you mean \"perspective\" (a pinhole camera), \"thinlens\" or \"orthographic\"?"},
    };
    auto it = table.find({kind, type});
    return it == table.end() ? nullptr : it->second;
}

bool equal_ignoring_case(const std::string& a, const std::string& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
    return true;
}

}  // namespace

Ref<Object> create_plugin(ObjectKind kind, const Properties& props) {
    auto it = registry().find({kind, props.plugin_type()});
    if (it == registry().end()) {
        // A name that differs only in case ("Rectangle"): Mitsuba 3 finds its plugin file on
        // case-insensitive file systems (macOS, Windows) and some published scenes rely on it.
        for (auto candidate = registry().begin(); candidate != registry().end(); ++candidate)
            if (candidate->first.first == kind && equal_ignoring_case(candidate->first.second, props.plugin_type())) {
                warn(props.location(), std::string(kind_tag(kind)) + " type \"" + props.plugin_type() + "\" read as \"" +
                                           candidate->first.second + "\" (plugin names are case-sensitive in Mitsuba 3 on Linux)");
                it = candidate;
                break;
            }
    }
    if (it == registry().end()) {
        std::string what = std::string(kind_tag(kind)) + " type \"" + props.plugin_type() + "\"";
        if (const char* hint = instead_of(kind, props.plugin_type())) throw SceneError(props.location(), "unknown " + what + ": " + hint);
        std::string known;
        for (auto& name : plugin_names(kind)) known += (known.empty() ? "" : ", ") + name;
        std::string nearest = nearest_name(props.plugin_type(), plugin_names(kind));
        throw SceneError(props.location(), "unknown " + what + (nearest.empty() ? "" : " (nearest supported: \"" + nearest + "\")") +
                                               " (known: " + known + ")");
    }
    if (props.variant() != Variant::ScalarRGB && carries_colour(kind) && !it->second.spectral)
        throw SceneError(props.location(), std::string(kind_tag(kind)) + " type \"" + it->first.second + "\" does not render in variant " +
                                               variant_name(props.variant()) + " yet; it renders in scalar_rgb (--variant scalar_rgb)");
    Ref<Object> obj;
    try {
        obj = it->second.factory(props);
    } catch (const SceneError&) {
        throw;
    } catch (const std::exception& e) {
        // Errors from libraries (image readers, ...) get the object's location.
        throw SceneError(props.location(), e.what());
    }
    obj->id = props.id;
    // Mitsuba lets an emitter name the medium it stands in (an Endpoint's medium). Nothing needs
    // it here: volumetric integrators follow shadow rays from the scattering point through
    // whatever media lie on the way. It is accepted, one at most.
    if (kind == ObjectKind::Emitter && props.get_objects(ObjectKind::Medium).size() > 1)
        props.fail("an emitter stands in at most one medium");
    props.check_all_used();
    return obj;
}

}  // namespace candela
