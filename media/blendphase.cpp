// blendphase: a mix of two phase functions (Mitsuba 3's `blendphase`),
//   p = (1 - weight) p_first + weight p_second.
//
// Parameters:
//   weight         float in [0, 1]   0 gives the first nested phase function, 1 the second
//                                    (default 0.5); Mitsuba also takes a texture here, which has
//                                    no meaning at a point in a medium without a uv, so only a
//                                    number is accepted
//   (two nested phase functions, in document order)
// Sampled by choosing one of the two with probability (1 - weight, weight) and sampling it; the
// pdf is the mixture of the two pdfs, the weight p / pdf (1 when both parts are sampled exactly).

#include "core/phase.h"
#include "core/properties.h"
#include "core/registry.h"

namespace candela {

class BlendPhase : public PhaseFunction {
public:
    explicit BlendPhase(const Properties& props) {
        weight_ = props.get_float("weight", 0.5f);
        if (!(weight_ >= 0.0f && weight_ <= 1.0f)) props.fail("weight", "blendphase: the weight must lie in [0, 1]");
        auto phases = props.get_objects(ObjectKind::Phase);
        if (phases.size() != 2) props.fail("blendphase needs exactly two nested phase functions");
        first_ = std::static_pointer_cast<PhaseFunction>(phases[0]);
        second_ = std::static_pointer_cast<PhaseFunction>(phases[1]);
    }

    float eval(const Vec3& wi, const Vec3& wo) const override {
        return (1.0f - weight_) * first_->eval(wi, wo) + weight_ * second_->eval(wi, wo);
    }
    float pdf(const Vec3& wi, const Vec3& wo) const override {
        return (1.0f - weight_) * first_->pdf(wi, wo) + weight_ * second_->pdf(wi, wo);
    }
    PhaseSample sample(const Vec3& wi, const Vec2& u) const override {
        // u.x picks the part, then is stretched back to [0, 1) for it.
        bool second = u.x >= 1.0f - weight_;
        float ux = second ? (u.x - (1.0f - weight_)) / weight_ : u.x / (1.0f - weight_);
        // 0x1.fffffep-1 is the largest float below one: rounding must not push ux to 1.
        PhaseSample ps = (second ? second_ : first_)->sample(wi, Vec2(std::min(ux, 0x1.fffffep-1f), u.y));
        if (!ps.valid()) return ps;
        ps.pdf = pdf(wi, ps.wo);
        float f = eval(wi, ps.wo);
        ps.weight = ps.pdf > 0.0f ? f / ps.pdf : 0.0f;
        return ps;
    }
    float mean_cosine() const override { return (1.0f - weight_) * first_->mean_cosine() + weight_ * second_->mean_cosine(); }
    std::string to_string() const override { return "blendphase"; }

private:
    float weight_ = 0.5f;
    Ref<PhaseFunction> first_, second_;
};

CANDELA_REGISTER(BlendPhase, ObjectKind::Phase, "blendphase");

}  // namespace candela
