// gen_srgb_sigmoid: computes the coefficient table of core/rgb2spec.h (Jakob and Hanika 2019, "A
// Low-Dimensional Function Space for Efficient Spectral Upsampling") from the CIE 1931 and D65
// tables the renderer itself uses (core/spectral.h). Not part of the renderer: CMake builds and
// runs it when the project configures (cmake/srgb_sigmoid_table.cmake), and core/rgb2spec_table.cpp
// compiles its output in. By hand:
//
//   gen_srgb_sigmoid OUTPUT.coeff [threads]
//
// Here (2 cores, 2 threads, -O2): 15 s for the fits, 16 s in all with the check at the end. The
// output does not depend on the thread count (each row is fitted on its own).
//
// The fit. A node's colour is `target`; its spectrum s(l) = S(a t^2 + b t + c), t = (l - 360) /
// 470 in [0, 1] (the coefficients of t are of order 1-100, well conditioned; they are turned
// into coefficients of l in nm when stored). Its colour is core/spectral.h's spectrum_to_rgb
// (weight_by_d65 = true) of s sampled every 1 nm from 360 to 830 nm, which is linear in the
// samples: rgb(s) = sum_i w_i s(l_i), w_i = spectrum_to_rgb_weights. The residual
// r = rgb(s) - target is minimised in least squares by Levenberg-Marquardt (the 3 x 3 normal
// equations with Marquardt's diagonal damping), with the Jacobian
// dr/d(a, b, c) = sum_i w_i S'(x_i) (t_i^2, t_i, 1), S'(x) = 1 / (2 (1 + x^2)^(3/2)).
// The residual is in linear sRGB, not CIELAB as in the paper: that is the error the renderer's
// round trip is judged by, and where a colour is reachable both are zero at the solution.
// A small Tikhonov term, (1e-6 z)^2 |(a, b, c)|^2 (z the largest component), is added to the
// cost: near white some colours are out of reach (spectrum_to_rgb makes the flat spectrum 1
// (0.99899, 0.99887, 0.99880)), and there the least-squares coefficients grow without bound
// (white's reached 1e17 without it, and spoiled every colour interpolated from it); with it
// white's (c0, c1, c2) are (1.2e-4, 0.049, 150). The mean |r| at the nodes is 1.3e-7 with it,
// 6.8e-8 without.
//
// The walk (the paper's): for each table l and each (x, y) node, the first fit is at z index
// res / 5 from the flat spectrum 1/2 (a = b = c = 0); from there z goes up to 1 and then down
// to 0, each fit starting from its neighbour's solution. z = 0 is black, which no finite
// coefficients reach: that node takes its neighbour's (z = 1.7e-6) coefficients; the lookup
// reaches it only below that z, where the error is below 1.7e-6. Work is shared by std::thread
// over (l, y) rows.
//
// At the end it reads its table back through fetch_sigmoid_polynomial (the renderer's lookup)
// and prints the round-trip error at the nodes and on a 33^3 grid of the sRGB cube (sampled every
// 1 nm, spectrum_to_rgb bounded, as tests/core/test_rgb2spec.cpp measures it).

#include "core/rgb2spec.h"
#include "core/spectral.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <thread>
#include <vector>

using namespace candela;

