// gaussian: a truncated Gaussian reconstruction filter, shifted down so that it reaches zero at
// its radius (as in Mitsuba 3): exp(-x^2 / (2 s^2)) - exp(-r^2 / (2 s^2)), r = 4 s.
//
// Parameters:
//   stddev   float   standard deviation in pixels (default 0.5, so the radius is 2 pixels)

#include "core/filter.h"
#include "core/properties.h"
#include "core/registry.h"

namespace candela {

class GaussianFilter final : public ReconstructionFilter {
public:
    explicit GaussianFilter(const Properties& props) {
        stddev_ = props.get_float("stddev", 0.5f);
        if (!(stddev_ > 0.0f && stddev_ <= 1.0f)) props.fail("stddev", "gaussian stddev must be in (0, 1]");
        radius_ = 4.0f * stddev_;
        offset_ = std::exp(-radius_ * radius_ / (2.0f * stddev_ * stddev_));
        // Closed-form integral of the shifted Gaussian over [-r, r].
        double s = stddev_, r = radius_;
        double integral = s * std::sqrt(2.0 * 3.14159265358979323846) * std::erf(r / (s * std::sqrt(2.0))) - 2.0 * r * offset_;
        norm_ = float(1.0 / integral);
    }
    float eval(float x) const override {
        if (std::abs(x) >= radius_) return 0.0f;
        return std::max(0.0f, std::exp(-x * x / (2.0f * stddev_ * stddev_)) - offset_) * norm_;
    }

private:
    float stddev_, offset_, norm_;
};

CANDELA_REGISTER(GaussianFilter, ObjectKind::Filter, "gaussian");

}  // namespace candela
