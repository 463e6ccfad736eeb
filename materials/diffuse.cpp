// diffuse: the ideal diffuse (Lambertian) reflector, f = reflectance / pi. One-sided: black when
// seen from the back (wrap it in `twosided` for both sides).
//
// Parameters:
//   reflectance   rgb or texture   diffuse albedo in [0, 1] (default 0.5)
// Sampling: cosine-weighted hemisphere, so the sample weight is the reflectance itself.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"
#include "core/warp.h"

namespace candela {

class DiffuseBSDF final : public BSDF {
public:
    explicit DiffuseBSDF(const Properties& props) {
        reflectance_ = props.get_reflectance("reflectance", Spectrum(0.5f));
        flags_ = DiffuseReflection;
        reads_lobe_sample_ = false;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float, const Vec2& u) const override {
        // One named result on every path, so that it is built in the caller's storage (a second
        // `return BSDFSample()` made a copy whose reloads stalled store forwarding).
        BSDFSample bs;
        if (!ctx.allows(DiffuseReflection) || Frame::cos_theta(si.wi) <= 0.0f) return bs;
        Vec3 wo = warp::square_to_cosine_hemisphere(u);
        float pdf = warp::square_to_cosine_hemisphere_pdf(wo);
        if (pdf <= 0.0f) return bs;
        bs.wo = wo;
        bs.pdf = pdf;
        bs.lobe = DiffuseReflection;
        bs.weight = reflectance_->eval(si);
        return bs;
    }

    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        if (!ctx.allows(DiffuseReflection) || Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return Spectrum(0.0f);
        return reflectance_->eval(si) * (InvPi * Frame::cos_theta(wo));
    }

    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        if (!ctx.allows(DiffuseReflection) || Frame::cos_theta(si.wi) <= 0.0f) return 0.0f;
        return warp::square_to_cosine_hemisphere_pdf(wo);
    }

    // Both at once for next-event estimation (one virtual call, one texture lookup), equal to the two.
    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        BSDFEvalPdf result;
        if (!ctx.allows(DiffuseReflection) || Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return result;
        result.value = reflectance_->eval(si) * (InvPi * Frame::cos_theta(wo));
        result.pdf = warp::square_to_cosine_hemisphere_pdf(wo);
        return result;
    }

    Spectrum albedo(const SurfaceInteraction& si) const override { return reflectance_->eval(si); }
    // Local model: kd = reflectance; no highlight, no reflection.
    LocalShading local_shading() const override {
        LocalShading s;
        s.diffuse = reflectance_;
        return s;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override { visitor.object("reflectance", reflectance_.get()); }
    std::string to_string() const override { return "diffuse"; }

private:
    Ref<Texture> reflectance_;
};

CANDELA_REGISTER_SPECTRAL(DiffuseBSDF, ObjectKind::BSDF, "diffuse");

}  // namespace candela
