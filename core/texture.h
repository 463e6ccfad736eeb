#pragma once
// Textures: spatially varying colours looked up by surface uv. Every rgb parameter of a BSDF can
// be a texture; a plain rgb value becomes a ConstantTexture.

#include "core/object.h"
#include "core/spectrum.h"

namespace candela {

class Texture : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Texture; }
    // The colour at uv, unfiltered beyond the texture's own reconstruction (bilinear or nearest).
    virtual Spectrum eval(const Vec2& uv) const = 0;
    // A scalar view (roughness, heights): the mean of the channels.
    float eval_1(const Vec2& uv) const { return average(eval(uv)); }
    // The average over the whole texture (for albedo and power estimates).
    virtual Spectrum mean() const = 0;
    virtual bool is_constant() const { return false; }
    // The largest value any channel reaches (for energy bounds).
    virtual float max_value() const = 0;
};

class ConstantTexture final : public Texture {
public:
    explicit ConstantTexture(const Spectrum& value) : value_(value) {}
    Spectrum eval(const Vec2&) const override { return value_; }
    Spectrum mean() const override { return value_; }
    bool is_constant() const override { return true; }
    float max_value() const override { return max_component(value_); }
    const Spectrum& value() const { return value_; }

private:
    Spectrum value_;
};

}  // namespace candela