namespace {

constexpr int Resolution = 64;
constexpr double LambdaMin = 360.0, LambdaMax = 830.0;
constexpr int Samples = 471;  // every 1 nm
// Tikhonov weight on the coefficients, times the largest component (see the top).
constexpr double Regularization = 1e-6;

struct Model {
    double t[Samples];
    Vec3d w[Samples];
};

struct Coefficients {
    double a = 0, b = 0, c = 0;
};

double smoothstep(double x) { return x * x * (3.0 - 2.0 * x); }

// rgb(s) - target, and optionally the Jacobian's columns d/da, d/db, d/dc.
Vec3d residual(const Model& m, const Coefficients& k, const Vec3d& target, Vec3d* jacobian) {
    Vec3d rgb(0.0), ja(0.0), jb(0.0), jc(0.0);
    for (int i = 0; i < Samples; ++i) {
        double t = m.t[i];
        double x = (k.a * t + k.b) * t + k.c;
        double root = std::sqrt(1.0 + x * x);
        rgb += m.w[i] * (0.5 + 0.5 * x / root);
        if (jacobian) {
            Vec3d d = m.w[i] * (0.5 / (root * root * root));
            ja += d * (t * t);
            jb += d * t;
            jc += d;
        }
    }
    if (jacobian) jacobian[0] = ja, jacobian[1] = jb, jacobian[2] = jc;
    return rgb - target;
}

double norm2(const Vec3d& v) { return glm::dot(v, v); }

// Solves the 3 x 3 system m x = v (Cramer's rule; m is symmetric positive definite here).
bool solve3(const double m[3][3], const double v[3], double x[3]) {
    auto det = [](const double a[3][3]) {
        return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
               a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    };
    double d = det(m);
    if (!(std::abs(d) > 0.0) || !std::isfinite(d)) return false;
    for (int c = 0; c < 3; ++c) {
        double a[3][3];
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k) a[r][k] = k == c ? v[r] : m[r][k];
        x[c] = det(a) / d;
    }
    return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

double norm2(const Coefficients& k) { return k.a * k.a + k.b * k.b + k.c * k.c; }

// Levenberg-Marquardt from `k` on |r|^2 + (Regularization z)^2 |k|^2; returns the final |r|.
double fit(const Model& m, const Vec3d& target, Coefficients& k) {
    const double tolerance = 1e-12 + 1e-9 * std::max(target.x, std::max(target.y, target.z));
    const double z = std::max(target.x, std::max(target.y, target.z));
    const double eps2 = (Regularization * z) * (Regularization * z);
    double mu = 1e-3;
    Vec3d j[3];
    Vec3d r = residual(m, k, target, j);
    double cost = norm2(r) + eps2 * norm2(k);
    for (int iteration = 0; iteration < 300 && std::sqrt(norm2(r)) > tolerance; ++iteration) {
        const double kv[3] = {k.a, k.b, k.c};
        double a[3][3], g[3];
        for (int p = 0; p < 3; ++p) {
            g[p] = -glm::dot(j[p], r) - eps2 * kv[p];
            for (int q = 0; q < 3; ++q) a[p][q] = glm::dot(j[p], j[q]) + (p == q ? eps2 : 0.0);
        }
        bool improved = false;
        while (mu < 1e16) {
            double damped[3][3], step[3];
            for (int p = 0; p < 3; ++p)
                for (int q = 0; q < 3; ++q) damped[p][q] = a[p][q] + (p == q ? mu * a[p][p] : 0.0);
            if (solve3(damped, g, step)) {
                Coefficients trial{k.a + step[0], k.b + step[1], k.c + step[2]};
                Vec3d trial_j[3];
                Vec3d trial_r = residual(m, trial, target, trial_j);
                double trial_cost = norm2(trial_r) + eps2 * norm2(trial);
                if (trial_cost < cost) {
                    bool stalled = cost - trial_cost < 1e-12 * cost;
                    k = trial, r = trial_r, cost = trial_cost;
                    for (int p = 0; p < 3; ++p) j[p] = trial_j[p];
                    mu = std::max(mu / 3.0, 1e-12);
                    improved = !stalled;
                    break;
                }
            }
            mu *= 4.0;
        }
        if (!improved) break;
    }
    return std::sqrt(norm2(r));
}

// The coefficients of t = (l - 360) / 470 as coefficients of l in nm:
// a t^2 + b t + c = c0 l^2 + c1 l + c2 with t = (l - L0) / D.
void to_nanometres(const Coefficients& k, float out[3]) {
    const double l0 = LambdaMin, d = LambdaMax - LambdaMin;
    out[0] = float(k.a / (d * d));
    out[1] = float(k.b / d - 2.0 * k.a * l0 / (d * d));
    out[2] = float(k.c - k.b * l0 / d + k.a * l0 * l0 / (d * d));
}

Vec3d node_colour(int l, double z, int i, int j) {
    Vec3d rgb;
    rgb[l] = z;
    rgb[(l + 1) % 3] = z * i / double(Resolution - 1);
    rgb[(l + 2) % 3] = z * j / double(Resolution - 1);
    return rgb;
}

struct ErrorSummary {
    double max = 0, sum = 0;
    long count = 0;
    Vec3d worst{0.0};
    void add(const Vec3d& rgb, const Vec3d& back) {
        for (int c = 0; c < 3; ++c) {
            double e = std::abs(back[c] - rgb[c]);
            sum += e;
            if (e > max) max = e, worst = rgb;
        }
        count += 3;
    }
    void print(const char* what) const {
        std::printf("%s: max %.3g (at rgb %.6f %.6f %.6f), mean %.3g over %ld channels\n", what, max, worst.x, worst.y, worst.z,
                    sum / count, count);
    }
};

// spectrum_to_rgb (bounded) of the spectrum sampled every 1 nm, as the tests measure it.
Vec3d round_trip(const SigmoidPolynomial& s) {
    SampledSpectrum sampled;
    for (int i = 0; i < Samples; ++i) {
        double lambda = LambdaMin + i;
        sampled.wavelengths.push_back(lambda);
        sampled.values.push_back(s(float(lambda)));
    }
    return Vec3d(spectrum_to_rgb(sampled, true, true));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argc > 3) {
        std::fprintf(stderr, "usage: gen_srgb_sigmoid OUTPUT.coeff [threads]\n");
        return 2;
    }
    int threads = argc == 3 ? std::atoi(argv[2]) : int(std::thread::hardware_concurrency());
    threads = std::max(threads, 1);
    auto start = std::chrono::steady_clock::now();

