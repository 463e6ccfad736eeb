#pragma once
// Participating media: the space inside (or outside) shapes, or around the camera, that absorbs
// and scatters light. A medium answers the extinction sigma_t and scattering coefficient
// sigma_s = albedo * sigma_t at a point (per unit length, per RGB channel or, in the spectral
// variant, per wavelength of the path), hands out majorants
// (bounds on sigma_t along a ray, one piece at a time), and owns a phase function. Free-flight
// sampling (delta tracking) and transmittance estimation (ratio tracking) work on any medium
// through those majorants (Novak et al., "Monte Carlo methods for volumetric light transport
// simulation", 2018); a homogeneous medium answers its transmittance in closed form.
//
// Media are attached as Mitsuba 3 attaches them: a shape's `interior` and `exterior` media (the
// medium a ray enters when it crosses the surface against or along its normal), and a sensor's
// medium (where camera rays start).
//
// The spectral variant (core/wavelengths.h): queries at a point take the path's wavelengths (null
// in the RGB variant, whose code path is unchanged), and the queries along a ray take them from
// Ray::wavelengths. sigma_t is an unbounded spectrum and the albedo a reflectance, as Mitsuba 3's
// spectral variants upsample them (core/volume.h); majorants bound sigma_t at every wavelength.

#include "core/phase.h"
#include "core/ray.h"
#include "core/rng.h"
#include "core/spectrum.h"

#include <vector>

namespace candela {

class Properties;
class Volume;

// The coefficients at a point, per unit length: per RGB channel, or at the path's wavelengths.
struct MediumPoint {
    Spectrum sigma_t{0.0f}, sigma_s{0.0f};
};

// A piece [t0, t1] of a ray over which sigma_t never exceeds sigma_maj, channel by channel (in
// the spectral variant, wavelength by wavelength).
struct MajorantSegment {
    float t0 = 0.0f, t1 = 0.0f;
    Spectrum sigma_maj{0.0f};
};

// Maxima of a volume's values over a coarse grid of cells spanning its unit cube (times a
// scale): the majorants of a heterogeneous medium. `spectral`: each cell holds instead one bound
// valid at every wavelength, Volume::max_spectrum_in_local_box (in all three components).
class MajorantGrid {
public:
    MajorantGrid() = default;
    MajorantGrid(const Volume& volume, const glm::ivec3& resolution, float scale, bool spectral = false);
    const glm::ivec3& resolution() const { return resolution_; }
    const Spectrum& at(const glm::ivec3& cell) const {
        return maxima_[(size_t(cell.z) * size_t(resolution_.y) + size_t(cell.y)) * size_t(resolution_.x) + size_t(cell.x)];
    }
    const Volume& volume() const { return *volume_; }

private:
    const Volume* volume_ = nullptr;
    glm::ivec3 resolution_{0};
    std::vector<Spectrum> maxima_;
};

// Walks a ray through its majorant segments in order: one segment for a homogeneous medium, a
// 3D DDA over the cells of a MajorantGrid otherwise (Amanatides and Woo 1987). Lives on the
// stack; nothing is allocated.
class MajorantIterator {
public:
    // No segment at all (a ray that misses the medium's bounds).
    MajorantIterator() = default;
    // One segment.
    MajorantIterator(float t0, float t1, const Spectrum& sigma_maj);
    // The cells of `grid` along the ray, clipped to [tmin, tmax].
    MajorantIterator(const MajorantGrid& grid, const Ray& ray, float tmin, float tmax);
    // The next segment; false when there is none.
    bool next(MajorantSegment& segment);
    // Multiplies every segment's majorant by `factor` (a microflake phase function's bound).
    void scale_by(float factor) { factor_ = factor; }

private:
    const MajorantGrid* grid_ = nullptr;
    bool done_ = true;
    float t0_ = 0.0f, t1_ = 0.0f;  // the current position and the end of the walk
    Spectrum sigma_{0.0f};         // for a single segment
    float factor_ = 1.0f;
    glm::ivec3 cell_{0}, step_{0};
    Vec3 next_t_{0.0f}, delta_t_{0.0f};
};

class Medium : public Object {
public:
    // Reads the parameters every medium shares (Mitsuba 3): `sample_emitters` (boolean,
    // default true: next-event estimation from points inside it) and the nested phase
    // function (default isotropic).
    explicit Medium(const Properties& props);
    ObjectKind kind() const override { return ObjectKind::Medium; }

