// blendphase: a mix of two phase functions (Mitsuba 3's `blendphase`),
//   p = (1 - weight) p_first + weight p_second.
//
// Parameters:
//   weight         float or volume   0 gives the first nested phase function, 1 the second
//                                    (default 0.5). A volume (constvolume, gridvolume) is
//                                    evaluated at the scattering point, as Mitsuba's
//                                    props.volume("weight"): the mean of its channels (a grey
//                                    volume's value), clamped to [0, 1] as Mitsuba clamps it.
//                                    A number must lie in [0, 1].
//   (two nested phase functions, in document order; neither may be a microflake one such as
//    sggx, whose projected area sets the medium's extinction: a blend has none, and Mitsuba 3
//    stops on it at render time)
// Sampled by choosing one of the two with probability (1 - weight, weight) and sampling it; the
// pdf is the mixture of the two pdfs, the weight p / pdf (1 when both parts are sampled exactly).

#include "core/phase.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/volume.h"

namespace candela {

class BlendPhase : public PhaseFunction {
public:
    explicit BlendPhase(const Properties& props) {
        Properties::Type type = Properties::Type::Float;
        if (props.has("weight")) props.get_raw("weight", &type);
        if (type == Properties::Type::Object) {
            weight_volume_ = get_volume(props, "weight", Spectrum(0.5f));
            if (weight_volume_->is_constant())
                weight_ = weight_at(Vec3(0.0f));
            else
                constant_ = false;
        } else {
            weight_ = props.get_float("weight", 0.5f);
            if (!(weight_ >= 0.0f && weight_ <= 1.0f)) props.fail("weight", "blendphase: the weight must lie in [0, 1]");
        }
        auto phases = props.get_objects(ObjectKind::Phase);
        if (phases.size() != 2) props.fail("blendphase needs exactly two nested phase functions");
        first_ = std::static_pointer_cast<PhaseFunction>(phases[0]);
        second_ = std::static_pointer_cast<PhaseFunction>(phases[1]);
        if (first_->is_microflake() || second_->is_microflake())
            props.fail("blendphase: a microflake phase function (" + (first_->is_microflake() ? first_ : second_)->to_string() +
                       ") sets the medium's extinction by its projected area, which a blend does not have");
    }

    float eval(const MediumInteraction& mi, const Vec3& wo) const override {
        float w = weight(mi);
        return (1.0f - w) * first_->eval(mi, wo) + w * second_->eval(mi, wo);
    }
    float pdf(const MediumInteraction& mi, const Vec3& wo) const override {
        float w = weight(mi);
        return (1.0f - w) * first_->pdf(mi, wo) + w * second_->pdf(mi, wo);
    }
    PhaseSample sample(const MediumInteraction& mi, const Vec2& u) const override {
        float w = weight(mi);
        // u.x picks the part, then is stretched back to [0, 1) for it.
        bool second = u.x >= 1.0f - w;
        float ux = second ? (u.x - (1.0f - w)) / w : u.x / (1.0f - w);
        // 0x1.fffffep-1 is the largest float below one: rounding must not push ux to 1.
        PhaseSample ps = (second ? second_ : first_)->sample(mi, Vec2(std::min(ux, 0x1.fffffep-1f), u.y));
        if (!ps.valid()) return ps;
        float f0 = first_->eval(mi, ps.wo), f1 = second_->eval(mi, ps.wo);
        ps.pdf = (1.0f - w) * first_->pdf(mi, ps.wo) + w * second_->pdf(mi, ps.wo);
        ps.weight = ps.pdf > 0.0f ? ((1.0f - w) * f0 + w * f1) / ps.pdf : 0.0f;
        return ps;
    }
    // A weight volume that varies gives no single mean cosine: its weight 0.5 stands in.
    float mean_cosine() const override { return (1.0f - weight_) * first_->mean_cosine() + weight_ * second_->mean_cosine(); }
    bool varies_in_space() const override { return !constant_ || first_->varies_in_space() || second_->varies_in_space(); }
    std::string to_string() const override { return "blendphase"; }

private:
    float weight(const MediumInteraction& mi) const { return constant_ ? weight_ : weight_at(mi.p); }
    float weight_at(const Vec3& p) const { return std::clamp(average(weight_volume_->eval(p)), 0.0f, 1.0f); }

    float weight_ = 0.5f;
    bool constant_ = true;
    Ref<Volume> weight_volume_;  // a weight given as a volume
    Ref<PhaseFunction> first_, second_;
};

CANDELA_REGISTER_SPECTRAL(BlendPhase, ObjectKind::Phase, "blendphase");

}  // namespace candela
