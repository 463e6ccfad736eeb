// constvolume: one value everywhere in its unit cube (Mitsuba 3's `constvolume`).
//
// Parameters:
//   value      float or rgb   the value (default 1)
//   to_world   transform      places the unit cube [0, 1]^3 (default identity); it bounds a
//                             heterogeneous medium whose sigma_t is this volume, as in Mitsuba

#include "core/registry.h"
#include "core/volume.h"

namespace candela {

class ConstVolume : public Volume {
public:
    explicit ConstVolume(const Properties& props) : Volume(props), value_(props.get_rgb("value", Spectrum(1.0f))) {
        if (!all_finite(value_)) props.fail("value", "the value must be finite");
    }
    Spectrum eval(const Vec3&) const override { return value_; }
    Spectrum max_in_local_box(const Vec3&, const Vec3&) const override { return value_; }
    bool is_constant() const override { return true; }
    std::string to_string() const override { return "constvolume"; }

private:
    Spectrum value_;
};

CANDELA_REGISTER(ConstVolume, ObjectKind::Volume, "constvolume");

}  // namespace candela
