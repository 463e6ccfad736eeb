#pragma once
// Textures: spatially varying colours looked up at a surface point, most by its uv. Every rgb
// parameter of a BSDF can be a texture; a plain rgb value becomes a ConstantTexture.

#include "core/object.h"
#include "core/ray.h"
#include "core/spectrum.h"
#include "core/transform.h"
#include "core/wavelengths.h"

namespace candela {

// How the rasterizer reconstructs a texture over a pixel's footprint: the nearest texel or
// bilinear at full resolution, or trilinear in the MIP pyramid.
enum class TextureFilter { Nearest, Bilinear, Trilinear };

class Properties;

// How a surface point finds its texture coordinates (the lecture's UV mapping, "uv coordinate
// <-> object coordinate"). `uv` takes the shape's own parameterisation. The others project the
// point p, carried into the mapping's frame by the inverse of `mapping_to_world` (q below):
//   planar       (s, t) = (q.x, q.y): orthogonal projection along the frame's z axis
//   cylindrical  s = phi / 2pi with phi = atan2(q.y, q.x) in [0, 2pi), t = q.z: the height
//                fraction on the cylinder whose axis runs along z from z = 0 (t = 0) to 1 (t = 1)
//   spherical    s = phi / 2pi, t = theta / pi with theta the angle of q from the +z pole
// With mapping_to_world equal to a shape's own placement these reproduce the parameterisations
// of Mitsuba's sphere (spherical) and cylinder (cylindrical, scaled to its radius and length),
// and of the rectangle when the frame's unit square [0, 1]^2 is put on the rectangle (planar).
struct TextureMapping {
    enum class Kind { UV, Planar, Cylindrical, Spherical };
    Kind kind = Kind::UV;
    Transform world_to_mapping;

    TextureMapping() = default;
    // Reads `mapping` (uv, planar, cylindrical or spherical; default uv) and `mapping_to_world`.
    explicit TextureMapping(const Properties& props);
    // Texture coordinates of the surface point p whose own uv is `uv`.
    Vec2 map(const Vec2& uv, const Vec3& p) const;
    // b - a in texture coordinates, the shorter way round where s wraps (cylindrical and
    // spherical), so that a footprint across the seam stays small.
    Vec2 difference(const Vec2& a, const Vec2& b) const;
};

class Texture : public Object {
public:
    Texture() = default;
    // Reads the parameters every texture plugin shares: `mapping` and `mapping_to_world`.
    explicit Texture(const Properties& props) : mapping_(props) {}
    ObjectKind kind() const override { return ObjectKind::Texture; }
    // The colour at texture coordinates uv, unfiltered beyond the texture's own reconstruction
    // (bilinear or nearest).
    virtual Spectrum eval(const Vec2& uv) const = 0;
    // The value at a surface point as a reflectance: what BSDFs ask. In the RGB variant the
    // colour; in the spectral variant (si.wavelengths set) its values at the path's wavelengths.
    Spectrum eval(const SurfaceInteraction& si) const { return eval_as(si, SpectrumRole::Reflectance); }
    // The same for a value of another role (an emission, an index of refraction: see
    // rgb_at_wavelengths in core/wavelengths.h).
    Spectrum eval_as(const SurfaceInteraction& si, SpectrumRole role) const {
        return si.wavelengths ? eval_spectrum(si, *si.wavelengths, role) : eval_rgb(si);
    }
    // The colour at a surface point. By default the lookup at the point's texture coordinates
    // (texture_uv); textures that read more of the hit (mesh_attribute: the shape's per-vertex
    // data) override this and eval_1.
    virtual Spectrum eval_rgb(const SurfaceInteraction& si) const { return eval(texture_uv(si)); }
    virtual float eval_1(const SurfaceInteraction& si) const { return eval_1(texture_uv(si)); }
    // The value at the wavelengths: by default the colour's spectrum for `role`; a measured
    // spectrum (SpectrumTexture) gives its own values.
    virtual Spectrum eval_spectrum(const SurfaceInteraction& si, const Wavelengths& w, SpectrumRole role) const {
        return rgb_at_wavelengths(eval_rgb(si), role, &w);
    }
    // The value at a sampled surface point (an emitter's position sample: no ray hit), looked up
    // as at a hit there, so that the mapping applies as it does when a path finds the point; at
    // `wavelengths` when they are given.
    Spectrum eval_at(const Vec3& p, const Vec3& n, const Vec2& uv, SpectrumRole role = SpectrumRole::Reflectance,
                     const Wavelengths* wavelengths = nullptr) const;
    // d eval_1 / d(u, v) at a surface point, with (u, v) the surface's own parameters: the
    // texture's gradient under the uv mapping; under another mapping central differences along
    // dp/du and dp/dv (bump mapping).
    Vec2 eval_1_gradient(const SurfaceInteraction& si) const;
    // Where `mapping` puts a surface point in the texture.
    Vec2 texture_uv(const SurfaceInteraction& si) const { return mapping_.map(si.uv, si.p); }
    const TextureMapping& mapping() const { return mapping_; }
    // A lookup over the footprint given by the screen-space derivatives of uv (the rasterizer's
    // texture filtering): nearest or bilinear reconstruction at full resolution, or trilinear
    // filtering in the MIP pyramid. Textures without a pyramid ignore the footprint.
    virtual Spectrum eval_filtered(const Vec2& uv, const Vec2& duv_dx, const Vec2& duv_dy, TextureFilter filter) const { return eval(uv); }

