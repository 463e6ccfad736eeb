// Fresnel and Snell against closed forms; the microfacet distributions against their integrals,
// and their sampling against their pdf.

#include "core/rng.h"
#include "materials/fresnel.h"
#include "materials/microfacet.h"
#include "tests/bsdf_harness.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;

TEST_CASE("fresnel: normal incidence reflectance is ((n - 1) / (n + 1))^2 from either side", "[fresnel]") {
    for (float n : {1.33f, 1.5f, 2.4f}) {
        float expected = sqr((n - 1) / (n + 1));
        CHECK(fresnel_dielectric(1.0f, n).F == Approx(expected).epsilon(1e-5));
        CHECK(fresnel_dielectric(-1.0f, n).F == Approx(expected).epsilon(1e-5));
    }
    CHECK(fresnel_dielectric(0.7f, 1.0f).F == 0.0f);          // no interface
    CHECK(fresnel_dielectric(0.0f, 1.5f).F == Approx(1.0f));  // grazing
}

TEST_CASE("fresnel: p-polarised reflectance vanishes at Brewster's angle", "[fresnel]") {
    for (float n : {1.33f, 1.5f}) {
        float brewster = std::atan(n);
        float rs, rp;
        fresnel_dielectric_polarized(std::cos(brewster), n, rs, rp);
        CHECK(rp < 1e-10f);
        CHECK(rs > 0.01f);
        // From inside, Brewster's angle is atan(1 / n).
        fresnel_dielectric_polarized(-std::cos(std::atan(1.0f / n)), n, rs, rp);
        CHECK(rp < 1e-10f);
    }
}

TEST_CASE("fresnel: total internal reflection beyond the critical angle", "[fresnel]") {
    float n = 1.5f, critical = std::asin(1.0f / n);
    for (float d : {0.01f, 0.2f, 0.5f}) CHECK(fresnel_dielectric(-std::cos(critical + d), n).F == 1.0f);
    CHECK(fresnel_dielectric(-std::cos(critical - 0.01f), n).F < 1.0f);
}

TEST_CASE("snell: refraction angles satisfy n1 sin(theta1) = n2 sin(theta2)", "[fresnel]") {
    for (float n : {1.33f, 1.5f}) {
        for (float cos_i : {0.95f, 0.6f, 0.2f, -0.9f, -0.8f}) {
            Vec3 wi(std::sqrt(1 - cos_i * cos_i), 0.0f, cos_i);
            DielectricFresnel fr = fresnel_dielectric(cos_i, n);
            if (fr.F >= 1.0f) continue;
            Vec3 wt = refract(wi, fr.cos_theta_t, fr.eta_ti);
            float n1 = cos_i > 0 ? 1.0f : n, n2 = cos_i > 0 ? n : 1.0f;
            CHECK(glm::length(wt) == Approx(1.0f).epsilon(1e-5));
            CHECK(n1 * std::sqrt(1 - cos_i * cos_i) == Approx(n2 * std::sqrt(1 - wt.z * wt.z)).epsilon(1e-5));
            CHECK(wt.z * cos_i < 0.0f);  // crosses the interface
            CHECK(wt.x * wi.x < 0.0f);   // stays in the plane of incidence, on the other side
            // Refraction about a microfacet normal equal to +z agrees.
            Vec3 wm = refract(wi, Vec3(0, 0, 1), fr.cos_theta_t, fr.eta_ti);
            CHECK(glm::length(wm - wt) < 1e-5f);
        }
    }
}

