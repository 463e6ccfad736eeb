#pragma once
// An RGB image pyramid (Williams 1983, "Pyramidal Parametrics") with nearest, bilinear and
// trilinear lookups and Mitsuba's wrap modes. Built once per bitmap texture; the path tracer
// reads level 0, the rasterizer picks a level from screen-space uv derivatives.

#include "core/spectrum.h"
#include "core/texture.h"

#include <string>
#include <vector>

namespace candela {

enum class WrapMode { Repeat, Mirror, Clamp };

// Parses "repeat", "mirror", "clamp" / "nearest", "bilinear", "trilinear"; false when unknown.
bool parse_wrap_mode(const std::string& s, WrapMode& mode);
bool parse_texture_filter(const std::string& s, TextureFilter& filter);

class MipMap {
public:
    MipMap() = default;
    // `rgb` holds width * height texels, row 0 at the top (v = 0), as Mitsuba stores bitmaps.
    MipMap(std::vector<Spectrum> rgb, int width, int height, WrapMode wrap);

    int levels() const { return int(levels_.size()); }
    int width(int level = 0) const { return levels_[level].width; }
    int height(int level = 0) const { return levels_[level].height; }
    // The wrapped texel (x, y) of a level.
    Spectrum texel(int level, int x, int y) const;

    // Lookups with texel centres at half-integers: (x, y) = (u W - 0.5, v H - 0.5).
    Spectrum nearest(int level, const Vec2& uv) const;
    Spectrum bilinear(int level, const Vec2& uv) const;
    // Trilinear: blends the two levels around lod = log2(footprint in level-0 texels), where
    // `footprint` is the filter width in uv units (e.g. the longer screen-space uv derivative).
    Spectrum trilinear(const Vec2& uv, float footprint) const;
    // The derivative of the level-0 bilinear interpolant with respect to (u, v).
    void bilinear_gradient(const Vec2& uv, Spectrum& d_du, Spectrum& d_dv) const;

    Spectrum mean() const { return mean_; }
    float max_value() const { return max_; }

private:
    struct Level {
        int width = 0, height = 0;
        std::vector<Spectrum> texels;
    };
    static Level downsample(const Level& prev);
    int wrap(int i, int n) const;
    std::vector<Level> levels_;
    WrapMode wrap_ = WrapMode::Repeat;
    Spectrum mean_{0.0f};
    float max_ = 0.0f;
};

}  // namespace candela
