// hg: the Henyey-Greenstein phase function (Henyey and Greenstein 1941),
//   p(mu) = (1 - g^2) / (4 pi (1 + g^2 - 2 g mu)^(3/2)),
// with mu the cosine between the incident and the scattered propagation directions.
//
// Parameters (Mitsuba 3):
//   g   float   the mean cosine, in (-1, 1): > 0 scatters forward, < 0 backward, 0 is
//               isotropic (default 0.8)
// Sampled exactly by inverting the CDF of mu (pbrt-v4, section 11.3.1), so weight = 1.

#include "core/phase.h"
#include "core/properties.h"
#include "core/registry.h"

namespace candela {

class HenyeyGreenstein : public PhaseFunction {
public:
    explicit HenyeyGreenstein(const Properties& props) : g_(props.get_float("g", 0.8f)) {
        if (!(g_ > -1.0f && g_ < 1.0f)) props.fail("g", "the asymmetry parameter g must lie strictly between -1 and 1");
    }

    float eval(const MediumInteraction& mi, const Vec3& wo) const override { return density(glm::dot(-mi.wi, wo)); }
    float pdf(const MediumInteraction& mi, const Vec3& wo) const override { return density(glm::dot(-mi.wi, wo)); }

    PhaseSample sample(const MediumInteraction& mi, const Vec2& u) const override {
        float mu;
        if (std::abs(g_) < 1e-3f) {
            mu = 1.0f - 2.0f * u.x;
        } else {
            float s = (1.0f - g_ * g_) / (1.0f - g_ + 2.0f * g_ * u.x);
            mu = (1.0f + g_ * g_ - s * s) / (2.0f * g_);
        }
        mu = std::clamp(mu, -1.0f, 1.0f);
        PhaseSample ps;
        ps.wo = direction_around(-mi.wi, mu, TwoPi * u.y);
        ps.pdf = density(mu);
        ps.weight = 1.0f;
        return ps;
    }
    float mean_cosine() const override { return g_; }
    std::string to_string() const override { return "hg"; }

private:
    float density(float mu) const {
        float denom = 1.0f + g_ * g_ - 2.0f * g_ * mu;
        return InvFourPi * (1.0f - g_ * g_) / (denom * safe_sqrt(denom));
    }
    float g_;
};

CANDELA_REGISTER_SPECTRAL(HenyeyGreenstein, ObjectKind::Phase, "hg");

}  // namespace candela
