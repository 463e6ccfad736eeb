// Sampling warps and distributions: chi-square goodness of fit of every warp against its pdf,
// and the discrete/continuous distributions against their weights. All tests together keep a
// family-wise significance of 1% (Sidak).

#include "core/distribution.h"
#include "core/rng.h"
#include "core/warp.h"
#include "tests/stats.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {
constexpr int SamplingTests = 10;  // number of statistical tests in this file
const double Alpha = sidak(0.01, SamplingTests);
constexpr int N = 1000000;

void check_spherical_warp(const char* name, const std::function<Vec3(Vec2)>& warp, const std::function<double(const Vec3&)>& pdf,
                          uint64_t seed) {
    PCG32 rng(seed, 7);
    SphericalHistogram hist(10, 20);
    for (int i = 0; i < N; ++i) {
        float a = rng.next_float();
        Vec3 w = warp(Vec2(a, rng.next_float()));
        REQUIRE(std::abs(glm::length(w) - 1.0f) < 1e-4f);
        hist.add(w);
    }
    ChiSquareResult r = chi_square(hist.counts, hist.expected(pdf, N));
    INFO(name << ": " << r.details << ", per-test alpha " << Alpha);
    CHECK(r.p_value > Alpha);
}
}  // namespace

TEST_CASE("warps: spherical warps match their pdfs (chi-square)", "[sampling]") {
    check_spherical_warp("uniform sphere", warp::square_to_uniform_sphere, [](const Vec3&) { return double(warp::square_to_uniform_sphere_pdf()); }, 1);
    check_spherical_warp("uniform hemisphere", warp::square_to_uniform_hemisphere,
                         [](const Vec3& v) { return double(warp::square_to_uniform_hemisphere_pdf(v)); }, 2);
    check_spherical_warp("cosine hemisphere", warp::square_to_cosine_hemisphere,
                         [](const Vec3& v) { return double(warp::square_to_cosine_hemisphere_pdf(v)); }, 3);
    const float cos_cutoff = std::cos(radians(35.0f));
    check_spherical_warp("uniform cone", [&](Vec2 u) { return warp::square_to_uniform_cone(u, cos_cutoff); },
                         [&](const Vec3& v) { return double(warp::square_to_uniform_cone_pdf(v, cos_cutoff)); }, 4);
}

TEST_CASE("warps: planar warps are uniform over their domains (chi-square)", "[sampling]") {
    // Concentric disk: histogram over a 20x20 grid on [-1,1]^2; expected = area of the disk in
    // each cell (by supersampling the indicator) / pi.
    for (int which = 0; which < 2; ++which) {
        PCG32 rng(11 + which, 3);
        const int G = 20;
        std::vector<double> obs(G * G, 0.0), expd(G * G, 0.0);
        for (int i = 0; i < N; ++i) {
            float a = rng.next_float();
            Vec2 u(a, rng.next_float());
            Vec2 p = which == 0 ? warp::square_to_uniform_disk_concentric(u) : warp::square_to_uniform_disk(u);
            REQUIRE(glm::length(p) <= 1.0f + 1e-6f);
            int x = std::min(int((p.x + 1.0f) * 0.5f * G), G - 1), y = std::min(int((p.y + 1.0f) * 0.5f * G), G - 1);
            obs[size_t(y) * G + x] += 1.0;
        }
        const int S = 64;
        for (int cy = 0; cy < G; ++cy)
            for (int cx = 0; cx < G; ++cx) {
                int inside = 0;
                for (int j = 0; j < S; ++j)
                    for (int i = 0; i < S; ++i) {
                        double x = -1.0 + 2.0 * (cx + (i + 0.5) / S) / G, y = -1.0 + 2.0 * (cy + (j + 0.5) / S) / G;
                        inside += x * x + y * y <= 1.0;
                    }
                double cell_area = 4.0 / (G * G);
                expd[size_t(cy) * G + cx] = N * cell_area * inside / double(S * S) / 3.14159265358979;
            }
        ChiSquareResult r = chi_square(obs, expd);
        INFO((which == 0 ? "concentric disk: " : "polar disk: ") << r.details);
        CHECK(r.p_value > Alpha);
    }
    // Triangle: barycentrics (b1, b2) uniform over the unit right triangle; bins on a grid, the
    // expected count is the triangle's area inside each cell.
    PCG32 rng(21, 5);
    const int G = 16;
    std::vector<double> obs(G * G, 0.0), expd(G * G, 0.0);
    for (int i = 0; i < N; ++i) {
        float a = rng.next_float();
        Vec2 b = warp::square_to_uniform_triangle(Vec2(a, rng.next_float()));
        REQUIRE(b.x >= 0.0f);
        REQUIRE(b.y >= 0.0f);
        REQUIRE(b.x + b.y <= 1.0f + 1e-6f);
        obs[size_t(std::min(int(b.y * G), G - 1)) * G + std::min(int(b.x * G), G - 1)] += 1.0;
    }
    for (int cy = 0; cy < G; ++cy)
        for (int cx = 0; cx < G; ++cx) {
            // Cells fully below the diagonal x + y = 1, on it (half), or above it.
            double frac = cx + cy + 2 <= G ? 1.0 : (cx + cy + 1 == G ? 0.5 : 0.0);
            expd[size_t(cy) * G + cx] = N * frac / (G * G) * 2.0;
        }
    ChiSquareResult r = chi_square(obs, expd);
    INFO("triangle: " << r.details);
    CHECK(r.p_value > Alpha);
}