    std::vector<double> wavelengths;
    for (int i = 0; i < Samples; ++i) wavelengths.push_back(LambdaMin + i);
    std::vector<Vec3d> weights = spectrum_to_rgb_weights(wavelengths, true);
    auto model = std::make_unique<Model>();
    for (int i = 0; i < Samples; ++i) {
        model->t[i] = (wavelengths[i] - LambdaMin) / (LambdaMax - LambdaMin);
        model->w[i] = weights[i];
    }

    const int res = Resolution;
    std::vector<float> scale(res);
    for (int k = 0; k < res; ++k) scale[k] = float(smoothstep(smoothstep(k / double(res - 1))));
    std::vector<float> table(size_t(3) * res * res * res * 3);
    std::vector<double> fit_error(size_t(3) * res * res * res);
    auto node = [&](int l, int k, int j, int i) { return ((size_t(l) * res + k) * res + j) * res + i; };

    std::atomic<int> next_row{0};
    auto work = [&]() {
        for (int row; (row = next_row++) < 3 * res;) {
            int l = row / res, j = row % res;
            for (int i = 0; i < res; ++i) {
                auto solve_at = [&](int k, Coefficients& c) {
                    fit_error[node(l, k, j, i)] = fit(*model, node_colour(l, scale[k], i, j), c);
                    to_nanometres(c, &table[3 * node(l, k, j, i)]);
                };
                const int first = res / 5;
                Coefficients start;
                solve_at(first, start);
                Coefficients c = start;
                for (int k = first + 1; k < res; ++k) solve_at(k, c);
                c = start;
                for (int k = first - 1; k >= 1; --k) solve_at(k, c);
                // z = 0 (black): the z = scale[1] node's coefficients (see the top).
                for (int n = 0; n < 3; ++n) table[3 * node(l, 0, j, i) + n] = table[3 * node(l, 1, j, i) + n];
                fit_error[node(l, 0, j, i)] = 0.0;
            }
        }
    };
    std::vector<std::thread> pool;
    for (int n = 0; n < threads; ++n) pool.emplace_back(work);
    for (auto& t : pool) t.join();
    double fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    for (float v : table)
        if (!std::isfinite(v)) {
            std::fprintf(stderr, "gen_srgb_sigmoid: a coefficient is not finite\n");
            return 1;
        }
    {
        std::ofstream out(argv[1], std::ios::binary);
        uint32_t resolution = res;
        out.write("CSG1", 4);
        out.write(reinterpret_cast<const char*>(&resolution), 4);  // little-endian hosts only
        out.write(reinterpret_cast<const char*>(scale.data()), std::streamsize(scale.size() * 4));
        out.write(reinterpret_cast<const char*>(table.data()), std::streamsize(table.size() * 4));
        if (!out) {
            std::fprintf(stderr, "gen_srgb_sigmoid: cannot write %s\n", argv[1]);
            return 1;
        }
        std::printf("wrote %s: resolution %d, %zu bytes; fitted in %.1f s with %d threads\n", argv[1], res,
                    8 + 4 * scale.size() + 4 * table.size(), fit_seconds, threads);
    }

    // The fit itself (double coefficients, the 1 nm sum), node by node.
    double worst_fit = 0, sum_fit = 0;
    size_t worst_node = 0;
    for (size_t n = 0; n < fit_error.size(); ++n) {
        sum_fit += fit_error[n];
        if (fit_error[n] > worst_fit) worst_fit = fit_error[n], worst_node = n;
    }
    {
        int i = int(worst_node % res), j = int(worst_node / res % res), k = int(worst_node / res / res % res),
            l = int(worst_node / res / res / res);
        Vec3d at = node_colour(l, scale[k], i, j);
        std::printf("fit |r| at the nodes: max %.3g (at rgb %.6f %.6f %.6f), mean %.3g over %zu nodes\n", worst_fit, at.x, at.y, at.z,
                    sum_fit / double(fit_error.size()), fit_error.size());
    }

    // The renderer's lookup (float coefficients, trilinear) on this table.
    SigmoidTable view;
    view.resolution = res;
    view.scale = scale.data();
    view.coefficients = table.data();
    ErrorSummary grid;
    const int n = 33;
    for (int b = 0; b < n; ++b)
        for (int g = 0; g < n; ++g)
            for (int r = 0; r < n; ++r) {
                if (r == g && g == b) continue;  // greys are the flat spectrum, not the table
                Vec3 rgb(r / float(n - 1), g / float(n - 1), b / float(n - 1));
                grid.add(Vec3d(rgb), round_trip(fetch_sigmoid_polynomial(view, rgb)));
            }
    grid.print("round trip, 33^3 grid without greys");
    std::printf("total %.1f s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return 0;
}
