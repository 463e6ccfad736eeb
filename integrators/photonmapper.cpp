// photonmapper: Jensen's two-pass photon mapping (Jensen 1996, "Global Illumination using Photon
// Maps"; Jensen 2001, "Realistic Image Synthesis Using Photon Mapping", chapter 9) with final
// gathering. Biased: a consistent estimator only as the photon counts grow and the lookups
// shrink; see "Bias" below.
//
// Parameters (Mitsuba 0.6 names, snake_case as Mitsuba 3 upgrades them):
//   global_photons          integer   photons to store in the global map (default 250000)
//   caustic_photons         integer   photons to store in the caustic map (default 250000; no
//                                     caustic map when no surface has a delta lobe)
//   lookup_radius           float     largest lookup radius, relative to the scene's bounding
//                                     radius (default 0.05): the global map's, and a quarter of it
//                                     the caustic map's
//   global_lookup_radius    float     Mitsuba 0.6's separate radii, overriding lookup_radius
//   caustic_lookup_radius   float     (defaults: lookup_radius and lookup_radius / 4)
//   lookup_size             integer   photons per lookup: the radius shrinks to the distance of the
//                                     lookup_size-th nearest photon (default 120)
//   direct_samples          integer   next-event estimation samples (light sampling with MIS, the
//                                     `path` integrator's one bounce) at the visible point (default 16)
//   glossy_samples          integer   final-gather rays at the visible point (default 32): Mitsuba
//                                     spends them on glossy surfaces; here every visible point
//                                     gathers its indirect light with them
//   granularity             integer   light paths per parallel work unit (default 0: 4096); maps are
//                                     filled in whole units, so it changes which photons are kept
//   max_depth               integer   longest path in segments, camera ray included (-1: unbounded,
//                                     the default; 1: emitters seen directly; 2: direct light)
//   rr_depth                integer   segments after which Russian roulette may end light paths and
//                                     camera paths through specular surfaces (default 5)
//   hide_emitters           boolean   emitters seen directly render black (default false)
//
// Pass 1: light paths from the emitters (by power, Emitter::sample_ray) store photons on
// surfaces with a diffuse lobe and no delta lobe: every such hit in the global map; the first such
// hit after one or more delta scatterings (light focused by glass or mirrors) in the caustic map.
// Each map is filled, in whole work units in path order, until it holds its count; its photons
// are weighted by 1 / (light paths emitted). Pass 2 (the pixel loop): a camera ray follows delta
// and glossy-only surfaces, adding the emission it meets, to the first surface x with a diffuse
// lobe and no delta lobe (as sppm); there L(x) = emission + direct (direct_samples next-event
// estimates) + caustics (the caustic map's radiance estimate at x) + indirect: glossy_samples
// BSDF-sampled gather rays, each followed through specular surfaces to a diffuse surface y where
// the global map's radiance estimate gives L(y) (emission met by a gather ray counts only after a
// glossy bounce: direct light and caustics are estimated apart). Radiance estimates take the
// lookup_size nearest photons within the radius r (r shrinking to the farthest of them):
// sum f beta / (pi r^2), uniform kernel.
//
// Bias (measured: docs/rendering.md, "Light paths"): density estimation blurs illumination over the
// lookup radius (corners and contact shadows brighten, small features blur), and k-nearest
// lookups are biased where the photon density varies. On the validation Cornell box the whole-
// image mean is 0.5-0.9% below Mitsuba's reference (200k global photons), mostly at edges and corners.
// In scalar_spectral the photons' flux is also blurred over wavelength, across a bin's width (below).
//
// In scalar_spectral the maps, built once, serve every camera sample's wavelengths: each light
// path draws its own wavelengths (from its own random numbers), and each photon keeps its flux as
// a histogram over SpectralBins (32) bins of 14.7 nm over 360-830 nm, the range the wavelengths are
// drawn from (integrators/photons.h, bin_photon_flux): an unbiased estimate of the flux per nm
// averaged over each bin. The irradiance points hold the same histograms. A camera sample reads
// the bins of its own wavelengths; direct light, final-gather rays and emission are evaluated at
// them, as `path` does. Spectral bias: the photon maps' light is the average over its bin at
// every wavelength, so spectral detail finer than a bin (an emission line, a narrow band's
// edges) is spread across it; smooth spectra change by the second order of the bin width only.
// Not in scalar_spectral_polarized (photons carry no Stokes vector).
//
// Deterministic: photons (their wavelengths too) depend on (seed, path index), maps on the order
// of whole work units, lookups sum in a fixed order (integrators/photons.h), camera samples on
// (seed, pixel, index).

