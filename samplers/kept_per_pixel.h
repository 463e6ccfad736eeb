#pragma once
// What a sampler computes from the current pixel alone and keeps for the pixel's other samples:
// entry k (below Count) is computed on first use and kept until forget(), which the sampler calls
// when anything the entries depend on changes (the pixel, the seed, the sample count, the film).
// A sampler's pixels come one after another (the pixel loop), so one set of entries suffices.
// Entries past Count are the caller's to compute each time.

#include <array>
#include <bitset>
#include <cstddef>

namespace candela {

template <typename Value, std::size_t Count>
class KeptPerPixel {
public:
    static constexpr std::size_t size = Count;

    void forget() { kept_.reset(); }

    // Entry k < Count: compute() the first time after forget(), the kept value after that.
    template <typename Compute>
    const Value& get(std::size_t k, Compute&& compute) {
        if (!kept_[k]) {
            values_[k] = compute();
            kept_[k] = true;
        }
        return values_[k];
    }

private:
    std::bitset<Count> kept_;
    std::array<Value, Count> values_{};
};

}  // namespace candela
