// Fresnel and Snell against closed forms.

#include "materials/fresnel.h"
#include "materials/microfacet.h"

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