#include "core/bsdf.h"
#include "core/memory_budget.h"
#include "core/parallel.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "core/wavelengths.h"
#include "integrators/direct_lighting.h"
#include "integrators/light_paths.h"
#include "integrators/path.h"
#include "integrators/photons.h"

#include <array>

namespace candela {

class PhotonMapIntegrator final : public SamplingIntegrator {
public:
    explicit PhotonMapIntegrator(const Properties& props) : direct_(direct_settings()) {
        global_.target = read_count(props, "global_photons");
        caustic_.target = read_count(props, "caustic_photons");
        const float lookup_radius = read_radius(props, "lookup_radius", 0.05f);
        global_.relative_radius = read_radius(props, "global_lookup_radius", lookup_radius);
        caustic_.relative_radius = read_radius(props, "caustic_lookup_radius", 0.25f * lookup_radius);
        lookup_size_ = props.get_int("lookup_size", 120);
        if (lookup_size_ <= 0) props.fail("lookup_size", "lookup_size must be positive");
        direct_samples_ = props.get_int("direct_samples", 16);
        if (direct_samples_ < 0) props.fail("direct_samples", "direct_samples must be >= 0");
        glossy_samples_ = props.get_int("glossy_samples", 32);
        if (glossy_samples_ < 0) props.fail("glossy_samples", "glossy_samples must be >= 0");
        granularity_ = props.get_int("granularity", 0);
        if (granularity_ < 0) props.fail("granularity", "granularity must be >= 0");
        settings_ = read_path_settings(props, DepthSettings | HideEmittersSetting);
        location_ = props.location();
        refuse_polarized_photons(props, "photonmapper");
    }

    // The photon maps are built in prepare(), with the render's threads, seed and interruption.
    // Its photons travel at no particular time.
    bool renders_motion() const override { return false; }
    RenderResult render(const Scene& scene, const RenderOptions& options) override {
        refuse_unrendered_media(scene);
        refuse_unrendered_motion(scene);
        threads_ = options.threads;
        interrupt_ = options.interrupt;
        seed_ = sample_settings(scene, options).seed;
        return SamplingIntegrator::render(scene, options);
    }
    void prepare(const Scene& scene) override;
    Spectrum sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const override;
    std::string to_string() const override { return "photonmapper"; }

private:
    struct PhotonMap {
        uint64_t target = 0;
        float relative_radius = 0.0f, radius = 0.0f;
        std::vector<Photon> photons;
        PhotonGrid grid;
        double emitted = 0.0;  // light paths traced to fill the map
    };
    // Irradiance precomputed at every fourth global photon (Christensen 1999), on the side the
    // photon arrived from.
    struct IrradiancePoint {
        Vec3 p, n;
        Spectrum E;  // RGB; the spectral variant keeps it binned, in irradiance_bins_
    };
    // An irradiance point's histogram over wavelength (integrators/photons.h): W m^-2 nm^-1.
    using BinnedIrradiance = std::array<float, SpectralBins>;
    using Neighbours = std::vector<std::pair<float, const Photon*>>;

