// The `measured` BSDF (RGL's .bsdf tensor files) against files written here from a known analytic
// BRDF, a GGX rough conductor tabulated the way Dupuy & Jakob's format stores a measurement: the
// tables ndf and sigma, per incident slice a VNDF density over half vectors, and the reflectance
// factor F(wi . h) G1(wo) at the nodes of the VNDF warp's sample space (jacobian = 1, so that
// f cos(wo) = factor * D(h) / (4 sigma(wi)), which is exactly roughconductor's F D G1 G1 / 4 cos).
// Checked: sampling against pdf (chi-square), eval against the analytic BRDF within the
// interpolation error of the tables, weight = eval / pdf, the spectral path, malformed files, and
// a scene that loads and renders.

#include "core/distribution.h"
#include "core/error.h"
#include "core/rng.h"
#include "core/spectral.h"
#include "core/tensor_file.h"
#include "core/warp.h"
#include "core/wavelengths.h"
#include "materials/fresnel.h"
#include "materials/microfacet.h"
#include "tests/bsdf_harness.h"
#include "tests/tensor_writer.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <functional>

using namespace candela;
using namespace candela::test;

namespace {

// ---- The analytic BRDF and its tabulation.

float to_u_theta(float theta) { return std::sqrt(theta * (2.0f / Pi)); }
float to_u_phi(float phi) { return (phi + Pi) * InvTwoPi; }
float u_theta(float u) { return u * u * (Pi / 2.0f); }
float u_phi(float u) { return (2.0f * u - 1.0f) * Pi; }
Vec3 spherical(float theta, float phi) { return Vec3(std::cos(phi) * std::sin(theta), std::sin(phi) * std::sin(theta), std::cos(theta)); }

// A GGX rough conductor: roughconductor with these parameters.
struct Conductor {
    float alpha_u, alpha_v;
    Spectrum eta{0.2f, 0.9f, 1.1f}, k{3.9f, 2.4f, 2.1f};
    MicrofacetDistribution distribution() const { return MicrofacetDistribution(MicrofacetType::GGX, alpha_u, alpha_v); }
    std::string xml() const {
        return "<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha_u\" value=\"" +
               std::to_string(alpha_u) + "\"/><float name=\"alpha_v\" value=\"" + std::to_string(alpha_v) +
               "\"/><rgb name=\"eta\" value=\"0.2, 0.9, 1.1\"/><rgb name=\"k\" value=\"3.9, 2.4, 2.1\"/></bsdf>";
    }
    // The projected area of the microsurface seen from w, cos(theta) (1 + Lambda(w)), in GGX's
    // closed form (finite at grazing angles).
    float sigma(const Vec3& w) const {
        float c = std::max(w.z, 0.0f), s2 = std::max(1.0f - c * c, 0.0f);
        float a2 = s2 > 0.0f ? (sqr(alpha_u * w.x) + sqr(alpha_v * w.y)) / s2 : 0.0f;
        return 0.5f * (c + std::sqrt(c * c + a2 * s2));
    }
};

// The tables of one file, in the file's layouts (see materials/measured.cpp).
struct Table {
    std::vector<float> theta_i, phi_i, ndf, sigma, vndf, luminance, rgb;
    int n_ndf = 0, ndf_rows = 0, n = 0;  // ndf and sigma: ndf_rows x n_ndf; vndf, rgb: n x n
    bool isotropic = true;
    std::vector<Marginal2D> warps;  // per slice, the VNDF warp the file describes

