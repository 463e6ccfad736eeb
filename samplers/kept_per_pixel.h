#pragma once
// What a sampler computes from the current pixel alone and keeps for the pixel's other samples:
// entry k (below Count) is computed on first use and kept while keep_for() is called with the
// same key: everything the entries depend on (the pixel, and the seed, sample count or film where
// they matter). A sampler's pixels come one after another (the pixel loop), so one set of entries
// suffices. Entries past Count are the caller's to compute each time.

#include <array>
#include <bitset>
#include <cstddef>

namespace candela {

template <typename Key, typename Value, std::size_t Count>
class KeptPerPixel {
public:
    static constexpr std::size_t size = Count;

    // Whether the entries were kept for another key (or none yet): then they are forgotten, and
    // kept for `key` from now on.
    bool keep_for(const Key& key) {
        if (has_key_ && key_ == key) return false;
        key_ = key;
        has_key_ = true;
        kept_.reset();
        return true;
    }

    // Entry k < Count: compute() the first time for the key, the kept value after that.
    template <typename Compute>
    const Value& get(std::size_t k, Compute&& compute) {
        if (!kept_[k]) {
            values_[k] = compute();
            kept_[k] = true;
        }
        return values_[k];
    }

private:
    Key key_{};
    bool has_key_ = false;
    std::bitset<Count> kept_;
    std::array<Value, Count> values_{};
};

}  // namespace candela