    static PathSettings direct_settings() {
        PathSettings s;
        s.max_depth = 2;  // one bounce from the visible point: next-event estimation with MIS
        return s;
    }
    static uint64_t read_count(const Properties& props, const char* name) {
        int n = props.get_int(name, 250000);
        if (n < 0) props.fail(name, std::string(name) + " must be >= 0");
        return uint64_t(n);
    }
    static float read_radius(const Properties& props, const char* name, float fallback) {
        float r = props.get_float(name, fallback);
        if (!(r > 0.0f) || !std::isfinite(r)) props.fail(name, std::string(name) + " must be positive");
        return r;
    }
    // Stops the render (a SceneError at the integrator, exit code 2) before the maps are filled
    // when they cannot fit in memory (core/memory_budget.h).
    void check_map_memory(bool caustic) const;
    void build_map(const LightPathTracer& tracer, bool caustic, uint64_t stream, PhotonMap& map) const;
    // The lookup_size nearest photons within the map's radius that pass `keep`, in photon order;
    // returns the squared radius of the estimate (the farthest of them, or the map's radius).
    template <typename Keep>
    float nearest_photons(const PhotonMap& map, const Vec3& p, Keep&& keep, Neighbours& near) const;
    Spectrum radiance_estimate(const PhotonMap& map, const GatherPoint& at) const;
    void precompute_irradiance();
    // L(y) at a gather hit: f E from the nearest irradiance point facing the same way on a
    // Lambertian surface, else the global map's radiance estimate.
    Spectrum gathered_radiance(const GatherPoint& y) const;
    Spectrum final_gather(const Scene& scene, Sampler& sampler, const GatherPoint& x) const;

