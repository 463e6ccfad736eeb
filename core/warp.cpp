#include "core/warp.h"

namespace candela::warp {

Vec2 square_to_uniform_disk(const Vec2& u) {
    float r = std::sqrt(u.x), phi = TwoPi * u.y;
    return Vec2(r * std::cos(phi), r * std::sin(phi));
}

Vec3 square_to_uniform_sphere(const Vec2& u) {
    float z = 1.0f - 2.0f * u.x;
    float r = safe_sqrt(1.0f - z * z);
    float phi = TwoPi * u.y;
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

Vec3 square_to_uniform_hemisphere(const Vec2& u) {
    float z = u.x;
    float r = safe_sqrt(1.0f - z * z);
    float phi = TwoPi * u.y;
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

Vec3 square_to_uniform_cone(const Vec2& u, float cos_cutoff) {
    float cos_theta = (1.0f - u.x) + u.x * cos_cutoff;
    float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
    float phi = TwoPi * u.y;
    return Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}

Vec2 square_to_uniform_triangle(const Vec2& u) {
    float b0, b1;
    if (u.y > u.x) {
        b0 = u.x * 0.5f;
        b1 = u.y - b0;
    } else {
        b1 = u.y * 0.5f;
        b0 = u.x - b1;
    }
    // Returns the weights of vertices 1 and 2; vertex 0 gets 1 - b0 - b1.
    return Vec2(b0, b1);
}

}  // namespace candela::warp
