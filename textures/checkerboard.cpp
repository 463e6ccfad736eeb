// checkerboard: two colours in a checker pattern of period 1 in uv.
//
// Parameters:
//   color0, color1   rgb or texture   the two colours (defaults 0.4 and 0.2)
//   to_uv            transform        uv transform (e.g. <scale x="8" y="8"/> for 8x8 periods),
//                                     applied after the mapping
//   mapping, mapping_to_world         how surface points find their uv (core/texture.h): uv
//                                     (default), planar, cylindrical or spherical
// color0 where frac(u) > 0.5 and frac(v) > 0.5 agree, color1 elsewhere. Scalar lookups (a
// roughness texture) use the opposite parity, as Mitsuba 3 does for backward compatibility.

#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"

namespace candela {

class CheckerboardTexture final : public Texture {
public:
    explicit CheckerboardTexture(const Properties& props) : Texture(props) {
        color0_ = props.get_texture("color0", Spectrum(0.4f));
        color1_ = props.get_texture("color1", Spectrum(0.2f));
        to_uv_ = UVTransform(props.get_transform("to_uv"));
    }

    Spectrum eval(const Vec2& uv_in) const override { return first_color(uv_in) ? color0_->eval(uv_in) : color1_->eval(uv_in); }
    float eval_1(const Vec2& uv_in) const override { return first_color(uv_in) ? color1_->eval_1(uv_in) : color0_->eval_1(uv_in); }
    // At a surface point the nested textures see the whole point (their own mappings apply; a mesh_attribute needs the whole point).
    Spectrum eval_rgb(const SurfaceInteraction& si) const override {
        return first_color(texture_uv(si)) ? color0_->eval_rgb(si) : color1_->eval_rgb(si);
    }
    Spectrum eval_spectrum(const SurfaceInteraction& si, const Wavelengths& w, SpectrumRole role) const override {
        return first_color(texture_uv(si)) ? color0_->eval_spectrum(si, w, role) : color1_->eval_spectrum(si, w, role);
    }
    float eval_1(const SurfaceInteraction& si) const override {
        return first_color(texture_uv(si)) ? color1_->eval_1(si) : color0_->eval_1(si);
    }
    Spectrum mean() const override { return 0.5f * (color0_->mean() + color1_->mean()); }
    float max_value() const override { return std::max(color0_->max_value(), color1_->max_value()); }
    std::string to_string() const override { return "checkerboard"; }

private:
    bool first_color(const Vec2& uv_in) const {
        Vec2 uv = to_uv_.apply(uv_in);
        bool mx = uv.x - std::floor(uv.x) > 0.5f, my = uv.y - std::floor(uv.y) > 0.5f;
        return mx == my;
    }
    Ref<Texture> color0_, color1_;
    UVTransform to_uv_;
};

CANDELA_REGISTER_SPECTRAL(CheckerboardTexture, ObjectKind::Texture, "checkerboard");

}  // namespace candela