    size_t slice(size_t p, size_t t) const { return p * theta_i.size() + t; }
    // `spectrum` scales the grey measurement per wavelength (spectral files).
    std::vector<OutField> fields(bool spectral = false, float (*spectrum)(float) = nullptr) const {
        uint64_t P = phi_i.size(), T = theta_i.size(), N = uint64_t(n);
        std::vector<OutField> f = {
            {"description", TensorType::UInt8, {9}, "synthetic"},
            {"jacobian", TensorType::UInt8, {1}, std::string(1, '\1')},
            {"theta_i", TensorType::Float32, {T}, float_bytes(theta_i)},
            {"phi_i", TensorType::Float32, {P}, float_bytes(phi_i)},
            {"ndf", TensorType::Float32, {uint64_t(ndf_rows), uint64_t(n_ndf)}, float_bytes(ndf)},
            {"sigma", TensorType::Float32, {uint64_t(ndf_rows), uint64_t(n_ndf)}, float_bytes(sigma)},
            {"vndf", TensorType::Float32, {P, T, N, N}, float_bytes(vndf)},
            {"luminance", TensorType::Float32, {P, T, N, N}, float_bytes(luminance)},
        };
        if (!spectral) {
            f.push_back({"rgb", TensorType::Float32, {P, T, 3, N, N}, float_bytes(rgb)});
            return f;
        }
        // A grey measurement: the luminance as a flat spectrum at 8 wavelengths.
        std::vector<float> wavelengths = {360, 420, 480, 540, 600, 660, 720, 830};
        std::vector<float> spectra;
        for (size_t s = 0; s < P * T; ++s)
            for (size_t w = 0; w < wavelengths.size(); ++w)
                for (size_t i = 0; i < N * N; ++i)
                    spectra.push_back(luminance[s * N * N + i] * (spectrum ? spectrum(wavelengths[w]) : 1.0f));
        f.push_back({"wavelengths", TensorType::Float32, {uint64_t(wavelengths.size())}, float_bytes(wavelengths)});
        f.push_back({"spectra", TensorType::Float32, {P, T, uint64_t(wavelengths.size()), N, N}, float_bytes(spectra)});
        return f;
    }
};

// Tabulates `c` at the given slices with n x n sample-space nodes (ndf and sigma at 2n).
Table tabulate(const Conductor& c, std::vector<float> theta_i, std::vector<float> phi_i, int n) {
    Table t;
    t.theta_i = std::move(theta_i);
    t.phi_i = std::move(phi_i);
    t.isotropic = t.phi_i.size() <= 2;
    t.n = n;
    t.n_ndf = 2 * n;
    t.ndf_rows = t.isotropic ? 2 : 2 * n;
    MicrofacetDistribution D = c.distribution();
    for (int y = 0; y < t.ndf_rows; ++y)
        for (int x = 0; x < t.n_ndf; ++x) {
            Vec3 w = spherical(u_theta(float(x) / float(t.n_ndf - 1)), u_phi(float(y) / float(t.ndf_rows - 1)));
            t.ndf.push_back(D.D(w));
            t.sigma.push_back(c.sigma(w));
        }
    t.rgb.assign(t.phi_i.size() * t.theta_i.size() * 3 * size_t(n * n), 0.0f);
    for (float phi : t.phi_i)
        for (float theta : t.theta_i) {
            Vec3 wi = spherical(theta, phi);
            // The density of visible normals on the square: D(m) <wi, m>+ times dm/du
            // (proportional to u_theta sin(theta_m)); the warp normalises it.
            std::vector<float> density;
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    float ux = float(x) / float(n - 1), th = u_theta(ux);
                    Vec3 m = spherical(th, u_phi(float(y) / float(n - 1)) + (t.isotropic ? phi : 0.0f));
                    density.push_back(D.D(m) * std::max(glm::dot(wi, m), 0.0f) * ux * std::sin(th));
                }
            t.vndf.insert(t.vndf.end(), density.begin(), density.end());
            t.warps.emplace_back(density.data(), n, n, std::vector<std::vector<float>>{}, Marginal2D::Mode::Distribution);
            size_t slice = t.warps.size() - 1;
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    float pdf;
                    Vec2 u = t.warps.back().sample(Vec2(float(x) / float(n - 1), float(y) / float(n - 1)), nullptr, &pdf);
                    Vec3 m = spherical(u_theta(u.x), u_phi(u.y) + (t.isotropic ? phi : 0.0f));
                    Vec3 wo = reflect(wi, m);
                    Spectrum factor(0.0f);
                    if (wo.z > 0.0f) factor = fresnel_conductor(glm::dot(wi, m), c.eta, c.k) * D.G1(wo, m);
                    for (int ch = 0; ch < 3; ++ch) t.rgb[(slice * 3 + size_t(ch)) * size_t(n * n) + size_t(y * n + x)] = factor[ch];
                    t.luminance.push_back(luminance(factor));
                }
        }
    return t;
}

std::vector<float> degrees(std::initializer_list<float> d) {
    std::vector<float> out;
    for (float v : d) out.push_back(v * Pi / 180.0f);
    return out;
}

// The materials under test: isotropic; anisotropic over a full turn of phi_i... reduced to a
// quarter (mirror symmetric in x and y) and to a half turn (symmetric under a half turn).
const Conductor Iso{0.3f, 0.3f};
const Conductor Aniso{0.25f, 0.45f};
const std::vector<float> Thetas = degrees({0, 16, 32, 48, 64, 80});

const Table& iso_table() {
    static const Table t = tabulate(Iso, Thetas, {0.0f}, 32);
    return t;
}
const Table& quarter_table() {
    static const Table t = tabulate(Aniso, Thetas, degrees({-180, -150, -120, -90}), 32);
    return t;
}
const Table& half_table() {
    static const Table t = tabulate(Aniso, Thetas, degrees({-180, -135, -90, -45, 0}), 32);
    return t;
}

