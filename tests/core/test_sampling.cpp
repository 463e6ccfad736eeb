// Sampling warps and distributions: chi-square goodness of fit of every warp against its pdf,
// and the discrete/continuous distributions against their weights. All tests together keep a
// family-wise significance of 1% (Sidak).

#include "core/distribution.h"
#include "core/rng.h"
#include "core/warp.h"
#include "tests/stats.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

using namespace candela;
using namespace candela::test;

namespace {
constexpr int SamplingTests = 11;  // number of statistical tests in this file
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
    check_spherical_warp(
        "uniform sphere", warp::square_to_uniform_sphere, [](const Vec3&) { return double(warp::square_to_uniform_sphere_pdf()); }, 1);
    check_spherical_warp(
        "uniform hemisphere", warp::square_to_uniform_hemisphere,
        [](const Vec3& v) { return double(warp::square_to_uniform_hemisphere_pdf(v)); }, 2);
    check_spherical_warp(
        "cosine hemisphere", warp::square_to_cosine_hemisphere,
        [](const Vec3& v) { return double(warp::square_to_cosine_hemisphere_pdf(v)); }, 3);
    const float cos_cutoff = std::cos(radians(35.0f));
    check_spherical_warp(
        "uniform cone", [&](Vec2 u) { return warp::square_to_uniform_cone(u, cos_cutoff); },
        [&](const Vec3& v) { return double(warp::square_to_uniform_cone_pdf(v, cos_cutoff)); }, 4);
}

TEST_CASE("warp: the concentric disk's branch-free case choice is Shirley and Chiu's two cases, bit for bit", "[sampling]") {
    // The mapping picks its case by bit masks (select_float); this is the two-branch form it
    // replaced, on random points, both diagonals, the axes and the centre.
    auto two_branches = [](const Vec2& u) {
        float x = 2.0f * u.x - 1.0f, y = 2.0f * u.y - 1.0f, s, c;
        if (x == 0.0f && y == 0.0f) return Vec2(0.0f);
        if (std::abs(x) > std::abs(y)) {
            sincos_quarter_pi((Pi / 4.0f) * (y / x), s, c);
            return Vec2(x * c, x * s);
        }
        sincos_quarter_pi((Pi / 4.0f) * (x / y), s, c);
        return Vec2(y * s, y * c);
    };
    std::vector<Vec2> points = {Vec2(0.5f), Vec2(0.0f), Vec2(0x1.fffffep-1f), Vec2(0.5f, 0.0f), Vec2(0.0f, 0.5f)};
    PCG32 rng(11, 5);
    for (int i = 0; i < 200000; ++i) {
        float a = rng.next_float();
        points.push_back(Vec2(a, rng.next_float()));
        points.push_back(Vec2(a, a));
        points.push_back(Vec2(a, 1.0f - a));
    }
    for (const Vec2& u : points) {
        const Vec2 got = warp::square_to_uniform_disk_concentric(u), want = two_branches(u);
        INFO(u.x << ", " << u.y);
        REQUIRE(std::memcmp(&got, &want, sizeof got) == 0);
    }
    CHECK(select_float(~0u, 1.5f, -2.0f) == 1.5f);
    CHECK(select_float(0u, 1.5f, -2.0f) == -2.0f);
    CHECK(std::signbit(select_float(~0u, -0.0f, 0.0f)));
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

TEST_CASE("distributions: Marginal2D samples its bilinear, parameter-blended density and inverts its warp", "[sampling]") {
    // Three 7 x 5 grids (parameter values 0, 1, 3), with a zero first column as the measured
    // BSDF's VNDF tables have at the pole; queried at parameter 0.6 (a blend of the first two).
    const int W = 7, H = 5;
    PCG32 rng(8, 2);
    std::vector<float> data(size_t(3 * W * H));
    for (size_t i = 0; i < data.size(); ++i) data[i] = (i % W == 0) ? 0.0f : rng.next_float() + 0.1f * float(i % 3);
    Marginal2D m(data.data(), W, H, {{0.0f, 1.0f, 3.0f}}, Marginal2D::Mode::Distribution);
    float param = 0.6f;
    // Histogram cells: each patch halved in x and y, so that the midpoint rule on each cell is
    // exact for the bilinear density.
    const int cx = 2 * (W - 1), cy = 2 * (H - 1);
    std::vector<double> observed(size_t(cx * cy), 0.0), expected(size_t(cx * cy), 0.0);
    double worst_roundtrip = 0.0, worst_pdf = 0.0;
    for (int i = 0; i < N; ++i) {
        float a = rng.next_float();
        Vec2 u(a, rng.next_float());
        float pdf, pdf_inverse;
        Vec2 p = m.sample(u, &param, &pdf);
        Vec2 back = m.invert(p, &param, &pdf_inverse);
        worst_roundtrip = std::max(worst_roundtrip, double(max_abs_component(Vec3(back - u, 0.0f))));
        worst_pdf = std::max(worst_pdf, double(std::abs(pdf - m.eval(p, &param)) / pdf));
        observed[size_t(std::min(int(p.y * cy), cy - 1) * cx + std::min(int(p.x * cx), cx - 1))] += 1.0;
    }
    for (int y = 0; y < cy; ++y)
        for (int x = 0; x < cx; ++x)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) {
                    Vec2 q((float(x) + (float(i) + 0.5f) / 2.0f) / cx, (float(y) + (float(j) + 0.5f) / 2.0f) / cy);
                    expected[size_t(y * cx + x)] += double(m.eval(q, &param)) / (4.0 * cx * cy) * N;
                }
    ChiSquareResult r = chi_square(observed, expected);
    INFO("Marginal2D: " << r.details << "; worst |invert(sample(u)) - u| " << worst_roundtrip << ", worst pdf vs eval " << worst_pdf);
    CHECK(r.p_value > Alpha);
    CHECK(worst_roundtrip < 1e-5);  // float rounding of the CDFs (values near 1: spacing 6e-8)
    CHECK(worst_pdf < 1e-5);
    // As an interpolant: the bilinear interpolation of the values as given, the parameter
    // clamped to its range.
    Marginal2D raw(data.data(), W, H, {{0.0f, 1.0f, 3.0f}}, Marginal2D::Mode::Interpolant);
    float at_node = 1.0f, beyond = 7.0f;
    CHECK(raw.eval(Vec2(2.0f / 6.0f, 3.0f / 4.0f), &at_node) == Approx(data[size_t(W * H + 3 * W + 2)]).epsilon(1e-6));
    CHECK(raw.eval(Vec2(0.25f, 0.5f), &beyond) ==
          Approx(0.5 * data[size_t(2 * W * H + 2 * W + 1)] + 0.5 * data[size_t(2 * W * H + 2 * W + 2)]).epsilon(1e-6));
    std::vector<float> zero(size_t(W * H), 0.0f);
    CHECK_THROWS_AS(Marginal2D(zero.data(), W, H, {}, Marginal2D::Mode::Distribution), std::invalid_argument);
    // A NaN point reads as the corner (0, 0), as a NaN parameter reads as the first slice: NaN
    // made a table index (undefined behaviour; UBSan stopped fuzz_measured there).
    const float nan = std::numeric_limits<float>::quiet_NaN();
    float first = 0.0f;
    CHECK(raw.eval(Vec2(nan, nan), &nan) == raw.eval(Vec2(0.0f, 0.0f), &first));
    float pdf = -1.0f;
    Vec2 u = m.invert(Vec2(nan, 0.5f), &first, &pdf);
    CHECK(std::isfinite(u.x));
    CHECK(std::isfinite(pdf));
}

