#include "materials/perturbed_frame.h"

namespace candela {

PerturbedFrameBSDF::PerturbedFrameBSDF(const Properties& props) {
    auto nested = props.get_objects(ObjectKind::BSDF);
    if (nested.size() != 1) props.fail(props.plugin_type() + " needs exactly one nested BSDF");
    nested_ = std::static_pointer_cast<BSDF>(nested[0]);
    flags_ = nested_->flags();
}

SurfaceInteraction PerturbedFrameBSDF::perturbed(const SurfaceInteraction& si) const {
    SurfaceInteraction p = si;
    p.shading = perturbed_frame(si);
    p.wi = p.shading.to_local(si.wi_world());
    return p;
}

BSDFSample PerturbedFrameBSDF::sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const {
    SurfaceInteraction p = perturbed(si);
    BSDFSample bs = nested_->sample(ctx, p, u_lobe, u);
    if (!bs.valid()) return bs;
    Vec3 wo_local = bs.wo;
    bs.wo = si.to_local(p.to_world(wo_local));
    if (Frame::cos_theta(bs.wo) * Frame::cos_theta(wo_local) <= 0.0f) return BSDFSample();
    return bs;
}

Spectrum PerturbedFrameBSDF::eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const {
    SurfaceInteraction p = perturbed(si);
    Vec3 wo_p = p.to_local(si.to_world(wo));
    if (Frame::cos_theta(wo) * Frame::cos_theta(wo_p) <= 0.0f) return Spectrum(0.0f);
    return nested_->eval(ctx, p, wo_p);
}

float PerturbedFrameBSDF::pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const {
    SurfaceInteraction p = perturbed(si);
    Vec3 wo_p = p.to_local(si.to_world(wo));
    if (Frame::cos_theta(wo) * Frame::cos_theta(wo_p) <= 0.0f) return 0.0f;
    return nested_->pdf(ctx, p, wo_p);
}

}  // namespace candela