// Writes the table as a .bsdf file in the scratch folder and loads it through the scene loader.
std::filesystem::path write_table(const Table& t, const std::string& name, bool spectral = false, float (*spectrum)(float) = nullptr) {
    static const std::filesystem::path dir = scratch_dir("measured");
    std::filesystem::path path = dir / (name + ".bsdf");
    write_bytes(path, tensor_bytes(t.fields(spectral, spectrum)));
    return path;
}
BSDFUnderTest load_measured(const std::filesystem::path& path) {
    return make_bsdf("<bsdf type=\"measured\"><string name=\"filename\" value=\"" + path.string() + "\"/></bsdf>");
}

// ---- The interpolation error bound.

// The tables are bilinear interpolants of smooth functions f known here. On a patch of a w x h
// grid on [0, 1]^2 (node spacing dx = 1 / (w - 1), dy = 1 / (h - 1)), the interpolant's error is
// at most (dx^2 max|f_xx| + dy^2 max|f_yy|) / 8: the linear interpolation error bound
// |f - I f| <= d^2 max|f''| / 8 applied in each direction. max|f''| is taken over a 5 x 5 grid of
// points on the patch (second differences with step d / 4), where f is evaluated exactly.
double interpolation_bound(const std::function<double(const Vec2&)>& f, int w, int h, const Vec2& p) {
    float dx = 1.0f / float(w - 1), dy = 1.0f / float(h - 1);
    float x0 = float(std::min(int(std::clamp(p.x, 0.0f, 1.0f) * float(w - 1)), w - 2)) * dx;
    float y0 = float(std::min(int(std::clamp(p.y, 0.0f, 1.0f) * float(h - 1)), h - 2)) * dy;
    double values[5][5];
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 5; ++i) values[j][i] = f(Vec2(x0 + float(i) * dx / 4.0f, y0 + float(j) * dy / 4.0f));
    double fxx = 0.0, fyy = 0.0;
    for (int j = 0; j < 5; ++j)
        for (int i = 1; i < 4; ++i) {
            fxx = std::max(fxx, std::abs(values[j][i - 1] - 2.0 * values[j][i] + values[j][i + 1]) * 16.0);  // times (dx / 4)^-2 dx^2
            fyy = std::max(fyy, std::abs(values[i - 1][j] - 2.0 * values[i][j] + values[i + 1][j]) * 16.0);
        }
    return (fxx + fyy) / 8.0;
}

struct Agreement {
    double worst_excess = 0.0;  // largest |measured - analytic| / allowed (must be <= 1)
    double mean_tolerance = 0.0;
    int compared = 0;
};

// eval of the measured BSDF against the analytic one at an incidence on a slice (theta_i and
// phi_i at nodes, so that no blending between slices enters) and wo drawn uniformly with
// cos(wo) >= 0.2 (away from the horizon, where G1's kink makes the bound large).
Agreement compare_with_analytic(const Table& t, const Conductor& c, const BSDF& measured, const BSDF& analytic, const Vec3& wi) {
    Agreement a;
    BSDFContext ctx;
    PCG32 rng(7, 3);
    MicrofacetDistribution D = c.distribution();
    float phi_i = std::atan2(wi.y, wi.x), theta_i = std::acos(std::min(wi.z, 1.0f));
    size_t p = 0, q = 0;
    for (size_t k = 0; k < t.phi_i.size(); ++k)
        if (std::abs(t.phi_i[k] - phi_i) < std::abs(t.phi_i[p] - phi_i)) p = k;
    for (size_t k = 0; k < t.theta_i.size(); ++k)
        if (std::abs(t.theta_i[k] - theta_i) < std::abs(t.theta_i[q] - theta_i)) q = k;
    if (t.isotropic) p = 0;
    size_t slice = t.slice(p, q);
    float phi_offset = t.isotropic ? phi_i : 0.0f;
    auto half_vector = [&](const Vec2& u) { return spherical(u_theta(u.x), u_phi(u.y) + phi_offset); };
    auto ndf = [&](const Vec2& u) { return double(D.D(spherical(u_theta(u.x), u_phi(u.y)))); };
    auto sigma = [&](const Vec2& u) { return double(c.sigma(spherical(u_theta(u.x), u_phi(u.y)))); };
    double tolerance_sum = 0.0;
    for (int i = 0; i < 400; ++i) {
        float u1 = rng.next_float(), u2 = rng.next_float();
        Vec3 wo = warp::square_to_uniform_hemisphere(Vec2(u1, u2));
        if (wo.z < 0.2f) continue;
        SurfaceInteraction si = local_interaction(wi);
        Spectrum fm = measured.eval(ctx, si, wo), fa = analytic.eval(ctx, si, wo);
        // Where the tables are read: h on the square, s = the warp's inverse, wi on the square.
        Vec3 m = glm::normalize(wi + wo);
        Vec2 u_m(to_u_theta(std::acos(std::min(m.z, 1.0f))), to_u_phi(std::atan2(m.y, m.x) - phi_offset));
        u_m.y -= std::floor(u_m.y);
        float unused;
        Vec2 s = t.warps[slice].invert(u_m, nullptr, &unused);
        Vec2 u_i(to_u_theta(theta_i), to_u_phi(phi_i));
        double rel = interpolation_bound(ndf, t.n_ndf, t.ndf_rows, u_m) / ndf(u_m) +
                     interpolation_bound(sigma, t.n_ndf, t.ndf_rows, u_i) / sigma(u_i);
        for (int ch = 0; ch < 3; ++ch) {
            // The reflectance factor at sample-space point x: through the slice's warp to h.
            auto factor = [&](const Vec2& x) {
                float pdf;
                Vec3 h = half_vector(t.warps[slice].sample(x, nullptr, &pdf));
                Vec3 o = reflect(wi, h);
                return o.z > 0.0f ? double(fresnel_conductor(glm::dot(wi, h), c.eta, c.k)[ch] * D.G1(o, h)) : 0.0;
            };
            double value = factor(s);
            if (!(value > 0.0) || !(fa[ch] > 0.0f)) continue;
            // Relative errors of a product and a quotient add (to first order); 1e-4 for float
            // rounding.
            double tolerance = interpolation_bound(factor, t.n, t.n, s) / value + rel + 1e-4;
            a.worst_excess = std::max(a.worst_excess, std::abs(double(fm[ch]) - double(fa[ch])) / (tolerance * fa[ch]));
            tolerance_sum += tolerance;
            ++a.compared;
        }
    }
    a.mean_tolerance = a.compared > 0 ? tolerance_sum / a.compared : 0.0;
    return a;
}

}  // namespace

