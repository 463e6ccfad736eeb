#pragma once
// Volumes: spatially varying values (a medium's sigma_t or albedo) over a region of space, as
// Mitsuba 3's Volume. A volume's local coordinates are the unit cube [0, 1]^3, placed in the
// world by `to_world` (default: the identity); constvolume has one value everywhere, gridvolume
// interpolates a voxel grid (Mitsuba's .vol files).
//
// A volume holds 1 (grey), 3 (rgb) or 6 values per point. Six are not a colour but the
// entries S_xx, S_yy, S_zz, S_xy, S_xz, S_yz of a symmetric 3x3 matrix (SGGX's S, Mitsuba's
// eval_6): only eval_channels reads them, and get_volume refuses them where a colour is meant.
//
// In the spectral variant a medium asks for the values at the path's wavelengths, for the role
// its parameter plays (eval_spectrum: albedo a reflectance, sigma_t unbounded, as Mitsuba 3's
// spectral variants upsample them): a grey value is the flat spectrum of itself, a colour is
// interpolated as a colour and then upsampled (rgb_at_wavelengths), a measured spectrum (a
// constvolume given a <spectrum>) gives its own values.

#include "core/object.h"
#include "core/properties.h"
#include "core/spectrum.h"
#include "core/transform.h"
#include "core/wavelengths.h"

namespace candela {

class Volume : public Object {
public:
    explicit Volume(const Properties& props);
    ObjectKind kind() const override { return ObjectKind::Volume; }

    // The value at a world-space point (a grey volume's value in all three channels).
    virtual Spectrum eval(const Vec3& p_world) const = 0;
    // Values per point: 1, 3 or 6.
    int channel_count() const { return channels_; }
    // All channel_count() values at a world-space point, into out[0 .. channel_count()).
    virtual void eval_channels(const Vec3& p_world, float* out) const = 0;
    // Each channel's largest value anywhere in the volume, into out[0 .. channel_count()).
    virtual void max_channels(float* out) const = 0;
    // A bound, channel by channel, on every value eval() can return at a point whose local
    // coordinates lie in the box [lo, hi] (a majorant grid's cell).
    virtual Spectrum max_in_local_box(const Vec3& lo, const Vec3& hi) const = 0;
    Spectrum max() const { return max_in_local_box(Vec3(0.0f), Vec3(1.0f)); }
    // The value at a world-space point at the wavelengths `w`, as a spectrum of role `role`.
    virtual Spectrum eval_spectrum(const Vec3& p_world, const Wavelengths& w, SpectrumRole role) const;
    // A bound, the same at every wavelength, on eval_spectrum(p, w, Unbounded) for every w and
    // every point whose local coordinates lie in [lo, hi] (the spectral variant's majorants).
    // By default the value itself for a grey volume (a flat spectrum), else 2 max(rgb) over the
    // box: the unbounded spectrum of rgb is 2 max(rgb) times a sigmoid, which lies in [0, 1].
    virtual float max_spectrum_in_local_box(const Vec3& lo, const Vec3& hi) const;
    // One value everywhere (constvolume).
    virtual bool is_constant() const { return false; }
    // Voxels along each axis (1 for a constant), for sizing majorant grids.
    virtual glm::ivec3 resolution() const { return glm::ivec3(1); }

    const Transform& to_world() const { return to_world_; }
    Vec3 to_local(const Vec3& p_world) const { return to_local_.apply_point(p_world); }
    Vec3 to_local_vector(const Vec3& v_world) const { return to_local_.apply_vector(v_world); }
    // The world-space bounding box of the unit cube.
    const BoundingBox& bbox() const { return bbox_; }

protected:
    // Places the unit cube by `to_world` (and updates to_local and the bounding box).
    void set_to_world(const Transform& to_world);
    Transform to_world_, to_local_;
    BoundingBox bbox_;
    int channels_ = 3;
};

// A volume-valued parameter as Mitsuba's props.volume(): a nested <volume>, or a float or rgb
// (or <spectrum>) constant made into a constvolume; `def` when absent. A 6-channel volume is
// refused here: these values are colours or numbers.
Ref<Volume> get_volume(const Properties& props, const std::string& name, const Spectrum& def);

}  // namespace candela
