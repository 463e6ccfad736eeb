// The classic 2D algorithms against brute-force references: lines in all eight octants against
// the exact line (and against each other), the midpoint circle against the exact circle, polygon
// fill against a per-pixel-centre crossing test (vertices exactly on scanlines included),
// triangle fill without gaps or double hits on shared edges, and trapezoid decomposition.

#include "core/rng.h"
#include "geometry2d/polygon.h"
#include "geometry2d/raster2d.h"

#include <catch2/catch.hpp>

#include <map>
#include <set>

using namespace candela;
using namespace candela::raster2d;

namespace {

using Pixels = std::vector<std::pair<int, int>>;

Pixels collect(void (*algo)(int, int, int, int, const Plot&), int x0, int y0, int x1, int y1) {
    Pixels p;
    algo(x0, y0, x1, y1, [&](int x, int y) { p.emplace_back(x, y); });
    return p;
}

long long floor_div(long long a, long long b) { return a / b - ((a % b != 0) && ((a < 0) != (b < 0))); }

// The exact line: one pixel per major-axis step, the minor coordinate the ideal value rounded
// half up, computed in integers.
Pixels exact_line(int x0, int y0, int x1, int y1) {
    Pixels p;
    int dx = x1 - x0, dy = y1 - y0, steps = std::max(std::abs(dx), std::abs(dy));
    if (steps == 0) return {{x0, y0}};
    bool x_major = std::abs(dx) >= std::abs(dy);
    for (int i = 0; i <= steps; ++i) {
        long long num = 2LL * i * (x_major ? dy : dx) + steps;  // round(v0 + i d / steps) = floor((2 i d + steps) / (2 steps))
        int minor = int((x_major ? y0 : x0) + floor_div(num, 2LL * steps));
        int major = (x_major ? x0 : y0) + i * ((x_major ? dx : dy) >= 0 ? 1 : -1);
        p.emplace_back(x_major ? major : minor, x_major ? minor : major);
    }
    return p;
}

}  // namespace

TEST_CASE("raster2d: DDA, Bresenham and midpoint lines equal the exact line in every octant", "[raster2d]") {
    PCG32 rng(1, 1);
    int octant_seen[8] = {0};
    for (int n = 0; n < 20000; ++n) {
        int x0 = int(rng.next_bounded(41)) - 20, y0 = int(rng.next_bounded(41)) - 20, x1 = int(rng.next_bounded(41)) - 20,
            y1 = int(rng.next_bounded(41)) - 20;
        int dx = x1 - x0, dy = y1 - y0;
        int octant = (dx < 0) * 4 + (dy < 0) * 2 + (std::abs(dy) > std::abs(dx));
        ++octant_seen[octant];
        Pixels exact = exact_line(x0, y0, x1, y1);
        INFO("(" << x0 << "," << y0 << ") -> (" << x1 << "," << y1 << ")");
        REQUIRE(collect(line_dda, x0, y0, x1, y1) == exact);
        REQUIRE(collect(line_bresenham, x0, y0, x1, y1) == exact);
        REQUIRE(collect(line_midpoint, x0, y0, x1, y1) == exact);
    }
    for (int o = 0; o < 8; ++o) CHECK(octant_seen[o] > 1000);
    // Ties: a slope of 1/2 passes exactly between pixels every other step.
    CHECK(collect(line_bresenham, 0, 0, 4, 2) == Pixels{{0, 0}, {1, 1}, {2, 1}, {3, 2}, {4, 2}});
    CHECK(collect(line_bresenham, 0, 0, 4, -2) == Pixels{{0, 0}, {1, 0}, {2, -1}, {3, -1}, {4, -2}});
}

TEST_CASE("raster2d: the midpoint circle equals the exact circle", "[raster2d]") {
    for (int r = 0; r <= 60; ++r) {
        std::set<std::pair<int, int>> got, expected;
        circle_midpoint(3, -2, r, [&](int x, int y) { CHECK(got.insert({x, y}).second); });  // no pixel twice
        // Second octant: y(x) = round_half_up(sqrt(r^2 - x^2)), the largest y with (2y - 1)^2 <= 4 (r^2 - x^2).
        for (int x = 0;; ++x) {
            long long rhs = 4LL * (1LL * r * r - 1LL * x * x);
            if (rhs < 0) break;
            int y = 0;
            while ((2LL * (y + 1) - 1) * (2LL * (y + 1) - 1) <= rhs) ++y;
            if (x > y) break;
            for (auto [a, b] : {std::pair{x, y}, {y, x}, {-x, y}, {-y, x}, {x, -y}, {y, -x}, {-x, -y}, {-y, -x}})
                expected.insert({3 + a, -2 + b});
        }
        INFO("r = " << r);
        CHECK(got == expected);
    }
}