TEST_CASE("measured: eval matches the tabulated analytic BRDF within the tables' interpolation error", "[bsdf][measured]") {
    struct Case {
        const char* name;
        const Table& table;
        Conductor c;
        std::vector<Vec3> incidences;
    };
    std::vector<Case> cases = {
        {"iso",
         iso_table(),
         Iso,
         {spherical(Thetas[1], 0.3f), spherical(Thetas[2], 2.0f), spherical(Thetas[3], -1.0f), spherical(Thetas[4], 0.0f)}},
        // Quarter: slices at phi in [-180, -90] degrees; incidences in every quadrant (mirrored).
        {"quarter",
         quarter_table(),
         Aniso,
         {spherical(Thetas[2], -150 * Pi / 180), spherical(Thetas[3], 60 * Pi / 180), spherical(Thetas[2], 150 * Pi / 180),
          spherical(Thetas[4], -30 * Pi / 180)}},
        // Half: slices at phi in [-180, 0]; an incidence with y > 0 is turned by a half turn.
        {"half",
         half_table(),
         Aniso,
         {spherical(Thetas[2], -45 * Pi / 180), spherical(Thetas[3], 135 * Pi / 180), spherical(Thetas[1], 90 * Pi / 180)}},
    };
    for (const Case& k : cases) {
        BSDFUnderTest measured = load_measured(write_table(k.table, std::string("eval-") + k.name));
        BSDFUnderTest analytic = make_bsdf(k.c.xml());
        std::vector<Vec3> reduced;
        Agreement agreement;
        // The incidences as the plugin reduces them (the table's slices hold the reduced ones).
        for (Vec3 wi : k.incidences) {
            Vec3 r = wi;
            if (!k.table.isotropic) {
                int reduction = k.table.phi_i.back() - k.table.phi_i.front() < 2.0f ? 4 : 2;
                bool flip_y = !std::signbit(wi.y), flip_x = reduction == 4 ? !std::signbit(wi.x) : flip_y;
                if (flip_x) r.x = -r.x;
                if (flip_y) r.y = -r.y;
            }
            // Compare at the reduced incidence and at the original one: the same slice.
            Agreement at_reduced = compare_with_analytic(k.table, k.c, *measured.bsdf, *analytic.bsdf, r);
            agreement.worst_excess = std::max(agreement.worst_excess, at_reduced.worst_excess);
            agreement.mean_tolerance += at_reduced.mean_tolerance / double(k.incidences.size());
            agreement.compared += at_reduced.compared;
            reduced.push_back(r);
        }
        INFO(k.name << ": " << agreement.compared << " comparisons, mean tolerance " << agreement.mean_tolerance
                    << ", worst error / tolerance " << agreement.worst_excess);
        CHECK(agreement.compared > 1000);
        CHECK(agreement.worst_excess <= 1.0);
        // The bound must say something: below the 10% and larger effects of the faults the
        // comparison is there to catch (a Jacobian, a cosine, a Fresnel colour).
        CHECK(agreement.mean_tolerance < 0.1);
        // The symmetry: the original incidence gives the reduced one's values, mirrored or turned.
        for (size_t i = 0; i < reduced.size(); ++i) {
            Vec3 wi = k.incidences[i], r = reduced[i];
            PCG32 rng(11, 5);
            for (int j = 0; j < 50; ++j) {
                float u1 = rng.next_float(), u2 = rng.next_float();
                Vec3 wo = warp::square_to_cosine_hemisphere(Vec2(u1, u2));
                Vec3 wo_r(r.x == wi.x ? wo.x : -wo.x, r.y == wi.y ? wo.y : -wo.y, wo.z);
                BSDFContext ctx;
                Spectrum a1 = measured.bsdf->eval(ctx, local_interaction(wi), wo),
                         a2 = measured.bsdf->eval(ctx, local_interaction(r), wo_r);
                CHECK(max_component(glm::abs(a1 - a2)) <= 1e-5f * std::max(max_component(a1), 1.0f));
            }
        }
    }
}

