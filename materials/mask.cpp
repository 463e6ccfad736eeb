// mask: an opacity mask over a nested BSDF (Mitsuba 3's `mask`): where the opacity is a, the
// surface scatters like the nested BSDF with weight a and lets light pass straight through with
// weight 1 - a (cut-out leaves, fences). Shadows included: shadow rays keep 1 - a.
//
// Parameters (Mitsuba 3):
//   opacity         float or texture   1 = opaque (default 0.5); looked up as a scalar, clamped
//                                      to [0, 1]
//   (nested bsdf)   the BSDF of the opaque part
//
//   f = a f_nested + (1 - a) delta(wo = -wi)   (the delta is the Null lobe)
// sample() picks the pass with probability 1 - a (weight 1) and the nested BSDF otherwise
// (weight f_nested / pdf_nested); pdf() = a pdf_nested; eval() = a eval_nested. When the context
// allows only one of the two, that one is taken surely and weighted by its share.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"
#include "materials/local_mix.h"

namespace candela {

class MaskBSDF final : public BSDF {
public:
    explicit MaskBSDF(const Properties& props) {
        opacity_ = props.get_texture("opacity", Spectrum(0.5f));
        auto nested = props.get_objects(ObjectKind::BSDF);
        if (nested.size() != 1) props.fail("mask needs exactly one nested BSDF");
        nested_ = std::static_pointer_cast<BSDF>(nested[0]);
        flags_ = nested_->flags() | Null;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override {
        float a = opacity(si), p_pass = pass_probability(ctx, a);
        if (u_lobe < p_pass) return null_lobe_sample(si, p_pass, Spectrum((1.0f - a) / p_pass));
        if (p_pass >= 1.0f) return BSDFSample();
        BSDFSample bs = nested_->sample(ctx, si, (u_lobe - p_pass) / (1.0f - p_pass), u);
        if (!bs.valid()) return bs;
        bs.pdf *= 1.0f - p_pass;
        bs.weight *= a / (1.0f - p_pass);
        return bs;
    }
    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        float a = opacity(si);
        return a > 0.0f ? a * nested_->eval(ctx, si, wo) : Spectrum(0.0f);
    }
    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        float p_pass = pass_probability(ctx, opacity(si));
        return p_pass < 1.0f ? (1.0f - p_pass) * nested_->pdf(ctx, si, wo) : 0.0f;
    }
    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        float a = opacity(si), p_pass = pass_probability(ctx, a);
        if (!(a > 0.0f) && !(p_pass < 1.0f)) return BSDFEvalPdf{};
        BSDFEvalPdf e = nested_->eval_pdf(ctx, si, wo);
        return BSDFEvalPdf{a > 0.0f ? a * e.value : Spectrum(0.0f), p_pass < 1.0f ? (1.0f - p_pass) * e.pdf : 0.0f};
    }
    // Polarized: what passes is unchanged (the identity); the rest is the nested BSDF's.
    bool eval_mueller(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe,
                      MuellerSpectrum& M) const override {
        if (lobe != Null) return nested_->eval_mueller(ctx, si, wo, lobe, M);
        M = identity_spectrum();
        return true;
    }
    Spectrum albedo(const SurfaceInteraction& si) const override { return opacity(si) * nested_->albedo(si); }
    // 1 - a (1 - t_nested), as Mitsuba: the pass, and whatever the nested BSDF lets pass.
    Spectrum null_transmission(const SurfaceInteraction& si) const override {
        float a = opacity(si);
        return Spectrum(1.0f - a) + a * nested_->null_transmission(si);
    }
    // Local model: the nested BSDF's weighted by the opacity (Lambertian texel by texel), and the
    // environment seen straight through with weight 1 - opacity.
    LocalShading local_shading() const override {
        LocalShading clear;
        clear.transmission = Spectrum(1.0f);
        clear.two_sided = true;
        return mix_local_shading(clear, nested_->local_shading(), opacity_);
    }
    Frame shading_frame(const SurfaceInteraction& si) const override { return nested_->shading_frame(si); }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        visitor.object("opacity", opacity_.get());
        visitor.object("bsdf", nested_.get());
    }
    std::string to_string() const override { return "mask"; }

private:
    float opacity(const SurfaceInteraction& si) const { return std::clamp(opacity_->eval_1(si), 0.0f, 1.0f); }
    // The probability of the pass: 1 - a, or surely / never when the context allows only one side.
    float pass_probability(const BSDFContext& ctx, float a) const {
        bool pass = ctx.allows(Null), scatter = (nested_->flags() & ctx.lobes) != 0;
        if (!pass) return 0.0f;
        return scatter ? 1.0f - a : 1.0f;
    }

    Ref<Texture> opacity_;
    Ref<BSDF> nested_;
};

CANDELA_REGISTER_SPECTRAL(MaskBSDF, ObjectKind::BSDF, "mask");

}  // namespace candela
