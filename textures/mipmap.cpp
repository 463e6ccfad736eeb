#include "textures/mipmap.h"

namespace candela {

bool parse_wrap_mode(const std::string& s, WrapMode& mode) {
    if (s == "repeat")
        mode = WrapMode::Repeat;
    else if (s == "mirror")
        mode = WrapMode::Mirror;
    else if (s == "clamp")
        mode = WrapMode::Clamp;
    else
        return false;
    return true;
}

bool parse_texture_filter(const std::string& s, TextureFilter& filter) {
    if (s == "nearest")
        filter = TextureFilter::Nearest;
    else if (s == "bilinear")
        filter = TextureFilter::Bilinear;
    else if (s == "trilinear")
        filter = TextureFilter::Trilinear;
    else
        return false;
    return true;
}

namespace {

// One output texel's share of the source texels along an axis: a box filter from size n down to
// m = ceil(n / 2) texels, where output texel i covers source [i n / m, (i + 1) n / m). For even
// n that is two whole texels; for odd n the edge texels count with their covered fraction.
struct Footprint {
    int first = 0, count = 0;
    float weight[3] = {0, 0, 0};  // covered fraction of texels first, first + 1, first + 2
};

std::vector<Footprint> box_footprints(int n, int m) {
    std::vector<Footprint> out(static_cast<size_t>(m));
    for (int i = 0; i < m; ++i) {
        // Exact in double: the bounds are multiples of 1/m of a texel.
        double lo = double(i) * n / m, hi = double(i + 1) * n / m;
        Footprint& f = out[size_t(i)];
        f.first = int(std::floor(lo));
        for (int j = f.first; j < n && double(j) < hi && f.count < 3; ++j)
            f.weight[f.count++] = float(std::min(double(j + 1), hi) - std::max(double(j), lo));
    }
    return out;
}

}  // namespace

MipMap::MipMap(std::vector<Spectrum> rgb, int width, int height, WrapMode wrap) : wrap_(wrap) {
    double sum[3] = {0, 0, 0};
    for (const Spectrum& s : rgb) {
        for (int c = 0; c < 3; ++c) sum[c] += s[c];
        max_ = std::max(max_, max_component(s));
    }
    double n = double(rgb.size());
    mean_ = Spectrum(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
    levels_.push_back(Level{width, height, std::move(rgb)});
    while (levels_.back().width > 1 || levels_.back().height > 1) levels_.push_back(downsample(levels_.back()));
}

// The next level, ceil(w / 2) by ceil(h / 2): each texel is the box-filtered average of the
// (possibly fractional) rectangle of the previous level it covers, so every level keeps the
// image's mean (the non-power-of-two reduction of pbrt and OpenGL's box filter).
MipMap::Level MipMap::downsample(const Level& prev) {
    Level next;
    next.width = (prev.width + 1) / 2;
    next.height = (prev.height + 1) / 2;
    next.texels.resize(size_t(next.width) * next.height);
    const std::vector<Footprint> fx = box_footprints(prev.width, next.width), fy = box_footprints(prev.height, next.height);
    // Every footprint covers n / m source texels; dividing by their product normalises.
    const float area = float(double(prev.width) / next.width * (double(prev.height) / next.height));
    for (int y = 0; y < next.height; ++y)
        for (int x = 0; x < next.width; ++x) {
            const Footprint &col = fx[size_t(x)], &row = fy[size_t(y)];
            Spectrum acc(0.0f);
            for (int j = 0; j < row.count; ++j)
                for (int i = 0; i < col.count; ++i)
                    acc += prev.texels[size_t(row.first + j) * prev.width + col.first + i] * (row.weight[j] * col.weight[i]);
            next.texels[size_t(y) * next.width + x] = acc / area;
        }
    return next;
}

int MipMap::wrap(int i, int n) const {
    switch (wrap_) {
        case WrapMode::Repeat: {
            int r = i % n;
            return r < 0 ? r + n : r;
        }
        case WrapMode::Clamp: return std::clamp(i, 0, n - 1);
        case WrapMode::Mirror: {
            int period = 2 * n;
            int r = i % period;
            if (r < 0) r += period;
            return r < n ? r : period - 1 - r;
        }
    }
    return 0;
}

Spectrum MipMap::texel(int level, int x, int y) const {
    const Level& l = levels_[level];
    return l.texels[size_t(wrap(y, l.height)) * l.width + wrap(x, l.width)];
}

Spectrum MipMap::nearest(int level, const Vec2& uv) const {
    const Level& l = levels_[level];
    return texel(level, int(std::floor(uv.x * float(l.width))), int(std::floor(uv.y * float(l.height))));
}

Spectrum MipMap::bilinear(int level, const Vec2& uv) const {
    const Level& l = levels_[level];
    float x = uv.x * float(l.width) - 0.5f, y = uv.y * float(l.height) - 0.5f;
    float fx = std::floor(x), fy = std::floor(y);
    int ix = int(fx), iy = int(fy);
    float wx = x - fx, wy = y - fy;
    return (texel(level, ix, iy) * (1.0f - wx) + texel(level, ix + 1, iy) * wx) * (1.0f - wy) +
           (texel(level, ix, iy + 1) * (1.0f - wx) + texel(level, ix + 1, iy + 1) * wx) * wy;
}

Spectrum MipMap::trilinear(const Vec2& uv, float footprint) const {
    float texels = footprint * float(std::max(width(), height()));
    float lod = texels > 1.0f ? std::log2(texels) : 0.0f;
    if (!std::isfinite(lod) || lod <= 0.0f) return bilinear(0, uv);
    if (lod >= float(levels() - 1)) return bilinear(levels() - 1, uv);
    int l0 = int(lod);
    float t = lod - float(l0);
    return bilinear(l0, uv) * (1.0f - t) + bilinear(l0 + 1, uv) * t;
}

void MipMap::bilinear_gradient(const Vec2& uv, Spectrum& d_du, Spectrum& d_dv) const {
    const Level& l = levels_[0];
    float x = uv.x * float(l.width) - 0.5f, y = uv.y * float(l.height) - 0.5f;
    float fx = std::floor(x), fy = std::floor(y);
    int ix = int(fx), iy = int(fy);
    float wx = x - fx, wy = y - fy;
    Spectrum t00 = texel(0, ix, iy), t10 = texel(0, ix + 1, iy), t01 = texel(0, ix, iy + 1), t11 = texel(0, ix + 1, iy + 1);
    d_du = ((t10 - t00) * (1.0f - wy) + (t11 - t01) * wy) * float(l.width);
    d_dv = ((t01 - t00) * (1.0f - wx) + (t11 - t10) * wx) * float(l.height);
}

}  // namespace candela
