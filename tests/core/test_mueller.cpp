// Stokes vectors and Mueller matrices (core/mueller.h) against closed forms: Mitsuba 3's
// documented examples of its basis rotations, Fresnel's matrices against the unpolarised
// reflectance, energy (R + T = 1), Brewster's angle (arctan n), Jones reciprocity, Malus' law.

#include "core/mueller.h"
#include "core/rng.h"
#include "materials/fresnel.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace candela;

namespace {

void check_stokes(const Stokes& actual, const Stokes& expected, float tolerance = 1e-5f) {
    for (int i = 0; i < 4; ++i) {
        INFO("component " << i << ": " << actual[i] << " expected " << expected[i]);
        CHECK(std::abs(actual[i] - expected[i]) <= tolerance);
    }
}

}  // namespace

TEST_CASE("mueller: rotations follow Mitsuba's documented examples", "[mueller]") {
    const float pi = 3.14159265f;
    // rotator(45 degrees) turns horizontal light [1, 1, 0, 0] into [1, 0, -1, 0].
    check_stokes(rotator(pi / 4) * Stokes(1, 1, 0, 0), Stokes(1, 0, -1, 0));
    // Horizontal light in basis x, re-expressed in basis (1, -1, 0) / sqrt 2 (light along +z), is +45 degrees.
    const Vec3 target = glm::normalize(Vec3(1, -1, 0));
    check_stokes(rotate_stokes_basis(Vec3(0, 0, 1), Vec3(1, 0, 0), target) * Stokes(1, 1, 0, 0), Stokes(1, 0, 1, 0));
    // A rotation there and back is the identity; the implicit basis is orthogonal to its direction.
    PCG32 rng(7, 1);
    for (int i = 0; i < 100; ++i) {
        const Vec3 d = glm::normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
        const Vec3 b = stokes_basis(d);
        CHECK(std::abs(glm::dot(b, d)) < 1e-6f);
        CHECK(glm::length(b) == Approx(1.0f).epsilon(1e-6));
        Vec3 other = glm::normalize(glm::cross(d, Vec3(0.3f, 0.5f, 0.7f)));
        const Mueller there = rotate_stokes_basis(d, b, other), back = rotate_stokes_basis(d, other, b);
        check_stokes(back * (there * Stokes(1, 0.3f, -0.5f, 0.2f)), Stokes(1, 0.3f, -0.5f, 0.2f));
    }
}

TEST_CASE("mueller: Malus' law through two ideal polarisers is cos^2", "[mueller]") {
    const Stokes unpolarised(1, 0, 0, 0);
    for (float degrees : {0.0f, 15.0f, 30.0f, 45.0f, 60.0f, 75.0f, 90.0f}) {
        const float a = glm::radians(degrees);
        const Stokes out = rotated_element(a, linear_polarizer()) * (linear_polarizer() * unpolarised);
        INFO("angle " << degrees);
        CHECK(out[0] == Approx(0.5f * sqr(std::cos(a))).margin(1e-6));
        CHECK(degree_of_polarization(out) == Approx(out[0] > 1e-6f ? 1.0f : 0.0f).margin(1e-4));
    }
    // A quarter-wave plate at 45 degrees makes horizontal light circular (|S3| = S0).
    const Stokes circular = rotated_element(glm::radians(45.0f), linear_retarder(glm::radians(90.0f))) * Stokes(1, 1, 0, 0);
    CHECK(std::abs(circular[3]) == Approx(1.0f).margin(1e-5));
}