    // The coefficients the medium holds at p, whatever the direction: in RGB (w null) or at the
    // wavelengths w.
    virtual MediumPoint coefficients(const Vec3& p, const Wavelengths* w) const = 0;
    MediumPoint coefficients(const Vec3& p) const { return coefficients(p, nullptr); }
    // The coefficients at p for light travelling along d (either way): coefficients(p, w), times
    // the projected area along d when the phase function is a microflake one (sggx), as Mitsuba
    // 3's media scale sigma_t by PhaseFunction::projected_area.
    MediumPoint eval(const Vec3& p, const Vec3& d, const Wavelengths* w = nullptr) const;
    // The majorant segments of the ray between ray.tmin and tmax (tmax may be infinite): they
    // bound eval(p, ray.d, ray.wavelengths) along it.
    MajorantIterator majorants(const Ray& ray, float tmax) const;
    // The transmittance from ray.tmin to tmax (at ray.wavelengths). By default ratio tracking with
    // one majorant for all channels (the largest), which is unbiased; homogeneous media answer
    // exactly.
    virtual Spectrum transmittance(const Ray& ray, float tmax, PCG32& rng) const;
    virtual bool is_homogeneous() const { return false; }

    const PhaseFunction& phase() const { return *phase_; }
    bool sample_emitters() const { return sample_emitters_; }

protected:
    // Majorants of coefficients(p, ray.wavelengths) along the ray (majorants() adds the
    // microflake factor).
    virtual MajorantIterator coefficient_majorants(const Ray& ray, float tmax) const = 0;
    // The phase function scales the extinction (cached is_microflake()).
    bool microflake_ = false;

private:
    Ref<PhaseFunction> phase_;
    bool sample_emitters_ = true;
};

// The weights of a path that crosses media, for delta tracking in RGB (or at the spectral
// variant's wavelengths, one per channel). Each channel k has its own
// sampling technique (free flights drawn with its majorant, real or null collisions chosen by
// its probabilities); one channel, `channel`, drew the path. `beta` is the path's throughput
// f over that technique's pdf, `ratio` every technique's pdf over that one's (ratio[channel] = 1).
// An estimate is beta / mean(ratio): the balance heuristic over the three techniques (spectral
// MIS, Miller et al. 2019), or beta alone when all channels share one majorant and one draw.
struct TrackingWeights {
    Spectrum beta{1.0f}, ratio{1.0f};
    int channel = 0;
    // True: every channel uses the largest channel's majorant (volpath). False: each channel its
    // own (volpathmis).
    bool shared_majorant = true;
    Spectrum estimate_weight() const { return beta / average(ratio); }
};

// Delta tracking from ray.tmin toward tmax: samples the distance to the next real collision.
// On a collision (returns true) `t` and `point` describe it and `weights` include its
// scattering coefficient sigma_s (the caller scatters by the phase function); otherwise the path
// passed through to tmax and `weights` include that.
bool sample_free_flight(const Medium& medium, const Ray& ray, float tmax, PCG32& rng, TrackingWeights& weights, float& t,
                        MediumPoint& point);

// Ratio tracking (Novak et al. 2014) from ray.tmin to tmax, with the largest channel's majorant.
Spectrum ratio_tracking_transmittance(const Medium& medium, const Ray& ray, float tmax, PCG32& rng);

}  // namespace candela
