#pragma once
// Sensors turn film positions into camera rays; each holds its film and sampler, as in Mitsuba.

#include "core/film.h"
#include "core/ray.h"
#include "core/sampler.h"
#include "core/transform.h"
#include "core/wavelengths.h"

#include <optional>

namespace candela {

class Properties;
class Medium;
class Scene;
class Shape;

// A pinhole camera's projection (the rasterizer's camera, and the projector light's): camera
// space has +z forward, +y up and +x toward the image's left (Mitsuba's convention). Film
// positions s are fractions of the full film in [0,1]^2 with the origin at the top-left corner.
struct PinholeProjection {
    Transform to_world;
    float tan_half_x = 1.0f;  // tan(fov_x / 2)
    float aspect = 1.0f;      // width / height of the full film
    float near_clip = 0.01f, far_clip = 1e4f;
    // Mitsuba's principal_point_offset_x/y: film position s looks where s + offset would look
    // without the shift, so the optical axis meets the film at (0.5, 0.5) - offset.
    Vec2 principal_point_offset{0.0f};

    // The camera-space direction through film position s, scaled to z = 1.
    Vec3 direction(const Vec2& s) const {
        Vec2 t = s + principal_point_offset;
        return Vec3((1.0f - 2.0f * t.x) * tan_half_x, (1.0f - 2.0f * t.y) * tan_half_x / aspect, 1.0f);
    }
    // The film position where a camera-space point in front of the camera (z > 0) appears.
    Vec2 film_position(const Vec3& p) const {
        return Vec2(0.5f - 0.5f * p.x / (p.z * tan_half_x), 0.5f - 0.5f * p.y * aspect / (p.z * tan_half_x)) - principal_point_offset;
    }
};

// Mitsuba's field of view parameters (fov in degrees along fov_axis x, y, diagonal, smaller or
// larger; or focal_length as a 35 mm equivalent such as "50mm", which spans the diagonal), read
// for an image of aspect width / height: returns tan(fov_x / 2).
float read_tan_half_fov_x(const Properties& props, float aspect);

// A connection from a point in the scene to the sensor, for light tracing (Mitsuba's
// Sensor::sample_direction): the inverse of sample_ray, with the importance it carries.
struct SensorSample {
    Vec3 p{0.0f};         // where the connection enters the sensor's view: on the near-clip plane,
                          // so a shadow ray from the reference point to p tests what the camera sees
    Vec3 d{0.0f};         // unit direction from the reference point toward the sensor
    float dist = 0.0f;    // distance from the reference point to p
    Vec2 film_pos{0.0f};  // where it lands on the film, in pixels of the full film (as sample_ray)
    float pdf = 0.0f;     // solid-angle density of d at the reference point (1 for a delta:
                          // pinhole, orthographic); 0 when the point is not in view
    bool delta = false;
    // The importance of the connection over its density, W_e cos(theta_sensor) / (dist_lens^2 p)
    // in film pixels: a particle of flux weight beta arriving at the reference point, scattered
    // toward the sensor by f |cos|, adds beta f |cos| * weight to the film at film_pos, through a
    // reconstruction filter of unit integral; dividing the film by the number of light paths
    // gives radiance. A surface of radiance L seen through the sensor measures the same L.
    float weight = 0.0f;
};

// A sensor: a camera (sensors/projective.h) or a measuring instrument (radiancemeter,
// irradiancemeter, distant) or a group of them (batch). Every sensor holds the film it fills and
// the sampler that drives it; the pixel loop asks it for one ray per sample.
class Sensor : public Object {
public:
    // The projection of a pinhole camera (nullopt for other camera models: the rasterizer
    // renders only through a pinhole).
    virtual std::optional<PinholeProjection> pinhole() const { return std::nullopt; }
    ObjectKind kind() const override { return ObjectKind::Sensor; }
    // A primary ray through continuous film position `film_pos` (pixels of the full film, origin
    // at the top-left corner) at shutter time `time` (an animated camera takes its pose then; the
    // ray carries the time); `aperture_u` is for cameras with a lens and for instruments that
    // sample a position (distant).
    virtual Ray sample_ray(const Vec2& film_pos, const Vec2& aperture_u, float time) const = 0;
    // The same at the shutter's opening.
    Ray sample_ray(const Vec2& film_pos, const Vec2& aperture_u) const { return sample_ray(film_pos, aperture_u, shutter_open_); }
    // What the radiance carried back along sample_ray's ray is multiplied by (Mitsuba's ray
    // weight): 1 for cameras and radiance meters; pi for the irradiance meter, whose rays are
    // cosine-distributed, so that pi L estimates the irradiance.
    virtual float sample_weight(const Vec2& film_pos) const { return 1.0f; }
    // The connection from world point `ref` to the sensor at shutter time `time` (an animated
    // camera takes its pose then, as sample_ray does); `aperture_u` picks the lens point of
    // cameras with a lens. pdf 0 when `ref` is outside the view or the clip range, and always
    // for sensors that light paths cannot reach (see reached_by_light_paths).
    virtual SensorSample sample_direction(const Vec3& ref, const Vec2& aperture_u, float time) const { return SensorSample(); }
    // Whether light paths can connect to the sensor (the particle tracer's condition): false for
    // a radiance meter or a distant sensor (a delta in both position and direction) and for a
    // batch of sensors.
    virtual bool reached_by_light_paths() const { return false; }
    // Whether the rays of one pixel's samples, and of neighbouring pixels, leave from about one
    // place in about one direction (a camera's; not an irradiance meter's hemisphere of
    // directions): the wavefront then traces its camera rays as coherent packets (Accel's
    // `coherent`). Only speed depends on it.
    virtual bool rays_coherent() const { return false; }

