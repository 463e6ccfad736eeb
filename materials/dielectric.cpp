// dielectric: a smooth interface between two dielectrics (glass, water): Fresnel-weighted mirror
// reflection and Snell refraction. Two-sided by nature; the side of wi says which medium the
// path is in.
//
// Parameters (Mitsuba 3):
//   int_ior                  float, name     interior index (default bk7 = 1.5046); a named glass
//                            or spectrum     (glass-BK7, glass-BAF10, glass-F2, glass-SF11,
//                                            glass-fused-silica: Sellmeier, materials/ior.h) or,
//                                            in the spectral variant, a <spectrum> of indices
//   ext_ior                  float, name     exterior index (default air = 1.000277), likewise
//                            or spectrum
//   specular_reflectance     rgb or texture  factor on reflection (default 1)
//   specular_transmittance   rgb or texture  factor on transmission (default 1)
//
// Reflection is sampled with probability F and refraction with 1 - F. In radiance mode the
// refracted radiance is scaled by (n_incident / n_transmitted)^2 (the eta^2 law); not for
// importance transport.
// Dispersion (not in Mitsuba 3): in the spectral variant an index that varies with wavelength is
// taken at the path's first (hero) wavelength, and the other wavelengths end there (their
// directions would differ); the RGB variant uses the indices at 589.3 nm.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/registry.h"
#include "core/texture.h"
#include "materials/fresnel.h"
#include "materials/ior.h"

namespace candela {

class DielectricBSDF final : public BSDF {
public:
    explicit DielectricBSDF(const Properties& props) {
        int_ior_ = read_spectral_ior(props, "int_ior", "bk7");
        ext_ior_ = read_spectral_ior(props, "ext_ior", "air");
        eta_ = int_ior_.value / ext_ior_.value;
        dispersive_ = int_ior_.dispersive() || ext_ior_.dispersive();
        reflectance_ = props.get_reflectance("specular_reflectance", Spectrum(1.0f));
        transmittance_ = props.get_reflectance("specular_transmittance", Spectrum(1.0f));
        flags_ = DeltaReflection | DeltaTransmission;
    }

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2&) const override {
        BSDFSample bs;
        float cos_i = Frame::cos_theta(si.wi);
        float eta = eta_;
        if (dispersive_ && si.wavelengths) {
            const float hero = si.wavelengths->lambda[0];
            eta = int_ior_.at(hero) / ext_ior_.at(hero);
            bs.dispersed = true;
        }
        DielectricFresnel fr = fresnel_dielectric(cos_i, eta);
        FresnelChoice c = choose_fresnel_lobe(ctx.allows(DeltaReflection), ctx.allows(DeltaTransmission), fr.F, u_lobe);
        if (!(c.pdf > 0.0f)) return bs;
        bs.pdf = c.pdf;
        if (c.reflect) {
            bs.wo = reflect(si.wi);
            bs.lobe = DeltaReflection;
            bs.weight = reflectance_->eval(si) * c.weight_factor;
        } else {
            bs.wo = refract(si.wi, fr.cos_theta_t, fr.eta_ti);
            bs.lobe = DeltaTransmission;
            bs.eta = fr.eta_it;
            float scale = ctx.mode == TransportMode::Radiance ? fr.eta_ti * fr.eta_ti : 1.0f;
            bs.weight = transmittance_->eval(si) * (scale * c.weight_factor);
        }
        return bs;
    }

    Spectrum eval(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return Spectrum(0.0f); }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3&) const override { return 0.0f; }
    // Polarized: Fresnel's reflection or refraction matrix of the sampled lobe (Mitsuba's), at
    // each wavelength's index.
    bool eval_mueller(const BSDFContext&, const SurfaceInteraction& si, const Vec3& wo, uint32_t lobe, MuellerSpectrum& M) const override {
        Spectrum eta(eta_);
        if (dispersive_ && si.wavelengths)
            for (int k = 0; k < 3; ++k) eta[k] = int_ior_.at(si.wavelengths->lambda[k]) / ext_ior_.at(si.wavelengths->lambda[k]);
        if (lobe == DeltaReflection)
            fresnel_reflection_mueller(Vec3(0, 0, 1), si.wi, wo, eta, Spectrum(0.0f), M);
        else if (lobe == DeltaTransmission)
            fresnel_transmission_mueller(Vec3(0, 0, 1), si.wi, wo, eta, M);
        else
            return false;
        return true;
    }
    Spectrum albedo(const SurfaceInteraction& si) const override {
        float F = fresnel_dielectric(Frame::cos_theta(si.wi), eta_).F;
        return reflectance_->eval(si) * F + transmittance_->eval(si) * (1.0f - F);
    }
    // Local model: environment reflection with weight F0 = ((eta - 1) / (eta + 1))^2 and
    // environment refraction (Snell, relative IOR eta) with weight 1 - F0.
    LocalShading local_shading() const override {
        LocalShading s;
        float F0 = fresnel_dielectric(1.0f, eta_).F;
        s.mirror = reflectance_->mean() * F0;
        s.transmission = transmittance_->mean() * (1.0f - F0);
        s.eta = eta_;
        s.two_sided = true;
        return s;
    }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        visitor.object("specular_reflectance", reflectance_.get());
        visitor.object("specular_transmittance", transmittance_.get());
    }
    std::string to_string() const override { return "dielectric"; }

private:
    float eta_;  // int_ior / ext_ior at 589.3 nm
    SpectralIOR int_ior_, ext_ior_;
    bool dispersive_ = false;
    Ref<Texture> reflectance_, transmittance_;
};

CANDELA_REGISTER_SPECTRAL(DielectricBSDF, ObjectKind::BSDF, "dielectric");

}  // namespace candela
