#pragma once
// What `polarizer` and `retarder` share: an ideal optical element that light crosses straight,
// unbent. Its one lobe is Null, taken surely, with weight (and shadow-ray transmission)
// fraction * transmittance; the raster mode sees the environment through it at that strength.
// In the polarized variant its Mueller matrix is an ideal element whose reference (x) axis is
// an axis of the surface, turned into the implicit Stokes basis of the light crossing it.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/properties.h"
#include "core/texture.h"

namespace candela {

class OpticalElementBSDF : public BSDF {
public:
    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float, const Vec2&) const override {
        return ctx.allows(Null) ? null_lobe_sample(si, 1.0f, null_transmission(si)) : BSDFSample();
    }
    Spectrum eval(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return Spectrum(0.0f); }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return 0.0f; }
    Spectrum albedo(const SurfaceInteraction& si) const override { return null_transmission(si); }
    Spectrum null_transmission(const SurfaceInteraction& si) const override { return fraction_ * transmittance_->eval(si); }
    LocalShading local_shading() const override {
        LocalShading s;
        s.transmission = fraction_ * transmittance_->mean();
        s.two_sided = true;
        return s;
    }

protected:
    // Reads `transmittance` (default 1); `fraction` is what passes of unpolarised light besides.
    OpticalElementBSDF(const Properties& props, float fraction)
        : transmittance_(props.get_texture("transmittance", Spectrum(1.0f))), fraction_(fraction) {
        flags_ = Null;
    }

    // `element`, whose reference axis is `element_x` (a unit vector normal to `forward`, local),
    // for light travelling along `forward`, in its implicit Stokes basis, at every wavelength.
    static void on_beam(const Vec3& forward, const Vec3& element_x, const Mueller& element, MuellerSpectrum& M) {
        const Mueller R = rotate_stokes_basis(forward, element_x, stokes_basis(forward));
        const Mueller m = R * element * transpose(R);
        for (Mueller& w : M.w) w = m;
    }

private:
    Ref<Texture> transmittance_;
    float fraction_;
};

}  // namespace candela
