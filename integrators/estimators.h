#pragma once
// Measurements with error bars: the irradiance arriving at a point, or the radiance along a ray,
// each estimated by the path tracer from independent samples, with its standard error and a 95%
// confidence interval (normal approximation, valid for the sample counts used here).
//
// Irradiance E(p, n) = integral of L(p, w) cos(theta) over the hemisphere around n, all light
// included (direct and indirect). It is estimated as pi times the radiance a virtual white
// Lambertian surface at p would reflect: next-event estimation and cosine sampling with MIS.

#include "integrators/path.h"

namespace candela {

struct Estimate {
    Spectrum mean{0.0f}, std_error{0.0f};
    double luminance = 0.0, luminance_std_error = 0.0;  // of the Rec.709 luminance per sample
    double luminance_kurtosis = 0.0;                    // E[(Y - mean)^4] / var^2 of the per-sample luminance
    uint64_t samples = 0;
    uint64_t nonfinite = 0;  // samples dropped as NaN or infinite
    static constexpr double Z95 = 1.959963984540054;
    Spectrum ci95_low() const { return mean - float(Z95) * std_error; }
    Spectrum ci95_high() const { return mean + float(Z95) * std_error; }
};

struct EstimatorOptions {
    uint64_t samples = 65536;
    uint64_t seed = 0;
    PathSettings path;  // max_depth, rr_depth, light sampler
    int threads = 0;
};

Estimate estimate_irradiance(const Scene& scene, const Vec3& p, const Vec3& n, const EstimatorOptions& options);
// The irradiance at many points at once (the mean of options.samples paths at each), for
// baking: point i draws the random numbers of one "pixel" of options.seed, so the values do
// not depend on the thread count; non-finite samples are dropped.
std::vector<Spectrum> estimate_irradiance_at(const Scene& scene, const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                             const EstimatorOptions& options);
Estimate estimate_radiance(const Scene& scene, const Vec3& origin, const Vec3& direction, const EstimatorOptions& options);

// A vertex at p with geometric and shading normal n, looking back along n, for estimators that
// start paths at arbitrary points. Its ray offsets use the scene's scale (the point may lie on a
// surface the caller does not name).
SurfaceInteraction virtual_vertex(const Scene& scene, const Vec3& p, const Vec3& n);
// The white Lambertian BSDF used for irradiance.
const BSDF& white_lambertian();

}  // namespace candela
