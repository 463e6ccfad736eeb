#include "materials/perturbed_frame.h"

namespace candela {

PerturbedFrameBSDF::PerturbedFrameBSDF(const Properties& props) {
    auto nested = props.get_objects(ObjectKind::BSDF);
    if (nested.size() != 1) props.fail(props.plugin_type() + " needs exactly one nested BSDF");
    nested_ = std::static_pointer_cast<BSDF>(nested[0]);
    flip_invalid_normals_ = props.get_bool("flip_invalid_normals", true);
    use_shadowing_function_ = props.get_bool("use_shadowing_function", true);
    flags_ = nested_->flags();
    reads_lobe_sample_ = nested_->reads_lobe_sample();  // sample() hands u_lobe on unchanged
}

PerturbedFrameBSDF::Perturbed PerturbedFrameBSDF::perturb(const SurfaceInteraction& si) const {
    Vec3 n = perturbation(si);
    if (flip_invalid_normals_ && Frame::cos_theta(si.wi) * glm::dot(si.wi, n) <= 0.0f) n = Vec3(-n.x, -n.y, n.z);
    const float len2 = glm::dot(n, n);
    n = len2 > 0.0f && std::isfinite(len2) ? n / std::sqrt(len2) : Vec3(0.0f, 0.0f, 1.0f);
    // The original s axis (1, 0, 0) made orthogonal to n; (0, 1, 0) when n lies along it.
    Vec3 s = Vec3(1.0f, 0.0f, 0.0f) - n * n.x;
    const float s_len2 = glm::dot(s, s);
    s = s_len2 > 0.0f && std::isfinite(1.0f / s_len2) ? s / std::sqrt(s_len2) : Vec3(0.0f, 1.0f, 0.0f);
    Perturbed p;
    p.local = Frame(s, glm::cross(n, s), n);
    p.si = si;
    p.si.shading = Frame(si.shading.to_world(p.local.s), si.shading.to_world(p.local.t), si.shading.to_world(p.local.n));
    p.si.wi = p.local.to_local(si.wi);
    return p;
}

float PerturbedFrameBSDF::shadowing(const Vec3& n, const Vec3& wo) const {
    if (!use_shadowing_function_) return 1.0f;
    auto tan2_theta = [](const Vec3& v) { return std::max(0.0f, 1.0f - v.z * v.z) / (v.z * v.z); };
    const float alpha2 = std::min(0.125f * tan2_theta(n), 1.0f);
    const float G = 2.0f / (1.0f + std::sqrt(1.0f + alpha2 * tan2_theta(wo)));
    return std::isfinite(G) ? G : 0.0f;  // wo in the tangent plane: tan^2 infinite, G = 0
}

BSDFSample PerturbedFrameBSDF::sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const {
    const Perturbed p = perturb(si);
    BSDFSample bs = nested_->sample(ctx, p.si, u_lobe, u);
    if (!bs.valid()) return bs;
    const Vec3 wo_p = bs.wo;
    bs.wo = p.local.to_world(wo_p);
    if (Frame::cos_theta(bs.wo) * Frame::cos_theta(wo_p) <= 0.0f) return BSDFSample();
    bs.weight *= shadowing(p.local.n, bs.wo);
    return bs;
}

Spectrum PerturbedFrameBSDF::eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const {
    const Perturbed p = perturb(si);
    const Vec3 wo_p = p.local.to_local(wo);
    if (Frame::cos_theta(wo) * Frame::cos_theta(wo_p) <= 0.0f) return Spectrum(0.0f);
    return nested_->eval(ctx, p.si, wo_p) * shadowing(p.local.n, wo);
}

bool PerturbedFrameBSDF::eval_mueller(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe,
                                      MuellerSpectrum& M) const {
    const Perturbed p = perturb(si);
    const Vec3 wo_p = p.local.to_local(wo);
    if (!nested_->eval_mueller(ctx, p.si, wo_p, lobe, M)) return false;
    local_to_parent(p.local, p.si.wi, wo_p).apply(M);
    return true;
}

float PerturbedFrameBSDF::pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const {
    const Perturbed p = perturb(si);
    const Vec3 wo_p = p.local.to_local(wo);
    if (Frame::cos_theta(wo) * Frame::cos_theta(wo_p) <= 0.0f) return 0.0f;
    return nested_->pdf(ctx, p.si, wo_p);
}

BSDFEvalPdf PerturbedFrameBSDF::eval_pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const {
    const Perturbed p = perturb(si);
    const Vec3 wo_p = p.local.to_local(wo);
    if (Frame::cos_theta(wo) * Frame::cos_theta(wo_p) <= 0.0f) return BSDFEvalPdf{};
    BSDFEvalPdf e = nested_->eval_pdf(ctx, p.si, wo_p);
    e.value *= shadowing(p.local.n, wo);
    return e;
}

}  // namespace candela
