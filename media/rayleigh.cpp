// rayleigh: scattering by particles much smaller than the wavelength (Rayleigh 1871),
//   p(mu) = 3 / (16 pi) (1 + mu^2),
// mu the cosine between incident and scattered directions. No parameters (Mitsuba 3's
// `rayleigh`; its wavelength dependence lives in the medium's sigma_t, not here).
// Sampled exactly: the CDF F(mu) = 1/2 + 3/8 (mu + mu^3 / 3) gives the cubic
// mu^3 + 3 mu = 2 q with q = 4 u - 2, whose one real root is mu = c - 1 / c with
// c = cbrt(q + sqrt(q^2 + 1)) (Cardano).

#include "core/phase.h"
#include "core/properties.h"
#include "core/registry.h"

namespace candela {

class RayleighPhase : public PhaseFunction {
public:
    explicit RayleighPhase(const Properties&) {}
    float eval(const MediumInteraction& mi, const Vec3& wo) const override { return density(glm::dot(mi.wi, wo)); }
    float pdf(const MediumInteraction& mi, const Vec3& wo) const override { return density(glm::dot(mi.wi, wo)); }
    PhaseSample sample(const MediumInteraction& mi, const Vec2& u) const override {
        float q = 4.0f * u.x - 2.0f;
        float c = std::cbrt(q + std::sqrt(q * q + 1.0f));
        float mu = std::clamp(c - 1.0f / c, -1.0f, 1.0f);
        PhaseSample ps;
        ps.wo = direction_around(-mi.wi, mu, TwoPi * u.y);
        ps.pdf = density(mu);
        ps.weight = 1.0f;
        return ps;
    }
    std::string to_string() const override { return "rayleigh"; }

private:
    static float density(float mu) { return (3.0f / 16.0f) * InvPi * (1.0f + mu * mu); }
};

CANDELA_REGISTER_SPECTRAL(RayleighPhase, ObjectKind::Phase, "rayleigh");

}  // namespace candela
