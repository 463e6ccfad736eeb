// stratified: one sample per stratum of a regular grid, in every dimension (Mitsuba 3's
// stratified sampler).
//
// Parameters (Mitsuba 3):
//   sample_count   integer   samples per pixel, rounded up to a square N = r * r (default 4)
//   seed           integer   seed offset (default 0)
//   jitter         boolean   a uniform random position inside each stratum; false puts every
//                            sample at its stratum's centre (default true)
//
// A 1D dimension has N strata of width 1/N; a 2D dimension an r x r grid. In each dimension the
// pixel's sample indices are shuffled by their own permutation (Kensler's hashed permutation,
// seeded by pixel and dimension), so every dimension is stratified and the dimensions are
// decorrelated from each other.

#include "core/properties.h"
#include "core/registry.h"
#include "samplers/pixel_sampler.h"

namespace candela {

class StratifiedSampler final : public PixelSequenceSampler {
public:
    explicit StratifiedSampler(const Properties& props) {
        jitter_ = props.get_bool("jitter", true);
        read_count_and_seed(props, "a square, as Mitsuba does");
    }

    Ref<Sampler> clone() const override { return std::make_shared<StratifiedSampler>(*this); }
    std::string to_string() const override { return "stratified"; }

    float next_1d() override {
        uint32_t dim = dimension_++;
        uint32_t stratum = permute_index(index_, count_divisor_, dimension_seed(dim));
        float j = jitter_ ? jitter(dim) : 0.5f;
        // x / n as x * (1 / n) where that is exact (n a power of two): a division's latency
        // would sit on every number drawn.
        float x = float(stratum) + j;
        return clamp_below_one(inv_sample_count_ != 0.0f ? x * inv_sample_count_ : x / float(sample_count_));
    }

    Vec2 next_2d() override {
        uint32_t dim = dimension_;
        dimension_ += 2;
        uint32_t stratum = permute_index(index_, count_divisor_, dimension_seed(dim));
        uint32_t y = resolution_divisor_.quotient(stratum), x = stratum - y * uint32_t(resolution_);
        Vec2 j = jitter_ ? jitter_2d(dim) : Vec2(0.5f);
        float inv = 1.0f / float(resolution_);
        return Vec2(clamp_below_one((float(x) + j.x) * inv), clamp_below_one((float(y) + j.y) * inv));
    }

protected:
    int round_sample_count(int spp) override {
        resolution_ = 1;
        while (int64_t(resolution_) * resolution_ < spp) ++resolution_;
        resolution_divisor_ = Divisor(uint32_t(resolution_));
        const int count = resolution_ * resolution_;  // at most 32768^2 = 2^30 for spp <= 2^30
        inv_sample_count_ = (count & (count - 1)) == 0 ? 1.0f / float(count) : 0.0f;
        return count;
    }

private:
    bool jitter_ = true;
    int resolution_ = 2;
    Divisor resolution_divisor_{2};
    float inv_sample_count_ = 0.0f;  // 1 / sample_count_ when exact, else 0
};

CANDELA_REGISTER(StratifiedSampler, ObjectKind::Sampler, "stratified");

}  // namespace candela