    // Called once the scene's geometry is built (the distant sensor places its rays outside the
    // scene's bounding sphere).
    virtual void set_scene(const Scene& scene) {}
    // A sensor nested in a shape measures on that shape (Mitsuba's irradiancemeter). The shape
    // calls this while it is built; sensors that cannot be nested fail at props' location.
    virtual void attach_to_shape(const Shape& shape, const Properties& shape_props);
    // The sub-sensors of a batch render into slices of the batch's film: each takes its
    // slice's size (Mitsuba's film()->set_size), keeping its field of view along x. Throws
    // InputError for a size the sensor cannot measure with.
    virtual void set_film_size(const Vec2i& size);

    Film& film() const { return *film_; }
    Sampler& sampler() const { return *sampler_; }
    // Replaces the sampler (candela render --sampler) and tells it the film's size.
    void set_sampler(Ref<Sampler> sampler) {
        sampler_ = std::move(sampler);
        sampler_->set_film(film_->full_size(), film_sampled_border(*film_));
    }
    // The camera's pose at the shutter's opening (the rasterizer's).
    const Transform& to_world() const { return to_world_; }
    // Its pose at shutter time `time` (to_world() when it does not move): a light path's.
    virtual Transform pose_at(float time) const { return to_world_; }
    // Whether the camera's to_world is animated (<animation name="to_world">).
    virtual bool is_animated() const { return false; }
    virtual SourceLocation motion_location() const { return {}; }
    // The exposure (Mitsuba's shutter_open, shutter_close - shutter_open): a camera sample's time
    // is shutter_open + u (close - open) for a uniform u, or shutter_open when they are equal.
    float shutter_open() const { return shutter_open_; }
    float shutter_open_time() const { return shutter_open_time_; }
    float sample_time(float u) const { return shutter_open_ + u * shutter_open_time_; }
    // The medium the camera stands in (Mitsuba: a <medium> or <ref> nested in the sensor); null
    // for vacuum.
    const Medium* medium() const { return medium_.get(); }
    // Where in its pixel a camera sample lies: `u` uniform in [0,1)^2 (jittered, the default)
    // or the pixel's centre (Mitsuba's jitter = false).
    Vec2 pixel_offset(const Vec2& u) const { return jitter_ ? u : Vec2(0.5f); }
    bool jitter() const { return jitter_; }
    // The spectral variant's sensor response (`srf`), or null: see SensorResponse.
    const SensorResponse* response() const { return response_.get(); }

protected:
    // What every sensor reads, as Mitsuba's Sensor does: film and sampler (nested; default
    // hdrfilm and DefaultSampler), a medium, shutter_open and shutter_close, and srf.
    explicit Sensor(const Properties& props);

    Ref<Medium> medium_;
    Ref<Film> film_;
    Ref<Sampler> sampler_;
    Transform to_world_;
    bool jitter_ = true;
    float shutter_open_ = 0.0f, shutter_open_time_ = 0.0f;
    std::shared_ptr<const SensorResponse> response_;
};

}  // namespace candela
