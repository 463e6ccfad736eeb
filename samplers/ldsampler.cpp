// ldsampler: Kollig and Keller's scrambled (0, 2)-sequence (Kollig and Keller 2002, "Efficient
// Multidimensional Sampling"), Mitsuba 3's low-discrepancy sampler.
//
// Parameters (Mitsuba 3):
//   sample_count   integer   samples per pixel, rounded up to the square of a power of two of at
//                            least 2 (4, 16, 64, 256, ...; default 4)
//   seed           integer   seed offset (default 0)
//
// Every dimension is filled from the same (0, 2)-sequence (van der Corput for x, the second
// Sobol' dimension for y), XOR-scrambled by a random digital shift per pixel, which keeps the
// (0, 2) property: the pixel's N points have one point in every elementary interval of area 1/N.
// Each dimension visits the points in its own random order (Kensler's permutation seeded by pixel
// and dimension), which decorrelates the dimensions ("padding"). The 1D points are exactly
// stratified in N strata.

#include "core/properties.h"
#include "core/registry.h"
#include "samplers/pixel_sampler.h"

namespace candela {

class LowDiscrepancySampler final : public PixelSequenceSampler {
public:
    explicit LowDiscrepancySampler(const Properties& props) { read_count_and_seed(props, "the square of a power of two, as Mitsuba does"); }

    Ref<Sampler> clone() const override { return std::make_shared<LowDiscrepancySampler>(*this); }
    std::string to_string() const override { return "ldsampler"; }

    float next_1d() override {
        uint32_t i = point(dimension_++);
        return bits_to_unit(reverse_bits(i) ^ scramble_1d_);
    }
    Vec2 next_2d() override {
        uint32_t i = point(dimension_);
        dimension_ += 2;
        uint32_t x = reverse_bits(i) ^ scramble_x_;
        uint32_t y = sobol_dimension1(i) ^ scramble_y_;
        return Vec2(bits_to_unit(x), bits_to_unit(y));
    }

protected:
    // The pixel's scrambles depend on its sequence only: hashed when the pixel changes instead of
    // on every number drawn.
    void sequence_changed() override {
        scramble_1d_ = hash_bits(sequence_, 0x48bc48ebu);
        scramble_x_ = hash_bits(sequence_, 0x98bc51abu);
        scramble_y_ = hash_bits(sequence_, 0x68bc21ebu);
    }

    int round_sample_count(int spp) override {
        int r = 2;
        while (int64_t(r) * r < spp) r *= 2;
        return r * r;  // at most 2^30 for spp <= 2^30
    }

private:
    uint32_t scramble_1d_ = 0, scramble_x_ = 0, scramble_y_ = 0;
    // The point of the (0, 2)-sequence that dimension `dim` of this sample takes.
    uint32_t point(uint32_t dim) const { return permute_index(index_, count_divisor_, dimension_seed(dim)); }
};

CANDELA_REGISTER(LowDiscrepancySampler, ObjectKind::Sampler, "ldsampler");

}  // namespace candela
