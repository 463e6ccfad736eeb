#pragma once
// The triangle rasterizer of the local-illumination mode: homogeneous clipping against the
// whole frustum, viewport mapping, fixed-point edge functions with the top-left fill rule (no
// gaps and no double hits along shared edges), depth interpolation, and perspective-correct (or
// affine) barycentrics with respect to each original triangle. Pixels are traversed in 32 x 32
// tiles in parallel; within a tile triangles are processed in submission order, so results do
// not depend on the thread count.
//
// Clip space: x, y in [-w, w], z in [0, w] (depth 0 at the near plane). Pixel (px, py) covers
// [px, px + 1) x [py, py + 1) with y down; a clip-space point maps to
// ((x / w + 1) / 2 * W - offset.x, (y / w + 1) / 2 * H - offset.y) for a W x H full viewport.

#include "core/math.h"
#include "core/parallel.h"

#include <array>
#include <vector>

namespace candela::raster {

// Sub-pixel precision of the fixed-point vertex coordinates: 1/256 of a pixel (as GPUs use).
constexpr int SubpixelBits = 8;
constexpr int TileSize = 32;

struct ScreenVertex {
    int64_t x, y;  // fixed-point pixel coordinates
    double depth;  // z / w
    double inv_w;  // 1 / w
    Vec3 bary;     // barycentric coordinates with respect to the original triangle
};

struct ScreenTriangle {
    ScreenVertex v[3];       // oriented so that the signed area is positive
    int64_t area2;           // twice the signed area in fixed point
    uint32_t id;             // index of the original triangle
    bool front;              // counter-clockwise as submitted (before reorientation), seen on screen
    int bx0, by0, bx1, by1;  // pixel bounding box, inclusive, within the target
};

// What a covered sample learns about the triangle there.
struct Fragment {
    int x, y, sample;
    // z / w (0 at the near plane), and w itself: 1 / w is affine in screen space, so w is exact
    // (for perspective projections w is the view depth, precise where z / w is not).
    double depth, w;
    Vec3 bary;  // perspective-correct (or affine) barycentrics of the original triangle
    const ScreenTriangle* triangle;
};

class Rasterizer {
public:
    // A target of width x height pixels with the given sample positions inside each pixel
    // (offsets in [0, 1)^2), mapping clip space through a full_width x full_height viewport
    // whose top-left corner is at -offset.
    Rasterizer(int width, int height, const std::vector<Vec2>& sample_offsets, Vec2i full_size, Vec2i offset = Vec2i(0));
    // One sample per pixel, at its centre; no target until set_target().
    Rasterizer() : Rasterizer(0, 0, {Vec2(0.5f)}, Vec2i(0)) {}
    // Another target size with the same sample offsets. Storage of earlier setups is kept, so a
    // rasterizer reused frame after frame does not allocate.
    void set_target(int width, int height, Vec2i full_size, Vec2i offset = Vec2i(0));
    // Other sample offsets within each pixel (as the constructor takes them), in kept storage.
    void set_samples(const std::vector<Vec2>& sample_offsets);

    // Clips, projects and bins triangles given in clip space. `perspective_correct` false
    // interpolates attributes linearly in screen space (the distortion the lecture warns about).
    void setup(const std::vector<std::array<Vec4, 3>>& triangles, bool perspective_correct);

    // Calls op(const Fragment&) for every covered sample, tile by tile in parallel; within a
    // tile, in triangle submission order.
    template <typename Op>
    void run(Op op) const;

    int width() const { return width_; }
    int height() const { return height_; }
    int samples_per_pixel() const { return int(offsets_.size()); }
    const std::vector<Vec2>& sample_offsets() const { return offsets_; }
    Vec2i full_size() const { return full_size_; }
    Vec2i offset() const { return offset_; }
    size_t triangle_count() const { return screen_.size(); }

private:
    void clip_and_add(const std::array<Vec4, 3>& tri, uint32_t id);
    void add_screen_triangle(const Vec4 clip[3], const Vec3 bary[3], uint32_t id);
    // Narrows the pixel columns [first, last] to those where value_at_0 + x * slope * 2^SubpixelBits
    // >= 0 (an edge function plus its fill-rule bias along a row); empty when first > last.
    static void clip_span(int64_t value_at_0, int64_t slope, int& first, int& last);
    template <typename Op>
    void raster_in_tile(const ScreenTriangle& t, int tx0, int ty0, int tx1, int ty1, Op& op) const;

