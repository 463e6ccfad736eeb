// twosided: makes a one-sided BSDF reflect on both sides. With one nested BSDF both sides use
// it; with two, the second is the back side's. Seen from the back, the directions are mirrored
// through the surface (z -> -z) before the nested BSDF is asked.
//
// Parameters:
//   (nested bsdf)   one or two reflective BSDFs (transmissive ones are two-sided already)

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/registry.h"

namespace candela {

class TwoSidedBSDF final : public BSDF {
public:
    explicit TwoSidedBSDF(const Properties& props) {
        auto nested = props.get_objects(ObjectKind::BSDF);
        if (nested.empty() || nested.size() > 2) props.fail("twosided needs one or two nested BSDFs");
        front_ = std::static_pointer_cast<BSDF>(nested[0]);
        back_ = nested.size() == 2 ? std::static_pointer_cast<BSDF>(nested[1]) : front_;
        if ((front_->flags() | back_->flags()) & Transmission)
            props.fail("twosided cannot wrap a transmissive BSDF (it is two-sided already)");
        if ((front_->flags() | back_->flags()) & Null)
            props.fail("twosided cannot wrap a BSDF that lets light pass (null, mask, polarizer): put the twosided inside it");
        flags_ = front_->flags() | back_->flags();
        reads_lobe_sample_ = front_->reads_lobe_sample() || back_->reads_lobe_sample();
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override {
        if (Frame::cos_theta(si.wi) >= 0.0f) return front_->sample(ctx, si, u_lobe, u);
        SurfaceInteraction flipped = mirrored(si);
        BSDFSample bs = back_->sample(ctx, flipped, u_lobe, u);
        bs.wo.z = -bs.wo.z;
        return bs;
    }

    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        if (Frame::cos_theta(si.wi) >= 0.0f) return front_->eval(ctx, si, wo);
        return back_->eval(ctx, mirrored(si), Vec3(wo.x, wo.y, -wo.z));
    }

    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        if (Frame::cos_theta(si.wi) >= 0.0f) return front_->pdf(ctx, si, wo);
        return back_->pdf(ctx, mirrored(si), Vec3(wo.x, wo.y, -wo.z));
    }

    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        if (Frame::cos_theta(si.wi) >= 0.0f) return front_->eval_pdf(ctx, si, wo);
        return back_->eval_pdf(ctx, mirrored(si), Vec3(wo.x, wo.y, -wo.z));
    }

    // Seen from the back the nested BSDF works in mirrored coordinates (z -> -z), which turn the
    // handedness of its Stokes bases: S2 and S3 change sign, M -> F M F with F = diag(1, 1, -1, -1),
    // before its bases are re-expressed in this frame's.
    bool eval_mueller(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe,
                      MuellerSpectrum& M) const override {
        if (Frame::cos_theta(si.wi) >= 0.0f) return front_->eval_mueller(ctx, si, wo, lobe, M);
        const SurfaceInteraction flipped = mirrored(si);
        const Vec3 wo_flipped(wo.x, wo.y, -wo.z);
        if (!back_->eval_mueller(ctx, flipped, wo_flipped, lobe, M)) return false;
        const Frame mirror(Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -1));
        for (Mueller& m : M.w)
            for (int i = 0; i < 4; ++i)
                for (int j = 0; j < 4; ++j)
                    if ((i >= 2) != (j >= 2)) m(i, j) = -m(i, j);
        local_to_parent(mirror, flipped.wi, wo_flipped).apply(M);
        return true;
    }

    Spectrum albedo(const SurfaceInteraction& si) const override {
        return Frame::cos_theta(si.wi) >= 0.0f ? front_->albedo(si) : back_->albedo(mirrored(si));
    }

    // Local model: the front BSDF's, lit from both sides.
    LocalShading local_shading() const override {
        LocalShading s = front_->local_shading();
        s.two_sided = true;
        return s;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        visitor.object("brdf_0", front_.get());
        visitor.object("brdf_1", back_.get());
    }
    std::string to_string() const override { return "twosided"; }

private:
    static SurfaceInteraction mirrored(const SurfaceInteraction& si) {
        SurfaceInteraction m = si;
        m.wi.z = -m.wi.z;
        return m;
    }
    Ref<BSDF> front_, back_;
};

CANDELA_REGISTER_SPECTRAL(TwoSidedBSDF, ObjectKind::BSDF, "twosided");

}  // namespace candela
