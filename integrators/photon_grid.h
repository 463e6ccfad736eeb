#pragma once
// Photons (the deposits of light paths on surfaces) and a hash grid over them for radius queries
// (spatial hashing, Teschner et al. 2003), as sppm and photonmapper use them.
//
// Determinism: build() is a stable counting sort of the photons by hash bucket, so every bucket
// lists its photons in index order; a query visits the cells it overlaps in a fixed order and
// each cell's photons in index order. Sums over a query are therefore the same floating-point
// sums whatever the thread count.

#include "core/math.h"
#include "core/spectrum.h"

#include <cstdint>
#include <vector>

namespace candela {

struct Photon {
    Vec3 p{0.0f};
    Vec3 wi{0.0f};       // unit direction back toward where the photon came from (world)
    Spectrum beta{0.0f};  // flux weight (W per emitted path)
    uint32_t depth = 0;   // segments from the emitter to p
};

class PhotonGrid {
public:
    // Bins `photons` (kept by reference: they must outlive the grid) into cubic cells of side
    // `cell_size`; queries are fastest with radii up to the cell size.
    void build(const std::vector<Photon>& photons, float cell_size);
    bool empty() const { return photons_ == nullptr || photons_->empty(); }

    // Calls f(photon, squared distance) for every photon within `radius` of p, in a fixed order.
    template <typename F>
    void for_each_within(const Vec3& p, float radius, F&& f) const {
        if (empty()) return;
        const float r2 = radius * radius;
        const glm::ivec3 lo = cell_of(p - Vec3(radius)), hi = cell_of(p + Vec3(radius));
        for (int x = lo.x; x <= hi.x; ++x)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int z = lo.z; z <= hi.z; ++z) {
                    const glm::ivec3 cell(x, y, z);
                    const size_t b = bucket(cell);
                    for (uint32_t k = starts_[b]; k < starts_[b + 1]; ++k) {
                        const Photon& ph = (*photons_)[order_[k]];
                        if (cell_of(ph.p) != cell) continue;  // another cell hashed into this bucket
                        float d2 = squared_length(ph.p - p);
                        if (d2 <= r2) f(ph, d2);
                    }
                }
    }

private:
    glm::ivec3 cell_of(const Vec3& p) const {
        Vec3 c = glm::floor(p * inv_cell_size_);
        // Clamped so that far-away points cannot overflow the integer cell coordinates.
        return glm::ivec3(glm::clamp(c, Vec3(-1e9f), Vec3(1e9f)));
    }
    size_t bucket(const glm::ivec3& c) const {
        uint64_t h = uint64_t(uint32_t(c.x)) * 73856093u ^ uint64_t(uint32_t(c.y)) * 19349663u ^ uint64_t(uint32_t(c.z)) * 83492791u;
        return size_t(h & (starts_.size() - 2));  // bucket count is a power of two
    }

    const std::vector<Photon>* photons_ = nullptr;
    float inv_cell_size_ = 1.0f;
    std::vector<uint32_t> starts_;  // bucket b holds order_[starts_[b] .. starts_[b + 1])
    std::vector<uint32_t> order_;   // photon indices sorted by bucket, ascending within a bucket
};

}  // namespace candela
