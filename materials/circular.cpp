// circular: an ideal circular polariser (Mitsuba 3's `circular`). Light passes straight through,
// unbent; half of unpolarised light passes, times `transmittance`. In scalar_spectral_polarized
// it passes only right-handed circularly polarised light (left-handed with left_handed): the
// Mueller matrix 1/2 [[1, 0, 0, +-1], [0, 0, 0, 0], [0, 0, 0, 0], [+-1, 0, 0, 1]] (+ for right),
// which turning about the beam leaves unchanged, so it has no angle. Two of the same hand pass
// half of unpolarised light, opposite hands nothing; after a linear polariser at any angle one
// passes a quarter. In the unpolarised variants it passes half, as in Mitsuba.
//
// Parameters (Mitsuba 3):
//   transmittance   rgb or texture   extra factor on what passes (default 1)
//   left_handed     boolean          pass left-handed light instead (default false: right-handed)
//
// Its one lobe is Null with weight 0.5 transmittance (materials/optical_element.h), as the
// linear `polarizer`'s.

#include "core/registry.h"
#include "materials/optical_element.h"

namespace candela {

class CircularPolarizerBSDF final : public OpticalElementBSDF {
public:
    explicit CircularPolarizerBSDF(const Properties& props)
        : OpticalElementBSDF(props, 0.5f), element_(circular_polarizer(props.get_bool("left_handed", false))) {}

    bool eval_mueller(const BSDFContext&, const SurfaceInteraction&, const Vec3&, uint32_t lobe, MuellerSpectrum& M) const override {
        if (lobe != Null) return false;
        // The element is invariant to rotation about the beam: it is the same in the light's
        // implicit Stokes basis, whatever axis the surface would give it.
        for (Mueller& w : M.w) w = element_;
        return true;
    }
    std::string to_string() const override { return "circular"; }

private:
    Mueller element_;
};

CANDELA_REGISTER_SPECTRAL(CircularPolarizerBSDF, ObjectKind::BSDF, "circular");

}  // namespace candela