// A second chi-square view of sample() against pdf(), histogrammed in the half-vector chart
// u = (sqrt(2 theta_h / pi), ((phi_h - phi_i) / 2 pi) mod 1), h = normalize(wi + wo), on
// 20 x 20 cells, plus one cell for failed samples. A cell's expected count is n times the
// integral of pdf(wo(u)) |d wo / d u| over it, |d wo / d u| = 4 <wi, h> 2 pi^2 u_x sin(theta_h)
// (u -> (theta_h, phi_h) -> h -> wo = reflect(wi, h)), by the midpoint rule on 16 x 16 points.
// The harness's spherical histogram (10 x 20 cells over the sphere) puts the whole glossy lobe
// in a few cells; this chart spreads it over hundreds, and its integrand is the smooth density
// of the tables (pdf() in solid angle has an integrable 1 / theta_h spike at the mirror
// direction: the format interpolates the VNDF on the square linearly from 0 at the pole, where
// the true density vanishes as u_x^3). It found pdf() several times too large near the mirror
// direction when sin(theta_h) came from sqrt(1 - cos^2) in float, as in Mitsuba.
ChiSquareResult half_vector_chi_square(const BSDF& bsdf, const Vec3& wi, int n, uint64_t seed) {
    const int bins = 20, sub = 16;
    BSDFContext ctx;
    SurfaceInteraction si = local_interaction(wi);
    float phi_i = std::atan2(wi.y, wi.x);
    std::vector<double> observed(size_t(bins * bins + 1), 0.0), expected(size_t(bins * bins + 1), 0.0);
    PCG32 rng(seed, 17);
    for (int i = 0; i < n; ++i) {
        float u_lobe = rng.next_float(), a = rng.next_float(), b = rng.next_float();
        BSDFSample bs = bsdf.sample(ctx, si, u_lobe, Vec2(a, b));
        if (!bs.valid()) {
            observed.back() += 1.0;
            continue;
        }
        Vec3 h = glm::normalize(wi + bs.wo);
        float theta = 2.0f * std::asin(std::min(0.5f * glm::length(h - Vec3(0, 0, 1)), 1.0f));
        float v = (std::atan2(h.y, h.x) - phi_i) * InvTwoPi;
        v -= std::floor(v);
        int x = std::min(int(to_u_theta(theta) * bins), bins - 1), y = std::min(int(v * bins), bins - 1);
        observed[size_t(y * bins + x)] += 1.0;
    }
    double total = 0.0;
    for (int y = 0; y < bins; ++y)
        for (int x = 0; x < bins; ++x) {
            double sum = 0.0;
            for (int j = 0; j < sub; ++j)
                for (int i = 0; i < sub; ++i) {
                    Vec2 u((float(x) + (float(i) + 0.5f) / sub) / bins, (float(y) + (float(j) + 0.5f) / sub) / bins);
                    float theta = u_theta(u.x);
                    Vec3 h = spherical(theta, 2.0f * Pi * u.y + phi_i);
                    Vec3 wo = reflect(wi, h);
                    float cos_ih = glm::dot(wi, h);
                    if (wo.z <= 0.0f || cos_ih <= 0.0f) continue;
                    sum += double(bsdf.pdf(ctx, si, glm::normalize(wo))) * 4.0 * cos_ih * 2.0 * Pi * Pi * u.x * std::sin(theta);
                }
            double e = sum / double(sub * sub * bins * bins) * n;
            expected[size_t(y * bins + x)] = e;
            total += e;
        }
    expected.back() = std::max(0.0, double(n) - total);
    return chi_square(observed, expected);
}

