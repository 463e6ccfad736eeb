#include "geometry2d/polygon.h"

namespace candela {

double polygon_signed_area2(const std::vector<glm::dvec2>& pts) {
    double a = 0.0;
    size_t n = pts.size();
    for (size_t i = 0; i < n; ++i) {
        const auto& p = pts[i];
        const auto& q = pts[(i + 1) % n];
        a += p.x * q.y - q.x * p.y;
    }
    return a;
}

bool point_in_polygon(const std::vector<glm::dvec2>& pts, const glm::dvec2& p) {
    bool inside = false;
    size_t n = pts.size();
    for (size_t i = 0, j = n - 1; i < n; j = i++) {
        const auto& a = pts[i];
        const auto& b = pts[j];
        // Half-open rule: the edge straddles the line y = p.y when exactly one endpoint is above.
        if ((a.y > p.y) != (b.y > p.y)) {
            double x_cross = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if (p.x < x_cross) inside = !inside;
        }
    }
    return inside;
}

namespace {
double cross2(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Inside or on the boundary of the counter-clockwise triangle abc.
bool in_triangle(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    return cross2(a, b, p) >= 0.0 && cross2(b, c, p) >= 0.0 && cross2(c, a, p) >= 0.0;
}
}  // namespace

std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<glm::dvec2>& input) {
    std::vector<std::array<int, 3>> tris;
    int n = int(input.size());
    if (n < 3) return tris;
    if (n == 3) {
        tris.push_back({0, 1, 2});
        return tris;
    }
    // Work counter-clockwise; remember to flip the output for clockwise input.
    bool ccw = polygon_signed_area2(input) >= 0.0;
    std::vector<int> idx(n);
    for (int i = 0; i < n; ++i) idx[i] = ccw ? i : n - 1 - i;

    // Drop repeated consecutive vertices (they make zero-length edges).
    std::vector<int> v;
    for (int i = 0; i < n; ++i)
        if (v.empty() || input[idx[i]] != input[v.back()]) v.push_back(idx[i]);
    while (v.size() > 1 && input[v.front()] == input[v.back()]) v.pop_back();

    auto emit = [&](int a, int b, int c) {
        if (ccw)
            tris.push_back({a, b, c});
        else
            tris.push_back({c, b, a});
    };

    // Scale-aware tolerance for "collinear".
    double extent = 0.0;
    for (auto& p : input) extent = std::max(extent, std::max(std::abs(p.x), std::abs(p.y)));
    const double eps = 1e-12 * std::max(extent * extent, 1e-300);

    size_t guard = 0;
    while (v.size() > 3 && guard++ < 4 * input.size() * input.size() + 16) {
        size_t m = v.size();
        bool clipped = false;
        for (size_t i = 0; i < m; ++i) {
            int ia = v[(i + m - 1) % m], ib = v[i], ic = v[(i + 1) % m];
            const auto &a = input[ia], &b = input[ib], &c = input[ic];
            double turn = cross2(a, b, c);
            if (std::abs(turn) <= eps) {
                // A collinear vertex (straight angle or a spike): remove it without a triangle
                // only if it does not fold back; a straight-through vertex adds no area.
                if (glm::dot(b - a, c - b) >= 0.0) {
                    v.erase(v.begin() + long(i));
                    clipped = true;
                    break;
                }
                continue;
            }
            if (turn < 0.0) continue;  // reflex vertex: not an ear
            bool blocked = false;
            for (size_t k = 0; k < m && !blocked; ++k) {
                int ip = v[k];
                if (ip == ia || ip == ib || ip == ic) continue;
                const auto& p = input[ip];
                if (p == a || p == b || p == c) continue;
                blocked = in_triangle(p, a, b, c);
            }
            if (blocked) continue;
            emit(ia, ib, ic);
            v.erase(v.begin() + long(i));
            clipped = true;
            break;
        }
        if (!clipped) break;  // not a simple polygon; give up on the rest
    }
    if (v.size() == 3 && std::abs(cross2(input[v[0]], input[v[1]], input[v[2]])) > eps) emit(v[0], v[1], v[2]);
    return tris;
}

std::vector<std::array<int, 3>> triangulate_polygon_3d(const std::vector<Vec3>& pts) {
    // Newell's method gives a robust normal for non-convex and slightly non-planar polygons.
    glm::dvec3 normal(0.0);
    size_t n = pts.size();
    for (size_t i = 0; i < n; ++i) {
        glm::dvec3 a(pts[i]), b(pts[(i + 1) % n]);
        normal.x += (a.y - b.y) * (a.z + b.z);
        normal.y += (a.z - b.z) * (a.x + b.x);
        normal.z += (a.x - b.x) * (a.y + b.y);
    }
    // Project along the normal's dominant axis. Any projection maps orientations consistently,
    // and triangulate_polygon winds its triangles like its input, so the triangles keep the
    // polygon's winding in 3D.
    int axis = 2;
    glm::dvec3 an = glm::abs(normal);
    if (an.x > an.y && an.x > an.z)
        axis = 0;
    else if (an.y > an.z)
        axis = 1;
    std::vector<glm::dvec2> flat(n);
    for (size_t i = 0; i < n; ++i) {
        glm::dvec3 p(pts[i]);
        flat[i] = axis == 0 ? glm::dvec2(p.y, p.z) : axis == 1 ? glm::dvec2(p.z, p.x) : glm::dvec2(p.x, p.y);
    }
    auto tris = triangulate_polygon(flat);
    return tris;
}

}  // namespace candela