TEST_CASE("fresnel: conductor reflectance limits", "[fresnel]") {
    // k = 0 reduces to the dielectric formula; a perfect mirror (eta 0, k 1) reflects everything.
    for (float c : {1.0f, 0.6f, 0.1f}) {
        CHECK(fresnel_conductor(c, Spectrum(1.5f), Spectrum(0.0f)).x == Approx(fresnel_dielectric(c, 1.5f).F).epsilon(1e-4));
        CHECK(fresnel_conductor(c, Spectrum(0.0f), Spectrum(1.0f)).x == Approx(1.0f).epsilon(1e-6));
    }
    // Normal incidence: ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).
    Spectrum eta(0.2f, 0.9f, 1.1f), k(3.9f, 2.4f, 2.1f);
    Spectrum F = fresnel_conductor(1.0f, eta, k);
    for (int i = 0; i < 3; ++i) CHECK(F[i] == Approx((sqr(eta[i] - 1) + sqr(k[i])) / (sqr(eta[i] + 1) + sqr(k[i]))).epsilon(1e-5));
}

TEST_CASE("fresnel: the diffuse reflectance fit matches the hemispherical integral", "[fresnel]") {
    for (float eta : {1.0f / 1.5f, 1.33f, 1.5f}) {
        // 2 int_0^1 F(mu) mu dmu by the midpoint rule.
        double sum = 0.0;
        const int n = 200000;
        for (int i = 0; i < n; ++i) {
            float mu = (i + 0.5f) / n;
            sum += fresnel_dielectric(mu, eta).F * mu;
        }
        // The published fits are accurate to about 1e-3 absolute.
        CHECK(fresnel_diffuse_reflectance(eta) == Approx(2.0 * sum / n).margin(2e-3));
    }
}

