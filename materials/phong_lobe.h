#pragma once
// What `phong` and `blinnphong` share: a diffuse term kd / pi plus a glossy lobe, sampled as a
// mixture chosen by the average of kd and ks. The lobes differ only in their shape.

#include "core/bsdf.h"
#include "core/local_model.h"
#include "core/parameters.h"
#include "core/properties.h"
#include "core/texture.h"

namespace candela {

class PhongFamilyBSDF : public BSDF {
public:
    // Reads kd (default 0.5), ks (default 0.2) and exponent (default 30); kd + ks must not exceed
    // one in any channel.
    explicit PhongFamilyBSDF(const Properties& props);

    BSDFSample sample(const BSDFContext& ctx, const SurfaceInteraction& si, float u_lobe, const Vec2& u) const override;
    Spectrum eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override;
    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3& wo) const override;
    Spectrum albedo(const SurfaceInteraction& si) const override { return kd_->eval(si) + ks_->eval(si); }

    // Local model: kd, ks and the exponent carry over directly (the rasterizer draws the lobe of
    // its chosen reflection model, Phong or Blinn-Phong, with the same normalisation).
    LocalShading local_shading() const override {
        LocalShading s;
        s.diffuse = kd_;
        s.specular = ks_->mean();
        s.shininess = exponent_;
        return s;
    }

    const Texture& kd() const { return *kd_; }
    const Texture& ks() const { return *ks_; }
    float exponent() const { return exponent_; }
    // Mitsuba's parameter names (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override {
        visitor.object("kd", kd_.get());
        visitor.object("ks", ks_.get());
    }

protected:
    // The normalised glossy lobe value (without ks and without cos wo) and its sampling.
    virtual float lobe(const Vec3& wi, const Vec3& wo) const = 0;
    virtual Vec3 sample_lobe(const Vec3& wi, const Vec2& u) const = 0;
    virtual float lobe_pdf(const Vec3& wi, const Vec3& wo) const = 0;

    float exponent_ = 30.0f;

private:
    float glossy_probability(const BSDFContext& ctx, const SurfaceInteraction& si) const;
    Ref<Texture> kd_, ks_;
};

}  // namespace candela
