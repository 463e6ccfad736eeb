#pragma once
// Where the light of infinite emitters (directional, constant, envmap, sunsky) enters the scene when it is
// traced from the emitter (sample_ray): every ray travelling along d starts on the disk of the
// scene's bounding-sphere radius r, across d, tangent to the sphere on the side the light comes
// from, so each ray that can meet the scene does. The density is 1 / (pi r^2) per unit area of the
// disk, and the flux through it is what power() reports (pi r^2 times the irradiance).

#include "core/emitter.h"
#include "core/warp.h"

namespace candela {

struct SceneDisk {
    Vec3 center{0.0f};
    float radius = 1.0f;

    // The disk of a scene's bounds: centred on them (the origin when there are none), with their
    // bounding radius (at least 1e-3).
    static SceneDisk around(const BoundingBox& bounds) {
        return {bounds.valid() ? bounds.center() : Vec3(0.0f), std::max(bounds.bounding_radius(), 1e-3f)};
    }

    float area() const { return Pi * radius * radius; }
    // The ray along unit direction d from the disk point picked by u.
    Ray ray(const Vec3& d, const Vec2& u) const {
        Vec3 s, t;
        coordinate_system(d, s, t);
        Vec2 q = radius * warp::square_to_uniform_disk_concentric(u);
        return Ray(center - d * radius + s * q.x + t * q.y, d);
    }
};

// The light paths of an infinite emitter whose next-event sampling draws its directions: a
// direction drawn as seen from the disk's centre (the light travels the opposite way), then a point
// on the disk across it. The ray's weight is radiance / (pdf_direction pdf_position).
inline EmitterRay environment_ray(const Emitter& emitter, const SceneDisk& disk, const Vec2& u_position, const Vec2& u_direction,
                                  Wavelengths* wavelengths, float time) {
    SurfaceInteraction center;
    center.p = disk.center;
    center.time = time;
    center.wavelengths = wavelengths;
    Spectrum radiance_over_pdf;
    DirectionSample ds = emitter.sample_direction(center, u_direction, radiance_over_pdf);
    EmitterRay r;
    if (!(ds.pdf > 0.0f)) return r;
    r.ray = disk.ray(-ds.d, u_position);
    r.pdf_position = 1.0f / disk.area();
    r.pdf_direction = ds.pdf;
    r.weight = radiance_over_pdf * disk.area();
    return r;
}

}  // namespace candela
