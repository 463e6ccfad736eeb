#include "materials/local_mix.h"

namespace candela {

namespace {
class MixTexture final : public Texture {
public:
    MixTexture(Ref<Texture> a, Ref<Texture> b, Ref<Texture> weight) : a_(std::move(a)), b_(std::move(b)), weight_(std::move(weight)) {}
    Spectrum eval(const Vec2& uv) const override { return mix(value(a_, uv), value(b_, uv), std::clamp(weight_->eval_1(uv), 0.0f, 1.0f)); }
    Spectrum eval_filtered(const Vec2& uv, const Vec2& dx, const Vec2& dy, TextureFilter filter) const override {
        Spectrum va = a_ ? a_->eval_filtered(uv, dx, dy, filter) : Spectrum(0.0f),
                 vb = b_ ? b_->eval_filtered(uv, dx, dy, filter) : Spectrum(0.0f);
        return mix(va, vb, std::clamp(luminance(weight_->eval_filtered(uv, dx, dy, filter)), 0.0f, 1.0f));
    }
    // Exact for a constant weight; otherwise the product of means (the textures are independent
    // enough for albedo and power estimates).
    Spectrum mean() const override {
        Spectrum ma = a_ ? a_->mean() : Spectrum(0.0f), mb = b_ ? b_->mean() : Spectrum(0.0f);
        return mix(ma, mb, std::clamp(luminance(weight_->mean()), 0.0f, 1.0f));
    }
    float max_value() const override { return std::max(a_ ? a_->max_value() : 0.0f, b_ ? b_->max_value() : 0.0f); }
    std::string to_string() const override { return "mix"; }

private:
    static Spectrum value(const Ref<Texture>& t, const Vec2& uv) { return t ? t->eval(uv) : Spectrum(0.0f); }
    static Spectrum mix(const Spectrum& a, const Spectrum& b, float w) { return (1.0f - w) * a + w * b; }
    Ref<Texture> a_, b_, weight_;
};
}  // namespace

Ref<Texture> mix_textures(const Ref<Texture>& a, const Ref<Texture>& b, const Ref<Texture>& weight) {
    if (!a && !b) return nullptr;
    return std::make_shared<MixTexture>(a, b, weight);
}

Ref<Texture> scaled_texture(const Ref<Texture>& t, float factor) {
    if (!t || factor == 1.0f) return t;
    return mix_textures(nullptr, t, std::make_shared<ConstantTexture>(Spectrum(factor)));
}

LocalShading mix_local_shading(const LocalShading& a, const LocalShading& b, const Ref<Texture>& weight) {
    float w = std::clamp(luminance(weight->mean()), 0.0f, 1.0f);
    auto lerp3 = [w](const Spectrum& x, const Spectrum& y) { return (1.0f - w) * x + w * y; };
    LocalShading s;
    s.diffuse = mix_textures(a.diffuse, b.diffuse, weight);
    s.specular = lerp3(a.specular, b.specular);
    s.mirror = lerp3(a.mirror, b.mirror);
    s.transmission = lerp3(a.transmission, b.transmission);
    s.roughness = lerp(w, a.roughness, b.roughness);
    bool b_glossier = w * luminance(b.specular) > (1.0f - w) * luminance(a.specular);
    s.shininess = b_glossier ? b.shininess : a.shininess;
    bool b_refracts = w * luminance(b.transmission) > (1.0f - w) * luminance(a.transmission);
    s.eta = b_refracts ? b.eta : a.eta;
    s.two_sided = a.two_sided || b.two_sided;
    const LocalShading& bumped = (b.height && (w >= 0.5f || !a.height)) ? b : a;
    s.height = bumped.height;
    s.height_scale = bumped.height_scale;
    return s;
}

}  // namespace candela
