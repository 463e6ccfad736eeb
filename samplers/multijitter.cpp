// multijitter: correlated multi-jittered sampling (Kensler 2013, "Correlated Multi-Jittered
// Sampling", Pixar technical memo 13-01), Mitsuba 3's multijitter sampler.
//
// Parameters (Mitsuba 3):
//   sample_count   integer   samples per pixel, rounded up to a grid of rows = floor(sqrt(n)) by
//                            columns = ceil(n / rows) cells (default 4)
//   seed           integer   seed offset (default 0)
//   jitter         boolean   a uniform random position inside each substratum; false puts every
//                            sample at its substratum's centre (default true)
//
// A 2D dimension puts one sample in each cell of the columns x rows grid and, within its cell,
// in a substratum chosen so that the N points are also stratified in N strata along each axis
// (multi-jitter). The substratum shuffles are the same for every row (and every column): that
// correlation is Kensler's, and it keeps the points from clumping. A 1D dimension is a jittered
// permutation of N strata. Every permutation is seeded by pixel and dimension.
// (Mitsuba releases after 3.5 round the count to a 3D grid for a next_3d() that Candela does not
// have, and their 2D points then share substrata; Candela keeps the 2D grid of the paper.)

#include "core/properties.h"
#include "core/registry.h"
#include "samplers/pixel_sampler.h"

#include <cmath>

namespace candela {

class MultijitterSampler final : public PixelSequenceSampler {
public:
    explicit MultijitterSampler(const Properties& props) {
        jitter_ = props.get_bool("jitter", true);
        read_count_and_seed(props, "a near-square grid, as Mitsuba does");
    }

    Ref<Sampler> clone() const override { return std::make_shared<MultijitterSampler>(*this); }
    std::string to_string() const override { return "multijitter"; }

    float next_1d() override {
        uint32_t dim = dimension_++;
        uint32_t stratum = permute_index(index_, count_divisor_, dimension_seed(dim, 1));
        float j = jitter_ ? jitter(dim) : 0.5f;
        return clamp_below_one((float(stratum) + j) / float(sample_count_));
    }

    Vec2 next_2d() override {
        uint32_t dim = dimension_;
        dimension_ += 2;
        const uint32_t nx = uint32_t(columns_), ny = uint32_t(rows_);
        // The cell (x, y) of this sample, then its substratum: sx shuffles the columns' x
        // substrata (the same shuffle in every row), sy the rows'.
        uint32_t s = permute_index(index_, count_divisor_, dimension_seed(dim, 2));
        uint32_t y = columns_divisor_.quotient(s), x = s - y * nx;
        uint32_t sx = permute_index(x, columns_divisor_, dimension_seed(dim, 3));
        uint32_t sy = permute_index(y, rows_divisor_, dimension_seed(dim, 4));
        Vec2 j = jitter_ ? jitter_2d(dim) : Vec2(0.5f);
        return Vec2(clamp_below_one((float(x) + (float(sy) + j.x) / float(ny)) / float(nx)),
                    clamp_below_one((float(y) + (float(sx) + j.y) / float(nx)) / float(ny)));
    }

protected:
    int round_sample_count(int spp) override {
        rows_ = std::max(1, int(std::sqrt(double(spp))));
        columns_ = (spp + rows_ - 1) / rows_;
        rows_divisor_ = Divisor(uint32_t(rows_));
        columns_divisor_ = Divisor(uint32_t(columns_));
        return rows_ * columns_;  // below spp + rows_, so within int for spp <= 2^30
    }

private:
    bool jitter_ = true;
    int rows_ = 2, columns_ = 2;
    Divisor rows_divisor_{2}, columns_divisor_{2};
};

CANDELA_REGISTER(MultijitterSampler, ObjectKind::Sampler, "multijitter");

}  // namespace candela
