#pragma once
// What `bumpmap` and `normalmap` share: a nested BSDF evaluated in a perturbed shading frame,
// with Mitsuba 3's conventions (since its 2025 rework of both plugins):
//   - the plugin gives the perturbed normal in the coordinates of the original shading frame
//     (perturbation(), not normalized);
//   - flip_invalid_normals: where wi lies below the perturbed normal (cos_theta(wi) and
//     wi . n of opposite signs, or zero), the normal's tangential part is mirrored,
//     n = (-n_x, -n_y, n_z), so that the viewer sees its front (Schuessler et al. 2017,
//     "Microfacet-based Normal Mapping for Robust Monte Carlo Path Tracing", section 5);
//   - the perturbed frame's s axis is the original s axis made orthogonal to n (Gram-Schmidt),
//     t = n x s: the identity map gives back the original frame exactly;
//   - any result is zero when wo lies on different sides of the original and the perturbed
//     surface (no light leaks);
//   - use_shadowing_function: eval and the sample weight (not the pdf) are multiplied by the
//     microfacet shadowing of Estevez et al. 2019 ("A Microfacet-Based Shadowing Function to
//     Solve the Bump Terminator Problem", Ray Tracing Gems ch. 12):
//         G(wo) = 2 / (1 + sqrt(1 + alpha^2 tan^2(theta_o))),  alpha^2 = min(tan^2(theta_n) / 8, 1)
//     with theta_o and theta_n the angles of wo and of the perturbed normal from the original
//     shading normal. It darkens grazing light where the normal is strongly tilted, the hard
//     shadow terminator of bumped low-polygon meshes.
//
// Parameters (both plugins; Mitsuba 3):
//   flip_invalid_normals     boolean   mirror normals that face away from wi (default true)
//   use_shadowing_function   boolean   apply G(wo) above (default true)

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/properties.h"

namespace candela {

class PerturbedFrameBSDF : public BSDF {
public:
    // Reads the one nested BSDF and the two switches.
    explicit PerturbedFrameBSDF(const Properties& props);

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override;
    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override;
    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override;
    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override;
    // The nested BSDF's matrix, from the perturbed frame's Stokes bases to the original one's.
    bool eval_mueller(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe,
                      MuellerSpectrum& M) const override;
    Spectrum albedo(const SurfaceInteraction& si) const override { return nested_->albedo(perturb(si).si); }
    // Local model: the nested BSDF's, shaded in the perturbed frame (bump / normal mapping).
    LocalShading local_shading() const override { return nested_->local_shading(); }
    Frame shading_frame(const SurfaceInteraction& si) const override { return perturb(si).si.shading; }

protected:
    // The perturbed normal at si in the coordinates of si.shading; need not be normalized.
    virtual Vec3 perturbation(const SurfaceInteraction& si) const = 0;

private:
    struct Perturbed {
        SurfaceInteraction si;  // as the nested BSDF sees it: perturbed frame, wi in it
        Frame local;            // the perturbed frame in the coordinates of the original one
    };
    Perturbed perturb(const SurfaceInteraction& si) const;
    // G(wo) above (1 when switched off); n and wo in the original frame's coordinates.
    float shadowing(const Vec3& n, const Vec3& wo) const;

    Ref<BSDF> nested_;
    bool flip_invalid_normals_ = true;
    bool use_shadowing_function_ = true;
};

}  // namespace candela