TEST_CASE("mueller: Fresnel matrices carry the unpolarised reflectance and conserve energy", "[mueller]") {
    for (float eta : {1.33f, 1.5f, 2.4f, 1.0f / 1.5f})
        for (float cos_i : {1.0f, 0.9f, 0.6f, 0.3f, 0.05f, -0.3f, -0.7f, -0.95f}) {
            INFO("eta " << eta << " cos " << cos_i);
            const Mueller R = specular_reflection(cos_i, std::complex<float>(eta, 0.0f));
            const Mueller T = specular_transmission(cos_i, eta);
            const float F = fresnel_dielectric(cos_i, eta).F;
            CHECK(R(0, 0) == Approx(F).margin(2e-6));
            CHECK(R(0, 0) + T(0, 0) == Approx(1.0f).margin(2e-6));  // 0 transmitted under total internal reflection
            // Jones reciprocity: Q M^T Q = M with Q = diag(1, 1, -1, 1).
            Mueller Q = Mueller::identity();
            Q(2, 2) = -1.0f;
            const Mueller reciprocal = Q * transpose(R) * Q;
            for (int i = 0; i < 4; ++i)
                for (int j = 0; j < 4; ++j) CHECK(reciprocal(i, j) == Approx(R(i, j)).margin(1e-6));
        }
    // Conductors: the (0, 0) element is the unpolarised conductor reflectance.
    for (float cos_i : {1.0f, 0.7f, 0.2f}) {
        const Spectrum F = fresnel_conductor(cos_i, Spectrum(0.2f, 0.9f, 1.1f), Spectrum(3.6f, 2.6f, 2.3f));
        CHECK(specular_reflection(cos_i, {0.2f, 3.6f})(0, 0) == Approx(F[0]).epsilon(1e-4));
        CHECK(specular_reflection(cos_i, {1.1f, 2.3f})(0, 0) == Approx(F[2]).epsilon(1e-4));
    }
}

TEST_CASE("mueller: reflected light is fully polarised at Brewster's angle, arctan(n)", "[mueller]") {
    for (float n : {1.33f, 1.5f, 1.9f}) {
        // The angle of least p reflectance, found by scanning, is arctan(n) within the scan step.
        float best_angle = 0.0f, best_dop = 0.0f;
        for (int i = 1; i < 8900; ++i) {
            const float theta = glm::radians(0.01f * float(i));
            const Stokes out = specular_reflection(std::cos(theta), {n, 0.0f}) * Stokes(1, 0, 0, 0);
            const float dop = degree_of_polarization(out);
            if (dop > best_dop) best_dop = dop, best_angle = theta;
        }
        INFO("n " << n);
        CHECK(std::abs(best_angle - std::atan(n)) < glm::radians(0.011f));
        CHECK(best_dop == Approx(1.0f).margin(1e-4));
        // There the reflection is s-polarised: S1 = S0 in the plane-of-incidence frame.
        const Stokes at_brewster = specular_reflection(std::cos(std::atan(n)), {n, 0.0f}) * Stokes(1, 0, 0, 0);
        CHECK(at_brewster[1] == Approx(at_brewster[0]).epsilon(1e-4));
    }
}

TEST_CASE("mueller: Fresnel, polariser and retarder matrices are physical", "[mueller]") {
    // Any fully polarised input leaves with degree of polarisation at most 1 and S0 >= 0.
    PCG32 rng(11, 3);
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
        const float cos_i = 2.0f * rng.next_float() - 1.0f;
        const float u = 2.0f * rng.next_float() - 1.0f, phi = 6.2831853f * rng.next_float();
        const float r = std::sqrt(std::max(0.0f, 1.0f - u * u));
        const Stokes in(1.0f, r * std::cos(phi), r * std::sin(phi), u);
        const Mueller ms[] = {specular_reflection(cos_i, {1.5f, 0.0f}),           specular_transmission(cos_i, 1.5f),
                              specular_reflection(std::abs(cos_i), {0.2f, 3.5f}), rotated_element(phi, linear_polarizer()),
                              rotated_element(phi, linear_retarder(3.0f * u)),    diattenuator(0.3f, 0.8f)};
        for (const Mueller& m : ms) {
            const Stokes out = m * in;
            CHECK(out[0] >= -1e-6f);
            if (out[0] > 1e-4f) {
                CHECK(degree_of_polarization(out) <= 1.0f + 1e-4f);
                ++checked;
            }
        }
    }
    CHECK(checked > 8000);
}
