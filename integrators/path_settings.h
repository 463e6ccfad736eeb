#pragma once
// The settings of every integrator that follows paths: path, volpath and volpathmis, irradiance,
// direct, the estimators, and the light-path integrators (ptracer, sppm, photonmapper). They are
// read and checked here and nowhere else, each bad value named at its own line (Mitsuba 3's
// names and meanings).

#include "core/spectrum.h"
#include "lights/light_sampler.h"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>

namespace candela {

class Properties;

struct PathSettings {
    int max_depth = -1;  // longest path (in segments or scattering events, as the integrator says); -1 unbounded
    int rr_depth = 5;    // depth from which Russian roulette may end paths
    bool hide_emitters = false;
    std::string light_sampler = DefaultLightSampler;

    // max_depth as a bound on the depth: UINT32_MAX when unbounded.
    uint32_t depth_limit() const { return max_depth < 0 ? UINT32_MAX : uint32_t(max_depth); }
    // Whether a path that has made `depth` segments (scattering events) may make one more.
    bool may_extend(uint32_t depth) const { return max_depth < 0 || depth + 1 < uint32_t(max_depth); }
    // Whether a path of `segments` segments is within max_depth.
    bool within_depth(uint32_t segments) const { return max_depth < 0 || segments <= uint32_t(max_depth); }
};

// Russian roulette's rule (Mitsuba's): a path whose depth has reached rr_depth goes on with
// probability min(max(beta) eta^2, 0.95). The relative index crossed, squared, keeps paths inside
// glass alive (radiance there is scaled by eta^2); the cap keeps every path a chance to end.
inline float roulette_continue_probability(const Spectrum& beta, float eta) { return std::min(max_component(beta) * eta * eta, 0.95f); }

// Which settings an integrator reads from its properties.
enum PathSettingFields : uint32_t {
    DepthSettings = 1,  // max_depth, rr_depth
    HideEmittersSetting = 2,
    LightSamplerSetting = 4,
};

struct PathSettingProblem {
    std::string parameter;  // Mitsuba name: max_depth, rr_depth or light_sampler
    std::string message;
};
// The first invalid setting, or nothing when all are valid.
std::optional<PathSettingProblem> check_path_settings(const PathSettings& settings);
// Reads the `fields` (PathSettingFields) from an integrator's properties; what they do not give
// keeps its value in `defaults`. An invalid value is a SceneError at its file:line.
PathSettings read_path_settings(const Properties& props, uint32_t fields, const PathSettings& defaults = PathSettings{});
// The settings of Mitsuba 3's differentiable integrators (prb, prb_basic, prb_projective,
// direct_projective, prbvolpath): the `fields` as read_path_settings reads them, max_depth
// `default_max_depth` where the scene gives none. They do not render in the polarized variant:
// in it, a SceneError at the integrator's line naming `integrator`.
PathSettings read_differentiable_settings(const Properties& props, const std::string& integrator, uint32_t fields, int default_max_depth);

}  // namespace candela