TEST_CASE("measured: sample() draws what pdf() says (chi-square, two charts)", "[bsdf][measured]") {
    struct Case {
        const char* name;
        const Table& table;
        std::vector<Vec3> incidences;  // between slices too: the blended tables must still agree
    };
    std::vector<Case> cases = {
        {"iso", iso_table(), {direction(0.9f, 0.7f), direction(0.5f, -2.0f), direction(0.15f, 1.0f)}},
        {"quarter", quarter_table(), {direction(0.7f, 0.7f), direction(0.6f, 2.5f), direction(0.4f, -2.0f), direction(0.3f, -0.9f)}},
        {"half", half_table(), {direction(0.8f, 1.2f), direction(0.35f, -2.2f)}},
    };
    int tests = 0;
    for (const Case& k : cases) tests += 2 * int(k.incidences.size());
    // Family-wise significance 1% over the chi-square tests of this file (Sidak).
    const double alpha = sidak(0.01, tests);
    const int samples = effort_scaled(1000000, 100000);
    uint64_t seed = 1;
    for (const Case& k : cases) {
        BSDFUnderTest t = load_measured(write_table(k.table, std::string("sample-") + k.name));
        for (const Vec3& wi : k.incidences) {
            INFO(k.name << ", wi = (" << wi.x << ", " << wi.y << ", " << wi.z << "), per-test alpha " << alpha);
            // The project's harness: 10 x 20 cells over the sphere, and per sample pdf = pdf(),
            // weight = eval / pdf, finite and non-negative.
            SamplingCheck check = check_sampling(*t.bsdf, local_interaction(wi), BSDFContext(), samples, {}, seed++);
            for (const std::string& f : check.failures) FAIL_CHECK(f);
            INFO("sphere: " << check.chi2.details);
            CHECK(check.chi2.p_value > alpha);
            ChiSquareResult chi2 = half_vector_chi_square(*t.bsdf, wi, samples, seed++);
            INFO("half-vector chart: " << chi2.details);
            CHECK(chi2.p_value > alpha);
        }
    }
}

TEST_CASE("measured: every sample's weight is eval / pdf and its pdf is pdf()", "[bsdf][measured]") {
    BSDFContext ctx;
    for (const Table* table : {&iso_table(), &quarter_table(), &half_table()}) {
        BSDFUnderTest t = load_measured(write_table(*table, "weights"));
        PCG32 rng(5, 9);
        int valid = 0;
        for (int i = 0; i < 20000; ++i) {
            float a = rng.next_float(), b = rng.next_float(), c = rng.next_float(), d = rng.next_float();
            Vec3 wi = warp::square_to_uniform_hemisphere(Vec2(a, b));
            SurfaceInteraction si = local_interaction(wi);
            BSDFSample bs = t.bsdf->sample(ctx, si, 0.5f, Vec2(c, d));
            if (!bs.valid()) continue;
            ++valid;
            REQUIRE(bs.wo.z > 0.0f);
            REQUIRE(bs.lobe == GlossyReflection);
            float pdf = t.bsdf->pdf(ctx, si, bs.wo);
            Spectrum f = t.bsdf->eval(ctx, si, bs.wo);
            INFO("wi (" << wi.x << ", " << wi.y << ", " << wi.z << ") wo (" << bs.wo.x << ", " << bs.wo.y << ", " << bs.wo.z << ")");
            // Float rounding of the two routes (forward warp; inverse warp) only.
            REQUIRE(std::abs(pdf - bs.pdf) <= 1e-3f * std::max(pdf, bs.pdf));
            REQUIRE(max_component(glm::abs(f / bs.pdf - bs.weight)) <= 1e-3f * std::max(max_component(bs.weight), 1e-3f));
        }
        CHECK(valid > 15000);
        // One-sided: black from below, no samples.
        SurfaceInteraction below = local_interaction(direction(-0.5f, 0.3f));
        CHECK(!t.bsdf->sample(ctx, below, 0.5f, Vec2(0.3f, 0.6f)).valid());
        CHECK(t.bsdf->eval(ctx, below, direction(0.7f, 1.0f)) == Spectrum(0.0f));
        CHECK(t.bsdf->eval(ctx, local_interaction(direction(0.5f, 0.3f)), direction(-0.7f, 1.0f)) == Spectrum(0.0f));
        CHECK(t.bsdf->pdf(ctx, local_interaction(direction(0.5f, 0.3f)), direction(-0.7f, 1.0f)) == 0.0f);
    }
}

TEST_CASE("measured: a spectral file is converted to RGB as Mitsuba converts a reflectance", "[bsdf][measured][spectral]") {
    // The grey measurement: its spectrum at every node is the luminance Y, flat. Converted, the
    // colour is Y times the colour of a flat reflectance of 1; the RGB file with exactly that
    // colour must evaluate and sample the same.
    Table grey = iso_table();
    SampledSpectrum flat{{360, 420, 480, 540, 600, 660, 720, 830}, std::vector<double>(8, 1.0)};
    Spectrum white = spectrum_to_rgb(flat, true, false);
    size_t nodes = size_t(grey.n * grey.n);
    for (size_t s = 0; s < grey.theta_i.size(); ++s)
        for (int ch = 0; ch < 3; ++ch)
            for (size_t i = 0; i < nodes; ++i) grey.rgb[(s * 3 + size_t(ch)) * nodes + i] = grey.luminance[s * nodes + i] * white[ch];
    BSDFUnderTest spectral = load_measured(write_table(grey, "spectral", true));
    BSDFUnderTest rgb = load_measured(write_table(grey, "spectral-rgb"));
    PointwiseDifference d = compare_pointwise(*spectral.bsdf, *rgb.bsdf, BSDFContext(), 5000, 13, false);
    INFO("eval " << d.eval << ", pdf " << d.pdf);
    CHECK(d.nonzero > 1000);
    CHECK(d.eval < 1e-4);
    CHECK(d.pdf == 0.0);
}

