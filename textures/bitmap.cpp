// bitmap: an image texture (PNG, JPEG, EXR, HDR, ... through OpenImageIO).
//
// Parameters:
//   filename      string      the image (relative to the scene file)
//   filter_type   string      bilinear (default) or nearest; the rasterizer may also ask for
//                             trilinear lookups in the MIP pyramid
//   wrap_mode     string      repeat (default), mirror or clamp
//   raw           boolean     keep stored values; by default 8/16-bit images are decoded from
//                             sRGB to linear, float images are used as they are (default false)
//   to_uv         transform   uv transform (default identity), applied after the mapping
//   format        string      storage precision of the texels, as Mitsuba stores them:
//                             variant (default: float32), float16 (or fp16: values rounded to
//                             half precision), uint8 (8 bits per channel; sRGB-encoded sources
//                             keep their encoding and are decoded on lookup), auto (uint8 for
//                             8-bit files, float16 for 16-bit files, variant otherwise)
//   accel         boolean     Mitsuba's hardware texture units in CUDA mode; without a GPU it
//                             changes nothing (default true)
//   max_anisotropy integer    the anisotropic filter's limit (at least 1); only
//                             that filter, which Candela does not have, uses it
//   mapping, mapping_to_world  how surface points find their uv (core/texture.h): uv (default),
//                 planar, cylindrical or spherical, with the mapping's frame
// v = 0 is the top row of the image (no flip), as in Mitsuba 3; texel centres sit at
// half-integers. Alpha is ignored; one- and two-channel (grey, grey + alpha) images are grey.
// Mitsuba's newest filter types trilinear and anisotropic (ray-cone footprints) are not
// supported and are an error.

#include "core/error.h"
#include "core/image.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/texture.h"
#include "textures/mipmap.h"

#include <Imath/half.h>

namespace candela {

namespace {

enum class TexelFormat { Float32, Float16, UInt8 };

TexelFormat parse_format(const Properties& props, int integer_bits) {
    std::string f = props.get_string("format", "variant");
    if (f == "variant") return TexelFormat::Float32;
    if (f == "float16" || f == "fp16") return TexelFormat::Float16;
    if (f == "uint8") return TexelFormat::UInt8;
    if (f == "auto") return integer_bits == 8 ? TexelFormat::UInt8 : integer_bits == 16 ? TexelFormat::Float16 : TexelFormat::Float32;
    props.fail("format", "format must be variant, auto, float16 (fp16) or uint8, not \"" + f + "\"");
}

// A value as the texel format stores it.
float quantize(float v, TexelFormat format) {
    switch (format) {
        case TexelFormat::Float32: return v;
        case TexelFormat::Float16: return float(half(v));
        case TexelFormat::UInt8: return std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
    }
    return v;
}

}  // namespace

class BitmapTexture final : public Texture {
public:
    explicit BitmapTexture(const Properties& props) : Texture(props) {
        std::string path = props.get_file_path("filename");
        std::string filter = props.get_string("filter_type", "bilinear");
        if (filter == "trilinear" || filter == "anisotropic")
            props.fail("filter_type",
                       "filter_type \"" + filter + "\" needs ray-cone footprints, which Candela does not track; use bilinear or nearest");
        if (!parse_texture_filter(filter, filter_) || filter_ == TextureFilter::Trilinear)
            props.fail("filter_type", "filter_type must be bilinear or nearest, not \"" + filter + "\"");
        std::string wrap = props.get_string("wrap_mode", "repeat");
        WrapMode wrap_mode;
        if (!parse_wrap_mode(wrap, wrap_mode)) props.fail("wrap_mode", "wrap_mode must be repeat, mirror or clamp, not \"" + wrap + "\"");
        bool raw = props.get_bool("raw", false);
        to_uv_ = UVTransform(props.get_transform("to_uv"));

        props.get_bool("accel", true);  // CUDA texture units: nothing to switch on a CPU
        if (props.get_int("max_anisotropy", 16) < 1) props.fail("max_anisotropy", "max_anisotropy must be at least 1");

        Image img;
        try {
            img = read_image(path);
        } catch (const InputError& e) {
            props.fail("filename", e.what());
        }
        const int integer_bits = img.integer_bits;
        bool srgb = !raw && integer_bits > 0;
        TexelFormat format = parse_format(props, integer_bits);
        int nch = img.channel_count();
        if (img.width() <= 0 || img.height() <= 0 || nch <= 0) props.fail("filename", "image \"" + path + "\" is empty");
        std::vector<Spectrum> texels(size_t(img.width()) * img.height());
        for (int y = 0; y < img.height(); ++y)
            for (int x = 0; x < img.width(); ++x) {
                Spectrum s = img.colour_at(x, y);
                // 8 bits hold what the file encodes (decoded on lookup); half precision holds the
                // decoded, linear values.
                for (int c = 0; c < 3; ++c) {
                    if (format == TexelFormat::UInt8) s[c] = quantize(s[c], format);
                    if (srgb) s[c] = srgb_to_linear(s[c]);
                    if (format == TexelFormat::Float16) s[c] = quantize(s[c], format);
                }
                for (int c = 0; c < 3; ++c)
                    if (!std::isfinite(s[c])) s[c] = 0.0f;
                texels[size_t(y) * img.width() + x] = s;
            }
        mip_ = MipMap(std::move(texels), img.width(), img.height(), wrap_mode);
    }

