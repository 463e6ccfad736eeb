#include "tests/stats.h"

#include "core/integrator.h"
#include "core/scene.h"

#include <cmath>

namespace candela::test {

SphericalHistogram::SphericalHistogram(int t, int p) : theta_bins(t), phi_bins(p), counts(size_t(t) * p, 0.0) {}

void SphericalHistogram::add(const Vec3& w) {
    // Bins uniform in cos(theta) over [-1, 1] (equal solid angle per cell) and in phi.
    double z = std::clamp(double(w.z), -1.0, 1.0);
    int ti = std::min(int((1.0 - z) * 0.5 * theta_bins), theta_bins - 1);
    double phi = std::atan2(double(w.y), double(w.x));
    if (phi < 0.0) phi += 2.0 * 3.14159265358979323846;
    int pi = std::min(int(phi / (2.0 * 3.14159265358979323846) * phi_bins), phi_bins - 1);
    counts[size_t(ti) * phi_bins + pi] += 1.0;
}

namespace {
// Adaptive Simpson quadrature (Lyness 1969): splits until the two halves agree, which resolves
// jumps of the integrand (hemisphere edges, cone cut-offs) inside a cell.
double adaptive_simpson(const std::function<double(double)>& f, double a, double b, double fa, double fm, double fb, double whole,
                        double eps, int depth) {
    double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    double flm = f(lm), frm = f(rm);
    double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm), right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    double delta = left + right - whole;
    if (depth <= 0 || std::abs(delta) <= 15.0 * eps) return left + right + delta / 15.0;
    return adaptive_simpson(f, a, m, fa, flm, fm, left, eps / 2.0, depth - 1) +
           adaptive_simpson(f, m, b, fm, frm, fb, right, eps / 2.0, depth - 1);
}

double integrate(const std::function<double(double)>& f, double a, double b, double eps, int depth) {
    // Start from a few panels so that a narrow feature is not missed by the first estimate.
    const int panels = 4;
    double sum = 0.0, h = (b - a) / panels;
    for (int i = 0; i < panels; ++i) {
        double x0 = a + i * h, x1 = x0 + h, xm = 0.5 * (x0 + x1);
        double f0 = f(x0), fm = f(xm), f1 = f(x1);
        sum += adaptive_simpson(f, x0, x1, f0, fm, f1, h / 6.0 * (f0 + 4.0 * fm + f1), eps / panels, depth);
    }
    return sum;
}
}  // namespace

std::vector<double> SphericalHistogram::expected(const std::function<double(const Vec3&)>& pdf, double samples) const {
    std::vector<double> out(counts.size(), 0.0);
    const double two_pi = 2.0 * 3.14159265358979323846;
    // dOmega = dz dphi: integrate the pdf over each (z, phi) cell, phi inside z. The tolerances
    // hold the quadrature's error to about 0.02 expected samples per cell (0.002 for the inner
    // integral), far below a cell's Poisson deviation; they were fixed at 1e-7 and 1e-8, which
    // is that at 2e5 samples, and are never tighter than that. Fewer samples (the sanitizer
    // run's CANDELA_TEST_EFFORT) need proportionally less accurate expectations.
    const double outer_tolerance = std::max(1e-7, 0.02 / samples), inner_tolerance = std::max(1e-8, 0.002 / samples);
    for (int ti = 0; ti < theta_bins; ++ti) {
        double z0 = 1.0 - 2.0 * (ti + 1) / theta_bins, z1 = 1.0 - 2.0 * ti / theta_bins;
        for (int pi = 0; pi < phi_bins; ++pi) {
            double p0 = two_pi * pi / phi_bins, p1 = two_pi * (pi + 1) / phi_bins;
            auto over_phi = [&](double z) {
                double r = std::sqrt(std::max(0.0, 1.0 - z * z));
                auto g = [&](double phi) { return pdf(Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z))); };
                return integrate(g, p0, p1, inner_tolerance, 12);
            };
            out[size_t(ti) * phi_bins + pi] = std::max(0.0, integrate(over_phi, z0, z1, outer_tolerance, 14)) * samples;
        }
    }
    return out;
}

