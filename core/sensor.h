#pragma once
// Sensors turn film positions into camera rays; each holds its film and sampler, as in Mitsuba.

#include "core/film.h"
#include "core/ray.h"
#include "core/sampler.h"
#include "core/transform.h"

#include <optional>

namespace candela {

// A pinhole camera's projection, for the rasterizer: camera space has +z forward, +y up and +x
// toward the image's left (Mitsuba's convention).
struct PinholeProjection {
    Transform to_world;
    float tan_half_x = 1.0f;  // tan(fov_x / 2)
    float aspect = 1.0f;      // width / height of the full film
    float near_clip = 0.01f, far_clip = 1e4f;
};

class Sensor : public Object {
public:
    // The projection of a pinhole camera (nullopt for other camera models).
    virtual std::optional<PinholeProjection> pinhole() const { return std::nullopt; }
    ObjectKind kind() const override { return ObjectKind::Sensor; }
    // A primary ray through continuous film position `film_pos` (pixels of the full film, origin
    // at the top-left corner); `aperture_u` is for cameras with a lens.
    virtual Ray sample_ray(const Vec2& film_pos, const Vec2& aperture_u) const = 0;

    Film& film() const { return *film_; }
    Sampler& sampler() const { return *sampler_; }
    const Transform& to_world() const { return to_world_; }

protected:
    Ref<Film> film_;
    Ref<Sampler> sampler_;
    Transform to_world_;
};

}  // namespace candela
