#include "apps/commands.h"

#include "core/error.h"

namespace candela::app {

void RasterOptionArgs::add_to(CLI::App* cmd) {
    for (const char* name : {"shading", "reflection", "shadows", "aa", "aa-filter", "texture-filter", "environment-mapping"}) {
        std::string key = name;
        std::replace(key.begin(), key.end(), '-', '_');
        cmd->add_option(std::string("--") + name, values[key], "Raster mode: " + key + " (see integrators/raster/raster.cpp)");
    }
    cmd->add_flag("--wireframe", wireframe, "Raster mode: draw visible triangle edges");
    cmd->add_flag("--light-gizmos", light_gizmos, "Raster mode: draw the lights");
    cmd->add_flag("--affine", affine, "Raster mode: affine (not perspective-correct) interpolation");
    cmd->add_flag("--backface-culling", backface_culling, "Raster mode: cull back faces");
}

std::map<std::string, std::string> RasterOptionArgs::given() const {
    std::map<std::string, std::string> out;
    for (const auto& [k, v] : values)
        if (!v.empty()) out[k] = v;
    if (wireframe) out["wireframe"] = "true";
    if (light_gizmos) out["light_gizmos"] = "true";
    if (affine) out["affine"] = "true";
    if (backface_culling) out["backface_culling"] = "true";
    return out;
}

void RasterOptionArgs::apply(RasterSettings& settings) const {
    std::string error;
    for (const auto& [k, v] : given())
        if (!settings.set(k, v, error)) throw InputError(error);
}

}  // namespace candela::app
