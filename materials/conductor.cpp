// conductor: a smooth metal, a perfect mirror weighted by the conductor Fresnel reflectance.
// One-sided.
//
// Parameters (Mitsuba 3):
//   material               string           a name of Mitsuba 3's conductor table (Au, Ag, Al, Cu,
//                                           Cr, Cu_palik, TiN, ...: see named_conductors() in
//                                           materials/ior.h) or none (default none: a perfect
//                                           mirror, F = 1)
//   eta, k                 rgb or texture   real and imaginary index of refraction (instead of
//                                           material)
//   specular_reflectance   rgb or texture   extra factor (default 1)

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "materials/fresnel.h"
#include "materials/ior.h"

namespace candela {

class ConductorBSDF final : public BSDF {
public:
    explicit ConductorBSDF(const Properties& props) {
        read_conductor_ior(props, eta_, k_);
        specular_ = props.get_reflectance("specular_reflectance", Spectrum(1.0f));
        flags_ = DeltaReflection;
        reads_lobe_sample_ = false;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float, const Vec2&) const override {
        BSDFSample bs;
        float cos_i = Frame::cos_theta(si.wi);
        if (!ctx.allows(DeltaReflection) || cos_i <= 0.0f) return bs;
        bs.wo = reflect(si.wi);
        bs.pdf = 1.0f;
        bs.lobe = DeltaReflection;
        bs.weight = reflectance(si, cos_i);
        return bs;
    }
    Spectrum eval(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return Spectrum(0.0f); }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return 0.0f; }
    // Polarized: the mirror's Fresnel matrix with the complex index eta + i k (Mitsuba's).
    bool eval_mueller(const BSDFContext&, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe, MuellerSpectrum& M) const override {
        if (lobe != DeltaReflection) return false;
        fresnel_reflection_mueller(Vec3(0, 0, 1), si.wi, wo, eta_->eval_as(si, SpectrumRole::Unbounded),
                                   k_->eval_as(si, SpectrumRole::Unbounded), M);
        return true;
    }
    Spectrum albedo(const SurfaceInteraction& si) const override { return reflectance(si, std::max(Frame::cos_theta(si.wi), 0.0f)); }
    // Local model: a mirror reflecting the environment with weight F0, the conductor Fresnel
    // reflectance at normal incidence (times specular_reflectance); no highlight (a perfect
    // mirror reflects a point light only in one direction).
    LocalShading local_shading() const override {
        LocalShading s;
        s.mirror = specular_->mean() * fresnel_conductor(1.0f, eta_->mean(), k_->mean());
        return s;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        visitor.object("eta", eta_.get());
        visitor.object("k", k_.get());
        visitor.object("specular_reflectance", specular_.get());
    }
    std::string to_string() const override { return "conductor"; }

private:
    Spectrum reflectance(const SurfaceInteraction& si, float cos_i) const {
        return specular_->eval(si) *
               fresnel_conductor(cos_i, eta_->eval_as(si, SpectrumRole::Unbounded), k_->eval_as(si, SpectrumRole::Unbounded));
    }
    Ref<Texture> eta_, k_, specular_;
};

CANDELA_REGISTER_SPECTRAL(ConductorBSDF, ObjectKind::BSDF, "conductor");

}  // namespace candela