TEST_CASE("measured: in the spectral variants a spectral file is read at the path's wavelengths", "[bsdf][measured][spectral]") {
    // A ramp over wavelength times the grey measurement, against the flat one: their ratio at each
    // path wavelength is the ramp there (linear between the table's wavelengths, so exact), and
    // clamped to its ends outside them. An RGB file's reflectance is upsampled (before the
    // D / (4 sigma) factor): a grey one is the same at every wavelength, its RGB value.
    auto ramp = [](float lambda) { return 0.2f + 0.6f * (lambda - 360.0f) / 470.0f; };
    BSDFUnderTest flat = load_measured(write_table(iso_table(), "spectral-flat", true));
    BSDFUnderTest ramped = load_measured(write_table(iso_table(), "spectral-ramp", true, +ramp));
    Table grey = iso_table();
    const size_t nodes = size_t(grey.n * grey.n);
    for (size_t s = 0; s < grey.theta_i.size() * grey.phi_i.size(); ++s)
        for (size_t ch = 0; ch < 3; ++ch)
            for (size_t i = 0; i < nodes; ++i) grey.rgb[(s * 3 + ch) * nodes + i] = 0.3f * grey.luminance[s * nodes + i];
    BSDFUnderTest rgb = load_measured(write_table(grey, "spectral-grey-rgb"));
    PCG32 rng(3, 8);
    int checked = 0;
    for (int i = 0; i < 500; ++i) {
        Wavelengths w = Wavelengths::at(Vec3(340.0f + 500.0f * rng.next_float(), 360.0f + 470.0f * rng.next_float(), 850.0f));
        SurfaceInteraction si = local_interaction(spherical(1.4f * rng.next_float(), 6.2831853f * rng.next_float()));
        si.wavelengths = &w;
        const Vec3 wo = spherical(1.4f * rng.next_float(), 6.2831853f * rng.next_float());
        const Spectrum a = ramped.bsdf->eval(BSDFContext(), si, wo), b = flat.bsdf->eval(BSDFContext(), si, wo);
        if (!(b.x > 1e-4f)) continue;
        ++checked;
        for (int k = 0; k < 3; ++k) {
            const float lambda = std::clamp(w.lambda[k], 360.0f, 830.0f);
            CHECK(a[k] / b[k] == Approx(ramp(lambda)).epsilon(1e-4));
            CHECK(b[k] == Approx(b.x).epsilon(1e-6));  // flat: the same at every wavelength
        }
        SurfaceInteraction plain = si;
        plain.wavelengths = nullptr;
        const Spectrum colour = rgb.bsdf->eval(BSDFContext(), plain, wo), upsampled = rgb.bsdf->eval(BSDFContext(), si, wo);
        for (int k = 0; k < 3; ++k) CHECK(upsampled[k] == Approx(colour[k]).epsilon(1e-4).margin(1e-8));
    }
    CHECK(checked > 300);
}