TEST_CASE("distributions: Marginal2D's blend at a node of its last parameter is blend() at that node's value, bit for bit", "[sampling]") {
    // Two interpolated parameters and a channel index (measured's rgb table): at_node skips the
    // channel's search and weights; every value must be the same float as blend()'s.
    const int W = 5, H = 4;
    const std::vector<float> first = {-1.0f, 0.5f, 2.0f}, second = {0.0f, 1.0f}, channel = {0.0f, 1.0f, 2.0f};
    std::vector<float> data(first.size() * second.size() * channel.size() * size_t(W * H));
    PCG32 rng(3, 7);
    for (float& v : data) v = rng.next_float();
    const Marginal2D m(data.data(), W, H, {first, second, channel}, Marginal2D::Mode::Interpolant);
    int differing = 0;
    for (int i = 0; i < 2000; ++i) {
        const float params[3] = {-1.5f + 4.0f * rng.next_float(), -0.2f + 1.4f * rng.next_float(), 0.0f};
        const Vec2 p(rng.next_float(), rng.next_float());
        const Marginal2D::Blend leading = m.blend_leading(params);
        for (int c = 0; c < 3; ++c) {
            const float with_value[3] = {params[0], params[1], float(c)};
            differing += m.eval(p, m.at_node(leading, c)) != m.eval(p, with_value);
        }
    }
    CHECK(differing == 0);
    const float inside[3] = {0.0f, 0.5f, 0.0f};
    CHECK_THROWS_AS(m.at_node(m.blend_leading(inside), 3), std::invalid_argument);
    CHECK_THROWS_AS(m.at_node(m.blend_leading(inside), -1), std::invalid_argument);
}