TEST_CASE("distributions: discrete and 2D piecewise-constant sampling follow the weights", "[sampling]") {
    std::vector<float> w = {0.0f, 1.0f, 3.0f, 0.0f, 0.5f, 2.0f, 0.0f};
    Distribution1D d(w);
    CHECK(d.total() == Approx(6.5f));
    PCG32 rng(5, 1);
    std::vector<double> obs(w.size(), 0.0), expd(w.size(), 0.0);
    for (int i = 0; i < N; ++i) {
        float u = rng.next_float();
        size_t k = d.sample_discrete(u);
        REQUIRE(w[k] > 0.0f);  // never a zero-weight bin
        REQUIRE(u >= 0.0f);
        REQUIRE(u < 1.0f);
        obs[k] += 1.0;
    }
    for (size_t k = 0; k < w.size(); ++k) expd[k] = N * w[k] / 6.5;
    ChiSquareResult r = chi_square(obs, expd);
    INFO("discrete: " << r.details);
    CHECK(r.p_value > Alpha);

    // 2D: a 6x4 grid; counts per cell against weight share; the pdf integrates to one.
    std::vector<float> grid = {1, 2, 0, 4, 1, 1, 0, 0, 3, 1, 2, 2, 5, 1, 0, 1, 1, 1, 2, 2, 2, 2, 0.5f, 7};
    Distribution2D d2(grid, 6, 4);
    double total = 0.0;
    for (float g : grid) total += g;
    std::vector<double> o2(grid.size(), 0.0), e2(grid.size(), 0.0);
    double pdf_mc = 0.0, pdf_mc2 = 0.0;
    for (int i = 0; i < N; ++i) {
        float a = rng.next_float();
        float pdf;
        Vec2 p = d2.sample(Vec2(a, rng.next_float()), &pdf);
        REQUIRE(pdf == Approx(d2.pdf(p)).epsilon(1e-4));
        o2[size_t(std::min(int(p.y * 4), 3)) * 6 + std::min(int(p.x * 6), 5)] += 1.0;
        float c = rng.next_float();
        double v = d2.pdf(Vec2(c, rng.next_float()));
        pdf_mc += v;
        pdf_mc2 += v * v;
    }
    for (size_t k = 0; k < grid.size(); ++k) e2[k] = N * grid[k] / total;
    ChiSquareResult r2 = chi_square(o2, e2);
    INFO("2D: " << r2.details);
    CHECK(r2.p_value > Alpha);
    // The pdf integrates to one: uniform Monte Carlo estimate within the z-threshold of the
    // estimate's own standard error.
    double mean = pdf_mc / N, se = std::sqrt((pdf_mc2 / N - mean * mean) / (N - 1));
    INFO("pdf integral " << mean << " +- " << se);
    CHECK(std::abs(mean - 1.0) < two_sided_z(Alpha) * se);
}
