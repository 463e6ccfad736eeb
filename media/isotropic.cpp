// isotropic: the phase function that scatters equally in every direction, p = 1 / (4 pi).
// No parameters. The default phase function of every medium (Mitsuba 3's `isotropic`).

#include "core/phase.h"
#include "core/properties.h"
#include "core/registry.h"

namespace candela {

class IsotropicPhase : public PhaseFunction {
public:
    explicit IsotropicPhase(const Properties&) {}
    float eval(const MediumInteraction&, const Vec3&) const override { return InvFourPi; }
    float pdf(const MediumInteraction&, const Vec3&) const override { return InvFourPi; }
    PhaseSample sample(const MediumInteraction&, const Vec2& u) const override {
        PhaseSample ps;
        ps.wo = direction_around(Vec3(0.0f, 0.0f, 1.0f), 1.0f - 2.0f * u.x, TwoPi * u.y);
        ps.pdf = InvFourPi;
        ps.weight = 1.0f;
        return ps;
    }
    std::string to_string() const override { return "isotropic"; }
};

CANDELA_REGISTER_SPECTRAL(IsotropicPhase, ObjectKind::Phase, "isotropic");

}  // namespace candela
