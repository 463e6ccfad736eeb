#pragma once
// What `bumpmap` and `normalmap` share: a nested BSDF evaluated in a perturbed shading frame.
// Directions are moved into the perturbed frame and back; as in Mitsuba 3, any result is zero
// when wo lies on different sides of the original and the perturbed surface (no light leaks).

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/properties.h"

namespace candela {

class PerturbedFrameBSDF : public BSDF {
public:
    // Reads the one nested BSDF.
    explicit PerturbedFrameBSDF(const Properties& props);

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override;
    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override;
    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override;
    Spectrum albedo(const SurfaceInteraction& si) const override { return nested_->albedo(perturbed(si)); }
    // Local model: the nested BSDF's, shaded in the perturbed frame (bump / normal mapping).
    LocalShading local_shading() const override { return nested_->local_shading(); }
    Frame shading_frame(const SurfaceInteraction& si) const override { return perturbed_frame(si); }

    // The interaction as the nested BSDF sees it: perturbed frame, wi expressed in it.
    SurfaceInteraction perturbed(const SurfaceInteraction& si) const;

protected:
    // The perturbed shading frame (world space) at si.
    virtual Frame perturbed_frame(const SurfaceInteraction& si) const = 0;

private:
    Ref<BSDF> nested_;
};

}  // namespace candela
