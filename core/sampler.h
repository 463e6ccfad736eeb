#pragma once
// Samplers hand out the random numbers of one pixel sample. A sample's numbers depend only on
// (seed, pixel, sample index, dimension), never on thread or tile order or on which other samples
// were taken, so renders are reproducible bit for bit with any number of threads and any sample
// range [begin, end) of a pixel gives the same numbers as the whole.
//
// Dimensions count scalars: next_1d() takes one, next_2d() two. A path hands them out in a fixed
// layout (SampleDimensions below), so that the best-distributed dimensions of a low-discrepancy
// sampler reach the same integrand in every sample.

#include "core/math.h"
#include "core/object.h"
#include "core/rng.h"

namespace candela {

class Properties;

class Sampler : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Sampler; }

    int sample_count() const { return sample_count_; }
    // Samplers that need a particular count (a square, a power of two, ...) round `spp` up as
    // Mitsuba (or pbrt-v4, for sobol and zsobol) does; sample_count() then gives the rounded count.
    virtual void set_sample_count(int spp) { sample_count_ = spp; }
    uint64_t seed() const { return seed_; }
    void set_seed(uint64_t seed) { seed_ = seed; }
    // The size of the whole film in pixels. Samplers whose sequences span the image (sobol,
    // zsobol) need it; the sensor tells its sampler when both are built.
    virtual void set_film_size(const Vec2i& size) {}

    // Each thread works on its own copy.
    virtual Ref<Sampler> clone() const = 0;
    // Positions the sampler at sample `index` (below sample_count()) of `pixel` (film
    // coordinates, crop included), at dimension 0.
    virtual void start(const Vec2i& pixel, uint32_t index) = 0;
    // Continues at dimension `d` (see SampleDimensions).
    void set_dimension(uint32_t d) { dimension_ = d; }
    uint32_t dimension() const { return dimension_; }
    virtual float next_1d() = 0;
    virtual Vec2 next_2d() = 0;
    // True when a pixel's samples are stratified only as a whole: a pixel that adaptive sampling
    // stops early keeps a random subset of the strata and loses the stratification.
    virtual bool stratified_only_as_a_whole() const { return false; }

protected:
    int sample_count_ = 4;
    uint64_t seed_ = 0;
    uint32_t dimension_ = 0;  // the next dimension handed out
};

// The sampler of a sensor that names none: the one that measured best (bench/bench_samplers.cpp;
// README says why).
constexpr const char* DefaultSampler = "stratified";

// The dimensions of a camera path: the film position, the aperture, then per bounce (scattering
// vertex k, counted from 0 at the first surface the camera ray meets) the light pick, the
// position on the light, the BSDF lobe, the BSDF direction and Russian roulette. Every bounce
// claims all of them whether it uses them or not, so bounce k always starts at bounce(k).
//
// The shutter time (drawn only when the sensor's shutter is open for a while) has a dimension of
// its own far beyond any path's bounces, so that a scene that does not draw it keeps its layout
// and its images bit for bit (Mitsuba draws it after the aperture, which would shift them).
struct SampleDimensions {
    static constexpr uint32_t Film = 0, Aperture = 2, FirstBounce = 4, PerBounce = 7;
    static constexpr uint32_t Time = 0x7fffff00u;
    // Offsets within a bounce.
    static constexpr uint32_t LightPick = 0, LightPosition = 1, Lobe = 3, Direction = 4, Roulette = 6;
    static constexpr uint32_t bounce(uint32_t k) { return FirstBounce + PerBounce * k; }
};

// Seeds a PCG32 for one sample: state from (seed, pixel), stream from (seed, sample index).
inline void seed_for_sample(PCG32& rng, uint64_t seed, const Vec2i& pixel, uint32_t index) {
    uint64_t pixel_key = (uint64_t(uint32_t(pixel.y)) << 32) | uint32_t(pixel.x);
    rng.seed(hash_combine(seed, pixel_key), hash_combine(~seed, index));
}

}  // namespace candela
