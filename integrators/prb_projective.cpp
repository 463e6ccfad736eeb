// prb_projective and direct_projective: Mitsuba 3's projective-sampling differentiable
// integrators (Zhang, Roussel and Jakob 2023), which its shape-optimisation tutorials name.
// Candela renders forward only. Their forward (primal) estimates are the path tracer's: next-event
// estimation and BSDF sampling with MIS, Russian roulette from rr_depth (prb_projective), and the
// same limited to direct illumination (direct_projective, which Mitsuba's documentation calls
// prb_projective with max_depth 2). So each is `path` with its defaults; the projective
// sampling of visibility gradients is not computed, and the parameters that steer it change no
// pixel of the image.
//
// Parameters (Mitsuba 3 names and defaults):
//   max_depth       integer   prb_projective: longest path in segments; -1 = unbounded (default
//                             -1). direct_projective: accepted (Mitsuba's base class reads it)
//                             and ignored: always 2, emitters seen directly and direct light
//   rr_depth        integer   depth from which Russian roulette may end paths (default 5;
//                             direct_projective: accepted and ignored)
//   hide_emitters   boolean   emitters seen directly render black (default false)
//   sppc, sppp,     integer   samples per pixel of the continuous, primary-visibility and
//   sppi                      indirect-visibility gradient estimates (default 0: the render's);
//                             gradient only: checked (0 or more) and unused
//   guiding         string    none, grid or octree (default octree): guiding of the indirect
//                             visibility gradients; checked and unused
//   guiding_proj    boolean   (default true) gradient only; unused
//   guiding_rounds  integer   1 or more (default 1); gradient only: checked and unused
// Like Mitsuba's, neither renders in the polarized variant.

#include "core/properties.h"
#include "core/registry.h"
#include "integrators/path.h"

namespace candela {

namespace {

// Reads what steers the projective gradients, which a forward render does not compute: each
// value is checked at its line, so that a scene Mitsuba would refuse is refused here too.
void read_projective_gradient_settings(const Properties& props) {
    for (const char* name : {"sppc", "sppp", "sppi"})
        if (props.get_int(name, 0) < 0) props.fail(name, std::string(name) + " must be 0 (the render's samples) or more");
    const std::string guiding = props.get_string("guiding", "octree");
    if (guiding != "none" && guiding != "grid" && guiding != "octree")
        props.fail("guiding", "guiding must be none, grid or octree, not \"" + guiding + "\"");
    props.get_bool("guiding_proj", true);
    if (props.get_int("guiding_rounds", 1) < 1) props.fail("guiding_rounds", "guiding_rounds must be 1 or more");
}

PathSettings projective_settings(const Properties& props, const std::string& name, bool direct) {
    PathSettings settings = read_differentiable_settings(props, name, DepthSettings | HideEmittersSetting, -1);
    read_projective_gradient_settings(props);
    if (direct) {
        settings.max_depth = 2;
        settings.rr_depth = PathSettings().rr_depth;
    }
    return settings;
}

}  // namespace

class PrbProjectiveIntegrator final : public PathIntegrator {
public:
    explicit PrbProjectiveIntegrator(const Properties& props) : PathIntegrator(projective_settings(props, "prb_projective", false)) {}
    std::string to_string() const override { return "prb_projective"; }
};

class DirectProjectiveIntegrator final : public PathIntegrator {
public:
    explicit DirectProjectiveIntegrator(const Properties& props) : PathIntegrator(projective_settings(props, "direct_projective", true)) {}
    std::string to_string() const override { return "direct_projective"; }
};

CANDELA_REGISTER_SPECTRAL(PrbProjectiveIntegrator, ObjectKind::Integrator, "prb_projective");
CANDELA_REGISTER_SPECTRAL(DirectProjectiveIntegrator, ObjectKind::Integrator, "direct_projective");

}  // namespace candela
