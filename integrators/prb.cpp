// prb: Mitsuba 3's path replay backpropagation integrator, which differentiable-rendering scripts
// name. Candela renders forward only, and PRB's forward (primal) estimate is the path tracer's:
// next-event estimation and BSDF sampling with MIS by the power heuristic, Russian roulette from
// rr_depth with survival min(max(throughput) * eta^2, 0.95) (Mitsuba's prb.py). So this is the
// `path` integrator with prb's defaults; its gradients are not computed.
//
// Parameters (Mitsuba 3 names and defaults):
//   max_depth       integer   longest path in segments; -1 = unbounded (default 6, prb's)
//   rr_depth        integer   depth from which Russian roulette may end paths (default 5)
//   hide_emitters   boolean   emitters seen directly render black (default false)
// Like Mitsuba's prb it does not render in the polarized variant.

#include "core/properties.h"
#include "core/registry.h"
#include "integrators/path.h"

namespace candela {

class PrbIntegrator final : public PathIntegrator {
public:
    // max_depth 6: prb.py's default, where path's is unbounded.
    explicit PrbIntegrator(const Properties& props)
        : PathIntegrator(read_differentiable_settings(props, "prb", DepthSettings | HideEmittersSetting, 6)) {}
    std::string to_string() const override { return "prb"; }
};

CANDELA_REGISTER_SPECTRAL(PrbIntegrator, ObjectKind::Integrator, "prb");

}  // namespace candela
