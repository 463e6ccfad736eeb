#include "core/texture.h"

#include "core/parameters.h"
#include "core/properties.h"

namespace candela {

TextureMapping::TextureMapping(const Properties& props) {
    std::string name = props.get_string("mapping", "uv");
    if (name == "uv")
        kind = Kind::UV;
    else if (name == "planar")
        kind = Kind::Planar;
    else if (name == "cylindrical")
        kind = Kind::Cylindrical;
    else if (name == "spherical")
        kind = Kind::Spherical;
    else
        props.fail("mapping", "mapping must be uv, planar, cylindrical or spherical, not \"" + name + "\"");
    if (props.has("mapping_to_world")) {
        if (kind == Kind::UV) props.fail("mapping_to_world", "mapping_to_world needs a planar, cylindrical or spherical mapping");
        Transform to_world = props.get_transform("mapping_to_world");
        world_to_mapping = to_world.inverse();
        if (!to_world.all_finite() || !world_to_mapping.all_finite() || to_world.determinant3() == 0.0f)
            props.fail("mapping_to_world", "mapping_to_world must be an invertible transform");
    }
}

Vec2 TextureMapping::map(const Vec2& uv, const Vec3& p) const {
    if (kind == Kind::UV) return uv;
    Vec3 q = world_to_mapping.apply_point(p);
    if (kind == Kind::Planar) return Vec2(q.x, q.y);
    float phi = std::atan2(q.y, q.x);
    if (phi < 0.0f) phi += TwoPi;
    if (kind == Kind::Cylindrical) return Vec2(phi * InvTwoPi, q.z);
    float r = glm::length(q);
    return Vec2(phi * InvTwoPi, r > 0.0f ? safe_acos(q.z / r) * InvPi : 0.0f);
}

Vec2 TextureMapping::difference(const Vec2& a, const Vec2& b) const {
    Vec2 d = b - a;
    if (kind == Kind::Cylindrical || kind == Kind::Spherical) d.x -= std::round(d.x);
    return d;
}

Vec2 Texture::eval_1_gradient(const SurfaceInteraction& si) const {
    if (mapping_.kind == TextureMapping::Kind::UV) return eval_1_gradient(si.uv);
    // The height as a function of the surface parameters: h(map(uv + du, p + dp/du du)).
    const float h = 1e-4f;
    auto height = [&](float du, float dv) { return eval_1(mapping_.map(si.uv + Vec2(du, dv), si.p + si.dpdu * du + si.dpdv * dv)); };
    return Vec2(height(h, 0.0f) - height(-h, 0.0f), height(0.0f, h) - height(0.0f, -h)) / (2.0f * h);
}

Spectrum Texture::eval_at(const Vec3& p, const Vec3& n, const Vec2& uv, SpectrumRole role, const Wavelengths* wavelengths) const {
    SurfaceInteraction at;
    at.p = p;
    at.n = n;
    at.shading = Frame(n);
    at.uv = uv;
    return wavelengths ? eval_spectrum(at, *wavelengths, role) : eval_rgb(at);
}

Spectrum emission_at(const Spectrum& rgb, const SpectrumTexture* measured, const Wavelengths* w) {
    if (!w) return rgb;
    if (measured) return measured->eval_spectrum(SurfaceInteraction(), *w, SpectrumRole::Emission);
    return rgb_at_wavelengths(rgb, SpectrumRole::Emission, w);
}

void SpectrumTexture::parameters_changed(const std::vector<std::string>& keys) {
    ConstantTexture::parameters_changed(keys);
    spectrum_ = SampledSpectrum();
}

Spectrum SpectrumTexture::eval_spectrum(const SurfaceInteraction& si, const Wavelengths& w, SpectrumRole role) const {
    if (spectrum_.wavelengths.empty()) return ConstantTexture::eval_spectrum(si, w, role);
    Spectrum out;
    for (int j = 0; j < WavelengthSamples; ++j) out[j] = float(spectrum_.at(w.lambda[j]));
    return out;
}

void ConstantTexture::traverse(ParameterVisitor& visitor) { expose_color(visitor, "value", value_); }

void ConstantTexture::parameters_changed(const std::vector<std::string>&) {
    for (SpectrumRole role : {SpectrumRole::Reflectance, SpectrumRole::Unbounded, SpectrumRole::Emission})
        spectra_[int(role)] = RGBSpectrum(value_, role);
}

}  // namespace candela
