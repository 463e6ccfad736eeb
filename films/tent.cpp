// tent: the tent (triangle) reconstruction filter, 1 - |x| / radius.
//
// Parameters:
//   radius   float   support radius in pixels (default 1)

#include "core/filter.h"
#include "core/properties.h"
#include "core/registry.h"

namespace candela {

class TentFilter final : public ReconstructionFilter {
public:
    explicit TentFilter(const Properties& props) {
        radius_ = props.get_float("radius", 1.0f);
        if (!(radius_ > 0.0f && radius_ <= 4.0f)) props.fail("radius", "tent radius must be in (0, 4]");
    }
    // The triangle of height 1/r and half-width r has unit area.
    float eval(float x) const override { return std::max(0.0f, 1.0f - std::abs(x) / radius_) / radius_; }
};

CANDELA_REGISTER(TentFilter, ObjectKind::Filter, "tent");

}  // namespace candela
