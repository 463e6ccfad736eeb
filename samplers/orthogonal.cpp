// orthogonal: orthogonal array sampling (Jarosz, Enayet, Kensler, Kilpatrick and Christensen
// 2019, "Orthogonal Array Sampling for Monte Carlo Rendering"), Mitsuba 3's orthogonal sampler.
//
// Parameters (Mitsuba 3):
//   sample_count   integer   samples per pixel, rounded up to p * p for a prime p (default 4)
//   seed           integer   seed offset (default 0)
//   jitter         boolean   a uniform random position inside each substratum; false puts every
//                            sample at its substratum's centre (default true)
//   strength       integer   the orthogonal array's strength t (default 2). With t = 2 (Bose's
//                            construction) every pair of dimensions is stratified in p x p cells
//                            as multi-jitter is, and every dimension in p * p strata. Bush's
//                            construction for t > 2 indexes an array of p^t rows with the
//                            pixel's p * p samples, which Mitsuba does not recommend either.
//
// Bose's array has p + 1 distinct columns (a0, a1, then a0 + k a1 mod p for k = 1 .. p - 1): the
// dimensions come in groups of p + 1, one per column, whose rows (the pixel's samples) share one
// shuffle, so every pair within a group is stratified; each group has its own row shuffle, which
// decorrelates the groups (Mitsuba instead reuses the columns, so that dimensions p apart are
// coupled one to one: a test of the 2D projections showed it). Each dimension then relabels its
// symbols with its own permutations.

#include "core/properties.h"
#include "core/registry.h"
#include "samplers/pixel_sampler.h"

namespace candela {

namespace {
bool is_prime(int x) {
    for (int i = 2; i * i <= x; ++i)
        if (x % i == 0) return false;
    return x >= 2;
}
}  // namespace

class OrthogonalSampler final : public PixelSequenceSampler {
public:
    explicit OrthogonalSampler(const Properties& props) {
        jitter_ = props.get_bool("jitter", true);
        strength_ = props.get_int("strength", 2);
        if (strength_ < 2) props.fail("strength", "the orthogonal array's strength must be at least 2");
        read_count_and_seed(props, "the square of a prime, as Mitsuba does");
        if (array_rows() > 0xffffffffull) props.fail("strength", "the orthogonal array would have more than 2^32 rows (prime^strength)");
    }

    Ref<Sampler> clone() const override { return std::make_shared<OrthogonalSampler>(*this); }
    std::string to_string() const override { return "orthogonal"; }

    float next_1d() override {
        uint32_t dim = dimension_++;
        return strength_ == 2 ? bose(dim) : bush(dim);
    }
    Vec2 next_2d() override {
        float x = next_1d();
        return Vec2(x, next_1d());
    }

protected:
    int round_sample_count(int spp) override {
        prime_ = 2;
        while (int64_t(prime_) * prime_ < spp || !is_prime(prime_)) ++prime_;
        rows_ = uint32_t(std::min<uint64_t>(array_rows(), 0xffffffffull));
        prime_divisor_ = Divisor(uint32_t(prime_));
        rows_divisor_ = Divisor(rows_);
        substrata_divisor_ = Divisor(rows_ / uint32_t(prime_));
        return prime_ * prime_;  // the next prime above 2^15 is 32771: 32771^2 < 2^31
    }

private:
    // p^strength, saturated beyond 2^33.
    uint64_t array_rows() const {
        uint64_t rows = 1;
        for (int k = 0; k < strength_ && rows <= 0xffffffffull; ++k) rows *= uint64_t(prime_);
        return rows;
    }

    // The stratum (symbol of column `dim`) and substratum of this sample, each relabelled by the
    // column's own permutation, jittered: (stratum + (substratum + jitter) / sub_count) / p.
    float place(uint32_t dim, uint32_t symbol, uint32_t sub, const Divisor& sub_count) const {
        uint32_t stratum = permute_index(symbol, prime_divisor_, dimension_seed(dim, 1));
        uint32_t substratum = permute_index(sub, sub_count, dimension_seed(dim, 2));
        float j = jitter_ ? jitter(dim) : 0.5f;
        return clamp_below_one((float(stratum) + (float(substratum) + j) / float(sub_count.n)) / float(prime_));
    }

    // Bose's OA(p^2, p + 1, p, 2): row i = (a0, a1) in base p; column 0 is a0, column 1 is a1,
    // column j >= 2 is a0 + (j - 1) a1 mod p. The substratum is the neighbouring column's symbol,
    // which is orthogonal to this one, so each dimension is stratified in p^2 strata too.
    float bose(uint32_t dim) const {
        const uint32_t p = uint32_t(prime_);
        const uint32_t group = dim / (p + 1), c = dim % (p + 1);
        uint32_t row = permute_index(index_, count_divisor_, dimension_seed(group, 0));
        uint32_t a0 = prime_divisor_.quotient(row), a1 = row - a0 * p;
        auto column = [&](uint32_t j) { return j == 0 ? a0 : j == 1 ? a1 : prime_divisor_.remainder(a0 + (j - 1) * a1); };
        uint32_t neighbour = (c ^ 1u) <= p ? (c ^ 1u) : 0;
        return place(dim, column(c), column(neighbour), prime_divisor_);
    }

    // Bush's OA(p^t, p, t): row i has base-p digits c_0 ... c_{t-1}; column j holds the
    // polynomial sum c_k j^k evaluated mod p. The substratum is the row's remaining digits. As
    // for Bose's array, each group of p dimensions has its own row shuffle.
    float bush(uint32_t dim) const {
        const uint32_t p = uint32_t(prime_);
        uint32_t row = permute_index(index_, rows_divisor_, dimension_seed(dim / p, 0));
        uint32_t x = dim % p, symbol = 0, rest = row;
        uint32_t digits[32];
        for (int k = 0; k < strength_; ++k, rest /= p) digits[k] = rest % p;
        for (int k = strength_ - 1; k >= 0; --k) symbol = uint32_t((uint64_t(symbol) * x + digits[k]) % p);
        return place(dim, symbol, substrata_divisor_.remainder(prime_divisor_.quotient(row)), substrata_divisor_);
    }

    bool jitter_ = true;
    int strength_ = 2;
    int prime_ = 2;
    uint32_t rows_ = 4;
    // What the draws divide by: p, the array's rows and Bush's substrata per stratum (rows / p).
    Divisor prime_divisor_{2}, rows_divisor_{4}, substrata_divisor_{2};
};

CANDELA_REGISTER(OrthogonalSampler, ObjectKind::Sampler, "orthogonal");

}  // namespace candela
