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

#include <string>

namespace candela {

class Properties;

// Where one sample stands in its sampler: what start() set and the next dimension, with what the
// sampler derived from them (a hashed sequence, a generator's state) in `words`. Only the sampler
// that saved it reads it.
struct SamplerState {
    Vec2i pixel{0};
    uint32_t index = 0, dimension = 0;
    uint64_t words[2] = {0, 0};
};

class Sampler : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Sampler; }

    int sample_count() const { return sample_count_; }
    // Samplers that need a particular count (a square, a power of two, ...) round `spp` up as
    // Mitsuba (or pbrt-v4, for sobol and zsobol) does; sample_count() then gives the rounded count.
    // `spp` must lie in [1, MaxSampleCount] (check_sample_count says so to the user first).
    void set_sample_count(int spp);
    uint64_t seed() const { return seed_; }
    void set_seed(uint64_t seed) { seed_ = seed; }
    // The pixels this sampler serves: a film of `size` pixels and the ring of `border` pixels
    // around it that a crop's sample_border may sample (film_sampled_border). Samplers whose
    // sequences span the image (sobol, zsobol) lay them over all of these; every sampler checks
    // that start() stays inside. The sensor tells its sampler when both are built.
    void set_film(const Vec2i& size, int border);
    Vec2i film_size() const { return film_size_; }
    int film_border() const { return film_border_; }

    // Each thread works on its own copy.
    virtual Ref<Sampler> clone() const = 0;
    // Positions the sampler at sample `index` of `pixel` (film coordinates, crop included), at
    // dimension 0. The contract, checked in every build (a wrong index would walk a permutation's
    // cycles forever, a wrong pixel read past a sequence's tables): index below sample_count(),
    // pixel inside the film plus its border. A call outside it throws InternalError.
    void start(const Vec2i& pixel, uint32_t index) {
        if (index >= uint32_t(sample_count_) || pixel.x < -film_border_ || pixel.y < -film_border_ ||
            pixel.x >= film_size_.x + film_border_ || pixel.y >= film_size_.y + film_border_)
            refuse_start(pixel, index);
        started_pixel_ = pixel;
        started_index_ = index;
        start_sample(pixel, index);
    }
    // For integrators that advance many samples in turn (a wavefront), one sampler serving them
    // all: save() where a sample stands (after start() and any draws) and restore() it later to go
    // on exactly there, the next numbers bit for bit those it would have drawn. The default keeps
    // the pixel, index and dimension and restores by start() and set_dimension(): right for every
    // sampler whose numbers depend on the dimension and not on the draws before. Stream samplers
    // (independent) must override both; others may, to skip start()'s hashing.
    virtual void save(SamplerState& state) const {
        state.pixel = started_pixel_;
        state.index = started_index_;
        state.dimension = dimension_;
    }
    virtual void restore(const SamplerState& state) {
        start(state.pixel, state.index);
        dimension_ = state.dimension;
    }
    // Continues at dimension `d` (see SampleDimensions).
    void set_dimension(uint32_t d) { dimension_ = d; }
    uint32_t dimension() const { return dimension_; }
    virtual float next_1d() = 0;
    virtual Vec2 next_2d() = 0;
    // Passes over the next 1D number without computing it, leaving every later number what it
    // would have been had it been drawn (a stream sampler steps its stream): for a number its
    // consumer would not read (BSDF::reads_lobe_sample, LightSampler::reads_pick_sample).
    virtual void skip_1d() { ++dimension_; }
    // True when a pixel's samples are stratified only as a whole: a pixel that adaptive sampling
    // stops early keeps a random subset of the strata and loses the stratification.
    virtual bool stratified_only_as_a_whole() const { return false; }

protected:
    // start() once the contract holds.
    virtual void start_sample(const Vec2i& pixel, uint32_t index) = 0;
    // The rounded count for `spp` (in [1, MaxSampleCount]); the default keeps it. Samplers that
    // derive more from the count (a grid's resolution) set it here too.
    virtual int round_sample_count(int spp) { return spp; }
    // Called after set_film() (sobol and zsobol rebuild what depends on the film's size).
    virtual void film_changed() {}

    int sample_count_ = 4;
    uint64_t seed_ = 0;
    uint32_t dimension_ = 0;  // the next dimension handed out
    Vec2i started_pixel_{0};  // what start() was last given (save())
    uint32_t started_index_ = 0;
    // The part of restore() every override shares: the sample's pixel, index and next dimension.
    void restore_position(const SamplerState& state) {
        started_pixel_ = state.pixel;
        started_index_ = state.index;
        dimension_ = state.dimension;
    }
    Vec2i film_size_{1};
    int film_border_ = 0;

private:
    [[noreturn]] void refuse_start(const Vec2i& pixel, uint32_t index) const;
};

// The most samples per pixel any sampler takes: 2^30, so that counts, their rounding (up to a
// square or a power of two) and sample indices fit an int.
constexpr int MaxSampleCount = 1 << 30;
// Why `spp` is not a sample count a sampler can take ("" when it is): whole, in [1, 2^30].
std::string sample_count_problem(int64_t spp);

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
    static constexpr uint32_t Wavelength = 0x7fffff01u;  // the spectral variant's wavelengths
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
