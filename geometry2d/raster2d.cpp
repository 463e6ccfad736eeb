#include "geometry2d/raster2d.h"

#include <algorithm>

namespace candela::raster2d {

namespace {
// Rounds to the nearest integer, halves toward +infinity (the tie rule of all line algorithms).
int round_half_up(double v) { return int(std::floor(v + 0.5)); }
}  // namespace

void line_dda(int x0, int y0, int x1, int y1, const Plot& plot) {
    int dx = x1 - x0, dy = y1 - y0;
    int steps = std::max(std::abs(dx), std::abs(dy));
    if (steps == 0) {
        plot(x0, y0);
        return;
    }
    // One pixel per step along the major axis; the minor coordinate advances by the slope each
    // step. It is kept as the exact fraction numerator / steps (the numerator grows by the minor
    // delta), so that exact ties round the same way as the integer algorithms.
    bool x_major = std::abs(dx) >= std::abs(dy);
    int major_step = x_major ? (dx > 0 ? 1 : -1) : (dy > 0 ? 1 : -1);
    long long numerator = 0, delta = x_major ? dy : dx;
    int start_minor = x_major ? y0 : x0, major = x_major ? x0 : y0;
    for (int i = 0; i <= steps; ++i) {
        int minor = round_half_up(double(start_minor) + double(numerator) / steps);
        if (x_major)
            plot(major, minor);
        else
            plot(minor, major);
        major += major_step;
        numerator += delta;
    }
}

void line_bresenham(int x0, int y0, int x1, int y1, const Plot& plot) {
    // Integer error term along the major axis (Bresenham 1965). The error tracks
    // 2 * dmajor * (ideal minor - current minor) relative to a half-pixel threshold.
    int dx = std::abs(x1 - x0), dy = std::abs(y1 - y0);
    int sx = x1 >= x0 ? 1 : -1, sy = y1 >= y0 ? 1 : -1;
    bool steep = dy > dx;
    int major = steep ? dy : dx, minor = steep ? dx : dy;
    int s_major = steep ? sy : sx, s_minor = steep ? sx : sy;
    int a = steep ? y0 : x0, b = steep ? x0 : y0;
    // Ties round toward +infinity on the minor axis: when stepping minor negatively, a tie must
    // not step, when stepping positively it must.
    int err = 2 * minor - major;  // decision for the first step
    for (int i = 0; i <= major; ++i) {
        if (steep)
            plot(b, a);
        else
            plot(a, b);
        if (i == major) break;
        bool step = s_minor > 0 ? err >= 0 : err > 0;
        if (step) {
            b += s_minor;
            err -= 2 * major;
        }
        err += 2 * minor;
        a += s_major;
    }
}

void line_midpoint(int x0, int y0, int x1, int y1, const Plot& plot) {
    // Pitteway's midpoint form: evaluate the implicit line F(u, v) = dv u - du v at the midpoint
    // between the two candidate pixels and step the minor axis when the midpoint lies below the
    // line. u runs along the major axis, v along the minor, both counted from the start.
    int dx = x1 - x0, dy = y1 - y0;
    bool steep = std::abs(dy) > std::abs(dx);
    int d_major = steep ? dy : dx, d_minor = steep ? dx : dy;
    int su = d_major >= 0 ? 1 : -1, sv = d_minor >= 0 ? 1 : -1;
    int du = std::abs(d_major), dv = std::abs(d_minor);
    int u = 0, v = 0;
    long long f = 2LL * dv - du;  // 2 F(1, 1/2)
    for (int i = 0; i <= du; ++i) {
        int major = (steep ? y0 : x0) + su * u, minor = (steep ? x0 : y0) + sv * v;
        plot(steep ? minor : major, steep ? major : minor);
        if (i == du) break;
        bool step = sv > 0 ? f >= 0 : f > 0;  // ties toward +infinity on the minor axis
        if (step) {
            ++v;
            f -= 2LL * du;
        }
        f += 2LL * dv;
        ++u;
    }
}

void circle_midpoint(int cx, int cy, int r, const Plot& plot) {
    if (r < 0) return;
    if (r == 0) {
        plot(cx, cy);
        return;
    }
    // Second octant from (0, r): x advances, y steps down when the midpoint (x + 1, y - 1/2)
    // lies outside the circle. Decision d = 4 F(x + 1, y - 1/2) in integers, F = x^2 + y^2 - r^2.
    int x = 0, y = r;
    long long d = 5 - 4LL * r;
    std::vector<std::pair<int, int>> octant;
    while (x <= y) {
        octant.emplace_back(x, y);
        if (d > 0) {
            d += 8LL * (x - y) + 20;
            --y;
        } else {
            d += 8LL * x + 12;
        }
        ++x;
    }
    // Eight-way symmetry; skip duplicates where octants meet.
    std::vector<std::pair<int, int>> pts;
    for (auto [a, b] : octant)
        for (auto [px, py] : {std::pair{a, b}, {b, a}, {-a, b}, {-b, a}, {a, -b}, {b, -a}, {-a, -b}, {-b, -a}}) pts.emplace_back(px, py);
    std::sort(pts.begin(), pts.end());
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    for (auto [px, py] : pts) plot(cx + px, cy + py);
}

void fill_triangle(const Vec2& a, const Vec2& b, const Vec2& c, const Plot& plot) { fill_polygon({a, b, c}, plot); }

void fill_polygon(const std::vector<Vec2>& poly, const Plot& plot) {
    size_t n = poly.size();
    if (n < 3) return;
    float ymin = Infinity, ymax = -Infinity;
    for (const Vec2& p : poly) {
        ymin = std::min(ymin, p.y);
        ymax = std::max(ymax, p.y);
    }
    std::vector<double> xs;
    // Scanlines through pixel centres y + 0.5.
    for (int y = int(std::floor(ymin - 0.5f)); y <= int(std::ceil(ymax - 0.5f)); ++y) {
        double sy = y + 0.5;
        xs.clear();
        for (size_t i = 0, j = n - 1; i < n; j = i++) {
            double ay = poly[i].y, by = poly[j].y;
            // Half-open: exactly one endpoint strictly above the scanline (larger y counts as
            // "below" in image coordinates; the rule is symmetric).
            if ((ay > sy) != (by > sy)) xs.push_back(poly[i].x + (sy - ay) * (double(poly[j].x) - poly[i].x) / (by - ay));
        }
        std::sort(xs.begin(), xs.end());
        // Even-odd spans: pixel centres x + 0.5 in [x_enter, x_exit).
        for (size_t k = 0; k + 1 < xs.size(); k += 2) {
            int x_begin = int(std::ceil(xs[k] - 0.5)), x_end = int(std::ceil(xs[k + 1] - 0.5));
            for (int x = x_begin; x < x_end; ++x) plot(x, y);
        }
    }
}

std::vector<Trapezoid> trapezoid_decomposition(const std::vector<Vec2>& poly) {
    std::vector<Trapezoid> out;
    size_t n = poly.size();
    if (n < 3) return out;
    std::vector<float> ys;
    for (const Vec2& p : poly) ys.push_back(p.y);
    std::sort(ys.begin(), ys.end());
    ys.erase(std::unique(ys.begin(), ys.end()), ys.end());
    // Between consecutive vertex heights no edge starts or ends, so the edges crossing the band
    // pair up (even-odd) into trapezoids.
    for (size_t k = 0; k + 1 < ys.size(); ++k) {
        float y0 = ys[k], y1 = ys[k + 1], mid = 0.5f * (y0 + y1);
        struct Crossing {
            float x_mid, x0, x1;
        };
        std::vector<Crossing> cross;
        for (size_t i = 0, j = n - 1; i < n; j = i++) {
            const Vec2 &a = poly[i], &b = poly[j];
            if ((a.y > mid) == (b.y > mid)) continue;
            auto x_at = [&](float y) { return a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y); };
            cross.push_back({x_at(mid), x_at(y0), x_at(y1)});
        }
        std::sort(cross.begin(), cross.end(), [](const Crossing& l, const Crossing& r) { return l.x_mid < r.x_mid; });
        for (size_t c = 0; c + 1 < cross.size(); c += 2)
            out.push_back({y0, y1, cross[c].x0, cross[c + 1].x0, cross[c].x1, cross[c + 1].x1});
    }
    return out;
}

}  // namespace candela::raster2d
