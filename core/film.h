#pragma once
// The film (Mitsuba's `hdrfilm`) and the image blocks that accumulate filtered samples.

#include "core/error.h"
#include "core/filter.h"
#include "core/object.h"
#include "core/spectrum.h"
#include "core/wavelengths.h"

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace candela {

// Mitsuba's pixel formats: the film's own channels, before any AOVs.
enum class PixelFormat { Luminance, LuminanceAlpha, RGB, RGBA, XYZ, XYZA };

// The channels a pixel format writes, named as Mitsuba names them: Y; Y, A; R, G, B; R, G, B, A;
// X, Y, Z; X, Y, Z, A.
std::vector<std::string> pixel_format_channels(PixelFormat format);
bool pixel_format_has_alpha(PixelFormat format);
// Writes the channels of `format` from filtered linear sRGB and alpha (the fraction of the
// filter weight that came from valid samples). XYZ and Y are linear in RGB (CIE 1931 through
// Rec. 709 primaries), so converting after filtering equals converting every sample.
void write_pixel_format(PixelFormat format, const Spectrum& rgb, float alpha, float* out);

// A spectral film's channels (Mitsuba's specfilm), in the spectral variants: one per sensor
// response function srf_j, each the integral of srf_j(l) L(l) dl over 360-830 nm (no CIE
// normalisation). Wavelengths are drawn in proportion to the sum of the responses (`sampling`),
// so each sample's band values are (1/n) sum_i srf_j(l_i) L(l_i) / p(l_i) over its n wavelengths.
struct FilmBands {
    std::vector<std::string> names;          // the channels, in alphabetical order (Mitsuba's)
    std::vector<SampledSpectrum> responses;  // srf_j, in the order of `names`
    std::shared_ptr<const SensorResponse> sampling;

    // Throws SpectrumFormatError when their sum is negative somewhere or zero over 360-830 nm
    // (SensorResponse); specfilm refuses a negative band at its own line first.
    FilmBands(std::vector<std::string> names, std::vector<SampledSpectrum> responses);
    int count() const { return int(names.size()); }
    // The band values of one sample (count() of them) from its values at the wavelengths `w`.
    void values(const Spectrum& L, const Wavelengths& w, float* out) const;
};

// At most this many bands per film: a sample's values live on the stack of the pixel loop.
constexpr int MaxFilmBands = 32;

class Film : public Object {
public:
    ObjectKind kind() const override { return ObjectKind::Film; }
    virtual Vec2i full_size() const = 0;  // width, height of the whole film
    virtual Vec2i crop_offset() const = 0;
    virtual Vec2i crop_size() const = 0;  // the size of the image that is written
    virtual const ReconstructionFilter& filter() const = 0;
    virtual bool float32() const = 0;  // component_format: float32 or float16
    virtual PixelFormat pixel_format() const = 0;
    // A spectral film's bands, which replace the pixel format's channels; null for an RGB film.
    virtual const FilmBands* bands() const { return nullptr; }
    // Mitsuba's sample_border: pixels within the filter's reach outside the crop window are
    // sampled too, so that edge pixels get their full filter support.
    virtual bool sample_border() const = 0;
    // Where the scene declares the film (for errors about its size).
    virtual SourceLocation location() const { return {}; }
};

// Stops with an InputError when `film` renders bands (a specfilm) for what needs the image's
// colour; `use` says what and why ("--png previews the image's colour").
void require_colour_film(const Film& film, const std::string& use);

// The ring of pixels around the crop that is sampled too: the filter's reach with sample_border,
// else 0. Samplers serve the full film grown by it (Sampler::set_film).
int film_sampled_border(const Film& film);

// "film 1920 x 1080", or "film crop window 640 x 480" when a crop window is rendered: how the
// memory checks name the image they size.
std::string film_description(const Film& film);

// A sample value is stored only when finite and at most MaxSampleMagnitude in size. Image blocks
// sum filtered samples in float: with values up to 1e30, 3.4e8 samples fit in a pixel before the
// sum overflows to infinity (found by fuzz_image: a PFM texture of 3.4e38 values). No physical
// radiance comes near it; such samples are dropped and counted as the non-finite ones are.
constexpr float MaxSampleMagnitude = 1e30f;
inline bool storable_sample_value(float v) { return std::fabs(v) <= MaxSampleMagnitude; }
inline bool storable_sample_value(const Spectrum& v) {
    return storable_sample_value(v.x) && storable_sample_value(v.y) && storable_sample_value(v.z);
}

// A rectangle of the film that accumulates sum(w * v) for each of `channels` values per sample
// and sum(w) per pixel, with a border of the filter's radius so that samples near the edge can
// reach neighbouring pixels. Blocks are merged into the final image in a fixed order, which
// keeps renders deterministic.
class ImageBlock {
public:
    ImageBlock() = default;
    // `offset` and `size` are in film pixels (the crop's coordinate system).
    ImageBlock(const Vec2i& offset, const Vec2i& size, const ReconstructionFilter* filter, int channels = 3);
    // How many pixels beyond its own a sample reaches with this filter: the farthest pixel centre
    // within the filter radius of a point inside the pixel is ceil(radius - 0.5) pixels away.
    static int reach(const ReconstructionFilter& filter);

    // Splats `channels()` values at continuous film position `pos` (in pixels, crop coordinates).
    void put(const Vec2& pos, const float* values);
    void put(const Vec2& pos, const Spectrum& L) { put(pos, &L[0]); }  // a block of 3 channels
    // Adds this block into a full-size accumulation buffer (channels() + 1 values per pixel: the
    // weighted sums, then the weight).
    void accumulate_into(std::vector<double>& buffer, const Vec2i& buffer_size) const;
    void clear();

    const Vec2i& offset() const { return offset_; }
    const Vec2i& size() const { return size_; }
    int channels() const { return channels_; }

private:
    // put() for a sample whose filter reaches more than one pixel: pixels first..last (stored
    // area coordinates) around `local`.
    void put_footprint(const Vec2& local, const Vec2i& first, const Vec2i& last, const float* values);

    Vec2i offset_{0}, size_{0};
    int border_ = 0, channels_ = 3;
    Vec2i stored_size_{0};
    const ReconstructionFilter* filter_ = nullptr;
    std::vector<float> data_;  // (channels values, weight) per stored pixel
};

}  // namespace candela
