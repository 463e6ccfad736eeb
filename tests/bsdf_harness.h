#pragma once
// Statistical checks that any BSDF must pass, used by the material tests.

#include "core/bsdf.h"
#include "core/scene.h"
#include "tests/stats.h"

#include <string>
#include <vector>

namespace candela::test {

// A BSDF built from its XML (loaded through the real scene loader, nested in a sphere).
struct BSDFUnderTest {
    Ref<Scene> keep_alive;
    const BSDF* bsdf = nullptr;
};
BSDFUnderTest make_bsdf(const std::string& bsdf_xml);

// A scene (XML) of a unit sphere made of `bsdf_xml`, rendered by `integrator_xml`, under a constant
// sky of 0.5 and a point light, seen by a 24 x 24 camera at 4 spp with a box filter: what the
// measured-material tests render.
std::string lit_sphere_scene(const std::string& integrator_xml, const std::string& bsdf_xml);

// A surface interaction at the origin with the standard frame, uv (0.3, 0.6), looking from wi.
SurfaceInteraction local_interaction(const Vec3& wi);
// A unit direction from cos(theta) and phi.
Vec3 direction(float cos_theta, float phi);

// The discrete probability with which sample() should pick a delta lobe.
struct DeltaExpectation {
    uint32_t lobe;
    double probability;
};

struct SamplingCheck {
    ChiSquareResult chi2;
    std::vector<std::string> failures;  // deterministic consistency violations
    MeanAndError albedo;                // E[weight] (the directional albedo), per sample
};
// Draws `n` samples: histograms smooth lobes on a 10 x 20 spherical grid against pdf(), counts
// delta lobes against `deltas`, counts failed samples against what is left, and checks that each
// smooth sample's weight is eval / pdf, its pdf equals pdf() and eval_pdf() equals eval() and
// pdf() bit for bit.
SamplingCheck check_sampling(const BSDF& bsdf, const SurfaceInteraction& si, const BSDFContext& ctx, int n,
                             const std::vector<DeltaExpectation>& deltas, uint64_t seed);

// Monte Carlo estimate of the integral of pdf() over the sphere (uniform directions).
MeanAndError pdf_integral(const BSDF& bsdf, const SurfaceInteraction& si, const BSDFContext& ctx, int n, uint64_t seed);

// The largest relative differences of eval (any channel) and of pdf between two BSDFs over random
// direction pairs: wi from the upper hemisphere or, with `both_sides`, the whole sphere; wo from
// the whole sphere. Differences are relative to max(|a|, |b|, 1e-3).
struct PointwiseDifference {
    double eval = 0.0, pdf = 0.0;
    int nonzero = 0;  // pairs where either BSDF had a non-zero value (the comparison has content)
};
PointwiseDifference compare_pointwise(const BSDF& a, const BSDF& b, const BSDFContext& ctx, int pairs, uint64_t seed, bool both_sides);

// Largest relative violation of reciprocity, |f(wi, wo) - f(wo, wi)| / max, over random pairs
// in the upper hemisphere (f = eval / cos wo).
double reciprocity_error(const BSDF& bsdf, int pairs, uint64_t seed);

}  // namespace candela::test
