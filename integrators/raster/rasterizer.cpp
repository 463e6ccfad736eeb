#include "integrators/raster/rasterizer.h"

#include "core/random_2d.h"

#include <array>

namespace candela::raster {

std::vector<Vec2> sample_pattern(int n) {
    if (n <= 1) return {Vec2(0.5f)};
    if (n == 4)  // rotated grid (as in 4x multisampling): no two samples share a row or column
        return {Vec2(0.375f, 0.125f), Vec2(0.875f, 0.375f), Vec2(0.125f, 0.625f), Vec2(0.625f, 0.875f)};
    int k = int(std::ceil(std::sqrt(double(n))));
    std::vector<Vec2> out;
    PCG32 rng(0x5eed, uint64_t(n));
    for (int j = 0; j < k && int(out.size()) < n; ++j)
        for (int i = 0; i < k && int(out.size()) < n; ++i) {
            const Vec2 u = next_vec2(rng);  // jitter within cell (i, j)
            out.emplace_back((float(i) + u.x) / float(k), (float(j) + u.y) / float(k));
        }
    return out;
}

Rasterizer::Rasterizer(int width, int height, const std::vector<Vec2>& offsets, Vec2i full_size, Vec2i offset) {
    set_samples(offsets);
    set_target(width, height, full_size, offset);
}

void Rasterizer::set_samples(const std::vector<Vec2>& offsets) {
    offsets_.assign(offsets.begin(), offsets.end());
    offset_fx_.clear();
    offset_fy_.clear();
    for (const Vec2& o : offsets_) {
        offset_fx_.push_back(int64_t(std::lround(double(o.x) * (1 << SubpixelBits))));
        offset_fy_.push_back(int64_t(std::lround(double(o.y) * (1 << SubpixelBits))));
    }
}

void Rasterizer::set_target(int width, int height, Vec2i full_size, Vec2i offset) {
    width_ = width;
    height_ = height;
    full_size_ = full_size;
    offset_ = offset;
    tiles_x_ = (width_ + TileSize - 1) / TileSize;
    tiles_y_ = (height_ + TileSize - 1) / TileSize;
}

void Rasterizer::setup(const std::vector<std::array<Vec4, 3>>& triangles, bool perspective_correct) {
    perspective_ = perspective_correct;
    screen_.clear();
    screen_.reserve(triangles.size());
    for (size_t i = 0; i < triangles.size(); ++i) clip_and_add(triangles[i], uint32_t(i));
    // Emptied rather than replaced: the bins keep their storage from earlier setups.
    bins_.resize(size_t(tiles_x_) * tiles_y_);
    for (auto& bin : bins_) bin.clear();
    for (size_t i = 0; i < screen_.size(); ++i) {
        const ScreenTriangle& t = screen_[i];
        for (int ty = t.by0 / TileSize; ty <= t.by1 / TileSize; ++ty)
            for (int tx = t.bx0 / TileSize; tx <= t.bx1 / TileSize; ++tx) bins_[size_t(ty) * tiles_x_ + tx].push_back(uint32_t(i));
    }
}

void Rasterizer::clip_span(int64_t value_at_0, int64_t slope, int& first, int& last) {
    // value_at_0 + x * step >= 0 with step the change per pixel, solved in exact integers:
    // x >= ceil(-value_at_0 / step) for a positive step, x <= floor(value_at_0 / -step) for a
    // negative one; a zero step keeps the row or empties it.
    const int64_t step = slope * (int64_t(1) << SubpixelBits);
    auto floor_div = [](int64_t n, int64_t d) { return n / d - (n % d != 0 && n < 0 ? 1 : 0); };  // d > 0
    if (step == 0) {
        if (value_at_0 < 0) last = first - 1;
        return;
    }
    if (step > 0) {
        int64_t lowest = -floor_div(value_at_0, step);  // ceil(-value_at_0 / step)
        if (lowest > int64_t(first)) first = int(std::min<int64_t>(lowest, int64_t(last) + 1));
    } else {
        int64_t highest = floor_div(value_at_0, -step);
        if (highest < int64_t(last)) last = int(std::max<int64_t>(highest, int64_t(first) - 1));
    }
}

void Rasterizer::clip_and_add(const std::array<Vec4, 3>& tri, uint32_t id) {
    // Sutherland-Hodgman clipping in homogeneous coordinates against the six frustum planes
    // (plane value >= 0 inside); each vertex carries its barycentrics in the original triangle.
    struct V {
        Vec4 p;
        Vec3 b;
    };
    auto inside_all = [](const Vec4& p) { return p.x >= -p.w && p.x <= p.w && p.y >= -p.w && p.y <= p.w && p.z >= 0.0f && p.z <= p.w; };
    if (inside_all(tri[0]) && inside_all(tri[1]) && inside_all(tri[2])) {
        Vec4 clip[3] = {tri[0], tri[1], tri[2]};
        Vec3 bary[3] = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
        add_screen_triangle(clip, bary, id);
        return;
    }
    // Each of the six planes adds at most one vertex to the convex polygon: at most 3 + 6. The
    // room beyond that is for rounding, which can bend a sliver; one that would still overflow is
    // dropped (it covers no sample).
    constexpr size_t MaxVertices = 16;
    std::array<V, MaxVertices> poly = {V{tri[0], Vec3(1, 0, 0)}, V{tri[1], Vec3(0, 1, 0)}, V{tri[2], Vec3(0, 0, 1)}}, next;
    size_t count = 3;
    auto plane = [](const Vec4& p, int k) -> float {
        switch (k) {
            case 0: return p.w + p.x;
            case 1: return p.w - p.x;
            case 2: return p.w + p.y;
            case 3: return p.w - p.y;
            case 4: return p.z;
            default: return p.w - p.z;
        }
    };
    for (int k = 0; k < 6 && count > 0; ++k) {
        size_t next_count = 0;
        for (size_t i = 0; i < count; ++i) {
            const V& a = poly[i];
            const V& b = poly[(i + 1) % count];
            if (next_count + 2 > MaxVertices) return;
            float da = plane(a.p, k), db = plane(b.p, k);
            if (da >= 0.0f) next[next_count++] = a;
            if ((da >= 0.0f) != (db >= 0.0f)) {
                float t = da / (da - db);
                next[next_count++] = {a.p + t * (b.p - a.p), a.b + t * (b.b - a.b)};
            }
        }
        poly = next;
        count = next_count;
    }
    if (count < 3) return;
    for (size_t i = 1; i + 1 < count; ++i) {
        Vec4 clip[3] = {poly[0].p, poly[i].p, poly[i + 1].p};
        Vec3 bary[3] = {poly[0].b, poly[i].b, poly[i + 1].b};
        add_screen_triangle(clip, bary, id);
    }
}

void Rasterizer::add_screen_triangle(const Vec4 clip[3], const Vec3 bary[3], uint32_t id) {
    ScreenTriangle t;
    t.id = id;
    const double scale = double(1 << SubpixelBits);
    for (int i = 0; i < 3; ++i) {
        if (!(clip[i].w > 0.0f)) return;  // only after clipping: numerically on the eye plane
        double inv_w = 1.0 / double(clip[i].w);
        double px = (double(clip[i].x) * inv_w + 1.0) * 0.5 * full_size_.x - offset_.x;
        double py = (double(clip[i].y) * inv_w + 1.0) * 0.5 * full_size_.y - offset_.y;
        t.v[i].x = int64_t(std::llround(px * scale));
        t.v[i].y = int64_t(std::llround(py * scale));
        t.v[i].depth = double(clip[i].z) * inv_w;
        t.v[i].inv_w = inv_w;
        t.v[i].bary = bary[i];
    }
    int64_t area = (t.v[1].x - t.v[0].x) * (t.v[2].y - t.v[0].y) - (t.v[1].y - t.v[0].y) * (t.v[2].x - t.v[0].x);
    if (area == 0) return;
    // On screen (y down) a positive area is clockwise; a counter-clockwise triangle as seen by
    // the viewer (its front, for counter-clockwise-is-front winding) has a negative area.
    t.front = area < 0;
    if (area < 0) {
        std::swap(t.v[1], t.v[2]);
        area = -area;
    }
    t.area2 = area;
    int64_t minx = std::min({t.v[0].x, t.v[1].x, t.v[2].x}), maxx = std::max({t.v[0].x, t.v[1].x, t.v[2].x});
    int64_t miny = std::min({t.v[0].y, t.v[1].y, t.v[2].y}), maxy = std::max({t.v[0].y, t.v[1].y, t.v[2].y});
    // Pixels whose sample region [x, x + 1) can contain a covered sample.
    t.bx0 = std::max(0, int(minx >> SubpixelBits) - 1);
    t.by0 = std::max(0, int(miny >> SubpixelBits) - 1);
    t.bx1 = std::min(width_ - 1, int(maxx >> SubpixelBits) + 1);
    t.by1 = std::min(height_ - 1, int(maxy >> SubpixelBits) + 1);
    if (t.bx0 > t.bx1 || t.by0 > t.by1) return;
    screen_.push_back(t);
}

}  // namespace candela::raster