TEST_CASE("microfacet: D is normalised and G1 matches the masking integral", "[microfacet]") {
    for (MicrofacetType type : {MicrofacetType::Beckmann, MicrofacetType::GGX})
        for (float alpha : {0.1f, 0.5f}) {
            MicrofacetDistribution d(type, alpha, alpha * 1.5f);
            // int D(m) cos(theta_m) dm = 1 (midpoint rule in (cos theta, phi)), and the projected
            // area toward v: int D(m) max(0, v.m) dm = v.z (1 + Lambda(v)) = v.z / G1.
            const int nt = 4000, np = 256;
            Vec3 v = glm::normalize(Vec3(0.6f, 0.2f, 0.5f));
            double norm = 0.0, projected = 0.0;
            for (int i = 0; i < nt; ++i) {
                double z = (i + 0.5) / nt;
                double r = std::sqrt(1 - z * z);
                for (int j = 0; j < np; ++j) {
                    double phi = 2 * 3.14159265358979 * (j + 0.5) / np;
                    Vec3 m(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
                    double D = d.D(m);
                    norm += D * z;
                    projected += D * std::max(0.0f, glm::dot(v, m));
                }
            }
            double dA = (1.0 / nt) * (2 * 3.14159265358979 / np);
            INFO("type " << int(type) << " alpha " << alpha);
            CHECK(norm * dA == Approx(1.0).epsilon(2e-3));
            CHECK(projected * dA == Approx(v.z * (1.0 + d.lambda(v))).epsilon(2e-3));
        }
}

namespace {
// F(x) of Beckmann's visible slopes (alpha = 1, incidence at tan theta in the x-z plane), in
// double (at normal incidence, cot = infinity, the Gaussian's CDF).
double beckmann_slope_cdf(double x, double tan_theta) {
    const double cot = 1.0 / tan_theta;
    const double inv_sqrt_pi = 1.0 / std::sqrt(3.14159265358979323846);
    const double norm = 1.0 + std::erf(cot) + tan_theta * std::exp(-cot * cot) * inv_sqrt_pi;
    return (1.0 + std::erf(x) + tan_theta * std::exp(-x * x) * inv_sqrt_pi) / norm;
}
}  // namespace

TEST_CASE("microfacet: Beckmann's visible slopes invert their CDF to within 2e-6, in x and in y", "[microfacet]") {
    // alpha = 1 and wi in the x-z plane: m = normalize(-x, -y, 1) for the sampled slopes (x, y).
    MicrofacetDistribution d(MicrofacetType::Beckmann, 1.0f, 1.0f);
    PCG32 rng(5, 3);
    double worst_x = 0.0, worst_y = 0.0;
    for (float cos_theta : {1.0f, 0.99999f, 0.999f, 0.95f, 0.7f, 0.4f, 0.1f, 0.01f, 0.001f})
        for (int i = 0; i < 20000; ++i) {
            const float ux = rng.next_float(), uy = rng.next_float();
            const Vec3 wi(safe_sqrt(1.0f - cos_theta * cos_theta), 0.0f, cos_theta);
            float pdf;
            const Vec3 m = d.sample(wi, Vec2(ux, uy), pdf);
            REQUIRE(pdf > 0.0f);
            const double x = -double(m.x) / m.z, y = -double(m.y) / m.z;
            const double u_x = std::clamp(double(ux), 1e-6, 1.0 - 1e-6), u_y = std::clamp(double(uy), 1e-6, 1.0 - 1e-6);
            worst_x = std::max(worst_x, std::abs(beckmann_slope_cdf(x, double(wi.x) / wi.z) - u_x));
            worst_y = std::max(worst_y, std::abs(0.5 * (1.0 + std::erf(y)) - u_y));
        }
    INFO("largest |F(x) - u_x| " << worst_x << ", |F(y) - u_y| " << worst_y);
    CHECK(worst_x < 2e-6);
    CHECK(worst_y < 2e-6);
}

TEST_CASE("microfacet: sample() draws normals with the density pdf() reports (chi-square)", "[microfacet]") {
    // The histogram is over (cos theta, phi) of m: roughnesses that spread normals over the
    // hemisphere, isotropic and anisotropic, from normal to grazing incidence. `--rng-seed N`
    // draws other samples (the default seed is 0).
    struct Case {
        MicrofacetType type;
        float alpha_u, alpha_v;
    };
    const std::vector<Case> cases = {{MicrofacetType::Beckmann, 0.6f, 0.6f},
                                     {MicrofacetType::Beckmann, 1.0f, 1.0f},
                                     {MicrofacetType::Beckmann, 0.3f, 0.9f},
                                     {MicrofacetType::GGX, 0.6f, 0.6f},
                                     {MicrofacetType::GGX, 0.3f, 0.9f}};
    const std::vector<float> incidences = {1.0f, 0.9f, 0.5f, 0.1f, 0.01f};
    const double alpha = sidak(0.01, int(cases.size() * incidences.size()));
    const int n = test::effort_scaled(200000, 50000);
    PCG32 rng(1000 + Catch::rngSeed(), 7);
    for (const Case& c : cases)
        for (float cos_theta : incidences) {
            MicrofacetDistribution d(c.type, c.alpha_u, c.alpha_v);
            const Vec3 wi = test::direction(cos_theta, 0.7f);
            test::SphericalHistogram hist(10, 20);
            double failed = 0.0;
            for (int i = 0; i < n; ++i) {
                const float a = rng.next_float();
                float pdf;
                const Vec3 m = d.sample(wi, Vec2(a, rng.next_float()), pdf);
                if (pdf > 0.0f)
                    hist.add(m);
                else
                    failed += 1.0;
            }
            std::vector<double> observed = hist.counts;
            std::vector<double> expected = hist.expected([&](const Vec3& m) { return double(d.pdf(wi, m)); }, double(n));
            double total = 0.0;
            for (double e : expected) total += e;
            observed.push_back(failed);
            expected.push_back(std::max(0.0, n - total));
            const ChiSquareResult chi2 = chi_square(observed, expected);
            INFO((c.type == MicrofacetType::GGX ? "ggx" : "beckmann")
                 << " alpha " << c.alpha_u << ", " << c.alpha_v << ", cos theta_i " << cos_theta << ": " << chi2.details);
            CHECK(chi2.p_value > alpha);
        }
}
