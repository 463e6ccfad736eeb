#pragma once
// Rays and the surface interactions they find.

#include "core/frame.h"
#include "core/math.h"

namespace candela {

class Shape;
class BSDF;
class Emitter;
struct Wavelengths;

struct Ray {
    Vec3 o{0.0f}, d{0.0f, 0.0f, 1.0f};
    float tmin = 0.0f, tmax = Infinity;
    // When the ray travels (motion blur): the camera ray's shutter time, kept by every ray that
    // continues its path. Animated shapes, sensors and emitters take their pose at this time.
    float time = 0.0f;
    // The spectral variant's wavelengths of the camera sample (core/wavelengths.h), kept by every
    // ray of its path and by the interactions they find; null in the RGB variant. The path owns
    // them: a dispersive interface terminates the secondary ones (surface_step).
    Wavelengths* wavelengths = nullptr;

    Ray() = default;
    Ray(const Vec3& origin, const Vec3& dir, float t_max = Infinity) : o(origin), d(dir), tmax(t_max) {}
    Vec3 operator()(float t) const { return o + t * d; }
};

// The depth Mitsuba reports for a camera ray's hit at distance t along it (the aov integrator's
// `depth`, the `depth` integrator): from where the ray enters the view, since Mitsuba's cameras
// start their rays on the near plane. Candela's perspective and thinlens cameras start them at the
// lens with tmin on the near plane; its orthographic camera on the near plane, with tmin 0.
inline float camera_depth(const Ray& camera_ray, float t) { return t - camera_ray.tmin; }

// Shadow rays stop this fraction short of their target.
constexpr float ShadowEpsilon = 1e-4f;
// Factor over the computed error bounds: Embree's own intersection arithmetic is not part of them.
constexpr float OffsetSafety = 4.0f;

// Moves p off its surface along the geometric normal n, to the side that direction d leaves
// toward, by the bound `p_error` on p's floating-point error (pbrt-v4, section 6.8.6). The offset
// scales with the coordinates that produced p, so scenes scaled by 1000 or by 1/1000 behave the
// same; a fixed epsilon would cause self-hits in one case and visible bias in the other.
// `p_error` bounds the error of every coordinate (a max-norm bound, not per component): Embree's
// own arithmetic errs with the magnitude of all coordinates, so a plane lying exactly in y = 0
// still needs an offset in y.
inline Vec3 offset_ray_origin(const Vec3& p, float p_error, const Vec3& n, const Vec3& d) {
    float dist = (std::abs(n.x) + std::abs(n.y) + std::abs(n.z)) * p_error * OffsetSafety;
    Vec3 offset = dist * n;
    if (glm::dot(d, n) < 0.0f) offset = -offset;
    Vec3 po = p + offset;
    // Round away from p so that the rounding of the addition cannot undo the offset.
    for (int i = 0; i < 3; ++i) po[i] = next_float_toward(po[i], offset[i]);
    return po;
}

// The same segment as `ray` (spawn_ray_to's shadow rays have no unit direction), with a unit
// direction and tmax measured in its units.
inline Ray unit_direction(const Ray& ray) {
    float length = glm::length(ray.d);
    Ray r(ray.o, ray.d / length, ray.tmax * length);
    r.tmin = ray.tmin * length;
    r.time = ray.time;
    r.wavelengths = ray.wavelengths;
    return r;
}

// A point on a surface, as found by a ray or produced by sampling.
struct SurfaceInteraction {
    Vec3 p{0.0f};
    float p_error = 0.0f;  // bound on the absolute error of each coordinate of p
    float t = Infinity;
    Vec3 n{0.0f, 0.0f, 1.0f};  // geometric normal (unit), on the shape's front side
    Frame shading;             // shading frame around the (interpolated) shading normal
    Vec2 uv{0.0f};
    Vec3 dpdu{0.0f}, dpdv{0.0f};
    Vec3 wi{0.0f, 0.0f, 1.0f};  // toward the ray's origin, in the shading frame
    const Shape* shape = nullptr;
    unsigned prim_index = 0;
    Vec2 prim_uv{0.0f};                  // where on primitive prim_index: barycentrics (b1, b2) on a triangle
    float time = 0.0f;                   // the time of the ray that found it; rays spawned here keep it
    Wavelengths* wavelengths = nullptr;  // the same for the spectral variant's wavelengths

    bool is_valid() const { return shape != nullptr; }
    Vec3 to_world(const Vec3& v) const { return shading.to_world(v); }
    Vec3 to_local(const Vec3& v) const { return shading.to_local(v); }
    Vec3 wi_world() const { return shading.to_world(wi); }

    Ray spawn_ray(const Vec3& d) const {
        Ray r(offset_ray_origin(p, p_error, n, d), d);
        r.time = time;
        r.wavelengths = wavelengths;
        return r;
    }
    // A shadow ray toward `target`, stopping just short of it. As in Mitsuba 3 its direction is
    // target - origin, not a unit vector, and tmax is 1 - ShadowEpsilon: a visibility query needs
    // no more, and the square root and divisions of a normalisation stood between every light
    // sample and its query. Whatever measures distance along it takes unit_direction() first. A
    // target on a surface (normal not zero) is offset off that surface by its own error bound.
    Ray spawn_ray_to(const Vec3& target, const Vec3& target_normal = Vec3(0.0f), float target_error = 0.0f) const {
        Vec3 o = offset_ray_origin(p, p_error, n, target - p);
        Vec3 t = target_normal == Vec3(0.0f) ? target : offset_ray_origin(target, target_error, target_normal, o - target);
        Ray r(o, t - o, 1.0f - ShadowEpsilon);
        r.time = time;
        r.wavelengths = wavelengths;
        return r;
    }
};

}  // namespace candela
