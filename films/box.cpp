// box: the box reconstruction filter; each sample counts only in the pixel it falls in.
//
// Parameters: none (radius 0.5 pixels, as in Mitsuba 3).

#include "core/filter.h"
#include "core/properties.h"
#include "core/registry.h"

namespace candela {

class BoxFilter final : public ReconstructionFilter {
public:
    explicit BoxFilter(const Properties& props) { radius_ = 0.5f; }
    // Half-open support [-r, r) so a sample on a pixel boundary counts once.
    float eval(float x) const override { return (x >= -radius_ && x < radius_) ? 1.0f / (2.0f * radius_) : 0.0f; }
};

CANDELA_REGISTER(BoxFilter, ObjectKind::Filter, "box");

}  // namespace candela