    Spectrum eval(const Vec2& uv_in) const override {
        Vec2 uv = to_uv_.apply(uv_in);
        return filter_ == TextureFilter::Nearest ? mip_.nearest(0, uv) : mip_.bilinear(0, uv);
    }
    // The footprint is the longer of the two derivative vectors,
    // mapped through to_uv.
    Spectrum eval_filtered(const Vec2& uv_in, const Vec2& dx, const Vec2& dy, TextureFilter filter) const override {
        Vec2 uv = to_uv_.apply(uv_in);
        switch (filter) {
            case TextureFilter::Nearest: return mip_.nearest(0, uv);
            case TextureFilter::Bilinear: return mip_.bilinear(0, uv);
            case TextureFilter::Trilinear: {
                auto linear = [&](const Vec2& d) {
                    return Vec2(to_uv_.m[0][0] * d.x + to_uv_.m[0][1] * d.y, to_uv_.m[1][0] * d.x + to_uv_.m[1][1] * d.y);
                };
                float footprint = std::max(glm::length(linear(dx)), glm::length(linear(dy)));
                return mip_.trilinear(uv, footprint);
            }
        }
        return eval(uv_in);
    }

    Vec2 eval_1_gradient(const Vec2& uv_in) const override {
        if (filter_ == TextureFilter::Nearest) return Vec2(0.0f);  // piecewise constant
        Spectrum d_du, d_dv;
        mip_.bilinear_gradient(to_uv_.apply(uv_in), d_du, d_dv);
        // Chain rule through to_uv: dh/du = dh/du' du'/du + dh/dv' dv'/du.
        float gu = luminance(d_du), gv = luminance(d_dv);
        return Vec2(gu * to_uv_.m[0][0] + gv * to_uv_.m[1][0], gu * to_uv_.m[0][1] + gv * to_uv_.m[1][1]);
    }
    Spectrum mean() const override { return mip_.mean(); }
    float max_value() const override { return mip_.max_value(); }
    Vec2i resolution() const override { return Vec2i(mip_.width(), mip_.height()); }
    std::string to_string() const override { return "bitmap"; }
    const MipMap& mipmap() const { return mip_; }

private:
    MipMap mip_;
    TextureFilter filter_ = TextureFilter::Bilinear;
    UVTransform to_uv_;
};

CANDELA_REGISTER_SPECTRAL(BitmapTexture, ObjectKind::Texture, "bitmap");

}  // namespace candela
