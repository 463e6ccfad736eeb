#include "integrators/photon_grid.h"

namespace candela {

void PhotonGrid::build(const std::vector<Photon>& photons, float cell_size) {
    photons_ = &photons;
    inv_cell_size_ = 1.0f / std::max(cell_size, 1e-20f);
    size_t buckets = 1;
    while (buckets < 2 * photons.size()) buckets *= 2;
    starts_.assign(buckets + 1, 0);
    order_.resize(photons.size());
    // Counting sort by bucket; placing photons in index order keeps each bucket sorted.
    std::vector<uint32_t> of(photons.size());
    for (size_t i = 0; i < photons.size(); ++i) {
        of[i] = uint32_t(bucket(cell_of(photons[i].p)));
        ++starts_[of[i] + 1];
    }
    for (size_t b = 0; b < buckets; ++b) starts_[b + 1] += starts_[b];
    std::vector<uint32_t> next(starts_.begin(), starts_.end() - 1);
    for (size_t i = 0; i < photons.size(); ++i) order_[next[of[i]]++] = uint32_t(i);
}

}  // namespace candela