    SourceLocation location_;
    PhotonMap global_, caustic_;
    std::vector<IrradiancePoint> irradiance_;
    std::vector<BinnedIrradiance> irradiance_bins_;  // the spectral variant: one per irradiance point
    PointGrid<IrradiancePoint> irradiance_grid_;
    int lookup_size_ = 120, direct_samples_ = 16, glossy_samples_ = 32, granularity_ = 0;
    PathSettings settings_;  // max_depth counts segments, camera ray included
    PathIntegrator direct_;
    int threads_ = 0;
    bool spectral_ = false;  // photons carry binned flux (integrators/photons.h)
    const std::atomic<bool>* interrupt_ = nullptr;
    uint64_t seed_ = 0;
};

void PhotonMapIntegrator::prepare(const Scene& scene) {
    direct_.prepare(scene);
    spectral_ = scene.spectral();
    const LightPathTracer tracer(scene, settings_.max_depth < 0 ? -1 : settings_.max_depth - 1, settings_.rr_depth);
    const float scene_radius = std::max(scene.bbox().bounding_radius(), 1e-3f);
    bool specular = false;
    for (const auto& shape : scene.shapes()) specular = specular || (shape->bsdf()->flags() & Delta) != 0;
    for (PhotonMap* map : {&global_, &caustic_}) {
        map->radius = map->relative_radius * scene_radius;
        map->photons.clear();
        map->emitted = 0.0;
    }
    check_map_memory(specular);
    build_map(tracer, false, 2, global_);
    if (specular) build_map(tracer, true, 3, caustic_);
    global_.grid.build(global_.photons, global_.radius);
    caustic_.grid.build(caustic_.photons, caustic_.radius);
    precompute_irradiance();
}

// The maps' photons and, while a grid is built, a sorted copy, each photon's bucket and up to four
// bucket starts per photon (PointGrid::build); then the irradiance points at every fourth global
// photon with their own grid, and in the spectral variant their histograms (a photon's bins fit in
// its padding). A map may overshoot its target by part of a work unit: not counted.
void PhotonMapIntegrator::check_map_memory(bool caustic) const {
    const uint64_t caustic_photons = caustic ? caustic_.target : 0, grid_per_point = 5 * sizeof(uint32_t);
    const uint64_t per_photon = 2 * sizeof(Photon) + grid_per_point,
                   per_irradiance = 2 * sizeof(IrradiancePoint) + grid_per_point + (spectral_ ? sizeof(BinnedIrradiance) : 0);
    const uint64_t bytes = saturating_add(saturating_mul(saturating_add(global_.target, caustic_photons), per_photon),
                                          saturating_mul(global_.target / 4, per_irradiance));
    check_memory(
        bytes,
        "photonmapper's maps of " + std::to_string(global_.target) + " global and " + std::to_string(caustic_photons) + " caustic photons",
        location_);
}

// Irradiance at every fourth global photon from its lookup_size nearest photons on surfaces
// facing the same way (normals within 25 degrees), in parallel (each point on its own). The
// points are placed first and binned by their grid (which reorders them), then estimated in place.
void PhotonMapIntegrator::precompute_irradiance() {
    irradiance_.clear();
    irradiance_.reserve(global_.photons.size() / 4);
    for (size_t i = 0; i + 4 <= global_.photons.size(); i += 4)
        irradiance_.push_back({global_.photons[i].p, global_.photons[i].n, Spectrum(0.0f)});
    irradiance_grid_.build(irradiance_, 0.25f * global_.radius);
    irradiance_bins_.assign(spectral_ ? irradiance_.size() : 0, BinnedIrradiance{});
    tbb::task_arena arena(threads_ > 0 ? threads_ : tbb::task_arena::automatic);
    arena.execute([&] {
        parallel_chunks(irradiance_.size(), 256, [&](size_t begin, size_t end) {
            thread_local Neighbours near;
            for (size_t i = begin; i != end; ++i) {
                IrradiancePoint& at = irradiance_[i];
                float r2 = nearest_photons(
                    global_, at.p, [&](const Photon& ph) { return glm::dot(ph.n, at.n) > 0.9f; }, near);
                if (!(r2 > 0.0f)) continue;
                if (spectral_) {
                    BinnedIrradiance& E = irradiance_bins_[i];
                    for (const auto& entry : near)
                        for (int k = 0; k < WavelengthSamples; ++k) E[entry.second->bin[k]] += entry.second->beta[k];
                    for (float& e : E) e /= float(Pi * r2 * global_.emitted);
                    continue;
                }
                Spectrum E(0.0f);
                for (const auto& entry : near) E += entry.second->beta;
                at.E = E / float(Pi * r2 * global_.emitted);
            }
        });
    });
}

// Traces light paths in whole work units, in path order, until the map holds its target; the
// number of units per parallel batch follows the storage rate seen so far (a function of the
// results only, so the map is the same with any thread count). At most 100 paths per wanted
// photon are traced (Mitsuba cancels such gathering too).
void PhotonMapIntegrator::build_map(const LightPathTracer& tracer, bool caustic, uint64_t stream, PhotonMap& map) const {
    if (map.target == 0) return;
    struct Unit {
        std::vector<Photon> photons;
        uint64_t paths = 0;
    };
    const uint64_t unit = granularity_ > 0 ? uint64_t(granularity_) : 4096, limit = 100 * map.target;
    tbb::task_arena arena(threads_ > 0 ? threads_ : tbb::task_arena::automatic);
    std::atomic<uint64_t> rays{0};
    std::vector<Unit> units;
    uint64_t first = 0, batch = 8;
    while (map.photons.size() < map.target && first < limit) {
        bool complete = trace_in_chunks(arena, batch * unit, unit, units, interrupt_, rays, [&](uint64_t b, uint64_t e, Unit& out) {
            out.photons.clear();
            out.paths = e - b;
            for (uint64_t i = b; i < e; ++i) {
                PCG32 rng = light_path_rng(seed_, stream, first + i);
                LightPathStart start;
                // The spectral variant: the path's own wavelengths, from its own random numbers
                // (RGB draws nothing), over the whole visible range whatever the sensor's response.
                Wavelengths wavelengths;
                if (spectral_) {
                    wavelengths = sample_visible_wavelengths(rng.next_float());
                    start.wavelengths = &wavelengths;
                }
                // Its own shutter time: under a still scene (the only kind photonmapper renders) a
                // sky that changes over the shutter (timed_sunsky) is averaged over it.
                const float time = tracer.sample_time(rng);
                if (!tracer.start(rng, time, start)) continue;
                tracer.follow(rng, start, [&](const LightVertex& v) {
                    if (!settings_.within_depth(v.depth + 1)) return false;
                    bool gathers = gathers_photons(*v.bsdf);
                    if (gathers && (!caustic || v.caustic) && all_finite(v.beta)) {
                        out.photons.push_back(make_photon(*v.si, v.beta, v.depth));
                        if (spectral_) bin_photon_flux(out.photons.back(), wavelengths);  // as it arrives (dispersed or not)
                    }
                    return !(caustic && gathers);  // a caustic path ends at its first diffuse surface
                });
            }
        });
        if (!complete) return;  // interrupted: the render stops before its first sample
        for (const Unit& u : units) {
            if (map.photons.size() >= map.target) break;
            map.photons.insert(map.photons.end(), u.photons.begin(), u.photons.end());
            map.emitted += double(u.paths);
        }
        first += batch * unit;
        double rate = map.photons.empty() ? 0.0 : double(map.photons.size()) / map.emitted;
        double wanted = rate > 0.0 ? double(map.target - std::min<uint64_t>(map.target, map.photons.size())) / rate : double(64 * unit);
        batch = std::clamp<uint64_t>(uint64_t(std::ceil(wanted / double(unit))), 1, 256);
    }
}

template <typename Keep>
float PhotonMapIntegrator::nearest_photons(const PhotonMap& map, const Vec3& p, Keep&& keep, Neighbours& near) const {
    near.clear();
    map.grid.for_each_within(p, map.radius, [&](const Photon& ph, float d2) {
        if (keep(ph)) near.emplace_back(d2, &ph);
    });
    float r2 = map.radius * map.radius;
    const size_t k = size_t(lookup_size_);
    if (near.size() > k) {
        std::nth_element(near.begin(), near.begin() + (k - 1), near.end());  // by distance, then photon order
        r2 = near[k - 1].first;
        near.resize(k);
    }
    std::sort(near.begin(), near.end(), [](const auto& a, const auto& b) { return a.second < b.second; });  // sum in photon order
    return near.empty() ? 0.0f : r2;
}

// Jensen's radiance estimate: sum f beta / (pi r^2 emitted) over the nearest photons (in the
// spectral variant each photon's flux in the bins of the camera sample's wavelengths).
Spectrum PhotonMapIntegrator::radiance_estimate(const PhotonMap& map, const GatherPoint& at) const {
    thread_local Neighbours near;  // reused: no allocation per lookup
    float r2 = nearest_photons(
        map, at.si.p, [&](const Photon& ph) { return settings_.within_depth(at.depth + ph.depth); }, near);
    if (!(r2 > 0.0f)) return Spectrum(0.0f);
    const BSDFContext ctx;
    const CameraBins bins = spectral_ ? CameraBins(*at.si.wavelengths) : CameraBins();
    Spectrum sum(0.0f);
    for (const auto& entry : near) {
        Vec3 wi = at.si.to_local(entry.second->wi);
        float cos_theta = std::abs(Frame::cos_theta(wi));
        if (cos_theta > 1e-6f)
            sum += (spectral_ ? binned_flux(*entry.second, bins) : entry.second->beta) * at.bsdf->eval(ctx, at.si, wi) / cos_theta;
    }
    return sum / float(Pi * r2 * map.emitted);
}

Spectrum PhotonMapIntegrator::gathered_radiance(const GatherPoint& y) const {
    // Precomputed irradiance mixes photon depths: used only without a depth limit.
    if (y.bsdf->flags() != DiffuseReflection || settings_.max_depth >= 0 || irradiance_.empty()) return radiance_estimate(global_, y);
    Vec3 n = glm::dot(y.si.wi_world(), y.si.n) >= 0.0f ? y.si.n : -y.si.n;
    const IrradiancePoint* nearest = nullptr;
    for (float radius : {0.25f * global_.radius, global_.radius}) {
        float best = Infinity;
        irradiance_grid_.for_each_within(y.si.p, radius, [&](const IrradiancePoint& q, float d2) {
            if (d2 < best && glm::dot(q.n, n) > 0.9f) best = d2, nearest = &q;
        });
        if (nearest) break;
    }
    if (!nearest) return radiance_estimate(global_, y);
    // A Lambertian BSDF's f, looked up at y (its texture), for light from the normal's side.
    Vec3 wo(0.0f, 0.0f, Frame::cos_theta(y.si.wi) >= 0.0f ? 1.0f : -1.0f);
    Spectrum E = nearest->E;
    if (spectral_) {
        const CameraBins bins(*y.si.wavelengths);
        const BinnedIrradiance& binned = irradiance_bins_[size_t(nearest - irradiance_.data())];
        for (int j = 0; j < WavelengthSamples; ++j) E[j] = binned[bins.bin[j]];
    }
    return y.bsdf->eval(BSDFContext(), y.si, wo) * E;
}

// Indirect light at x: gather rays by BSDF sampling, each followed through specular surfaces to a
// diffuse surface y, where the global map estimates L(y).
Spectrum PhotonMapIntegrator::final_gather(const Scene& scene, Sampler& sampler, const GatherPoint& x) const {
    if (glossy_samples_ == 0 || !settings_.within_depth(x.depth + 2)) return Spectrum(0.0f);
    WalkSettings walk;
    walk.max_depth = settings_.max_depth;
    walk.rr_depth = settings_.rr_depth;
    Spectrum L(0.0f);
    for (int i = 0; i < glossy_samples_; ++i) {
        float u_lobe = draw_lobe_number(*x.bsdf, sampler);
        BSDFSample bs = x.bsdf->sample(BSDFContext(), x.si, u_lobe, sampler.next_2d());
        if (!bs.valid() || is_black(bs.weight)) continue;
        GatherPoint y = walk_to_gather_point(scene, sampler, x.si.spawn_ray(x.si.to_world(bs.wo)), bs.weight, x.depth, walk);
        L += y.emission_after_other;  // direct light and caustics are estimated apart
        if (y.bsdf) L += y.beta * gathered_radiance(y);
    }
    return L / float(glossy_samples_);
}

Spectrum PhotonMapIntegrator::sample_radiance(const Scene& scene, Sampler& sampler, const Ray& ray, SampleRecord& record) const {
    record.valid = !scene.infinite_emitters().empty();
    if (record.first_hit) {
        SurfaceInteraction first;
        if (scene.intersect(ray, first)) {
            record.valid = true;
            record.record_first_hit(first);
        }
    }
    WalkSettings walk;
    walk.max_depth = settings_.max_depth;
    walk.rr_depth = settings_.rr_depth;
    walk.hide_first = settings_.hide_emitters;
    GatherPoint x = walk_to_gather_point(scene, sampler, ray, Spectrum(1.0f), 0, walk);
    Spectrum L = x.emission_after_delta + x.emission_after_other;
    if (x.bsdf) record.valid = true;  // the walk reached a surface (Mitsuba's alpha)
    if (!x.bsdf || !settings_.within_depth(x.depth + 1)) return L;
    if (direct_samples_ > 0) {
        // Each estimate draws its own dimensions, after the walk's: direct_ paths claim two vertex
        // blocks, so estimate i starts at the same dimension in every sample whose walk drew as
        // many numbers (the layout stays fixed where the walk's length is), and later when a path
        // crossed Null surfaces and drew beyond its two blocks.
        const uint32_t stride = 2 * SampleDimensions::PerBounce;
        uint32_t first = sampler.dimension();
        Spectrum direct(0.0f);
        for (int i = 0; i < direct_samples_; ++i) {
            direct += direct_.continue_path(scene, sampler, x.si, *x.bsdf, 0, nullptr, first);
            first = std::max(first + stride, sampler.dimension());
        }
        sampler.set_dimension(first);  // the final gather's numbers come after them all
        L += x.beta * direct / float(direct_samples_);
    }
    if (!caustic_.photons.empty()) L += x.beta * radiance_estimate(caustic_, x);
    return L + x.beta * final_gather(scene, sampler, x);
}

CANDELA_REGISTER_SPECTRAL(PhotonMapIntegrator, ObjectKind::Integrator, "photonmapper");

}  // namespace candela
