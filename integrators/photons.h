#pragma once
// What sppm and photonmapper share: photons (the deposits of light paths on surfaces), a hash
// grid over them for radius queries (spatial hashing, Teschner et al. 2003), which surfaces
// gather photons, and the camera-side walk through the surfaces that do not.
//
// Determinism: build() is a stable counting sort of the photons by hash bucket, so every bucket
// keeps its photons in path order; a query visits the cells it overlaps in a fixed order and
// each cell's photons in that order. Sums over a query are therefore the same floating-point
// sums whatever the thread count.

#include "core/bsdf.h"
#include "core/math.h"
#include "core/properties.h"
#include "core/spectrum.h"
#include "core/wavelengths.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace candela {

class Scene;
class Sampler;

// Surfaces where photons are stored and gathered: a diffuse lobe and no delta lobe. Light and
// camera paths pass through the others (delta, glossy-only) by BSDF sampling.
inline bool gathers_photons(const BSDF& bsdf) { return (bsdf.flags() & Diffuse) != 0 && (bsdf.flags() & Delta) == 0; }

// Stops a photon integrator (`name`) built for the polarized variant at its line: its photons
// carry no Stokes vector.
void refuse_polarized_photons(const Properties& props, const char* name);

// Where a camera-side walk through non-gathering surfaces ends.
struct GatherPoint {
    SurfaceInteraction si;
    const BSDF* bsdf = nullptr;  // null: the walk ended without reaching a gathering surface
    Spectrum beta{0.0f};         // throughput from the walk's start to si
    uint32_t depth = 0;          // segments from the camera
    // Emission met on the way (times the throughput), split by whether every scattering since
    // the start was a delta one (light that a caustic photon map also carries) or not.
    Spectrum emission_after_delta{0.0f}, emission_after_other{0.0f};
};

struct WalkSettings {
    int max_depth = -1;  // segments from the camera, -1 unbounded
    int rr_depth = 5;
    bool hide_first = false;  // ignore emission at the walk's first hit (hide_emitters)
};

// Follows `ray` (whose origin is `depth` segments from the camera, with throughput `beta`) through
// delta and glossy-only surfaces by BSDF sampling, with Russian roulette as `path` applies it, to
// the first surface that gathers photons. Environment light along an escaping ray counts as
// emission.
GatherPoint walk_to_gather_point(const Scene& scene, Sampler& sampler, Ray ray, Spectrum beta, uint32_t depth,
                                 const WalkSettings& settings);

struct Photon {
    Vec3 p{0.0f};
    Vec3 wi{0.0f};  // unit direction back toward where the photon came from (world)
    Vec3 n{0.0f};   // the surface's geometric normal on the side the photon arrived from
    // Flux weight (W per emitted path), at the path's wavelengths in the spectral variants; a
    // binned photon (bin_photon_flux) keeps there each wavelength's share of its bin instead.
    Spectrum beta{0.0f};
    uint32_t depth = 0;  // segments from the emitter to p
    // The spectral variants: the path crossed a dispersive interface, so only its first (hero)
    // wavelength carries flux (core/wavelengths.h, terminate_secondary).
    bool hero_only = false;
    // A binned photon: the wavelength bin of each of beta's components (they fill the padding,
    // so a photon is as large with them as without).
    uint8_t bin[WavelengthSamples] = {0, 0, 0};
};
static_assert(sizeof(Photon) == 14 * sizeof(float), "a photon's bins fit in its padding");
// The photon a light path leaves at a vertex.
inline Photon make_photon(const SurfaceInteraction& si, const Spectrum& beta, uint32_t depth) {
    Vec3 wi = si.wi_world();
    return {si.p, wi,    glm::dot(wi, si.n) >= 0.0f ? si.n : -si.n,
            beta, depth, si.wavelengths != nullptr && si.wavelengths->secondary_terminated()};
}

