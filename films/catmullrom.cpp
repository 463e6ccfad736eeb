// catmullrom: the Catmull-Rom cubic reconstruction filter, the Mitchell-Netravali filter with
// B = 0, C = 1/2 (films/bc_spline.h), radius 2 pixels, as in Mitsuba 3. It interpolates (weight 1
// at the pixel's centre, 0 at its neighbours') and keeps edges sharper than mitchell, with more
// ringing.
//
// Parameters: none.

#include "core/filter.h"
#include "core/properties.h"
#include "core/registry.h"
#include "films/bc_spline.h"

namespace candela {

class CatmullRomFilter final : public ReconstructionFilter {
public:
    explicit CatmullRomFilter(const Properties&) { radius_ = 2.0f; }
    float eval(float x) const override { return bc_spline(x, 0.0f, 0.5f); }
};

CANDELA_REGISTER(CatmullRomFilter, ObjectKind::Filter, "catmullrom");

}  // namespace candela
