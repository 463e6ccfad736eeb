#include "integrators/path_settings.h"

#include "core/properties.h"

#include <algorithm>

namespace candela {

std::optional<PathSettingProblem> check_path_settings(const PathSettings& s) {
    if (s.max_depth < -1) return PathSettingProblem{"max_depth", "max_depth must be -1 (unbounded) or >= 0"};
    if (s.rr_depth <= 0) return PathSettingProblem{"rr_depth", "rr_depth must be positive"};
    const auto& names = light_sampler_names();
    if (std::find(names.begin(), names.end(), s.light_sampler) == names.end())
        return PathSettingProblem{"light_sampler", "unknown light_sampler \"" + s.light_sampler + "\" (" + light_sampler_choices() + ")"};
    return std::nullopt;
}

PathSettings read_differentiable_settings(const Properties& props, const std::string& integrator, uint32_t fields, int default_max_depth) {
    if (props.variant() == Variant::ScalarSpectralPolarized)
        props.fail(integrator +
                   " does not render in variant scalar_spectral_polarized (as in Mitsuba 3); it renders in scalar_rgb and "
                   "scalar_spectral, and path or volpath render polarization");
    PathSettings defaults;
    defaults.max_depth = default_max_depth;
    return read_path_settings(props, fields, defaults);
}

PathSettings read_path_settings(const Properties& props, uint32_t fields, const PathSettings& defaults) {
    PathSettings s = defaults;
    if (fields & DepthSettings) {
        s.max_depth = props.get_int("max_depth", s.max_depth);
        s.rr_depth = props.get_int("rr_depth", s.rr_depth);
    }
    if (fields & HideEmittersSetting) s.hide_emitters = props.get_bool("hide_emitters", s.hide_emitters);
    if (fields & LightSamplerSetting) s.light_sampler = props.get_string("light_sampler", s.light_sampler);
    if (auto problem = check_path_settings(s)) props.fail(problem->parameter, problem->message);
    return s;
}

}  // namespace candela
