#include "integrators/form_factor.h"

namespace candela {

double point_polygon_form_factor(const Vec3d& x, const Vec3d& n, const Vec3d* vertices, int count) {
    // Clip to the half-space above the tangent plane: keep r with n . r > 0. (Strictly: for a
    // polygon lying in the plane the contour integral would count the full hemisphere.)
    constexpr int MaxVertices = 9;  // a convex polygon gains at most one vertex per plane
    Vec3d clipped[MaxVertices];
    int m = 0;
    for (int k = 0; k < count && k < MaxVertices - 1; ++k) {
        Vec3d a = vertices[k] - x, b = vertices[(k + 1) % count] - x;
        double ha = glm::dot(n, a), hb = glm::dot(n, b);
        if (ha > 0.0) clipped[m++] = a;
        if ((ha > 0.0) != (hb > 0.0) && ha != hb) clipped[m++] = a + (b - a) * (ha / (ha - hb));
    }
    if (m < 3) return 0.0;
    double sum = 0.0;
    for (int k = 0; k < m; ++k) {
        const Vec3d &a = clipped[k], &b = clipped[(k + 1) % m];
        Vec3d c = glm::cross(a, b);
        double len_c = glm::length(c), len_ab = glm::length(a) * glm::length(b);
        if (!(len_c > 0.0) || !(len_ab > 0.0)) continue;  // an edge through x or a repeated vertex
        // The angle between a and b from atan2 of |a x b| and a . b: accurate at all angles.
        double gamma = std::atan2(len_c, glm::dot(a, b));
        sum += gamma * glm::dot(n, c) / len_c;
    }
    const double pi = 3.14159265358979323846;
    double f = std::abs(sum) / (2.0 * pi);
    return std::isfinite(f) ? std::min(f, 1.0) : 0.0;
}

}  // namespace candela