    // A scalar view (roughness, heights): the luminance, as in Mitsuba 3.
    virtual float eval_1(const Vec2& uv) const { return luminance(eval(uv)); }
    // d eval_1 / d(u, v), for bump mapping. By default central differences; textures with an
    // analytic derivative override it.
    virtual Vec2 eval_1_gradient(const Vec2& uv) const {
        const float h = 1e-4f;
        return Vec2(eval_1(uv + Vec2(h, 0.0f)) - eval_1(uv - Vec2(h, 0.0f)), eval_1(uv + Vec2(0.0f, h)) - eval_1(uv - Vec2(0.0f, h))) /
               (2.0f * h);
    }
    // The average over the whole texture (for albedo and power estimates).
    virtual Spectrum mean() const = 0;
    virtual bool is_constant() const { return false; }
    // The size in texels, 1 x 1 for textures without a grid (Mitsuba's Texture::resolution; the
    // projector light takes its aspect ratio from it).
    virtual Vec2i resolution() const { return Vec2i(1); }
    // The largest value any channel reaches (for energy bounds).
    virtual float max_value() const = 0;

protected:
    TextureMapping mapping_;
};

// A 2D affine map of texture coordinates (Mitsuba's `to_uv`): a 4x4 transform from the scene
// file with its third row and column dropped, applied to (u, v, 1).
struct UVTransform {
    float m[2][3] = {{1, 0, 0}, {0, 1, 0}};
    UVTransform() = default;
    explicit UVTransform(const Transform& t) {
        const Mat4& a = t.matrix();  // column-major: a[col][row]
        m[0][0] = a[0][0], m[0][1] = a[1][0], m[0][2] = a[3][0];
        m[1][0] = a[0][1], m[1][1] = a[1][1], m[1][2] = a[3][1];
    }
    Vec2 apply(const Vec2& uv) const { return Vec2(m[0][0] * uv.x + m[0][1] * uv.y + m[0][2], m[1][0] * uv.x + m[1][1] * uv.y + m[1][2]); }
};

class ConstantTexture : public Texture {
public:
    explicit ConstantTexture(const Spectrum& value) : value_(value) { parameters_changed({}); }
    Spectrum eval(const Vec2&) const override { return value_; }
    // The same value everywhere: no texture coordinates to find (the mapping is never asked;
    // BSDFs and emitters look their constants up once or more per path vertex).
    Spectrum eval_rgb(const SurfaceInteraction&) const override { return value_; }
    // The spectra of the value, made once (not per lookup).
    Spectrum eval_spectrum(const SurfaceInteraction&, const Wavelengths& w, SpectrumRole role) const override {
        return spectra_[int(role)].at(w);
    }
    float eval_1(const SurfaceInteraction&) const override { return eval_1(Vec2(0.0f)); }
    // A grey value (a float parameter) is returned exactly, not through the luminance weights.
    float eval_1(const Vec2&) const override { return value_.x == value_.y && value_.y == value_.z ? value_.x : luminance(value_); }
    Spectrum mean() const override { return value_; }
    bool is_constant() const override { return true; }
    float max_value() const override { return max_component(value_); }
    const Spectrum& value() const { return value_; }
    // Mitsuba's srgb texture: "value".
    void traverse(ParameterVisitor& visitor) override;
    void parameters_changed(const std::vector<std::string>&) override;

private:
    Spectrum value_;
    RGBSpectrum spectra_[3];  // value_'s spectrum for each SpectrumRole
};

// A constant emission (an emitter's intensity, irradiance or radiance) at the wavelengths `w`: its
// measured spectrum when the scene gave one (Properties::measured_spectrum), else the colour's
// emission spectrum; in the RGB variant (no wavelengths) the colour itself.
class SpectrumTexture;
Spectrum emission_at(const Spectrum& rgb, const SpectrumTexture* measured, const Wavelengths* w);

// A measured or analytic spectrum (a <spectrum> of wavelength:value pairs or a file, Planck's
// law, an equal-energy emission): in the spectral variant its own values at the path's
// wavelengths, whatever the role; elsewhere the colour it was converted to for its role.
class SpectrumTexture final : public ConstantTexture {
public:
    SpectrumTexture(const Spectrum& rgb, SampledSpectrum spectrum) : ConstantTexture(rgb), spectrum_(std::move(spectrum)) {}
    Spectrum eval_spectrum(const SurfaceInteraction& si, const Wavelengths& w, SpectrumRole role) const override;
    const SampledSpectrum& spectrum() const { return spectrum_; }
    // An edited value ("value", traverse) is a colour: it replaces the measured spectrum.
    void parameters_changed(const std::vector<std::string>& keys) override;

private:
    SampledSpectrum spectrum_;
};

}  // namespace candela