// Binned spectral photons (photonmapper's maps in the spectral variant, which serve every camera
// sample's wavelengths; Mitsuba 0.6's spectral builds store photon flux as a histogram over
// wavelength bins likewise): SpectralBins bins of equal width over the range the light paths'
// wavelengths are drawn from, [CieMin, CieMax] nm. A photon's flux is the histogram whose bin b
// holds the sum over its wavelengths i in b of beta_i / (WavelengthSamples p_i), divided by the
// bin's width: an unbiased estimate of the flux per nm averaged over the bin (p_i the path's
// wavelength density; a dispersed path's hero alone, at p / WavelengthSamples, so its hero is
// weighed by 1 / p). A photon's wavelengths fall in at most WavelengthSamples bins, so the
// histogram is stored sparsely: component i of beta in bin[i]. A camera wavelength reads its
// bin's value: the flux is blurred over a bin's width.
constexpr int SpectralBins = 32;
constexpr float SpectralBinWidth = float((CieMax - CieMin) / SpectralBins);  // nm
inline uint8_t spectral_bin(float lambda_nm) {
    return uint8_t(std::clamp(int((lambda_nm - float(CieMin)) / SpectralBinWidth), 0, SpectralBins - 1));
}
// Turns a photon's flux at the wavelengths `w` of its path (as it arrived) into its histogram.
inline void bin_photon_flux(Photon& photon, const Wavelengths& w) {
    for (int i = 0; i < WavelengthSamples; ++i) {
        photon.bin[i] = spectral_bin(w.lambda[i]);
        photon.beta[i] = w.pdf[i] > 0.0f ? photon.beta[i] / (float(WavelengthSamples) * w.pdf[i] * SpectralBinWidth) : 0.0f;
    }
}
// The bins of a camera sample's wavelengths.
struct CameraBins {
    uint8_t bin[WavelengthSamples] = {0, 0, 0};
    CameraBins() = default;
    explicit CameraBins(const Wavelengths& w) {
        for (int j = 0; j < WavelengthSamples; ++j) bin[j] = spectral_bin(w.lambda[j]);
    }
};
// A binned photon's flux per nm at camera wavelengths in the bins `at`.
inline Spectrum binned_flux(const Photon& photon, const CameraBins& at) {
    Spectrum flux(0.0f);
    for (int j = 0; j < WavelengthSamples; ++j)
        for (int i = 0; i < WavelengthSamples; ++i)
            if (photon.bin[i] == at.bin[j]) flux[j] += photon.beta[i];
    return flux;
}

// A hash grid over points (any T with a position `p`) for radius queries. The points are kept
// by reference and must outlive the grid.
template <typename T>
class PointGrid {
public:
    // Bins the points into cubic cells of side `cell_size`, reordering them by bucket (a stable
    // counting sort, so a bucket keeps its points in their former order) so that a cell's points
    // lie together in memory; queries are fastest with radii up to about the cell size.
    void build(std::vector<T>& points, float cell_size) {
        points_ = &points;
        inv_cell_size_ = 1.0f / std::max(cell_size, 1e-20f);
        size_t buckets = 1;
        while (buckets < 2 * points.size()) buckets *= 2;
        starts_.assign(buckets + 1, 0);
        std::vector<uint32_t> of(points.size());
        for (size_t i = 0; i < points.size(); ++i) {
            of[i] = uint32_t(bucket(cell_of(points[i].p)));
            ++starts_[of[i] + 1];
        }
        for (size_t b = 0; b < buckets; ++b) starts_[b + 1] += starts_[b];
        std::vector<uint32_t> next(starts_.begin(), starts_.end() - 1);
        std::vector<T> sorted(points.size());
        for (size_t i = 0; i < points.size(); ++i) sorted[next[of[i]]++] = points[i];
        points.swap(sorted);
    }
    bool empty() const { return points_ == nullptr || points_->empty(); }

    // Calls f(point, squared distance) for every point within `radius` of p, in a fixed order.
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
                        const T& point = (*points_)[k];
                        if (cell_of(point.p) != cell) continue;  // another cell hashed into this bucket
                        float d2 = squared_length(point.p - p);
                        if (d2 <= r2) f(point, d2);
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
        return size_t(h & (starts_.size() - 2));  // the bucket count is a power of two
    }

    const std::vector<T>* points_ = nullptr;
    float inv_cell_size_ = 1.0f;
    std::vector<uint32_t> starts_;  // bucket b holds points [starts_[b], starts_[b + 1])
};

using PhotonGrid = PointGrid<Photon>;

}  // namespace candela
