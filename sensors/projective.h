#pragma once
// What perspective, thinlens and orthographic share (Mitsuba's Sensor and ProjectiveCamera):
//   to_world           transform   camera to world (default identity), or an
//                      animation   <animation name="to_world"> of keyframes: each camera ray
//                                  takes the pose at its time (camera motion blur)
//   near_clip          float       distance of the near plane (default 0.01)
//   far_clip           float       distance of the far plane (default 10000)
//   focus_distance     float       distance of the focal plane (default far_clip); only thinlens
//                                  uses it, the others accept it, as in Mitsuba
//   shutter_open,      float       the exposure interval (default 0, 0): each camera ray's time
//   shutter_close                  is uniform in [open, close] (drawn from the sampler's
//                                  SampleDimensions::Time), or exactly open when they are equal;
//                                  animated to_worlds take their pose at that time
//   jitter             boolean     place each sample at a random point of its pixel (default
//                                  true); false puts every sample at the pixel's centre
//   cone_scale         float       scales the ray-cone footprints of Mitsuba's trilinear and
//                                  anisotropic bitmap filtering (default 1, positive); accepted
//                                  and unused, as Candela's bitmap filters (nearest, bilinear)
//                                  take no footprint, in Mitsuba neither
//   srf                spectrum    the sensor's spectral response, spectral variant only (RGB
//                                  rejects it, as Mitsuba's RGB variants do): wavelengths are
//                                  drawn in proportion to it and each sample is weighted by it,
//                                  so a pixel is the colour of srf(l) L(l) (core/wavelengths.h)
//   film, sampler      nested      default: hdrfilm and independent

#include "core/animated_transform.h"
#include "core/sensor.h"

namespace candela {

class ProjectiveCamera : public Sensor {
public:
    bool is_animated() const override { return motion_.is_animated(); }
    SourceLocation motion_location() const override { return motion_.where; }
    Transform pose_at(float time) const override { return motion_.is_animated() ? motion_.eval(time) : to_world_; }
    // "to_world" (a camera that does not move) and its film (core/parameters.h).
    void traverse(ParameterVisitor& visitor) override;
    void parameters_changed(const std::vector<std::string>& keys) override;
    bool reached_by_light_paths() const override { return true; }
    bool rays_coherent() const override { return true; }
    // A batch's slice: the aspect follows the new size; the field of view along x is kept.
    void set_film_size(const Vec2i& size) override;

protected:
    explicit ProjectiveCamera(const Properties& props);
    // Film position in pixels of the full film -> fractions in [0,1]^2, and back.
    Vec2 film_fraction(const Vec2& film_pos) const { return film_pos * inv_size_; }
    Vec2 film_pixels(const Vec2& fraction) const { return fraction / inv_size_; }
    static bool on_film(const Vec2& fraction) {
        return fraction.x >= 0.0f && fraction.x <= 1.0f && fraction.y >= 0.0f && fraction.y <= 1.0f;
    }
    // The full film's area in pixels: importance is measured per pixel.
    float film_area() const { return 1.0f / (inv_size_.x * inv_size_.y); }
    // A lens camera's connection from camera-space point `local` through lens point `lens`
    // (camera space, z = 0; the origin for a pinhole) that reaches the film at `fraction`: the
    // ray runs from the lens through `local`, entering the view at depth near_clip, and carries
    // W_e cos / dist^2 = film_area / (A cos^3 dist^2), A the image plane's area at depth 1
    // (4 tan(fov_x / 2) tan(fov_y / 2)): pixel area per solid angle, then per area at `local`.
    // `pose`: the camera's at the connection's shutter time (pose_at), of which `local` is in
    // camera space.
    SensorSample lens_connection(const Vec3& ref, const Vec3& local, const Vec3& lens, const Vec2& fraction, float tan_half_x,
                                 const Transform& pose) const;
    // Stops at to_world when some keyframe scales (the pinhole cameras' requirement).
    void refuse_scaling(const Properties& props) const;
    // The pinhole of a perspective or thin-lens camera: its pose, the field of view read from
    // props (fov, fov_axis or focal_length), the film's aspect and the clip distances.
    PinholeProjection pinhole_projection(const Properties& props) const;
    // After to_world changed: what the camera derives from its pose.
    virtual void pose_changed() {}
    // After set_film_size: what the camera derives from its film's aspect.
    virtual void film_size_changed() {}
    // A pinhole camera's "x_fov" (degrees), read and written through its tan(fov_x / 2).
    static void expose_x_fov(ParameterVisitor& visitor, PinholeProjection& projection);

    AnimatedTransform motion_;
    float aspect_ = 1.0f;  // width / height of the full film
    float near_clip_ = 0.01f, far_clip_ = 1e4f, focus_distance_ = 1e4f;

private:
    // The aspect and the pixel scale of a film of `size` (the constructor's film, or a batch's
    // slice); not virtual, as the constructor calls it.
    void take_size(const Vec2i& size);
    Vec2 inv_size_{1.0f};
};

}  // namespace candela
