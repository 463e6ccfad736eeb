#pragma once
// Rays and the surface interactions they find.

#include "core/frame.h"
#include "core/math.h"

namespace candela {

class Shape;
class BSDF;
class Emitter;

struct Ray {
    Vec3 o{0.0f}, d{0.0f, 0.0f, 1.0f};
    float tmin = 0.0f, tmax = Infinity;

    Ray() = default;
    Ray(const Vec3& origin, const Vec3& dir, float t_max = Infinity) : o(origin), d(dir), tmax(t_max) {}
    Vec3 operator()(float t) const { return o + t * d; }
};

// Moves p off its surface along the geometric normal n, to the side that direction d leaves
// toward. The offset scales with the point's magnitude (floating-point error grows with it),
// so scaling a scene by 1000 keeps rays from re-hitting their own surface.
inline Vec3 offset_ray_origin(const Vec3& p, const Vec3& n, const Vec3& d) {
    float mag = (1.0f + max_abs_component(p)) * RayEpsilon;
    return p + (glm::dot(n, d) >= 0.0f ? mag : -mag) * n;
}

// A point on a surface, as found by a ray or produced by sampling.
struct SurfaceInteraction {
    Vec3 p{0.0f};
    float t = Infinity;
    Vec3 n{0.0f, 0.0f, 1.0f};  // geometric normal (unit), on the shape's front side
    Frame shading;             // shading frame around the (interpolated) shading normal
    Vec2 uv{0.0f};
    Vec3 dpdu{0.0f}, dpdv{0.0f};
    Vec3 wi{0.0f, 0.0f, 1.0f};  // toward the ray's origin, in the shading frame
    const Shape* shape = nullptr;
    unsigned prim_index = 0;

    bool is_valid() const { return shape != nullptr; }
    Vec3 to_world(const Vec3& v) const { return shading.to_world(v); }
    Vec3 to_local(const Vec3& v) const { return shading.to_local(v); }
    Vec3 wi_world() const { return shading.to_world(wi); }

    Ray spawn_ray(const Vec3& d) const { return Ray(offset_ray_origin(p, n, d), d); }
    // A shadow ray toward `target`, stopping just short of it. `target_normal` (zero if none)
    // offsets the far end off its own surface too.
    Ray spawn_ray_to(const Vec3& target, const Vec3& target_normal = Vec3(0.0f)) const {
        Vec3 d = target - p;
        Vec3 o = offset_ray_origin(p, n, d);
        Vec3 t = target_normal == Vec3(0.0f) ? target : offset_ray_origin(target, target_normal, -d);
        Vec3 dir = t - o;
        float dist = glm::length(dir);
        return Ray(o, dir / dist, dist * (1.0f - ShadowEpsilon));
    }
};

}  // namespace candela
