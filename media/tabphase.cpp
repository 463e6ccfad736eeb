// tabphase: a phase function tabulated against the cosine of the scattering angle (Mitsuba 3's
// `tabphase`).
//
// Parameters:
//   values   string   comma- or space-separated values of the phase function at n >= 2 cosines
//                     spaced regularly over [-1, 1] (the first at mu = -1, backward; the last at
//                     mu = 1, forward), non-negative, not all zero; scaled so the phase function
//                     integrates to one over the sphere (required)
// mu is the cosine between the incident and the scattered propagation directions (Mitsuba's
// "physics convention": mu = 1 scatters forward). Between the table's points p(mu) is linear; the
// phase function is p(mu) / (2 pi) with the integral of p over [-1, 1] equal to one. It is
// sampled exactly: mu by inverting the piecewise-quadratic CDF, the azimuth uniformly.

#include "core/phase.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/text.h"

#include <algorithm>
#include <vector>

namespace candela {

class TabulatedPhase : public PhaseFunction {
public:
    explicit TabulatedPhase(const Properties& props) {
        for (const std::string& item : split_list(props.get_string("values"))) {
            float v = 0.0f;
            if (!parse_finite_float(item, v)) props.fail("values", "tabphase: \"" + item + "\" is not a number");
            if (v < 0.0f) props.fail("values", "tabphase: the values must not be negative");
            values_.push_back(v);
        }
        if (values_.size() < 2) props.fail("values", "tabphase needs at least two values (at mu = -1 and mu = 1)");
        step_ = 2.0f / float(values_.size() - 1);
        // The CDF at each table point: trapezoids, then everything divided by the total.
        cdf_.assign(values_.size(), 0.0f);
        for (size_t i = 1; i < values_.size(); ++i) cdf_[i] = cdf_[i - 1] + 0.5f * step_ * (values_[i - 1] + values_[i]);
        float total = cdf_.back();
        if (!(total > 0.0f)) props.fail("values", "tabphase: the values are all zero");
        for (size_t i = 0; i < values_.size(); ++i) {
            values_[i] /= total;
            cdf_[i] /= total;
        }
    }

    float eval(const MediumInteraction& mi, const Vec3& wo) const override { return density(glm::dot(-mi.wi, wo)); }
    float pdf(const MediumInteraction& mi, const Vec3& wo) const override { return density(glm::dot(-mi.wi, wo)); }

    PhaseSample sample(const MediumInteraction& mi, const Vec2& u) const override {
        float mu = sample_mu(u.x);
        PhaseSample ps;
        ps.wo = direction_around(-mi.wi, mu, TwoPi * u.y);
        ps.pdf = density(mu);
        ps.weight = ps.pdf > 0.0f ? 1.0f : 0.0f;
        return ps;
    }
    float mean_cosine() const override {
        // The integral of mu p(mu) over each linear piece, in closed form.
        double sum = 0.0;
        for (size_t i = 0; i + 1 < values_.size(); ++i) {
            double a = -1.0 + double(i) * step_, b = a + step_, pa = values_[i], pb = values_[i + 1];
            sum += (b - a) * (pa * (2.0 * a + b) + pb * (a + 2.0 * b)) / 6.0;
        }
        return float(sum);
    }
    std::string to_string() const override { return "tabphase"; }

private:
    // p(mu) / (2 pi), p linear between the table's points.
    float density(float mu) const {
        float x = (std::clamp(mu, -1.0f, 1.0f) + 1.0f) / step_;
        size_t i = std::min(size_t(x), values_.size() - 2);
        float t = x - float(i);
        return InvTwoPi * ((1.0f - t) * values_[i] + t * values_[i + 1]);
    }

    // Inverts the CDF: the piece holding u, then within it the root of the quadratic
    // cdf_i + h (p0 t + (p1 - p0) t^2 / 2) = u for t in [0, 1].
    float sample_mu(float u) const {
        size_t i = size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
        i = std::clamp(i, size_t(1), values_.size() - 1) - 1;
        float p0 = values_[i], p1 = values_[i + 1], r = (u - cdf_[i]) / step_;
        float t;
        if (std::abs(p1 - p0) < 1e-6f * std::max(p0, p1)) {
            t = p0 > 0.0f ? r / p0 : 0.5f;
        } else {
            // (p1 - p0) / 2 t^2 + p0 t - r = 0; the root in [0, 1], in the form that avoids
            // cancellation: t = 2 r / (p0 + sqrt(p0^2 + 2 (p1 - p0) r)).
            float disc = std::max(0.0f, p0 * p0 + 2.0f * (p1 - p0) * r);
            float denom = p0 + std::sqrt(disc);
            t = denom > 0.0f ? 2.0f * r / denom : 0.0f;
        }
        t = std::clamp(t, 0.0f, 1.0f);
        return std::clamp(-1.0f + (float(i) + t) * step_, -1.0f, 1.0f);
    }

    std::vector<float> values_, cdf_;  // normalised p at the table's points, and its CDF there
    float step_ = 2.0f;
};

CANDELA_REGISTER_SPECTRAL(TabulatedPhase, ObjectKind::Phase, "tabphase");

}  // namespace candela