MeanAndVariance block_mean(const Image& img, int ch, int x0, int y0, int size) {
    int var = img.channel_index(std::string("variance.") + "RGB"[ch]);
    MeanAndVariance m;
    double n = double(size) * size;
    for (int y = y0; y < y0 + size; ++y)
        for (int x = x0; x < x0 + size; ++x) {
            m.mean += img.at(x, y, ch) / n;
            m.variance_of_mean += img.at(x, y, var) / (n * n);
        }
    return m;
}

MeanAndError channel_mean(const Image& img, int ch, int x0, int y0, int w, int h) {
    if (w < 0) w = img.width();
    if (h < 0) h = img.height();
    std::vector<double> v;
    for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x) v.push_back(img.at(x, y, ch));
    return mean_and_error(v);
}

MeanAndError mean_difference(const Image& a, const Image& b, int ch, int x0, int y0, int w, int h) {
    if (w < 0) w = a.width();
    if (h < 0) h = a.height();
    std::vector<double> diff;
    for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x) diff.push_back(double(a.at(x, y, ch)) - b.at(x, y, ch));
    return mean_and_error(diff);
}

double largest_block_z(const Image& a, const Image& b, std::string* where) {
    double largest = 0.0;
    for (int ch = 0; ch < 3; ++ch)
        for (int block = -1; block < 16; ++block) {
            int x0 = block < 0 ? 0 : 8 * (block % 4), y0 = block < 0 ? 0 : 8 * (block / 4), size = block < 0 ? 32 : 8;
            MeanAndError d = mean_difference(a, b, ch, x0, y0, size, size);
            // A difference with no spread at all is 0 (equal images) or infinitely significant.
            // A NaN counts as infinitely significant, so that no later block hides it.
            double z = d.std_error > 0.0 ? std::abs(d.mean) / d.std_error : (d.mean == 0.0 ? 0.0 : INFINITY);
            if (std::isnan(z)) z = INFINITY;
            bool first = block == -1 && ch == 0;
            if (!first && z <= largest) continue;
            largest = z;
            if (where)
                *where = "channel " + std::to_string(ch) + ", block " + std::to_string(block) + ": difference " + std::to_string(d.mean) +
                         " +- " + std::to_string(d.std_error);
        }
    return largest;
}

SeedBlockMeans seed_block_means(const Scene& scene, int seeds, int block) {
    SeedBlockMeans means;
    int blocks_x = 0;
    for (int k = 0; k < seeds; ++k) {
        RenderOptions options;
        options.seed = uint64_t(1000 + k);
        const Image image = scene.integrator().render(scene, options).image;
        blocks_x = image.width() / block;
        means.resize(size_t(blocks_x * (image.height() / block)));
        for (size_t b = 0; b < means.size(); ++b)
            for (int c = 0; c < 3; ++c)
                means[b][c].push_back(channel_mean(image, c, int(b % blocks_x) * block, int(b / blocks_x) * block, block, block).mean);
    }
    return means;
}

double smallest_welch_p(const SeedBlockMeans& a, const SeedBlockMeans& b, std::string& where) {
    double smallest = 1.0;
    for (size_t block = 0; block < a.size() && block < b.size(); ++block)
        for (int c = 0; c < 3; ++c) {
            const WelchResult w = welch_test(a[block][c], b[block][c]);
            if (w.p_value < smallest) {
                smallest = w.p_value;
                where = "block " + std::to_string(block) + " channel " + std::to_string(c) + ": t = " + std::to_string(w.t) + ", means " +
                        std::to_string(mean_and_error(a[block][c]).mean) + " and " + std::to_string(mean_and_error(b[block][c]).mean);
            }
        }
    return smallest;
}

}  // namespace candela::test