TEST_CASE("raster2d: polygon fill equals the per-pixel-centre crossing test", "[raster2d]") {
    std::vector<std::vector<Vec2>> polygons = {
        // Vertices exactly on scanlines (y = k + 0.5): a W whose inner vertex touches a scanline
        // between two edges on one side, and a diamond with side vertices on scanlines.
        {{0, 0}, {10, 0}, {10, 6.5f}, {7, 6.5f}, {5, 3.5f}, {3, 6.5f}, {0, 6.5f}},
        {{5, 0.5f}, {9, 4.5f}, {5, 8.5f}, {1, 4.5f}},
        {{1, 1}, {12, 2}, {3, 4}, {12, 7}, {1, 9}, {6, 5}},                          // concave
        {{2.5f, 1.5f}, {8.5f, 1.5f}, {8.5f, 5.5f}, {5.5f, 2.5f}, {2.5f, 5.5f}},      // horizontal edges on scanlines
        {{0.2f, 0.3f}, {15.7f, 3.1f}, {3.3f, 12.9f}, {9.9f, 0.1f}, {14.2f, 11.4f}},  // self-intersecting star: even-odd
    };
    PCG32 rng(3, 2);
    for (int k = 0; k < 200; ++k) {  // random polygons with vertices on half-integers
        std::vector<Vec2> p;
        int n = 3 + int(rng.next_bounded(6));
        for (int i = 0; i < n; ++i) p.emplace_back(0.5f * float(rng.next_bounded(40)), 0.5f * float(rng.next_bounded(40)));
        polygons.push_back(p);
    }
    for (const auto& poly : polygons) {
        std::set<std::pair<int, int>> filled, expected;
        fill_polygon(poly, [&](int x, int y) { CHECK(filled.insert({x, y}).second); });
        std::vector<glm::dvec2> d;
        for (auto& v : poly) d.emplace_back(v.x, v.y);
        for (int y = -2; y < 25; ++y)
            for (int x = -2; x < 25; ++x)
                if (point_in_polygon(d, {x + 0.5, y + 0.5})) expected.insert({x, y});
        CHECK(filled == expected);
    }
}

TEST_CASE("raster2d: triangles sharing an edge cover every pixel once", "[raster2d]") {
    PCG32 rng(4, 3);
    for (int k = 0; k < 300; ++k) {
        Vec2 a(rng.next_float() * 30, rng.next_float() * 30), b(rng.next_float() * 30, rng.next_float() * 30),
            c(rng.next_float() * 30, rng.next_float() * 30), d(rng.next_float() * 30, rng.next_float() * 30);
        // The quad a b c d (if convex) split along a-c both ways.
        std::vector<glm::dvec2> quad = {{a.x, a.y}, {b.x, b.y}, {c.x, c.y}, {d.x, d.y}};
        if (polygon_signed_area2(quad) == 0.0) continue;
        std::map<std::pair<int, int>, int> hits;
        fill_triangle(a, b, c, [&](int x, int y) { ++hits[{x, y}]; });
        fill_triangle(a, c, d, [&](int x, int y) { ++hits[{x, y}]; });
        std::set<std::pair<int, int>> quad_pixels;
        fill_polygon({a, b, c, d}, [&](int x, int y) { quad_pixels.insert({x, y}); });
        // Where the quad is simple and convex at the diagonal, the two halves tile it.
        bool convex = true;
        for (int i = 0; i < 4; ++i) {
            const auto &p = quad[i], &q = quad[(i + 1) % 4], &r = quad[(i + 2) % 4];
            double cross = (q.x - p.x) * (r.y - q.y) - (q.y - p.y) * (r.x - q.x);
            convex = convex && (cross * polygon_signed_area2(quad) > 0);
        }
        if (!convex) continue;
        for (auto& [px, count] : hits) CHECK(count == 1);
        std::set<std::pair<int, int>> covered;
        for (auto& [px, count] : hits) covered.insert(px);
        CHECK(covered == quad_pixels);
    }
}

TEST_CASE("raster2d: trapezoid decomposition covers the polygon exactly", "[raster2d]") {
    std::vector<std::vector<Vec2>> polygons = {
        {{0, 0}, {6, 0}, {6, 4}, {4, 4}, {3, 2}, {2, 4}, {0, 4}},
        {{0, 0}, {8, 4}, {0, 8}, {3, 4}},                                                                  // arrow
        {{0, 0}, {5, 0}, {5, 3}, {4, 3}, {4, 1}, {3, 1}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}},  // comb
        {{0, 0}, {4, 0}, {4, 3}},
    };
    for (const auto& poly : polygons) {
        auto traps = trapezoid_decomposition(poly);
        std::vector<glm::dvec2> d;
        for (auto& v : poly) d.emplace_back(v.x, v.y);
        double area = 0.0;
        for (const auto& t : traps) {
            area += t.area();
            CHECK(t.x_left_top <= t.x_right_top + 1e-5f);
            CHECK(t.x_left_bottom <= t.x_right_bottom + 1e-5f);
            // The trapezoid's centre lies inside the polygon.
            float cy = 0.5f * (t.y_top + t.y_bottom), cx = 0.25f * (t.x_left_top + t.x_right_top + t.x_left_bottom + t.x_right_bottom);
            CHECK(point_in_polygon(d, {cx, cy}));
        }
        CHECK(area == Approx(std::abs(0.5 * polygon_signed_area2(d))).epsilon(1e-5));
    }
}