TEST_CASE("measured: malformed tensor files are InputErrors naming the file and the fault", "[bsdf][measured][errors]") {
    std::filesystem::path dir = scratch_dir("measured-errors");
    const Table& t = iso_table();
    std::vector<OutField> good = t.fields();
    std::string bytes = tensor_bytes(good);
    auto check_error = [&](const std::string& name, const std::string& content, const std::string& fault) {
        std::filesystem::path path = dir / (name + ".bsdf");
        write_bytes(path, content);
        INFO(name);
        // The reader, then the plugin through the scene loader (a SceneError at the <bsdf>
        // element that carries the reader's message).
        bool thrown = false;
        try {
            TensorFile file(path.string());
            load_measured(path);
        } catch (const InputError& e) {
            thrown = true;
            CHECK_THAT(e.what(), Catch::Contains(path.string()) && Catch::Contains(fault));
        } catch (const SceneError& e) {
            thrown = true;
            CHECK_THAT(e.what(), Catch::Contains(path.string()) && Catch::Contains(fault));
        }
        CHECK(thrown);
    };
    // The good file loads (so the faults below are what the errors are about).
    write_bytes(dir / "good.bsdf", bytes);
    CHECK_NOTHROW(load_measured(dir / "good.bsdf"));

    check_error("empty", "", "truncated");
    check_error("short-header", bytes.substr(0, 10), "truncated");
    check_error("cut-in-fields", bytes.substr(0, 140), "\"description\" (uint8 [9] at offset 360) reaches past the end of the file");
    check_error("too-many-fields", bytes.substr(0, 60), "the header declares 9 fields, more than its 60 bytes can hold");
    check_error("cut-in-data", bytes.substr(0, bytes.size() - 100), "reaches past the end of the file");
    std::string magic = bytes;
    magic[0] = 'x';
    check_error("magic", magic, "not a tensor file");
    std::string version = bytes;
    version[12] = 2;
    check_error("version", version, "version 2.0");
    std::string many = bytes;
    many[14] = many[15] = many[16] = many[17] = char(0xff);
    check_error("field-count", many, "4294967295 fields");
    // A shape that the data does not fill: vndf declared with 40 x 40 nodes per slice.
    std::vector<OutField> wide = good;
    wide[6].shape = {1, 6, 40, 40};
    check_error("vndf-shape", tensor_bytes(wide), "overlaps");
    std::vector<OutField> longer = good;
    longer[8].shape = {1, 6, 3, 32, 33};
    check_error("rgb-shape", tensor_bytes(longer), "reaches past the end of the file");
    // Huge declared sizes: a shape whose product overflows, and one just beyond the file.
    std::vector<OutField> huge = good;
    huge[4].shape = {uint64_t(1) << 40, uint64_t(1) << 40};
    check_error("huge-shape", tensor_bytes(huge), "reaches past the end of the file");
    std::vector<OutField> dims = good;
    dims[0].shape = std::vector<uint64_t>(60000, 1);
    std::string dims_bytes = tensor_bytes(dims);
    check_error("huge-ndim", dims_bytes.substr(0, 200), "truncated");
    std::vector<OutField> type = good;
    type[2].dtype = TensorType(12);
    check_error("unknown-type", tensor_bytes(type), "unknown type code 12");
    std::vector<OutField> twice = good;
    twice.push_back(good[2]);
    check_error("duplicate", tensor_bytes(twice), "appears twice");
    // Well-formed files whose fields are not a measured BSDF.
    std::vector<OutField> missing(good.begin(), good.end() - 1);
    check_error("no-rgb", tensor_bytes(missing), "no field \"wavelengths\"");
    std::vector<OutField> theta = good;
    theta[6].shape = {1, 5, 32, 32};
    theta[6].data.resize(5 * 32 * 32 * 4);
    check_error("slices", tensor_bytes(theta), "the size of theta_i");
    std::vector<OutField> as_double = good;
    as_double[4].dtype = TensorType::Float64;
    as_double[4].shape = {2, 32};
    check_error("float64", tensor_bytes(as_double), "expected float32");
    std::vector<OutField> nan = good;
    std::vector<float> ndf = t.ndf;
    ndf[3] = std::nanf("");
    nan[4].data = float_bytes(ndf);
    check_error("nan", tensor_bytes(nan), "not finite");
    std::vector<OutField> order = good;
    order[2].data = float_bytes(degrees({0, 16, 16, 48, 64, 80}));
    check_error("theta-order", tensor_bytes(order), "\"theta_i\" must increase");
    std::vector<OutField> zero = good;
    zero[7].data = float_bytes(std::vector<float>(6 * 32 * 32, 0.0f));
    check_error("zero-luminance", tensor_bytes(zero), "integrates to zero");
}

TEST_CASE("measured: a scene with a measured BSDF loads and renders finite pixels", "[bsdf][measured][render]") {
    std::filesystem::path dir = scratch_dir("measured-scene");
    write_bytes(dir / "material.bsdf", tensor_bytes(quarter_table().fields()));
    auto render = [&](const std::string& integrator) {
        write_text(dir / "scene.xml",
                   lit_sphere_scene(integrator, R"(<bsdf type="measured"><string name="filename" value="material.bsdf"/></bsdf>)"));
        return render_file((dir / "scene.xml").string(), {}).image;
    };
    // The path tracer, and the raster mode (its local model: a Lambertian of the albedo at
    // normal incidence).
    for (const char* integrator :
         {R"(<integrator type="path"><integer name="max_depth" value="4"/></integrator>)", R"(<integrator type="raster"/>)"}) {
        INFO(integrator);
        Image image = render(integrator);
        for (int y = 0; y < image.height(); ++y)
            for (int x = 0; x < image.width(); ++x) {
                Spectrum v = image.rgb_at(x, y);
                REQUIRE(all_finite(v));
                REQUIRE(min_component(v) >= 0.0f);
            }
        double centre = 0.0;
        for (int y = 9; y < 15; ++y)
            for (int x = 9; x < 15; ++x) centre += luminance(image.rgb_at(x, y));
        CHECK(centre > 0.0);  // the sphere reflects
    }
}
