#include "materials/phong_lobe.h"

#include "core/warp.h"

namespace candela {

PhongFamilyBSDF::PhongFamilyBSDF(const Properties& props) {
    kd_ = props.get_texture("kd", Spectrum(0.5f));
    ks_ = props.get_texture("ks", Spectrum(0.2f));
    exponent_ = props.get_float("exponent", 30.0f);
    if (!(exponent_ >= 0.0f)) props.fail("exponent", "exponent must be non-negative");
    // Energy conservation: the lobes are normalised, so their weights must sum to at most one.
    if (kd_->max_value() + ks_->max_value() > 1.0f + 1e-6f) props.fail("kd + ks exceeds 1 (the BSDF would create energy); scale them down");
    flags_ = DiffuseReflection | GlossyReflection;
}

float PhongFamilyBSDF::glossy_probability(const BSDFContext& ctx, const SurfaceInteraction& si) const {
    bool has_d = ctx.allows(DiffuseReflection), has_g = ctx.allows(GlossyReflection);
    if (!has_g) return 0.0f;
    if (!has_d) return 1.0f;
    float d = average(kd_->eval(si)), s = average(ks_->eval(si));
    return d + s > 0.0f ? s / (d + s) : 0.5f;
}

BSDFSample PhongFamilyBSDF::sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const {
    BSDFSample bs;
    if (Frame::cos_theta(si.wi) <= 0.0f || !(ctx.allows(DiffuseReflection) || ctx.allows(GlossyReflection))) return bs;
    float p_glossy = glossy_probability(ctx, si);
    if (u_lobe < p_glossy) {
        bs.wo = sample_lobe(si.wi, u);
        bs.lobe = GlossyReflection;
    } else {
        bs.wo = warp::square_to_cosine_hemisphere(u);
        bs.lobe = DiffuseReflection;
    }
    if (bs.wo.z <= 0.0f) return BSDFSample();  // the glossy lobe reaches below the horizon
    bs.pdf = pdf(ctx, si, bs.wo);
    if (!(bs.pdf > 0.0f)) return BSDFSample();
    bs.weight = eval(ctx, si, bs.wo) / bs.pdf;
    return bs;
}

Spectrum PhongFamilyBSDF::eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const {
    float cos_o = Frame::cos_theta(wo);
    if (Frame::cos_theta(si.wi) <= 0.0f || cos_o <= 0.0f) return Spectrum(0.0f);
    Spectrum f(0.0f);
    if (ctx.allows(DiffuseReflection)) f += kd_->eval(si) * InvPi;
    if (ctx.allows(GlossyReflection)) f += ks_->eval(si) * lobe(si.wi, wo);
    return f * cos_o;
}

float PhongFamilyBSDF::pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const {
    if (Frame::cos_theta(si.wi) <= 0.0f || Frame::cos_theta(wo) <= 0.0f) return 0.0f;
    float p_glossy = glossy_probability(ctx, si);
    return p_glossy * lobe_pdf(si.wi, wo) + (1.0f - p_glossy) * warp::square_to_cosine_hemisphere_pdf(wo);
}

}  // namespace candela
