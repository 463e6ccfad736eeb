// mitchell: the Mitchell-Netravali cubic reconstruction filter (films/bc_spline.h), radius 2
// pixels, as in Mitsuba 3. Its negative lobes sharpen edges at the cost of slight ringing; the film
// divides by the sum of weights, which stays positive as every pixel's own samples weigh most.
//
// Parameters:
//   B   float   the paper's B (default 1/3)
//   C   float   the paper's C (default 1/3; B = C = 1/3 is the paper's recommendation)

#include "core/filter.h"
#include "core/properties.h"
#include "core/registry.h"
#include "films/bc_spline.h"

namespace candela {

class MitchellFilter final : public ReconstructionFilter {
public:
    explicit MitchellFilter(const Properties& props) {
        radius_ = 2.0f;
        b_ = props.get_float("B", 1.0f / 3.0f);
        c_ = props.get_float("C", 1.0f / 3.0f);
        // Any finite values, as Mitsuba: the centre weight is (6 - 2B) / 6, so B >= 3 leaves a
        // pixel only negative or zero sums of weights, and the film writes 0 where they are not
        // positive; refused, as no filter of the family is meant that way.
        if (!std::isfinite(b_) || b_ >= 3.0f) props.fail("B", "mitchell B must be below 3 (the centre weight is (6 - 2B) / 6)");
        if (!std::isfinite(c_)) props.fail("C", "mitchell C must be finite");
    }
    float eval(float x) const override { return bc_spline(x, b_, c_); }

private:
    float b_, c_;
};

CANDELA_REGISTER(MitchellFilter, ObjectKind::Filter, "mitchell");

}  // namespace candela
