// blendbsdf: a linear blend of two BSDFs (Mitsuba 3's `blendbsdf`).
//
// Parameters (Mitsuba 3):
//   weight          float or texture   0 = the first nested BSDF, 1 = the second (default 0.5);
//                                      looked up as a scalar, clamped to [0, 1]
//   (nested bsdf)   exactly two BSDFs
//
//   f = (1 - w) f_0 + w f_1
// sample() picks a nested BSDF with probability proportional to its weight (among those with a
// lobe the context allows). A smooth direction it returns is then weighted against the blend as
// a whole: pdf = sum p_k pdf_k, weight = f / pdf (so MIS sees the density actually sampled); a
// delta lobe keeps its own weight times w_k / p_k.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"
#include "materials/local_mix.h"

namespace candela {

class BlendBSDF final : public BSDF {
public:
    explicit BlendBSDF(const Properties& props) {
        weight_ = props.get_texture("weight", Spectrum(0.5f));
        auto nested = props.get_objects(ObjectKind::BSDF);
        if (nested.size() != 2) props.fail("blendbsdf needs exactly two nested BSDFs");
        nested_[0] = std::static_pointer_cast<BSDF>(nested[0]);
        nested_[1] = std::static_pointer_cast<BSDF>(nested[1]);
        flags_ = nested_[0]->flags() | nested_[1]->flags();
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override {
        float w[2], p[2];
        weights(ctx, si, w, p);
        // The second BSDF for u < p_1, as Mitsuba orders them.
        int k = u_lobe < p[1] ? 1 : 0;
        if (!(p[k] > 0.0f)) return BSDFSample();
        float u_rescaled = k == 1 ? u_lobe / p[1] : (u_lobe - p[1]) / p[0];
        BSDFSample bs = nested_[k]->sample(ctx, si, std::min(u_rescaled, 0.99999994f), u);
        if (!bs.valid()) return bs;
        if (is_delta(bs.lobe)) {
            bs.pdf *= p[k];
            bs.weight *= w[k] / p[k];
            return bs;
        }
        return weighted_by_pdf(ctx, si, bs);
    }
    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        float w = weight(si);
        Spectrum f(0.0f);
        if (w < 1.0f) f += (1.0f - w) * nested_[0]->eval(ctx, si, wo);
        if (w > 0.0f) f += w * nested_[1]->eval(ctx, si, wo);
        return f;
    }
    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        float w[2], p[2];
        weights(ctx, si, w, p);
        float result = 0.0f;
        for (int k = 0; k < 2; ++k)
            if (p[k] > 0.0f) result += p[k] * nested_[k]->pdf(ctx, si, wo);
        return result;
    }
    // eval() and pdf() with one eval_pdf of each nested BSDF that either needs.
    BSDFEvalPdf eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override {
        float w[2], p[2];
        weights(ctx, si, w, p);
        BSDFEvalPdf result;
        for (int k = 0; k < 2; ++k) {
            if (!(w[k] > 0.0f) && !(p[k] > 0.0f)) continue;
            const BSDFEvalPdf e = nested_[k]->eval_pdf(ctx, si, wo);
            if (w[k] > 0.0f) result.value += w[k] * e.value;
            if (p[k] > 0.0f) result.pdf += p[k] * e.pdf;
        }
        return result;
    }
    // Polarized: the smooth lobes' matrices, each scaled to its eval() intensity, blended as eval()
    // blends them; a delta lobe's matrix is that of the (first) nested BSDF that has the lobe.
    bool eval_mueller(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe,
                      MuellerSpectrum& M) const override {
        if (is_delta(lobe)) {
            for (const Ref<BSDF>& nested : nested_)
                if (nested->flags() & lobe) return nested->eval_mueller(ctx, si, wo, lobe, M);
            return false;
        }
        const float w = weight(si);
        const float share[2] = {1.0f - w, w};
        bool polarizing = false;
        M = MuellerSpectrum();
        for (int k = 0; k < 2; ++k) {
            if (!(share[k] > 0.0f)) continue;
            const Spectrum f = share[k] * nested_[k]->eval(ctx, si, wo);
            MuellerSpectrum part;
            const bool polarized = nested_[k]->eval_mueller(ctx, si, wo, lobe, part);
            polarizing = polarizing || polarized;
            for (int i = 0; i < 3; ++i) {
                const float m00 = polarized ? part.w[i](0, 0) : 0.0f;
                const Mueller unit = m00 > 0.0f ? (1.0f / m00) * part.w[i] : Mueller::depolarizer();
                M.w[i] = M.w[i] + f[i] * unit;
            }
        }
        return polarizing;
    }
    Spectrum albedo(const SurfaceInteraction& si) const override {
        float w = weight(si);
        return (1.0f - w) * nested_[0]->albedo(si) + w * nested_[1]->albedo(si);
    }
    Spectrum null_transmission(const SurfaceInteraction& si) const override {
        float w = weight(si);
        return (1.0f - w) * nested_[0]->null_transmission(si) + w * nested_[1]->null_transmission(si);
    }
    // Local model: the two nested models blended by the weight (see mix_local_shading).
    LocalShading local_shading() const override {
        return mix_local_shading(nested_[0]->local_shading(), nested_[1]->local_shading(), weight_);
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        visitor.object("weight", weight_.get());
        visitor.object("bsdf_0", nested_[0].get());
        visitor.object("bsdf_1", nested_[1].get());
    }
    std::string to_string() const override { return "blendbsdf"; }

private:
    float weight(const SurfaceInteraction& si) const { return std::clamp(weight_->eval_1(si), 0.0f, 1.0f); }
    // The blend weights w_k and the selection probabilities p_k (w_k renormalised over the nested
    // BSDFs that have a lobe the context allows).
    void weights(const BSDFContext& ctx, const SurfaceInteraction& si, float w[2], float p[2]) const {
        w[1] = weight(si);
        w[0] = 1.0f - w[1];
        for (int k = 0; k < 2; ++k) p[k] = (nested_[k]->flags() & ctx.lobes) != 0 ? w[k] : 0.0f;
        float total = p[0] + p[1];
        for (int k = 0; k < 2; ++k) p[k] = total > 0.0f ? p[k] / total : 0.0f;
    }

    Ref<Texture> weight_;
    Ref<BSDF> nested_[2];
};

CANDELA_REGISTER_SPECTRAL(BlendBSDF, ObjectKind::BSDF, "blendbsdf");

}  // namespace candela
