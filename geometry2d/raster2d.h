#pragma once
// The classic 2D raster algorithms, each producing the set of integer pixels it covers:
//   lines      DDA, Bresenham (1965) and the midpoint algorithm (Pitteway 1967), all octants
//   circles    the midpoint circle algorithm with eight-way symmetry
//   filling    scanline triangle fill and scanline polygon fill (even-odd, pixel centres at
//              half-integers, half-open vertex rule), and trapezoid decomposition
// Ear clipping and the point-in-polygon test live in geometry2d/polygon.h. Used by plots, the
// rasterizer's wireframe overlay and light gizmos.

#include "core/math.h"

#include <functional>
#include <vector>

namespace candela::raster2d {

using Plot = std::function<void(int x, int y)>;

// Lines from (x0, y0) to (x1, y1), both endpoints included, one pixel per step along the major
// axis. All three pick the pixel nearest the ideal line at each step; on exact ties (the line
// passes halfway between two pixels) they all round toward +infinity on the minor axis.
void line_dda(int x0, int y0, int x1, int y1, const Plot& plot);
void line_bresenham(int x0, int y0, int x1, int y1, const Plot& plot);
void line_midpoint(int x0, int y0, int x1, int y1, const Plot& plot);

// The circle of integer radius r around (cx, cy): every pixel whose centre lies nearest the
// ideal circle along its octant's major axis.
void circle_midpoint(int cx, int cy, int r, const Plot& plot);

// Fills the pixels whose centres (x + 0.5, y + 0.5) lie inside the triangle, with the top-left
// rule on its edges, scanline by scanline.
void fill_triangle(const Vec2& a, const Vec2& b, const Vec2& c, const Plot& plot);
// Fills the pixels whose centres lie inside the polygon by the even-odd rule: each scanline
// through pixel centres crosses edges that straddle it half-open (one end strictly above, the
// other on or below), so a vertex exactly on the scanline counts once between an upward and a
// downward edge and twice (or not at all) between two edges on the same side.
void fill_polygon(const std::vector<Vec2>& polygon, const Plot& plot);

// A trapezoid between two horizontal lines (y_top < y_bottom): left and right edges given by
// their x at both lines. Degenerate trapezoids (triangles) have equal x at one line.
struct Trapezoid {
    float y_top, y_bottom;
    float x_left_top, x_right_top, x_left_bottom, x_right_bottom;
    float area() const { return 0.5f * ((x_right_top - x_left_top) + (x_right_bottom - x_left_bottom)) * (y_bottom - y_top); }
};
// Decomposes a simple polygon into trapezoids by cutting at every vertex's y (the even-odd
// interior between consecutive cuts, paired left to right).
std::vector<Trapezoid> trapezoid_decomposition(const std::vector<Vec2>& polygon);

}  // namespace candela::raster2d
