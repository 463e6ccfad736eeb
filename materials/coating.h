#pragma once
// What the plastics (plastic, roughplastic, pplastic) share: a dielectric coating's specular lobe
// over a diffuse base, and how sample() chooses between the two (Mitsuba 3's
// specular_sampling_weight).

#include "core/bsdf.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/texture.h"
#include "core/warp.h"
#include "materials/fresnel.h"
#include "materials/microfacet.h"

namespace candela {

// What the plastics keep alike: the base's and the coating's reflectances (Mitsuba's
// diffuse_reflectance and specular_reflectance, editable by those names) and the specular lobe's
// share of the samples derived from them (specular_sampling_weight below).
class CoatedBSDF : public BSDF {
public:
    void traverse(ParameterVisitor& visitor) override {
        visitor.object("diffuse_reflectance", diffuse_.get());
        visitor.object("specular_reflectance", specular_.get());
    }
    void parameters_changed(const std::vector<std::string>&) override;

protected:
    // Reads diffuse_reflectance (default 0.5) and specular_reflectance (default 1).
    explicit CoatedBSDF(const Properties& props);

    Ref<Texture> diffuse_, specular_;
    float specular_weight_ = 0.5f;
};

// The specular lobe's share of the samples before the coating's reflectance is known: the mean
// specular reflectance over the sum of the mean specular and diffuse reflectances, and 1/2 when
// both are black (nothing to choose between; any finite choice will do).
inline float specular_sampling_weight(const Texture& specular, const Texture& diffuse) {
    const float s = average(specular.mean()), d = average(diffuse.mean());
    return s + d > 0.0f ? s / (s + d) : 0.5f;
}

// The probability that sample() takes the specular lobe (`specular_lobe`) rather than the diffuse
// one (`diffuse_lobe`), when the coating reflects the fraction `reflected` of what arrives (its
// Fresnel reflectance, or 1 - the rough coating's transmittance): proportional to
// reflected * weight against (1 - reflected) (1 - weight). 0 or 1 when `ctx` allows only one of
// the lobes, and finite whatever the inputs.
inline float specular_lobe_probability(const BSDFContext& ctx, uint32_t specular_lobe, uint32_t diffuse_lobe, float weight,
                                       float reflected) {
    if (!ctx.allows(specular_lobe)) return 0.0f;
    if (!ctx.allows(diffuse_lobe)) return 1.0f;
    const float ps = reflected * weight, pd = (1.0f - reflected) * (1.0f - weight);
    return ps + pd > 0.0f ? ps / (ps + pd) : weight;
}
// The same when the choice does not depend on the incidence (pplastic): the weight itself.
inline float specular_lobe_probability(const BSDFContext& ctx, uint32_t specular_lobe, uint32_t diffuse_lobe, float weight) {
    if (!ctx.allows(specular_lobe)) return 0.0f;
    if (!ctx.allows(diffuse_lobe)) return 1.0f;
    return weight;
}

// The base's albedo as seen through the coating, with the light the coating reflects back inside
// (its hemispherical internal reflectance R) summed in closed form: rho / (1 - R), or with
// `nonlinear` rho / (1 - rho R), which also shifts the colour of a saturated base (Mitsuba's
// plastic and roughplastic).
inline Spectrum coated_base_albedo(const Spectrum& rho, float internal_reflectance, bool nonlinear) {
    return nonlinear ? rho / (Spectrum(1.0f) - rho * internal_reflectance) : rho / (1.0f - internal_reflectance);
}

// The direction of a rough plastic's sample (roughplastic, pplastic): the coating's microfacet
// reflection when u_lobe < p_specular, else the base's cosine-weighted lobe; bs.wo and bs.lobe
// say which. False when the direction leaves below the surface or `ctx` refuses the lobe; the
// caller then weights the sample by its pdf (BSDF::weighted_by_pdf).
inline bool sample_rough_coating(const MicrofacetDistribution& distribution, const BSDFContext& ctx, const Vec3& wi, float p_specular,
                                 float u_lobe, const Vec2& u, BSDFSample& bs) {
    if (u_lobe < p_specular) {
        float pdf_m;
        const Vec3 m = distribution.sample(wi, u, pdf_m);
        bs.wo = reflect(wi, m);
        bs.lobe = GlossyReflection;
    } else {
        if (!ctx.allows(DiffuseReflection)) return false;
        bs.wo = warp::square_to_cosine_hemisphere(u);
        bs.lobe = DiffuseReflection;
    }
    return bs.wo.z > 0.0f;
}

inline CoatedBSDF::CoatedBSDF(const Properties& props) {
    diffuse_ = props.get_reflectance("diffuse_reflectance", Spectrum(0.5f));
    specular_ = props.get_reflectance("specular_reflectance", Spectrum(1.0f));
    specular_weight_ = specular_sampling_weight(*specular_, *diffuse_);
}

inline void CoatedBSDF::parameters_changed(const std::vector<std::string>&) {
    specular_weight_ = specular_sampling_weight(*specular_, *diffuse_);
}

}  // namespace candela