    int width_ = 0, height_ = 0;
    std::vector<Vec2> offsets_;
    std::vector<int64_t> offset_fx_, offset_fy_;  // sample offsets in fixed point
    Vec2i full_size_, offset_;
    bool perspective_ = true;
    std::vector<ScreenTriangle> screen_;
    int tiles_x_ = 0, tiles_y_ = 0;
    std::vector<std::vector<uint32_t>> bins_;  // screen triangle indices per tile
};

// Sample positions within a pixel for n samples: the centre for 1, a rotated grid for 4, a
// stratified (jittered, fixed seed) n = k x k grid otherwise.
std::vector<Vec2> sample_pattern(int n);

// ---- implementation of the templates -----------------------------------------------------

template <typename Op>
void Rasterizer::run(Op op) const {
    parallel_for(size_t(tiles_x_ * tiles_y_), [&](int tile) {
        int tx = tile % tiles_x_, ty = tile / tiles_x_;
        int x0 = tx * TileSize, y0 = ty * TileSize;
        int x1 = std::min(x0 + TileSize, width_) - 1, y1 = std::min(y0 + TileSize, height_) - 1;
        Op local = op;  // a copy per tile: operations may keep per-tile scratch
        for (uint32_t index : bins_[size_t(tile)]) raster_in_tile(screen_[index], x0, y0, x1, y1, local);
    });
}

template <typename Op>
void Rasterizer::raster_in_tile(const ScreenTriangle& t, int tx0, int ty0, int tx1, int ty1, Op& op) const {
    int x0 = std::max(t.bx0, tx0), x1 = std::min(t.bx1, tx1), y0 = std::max(t.by0, ty0), y1 = std::min(t.by1, ty1);
    if (x0 > x1 || y0 > y1) return;
    const ScreenVertex &a = t.v[0], &b = t.v[1], &c = t.v[2];
    // Edge functions E_ab(p) = (b - a) x (p - a); a sample is inside when all three are positive,
    // or zero on a top or left edge (bias 0), else (bias -1) strictly positive.
    auto edge = [](const ScreenVertex& p, const ScreenVertex& q, int64_t sx, int64_t sy) {
        return (q.x - p.x) * (sy - p.y) - (q.y - p.y) * (sx - p.x);
    };
    auto top_left = [](const ScreenVertex& p, const ScreenVertex& q) {
        bool top = p.y == q.y && q.x > p.x;  // horizontal, interior below (y down)
        bool left = q.y < p.y;               // going up: interior to its right
        return top || left;
    };
    const int64_t bias0 = top_left(b, c) ? 0 : -1, bias1 = top_left(c, a) ? 0 : -1, bias2 = top_left(a, b) ? 0 : -1;
    const double inv_area = 1.0 / double(t.area2);
    const int ns = int(offsets_.size());
    Fragment f;
    f.triangle = &t;
    for (int y = y0; y <= y1; ++y)
        for (int s = 0; s < ns; ++s) {
            const int64_t sy = (int64_t(y) << SubpixelBits) + offset_fy_[size_t(s)], sx_at_0 = offset_fx_[size_t(s)];
            // Along a row each edge function is affine in the pixel column x, so the samples
            // inside all three edges form one span, solved for exactly: no sample outside the
            // triangle is visited (its bounding box can be mostly empty).
            int first = x0, last = x1;
            clip_span(edge(b, c, sx_at_0, sy) + bias0, -(c.y - b.y), first, last);
            clip_span(edge(c, a, sx_at_0, sy) + bias1, -(a.y - c.y), first, last);
            clip_span(edge(a, b, sx_at_0, sy) + bias2, -(b.y - a.y), first, last);
            for (int x = first; x <= last; ++x) {
                int64_t sx = (int64_t(x) << SubpixelBits) + sx_at_0;
                int64_t e0 = edge(b, c, sx, sy), e1 = edge(c, a, sx, sy), e2 = edge(a, b, sx, sy);
                // Screen-space barycentrics; depth is affine in screen space.
                double l0 = double(e0) * inv_area, l1 = double(e1) * inv_area, l2 = double(e2) * inv_area;
                f.x = x;
                f.y = y;
                f.sample = s;
                f.depth = l0 * a.depth + l1 * b.depth + l2 * c.depth;
                double p0 = l0 * a.inv_w, p1 = l1 * b.inv_w, p2 = l2 * c.inv_w, sum = p0 + p1 + p2;
                f.w = 1.0 / sum;
                double w0 = l0, w1 = l1, w2 = l2;
                if (perspective_) {
                    w0 = p0 / sum;
                    w1 = p1 / sum;
                    w2 = p2 / sum;
                }
                f.bary = Vec3(float(w0)) * a.bary + Vec3(float(w1)) * b.bary + Vec3(float(w2)) * c.bary;
                op(f);
            }
        }
}

}  // namespace candela::raster
