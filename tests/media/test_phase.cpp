// Phase functions (isotropic, hg, rayleigh, tabphase, blendphase): each is sampled exactly with
// its pdf (blendphase: its weight is eval / pdf, 1 when its parts are exact).
//   - Chi-square: directions drawn by sample() against pdf() integrated over the cells of a
//     10 x 20 spherical grid around the incident direction. Six cases at a 1% family-wise level
//     (Sidak), together with the tests below.
//   - Deterministic: each sample's pdf equals pdf(wi, wo), its weight eval / pdf = 1, eval = pdf,
//     also for an oblique incident direction (the frame around it).
//   - Normalisation: the Monte Carlo integral of pdf over the sphere (uniform directions) is 1,
//     within a z-test at the same family-wise level.
//   - Known values: HG's mean cosine is g (estimated from the samples, z-test), Rayleigh's
//     density at mu = 0 and 1, tabphase's table in Mitsuba's convention (the last value is
//     forward scattering) and normalisation, blendphase at weights 0 and 1 equal to its parts.
//   - blendphase with a volume weight (Mitsuba's props.volume("weight")): a constant volume
//     equals the float weight sample by sample; weight volumes 0 and 1 are the parts; an rgb
//     constant counts by its channels' mean; a grid's weight is its value at the scattering
//     point, clamped to [0, 1], with samples consistent with pdf and eval there.

#include "core/phase.h"
#include "core/registry.h"
#include "core/rng.h"
#include "core/volume.h"
#include "tests/stats.h"
#include "tests/support/vol_writer.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

// A tabulated phase function: rising, falling and flat pieces, forward-peaked.
const char* const Table = "0.2, 0.5, 0.5, 1.0, 3.0, 0.1, 4.0";

// `g` is HG's g; for blendphase the weight of an hg (g = 0.7) against an isotropic first part.
Ref<PhaseFunction> make_phase(const std::string& type, float g = 0.0f, const std::string& values = Table) {
    Properties props(type, SourceLocation{"test", 1});
    if (type == "hg") props.set_float("g", g);
    if (type == "tabphase") props.set_string("values", values);
    if (type == "blendphase") {
        props.set_float("weight", g);
        props.set_object("first", make_phase("isotropic"), SourceLocation{"test", 2});
        props.set_object("second", make_phase("hg", 0.7f), SourceLocation{"test", 3});
    }
    return create_plugin_as<PhaseFunction>(ObjectKind::Phase, props);
}

struct PhaseCase {
    std::string type;
    float g;
};
const std::vector<PhaseCase> Cases = {{"isotropic", 0.0f}, {"hg", 0.7f},       {"hg", -0.4f},      {"hg", 0.0f},
                                      {"hg", 0.95f},       {"rayleigh", 0.0f}, {"tabphase", 0.0f}, {"blendphase", 0.3f}};
// Every statistical check below runs once per case.
const double Alpha = sidak(0.01, 3 * int(Cases.size()));

// The phase functions here do not vary in space: any point will do.
MediumInteraction at(const Vec3& wi) { return MediumInteraction{Vec3(0.0f), wi}; }

}  // namespace

TEST_CASE("phase functions: sampling matches pdf (chi-square) and is exact", "[phase][stats]") {
    // The histogram looks from the pole (a phase function depends only on the angle to wi, so its
    // cells' integrals converge quickly); an oblique wi checks the frame around it: every sample's
    // pdf is pdf(wi, wo) and the mean cosine is right.
    const Vec3 pole(0.0f, 0.0f, 1.0f), oblique = glm::normalize(Vec3(0.3f, -0.5f, 0.8f));
    const int n = 200000;
    for (const PhaseCase& c : Cases) {
        INFO(c.type << " g = " << c.g);
        Ref<PhaseFunction> phase = make_phase(c.type, c.g);
        PCG32 rng(7, 11);
        SphericalHistogram hist(10, 20);
        int inconsistent = 0;
        double sum_mu = 0.0, sum_mu2 = 0.0;
        for (int i = 0; i < 2 * n; ++i) {
            const Vec3& wi = i < n ? pole : oblique;
            PhaseSample ps = phase->sample(at(wi), Vec2(rng.next_float(), rng.next_float()));
            REQUIRE(ps.valid());
            float pdf = phase->pdf(at(wi), ps.wo), f = phase->eval(at(wi), ps.wo);
            if (std::abs(ps.pdf - pdf) > 1e-3f * pdf || std::abs(ps.weight - f / pdf) > 1e-4f ||
                std::abs(glm::length(ps.wo) - 1.0f) > 1e-4f)
                ++inconsistent;
            if (i < n) {
                hist.add(ps.wo);
                continue;
            }
            double mu = glm::dot(-wi, ps.wo);
            sum_mu += mu;
            sum_mu2 += mu * mu;
        }
        CHECK(inconsistent == 0);
        ChiSquareResult chi2 = chi_square(hist.counts, hist.expected([&](const Vec3& wo) { return double(phase->pdf(at(pole), wo)); }, n));
        INFO(chi2.details);
        CHECK(chi2.p_value > Alpha);
        // The mean cosine: g for HG, 0 for the symmetric ones.
        double mean = sum_mu / n, se = std::sqrt((sum_mu2 / n - mean * mean) / n);
        CHECK(std::abs(mean - phase->mean_cosine()) < two_sided_z(Alpha) * se);
    }
}

TEST_CASE("phase functions: pdf integrates to one over the sphere", "[phase][stats]") {
    const Vec3 wi = glm::normalize(Vec3(-0.2f, 0.1f, 0.9f));
    const int n = 400000;
    for (const PhaseCase& c : Cases) {
        INFO(c.type << " g = " << c.g);
        if (c.g > 0.9f) continue;  // too peaked for uniform sampling to estimate with power
        Ref<PhaseFunction> phase = make_phase(c.type, c.g);
        PCG32 rng(3, 5);
        std::vector<double> values(n);
        for (int i = 0; i < n; ++i) {
            Vec3 wo = direction_around(Vec3(0.0f, 0.0f, 1.0f), 1.0f - 2.0f * rng.next_float(), TwoPi * rng.next_float());
            values[size_t(i)] = double(phase->pdf(at(wi), wo)) * 4.0 * 3.14159265358979323846;
            CHECK(phase->eval(at(wi), wo) == phase->pdf(at(wi), wo));
        }
        MeanAndError m = mean_and_error(values);
        // A constant pdf (isotropic) has no spread: then only float rounding separates it from 1.
        CHECK(std::abs(m.mean - 1.0) < two_sided_z(Alpha) * m.std_error + 1e-6);
    }
}

TEST_CASE("phase functions: known values", "[phase]") {
    Vec3 z(0.0f, 0.0f, 1.0f), x(1.0f, 0.0f, 0.0f);
    Ref<PhaseFunction> rayleigh = make_phase("rayleigh");
    CHECK(rayleigh->eval(at(z), x) == Approx(3.0 / (16.0 * 3.14159265358979323846)));
    CHECK(rayleigh->eval(at(z), -z) == Approx(6.0 / (16.0 * 3.14159265358979323846)));
    // HG peaks in the forward direction (wo = -wi) for g > 0: (1 + g) / (4 pi (1 - g)^2).
    Ref<PhaseFunction> hg = make_phase("hg", 0.5f);
    CHECK(hg->eval(at(z), -z) == Approx(1.5 / (4.0 * 3.14159265358979323846 * 0.25)));
    CHECK(hg->eval(at(z), z) == Approx(0.5 / (4.0 * 3.14159265358979323846 * 2.25)));
    CHECK(make_phase("isotropic")->eval(at(z), x) == Approx(1.0 / (4.0 * 3.14159265358979323846)));
    // tabphase: values at mu = -1 and 1 (Mitsuba: mu = 1, the last value, scatters forward,
    // along wo = -wi). "0, 1" is p(mu) = (1 + mu) / 2 per unit mu, over 2 pi of azimuth.
    Ref<PhaseFunction> ramp = make_phase("tabphase", 0.0f, "0, 1");
    CHECK(ramp->eval(at(z), -z) == Approx(1.0 / (2.0 * 3.14159265358979323846)));
    CHECK(ramp->eval(at(z), z) == Approx(0.0).margin(1e-7));
    CHECK(ramp->eval(at(z), x) == Approx(0.5 / (2.0 * 3.14159265358979323846)));
    CHECK(ramp->mean_cosine() == Approx(1.0 / 3.0));
    // Any constant table is isotropic, whatever its scale.
    CHECK(make_phase("tabphase", 0.0f, "7 7 7")->eval(at(z), x) == Approx(1.0 / (4.0 * 3.14159265358979323846)));
    // blendphase: weight 0 is its first part (isotropic), 1 its second (hg 0.7).
    Ref<PhaseFunction> hg7 = make_phase("hg", 0.7f);
    for (const Vec3& wo : {z, x, Vec3(-z)}) {
        CHECK(make_phase("blendphase", 0.0f)->eval(at(z), wo) == Approx(1.0 / (4.0 * 3.14159265358979323846)));
        CHECK(make_phase("blendphase", 1.0f)->eval(at(z), wo) == Approx(hg7->eval(at(z), wo)));
    }
}

TEST_CASE("phase functions: tabphase and blendphase refuse what Mitsuba refuses", "[phase][errors]") {
    CHECK_THROWS_WITH(make_phase("tabphase", 0.0f, "1"), Catch::Contains("at least two"));
    CHECK_THROWS_WITH(make_phase("tabphase", 0.0f, "1, x"), Catch::Contains("not a number"));
    CHECK_THROWS_WITH(make_phase("tabphase", 0.0f, "1, -1"), Catch::Contains("negative"));
    CHECK_THROWS_WITH(make_phase("tabphase", 0.0f, "0 0"), Catch::Contains("all zero"));
    CHECK_THROWS_WITH(make_phase("blendphase", 1.5f), Catch::Contains("[0, 1]"));
}

namespace {

// A blendphase of isotropic and hg (g = 0.7) with `weight` a volume.
Ref<PhaseFunction> blend_with_volume(const Ref<Volume>& weight) {
    Properties props("blendphase", SourceLocation{"test", 1});
    props.set_object("weight", weight, SourceLocation{"test", 2});
    props.set_object("first", make_phase("isotropic"), SourceLocation{"test", 3});
    props.set_object("second", make_phase("hg", 0.7f), SourceLocation{"test", 4});
    return create_plugin_as<PhaseFunction>(ObjectKind::Phase, props);
}

Ref<Volume> constant_volume(const Spectrum& value) {
    Properties props("constvolume", SourceLocation{"test", 5});
    props.set_rgb("value", value);
    return create_plugin_as<Volume>(ObjectKind::Volume, props);
}

}  // namespace

TEST_CASE("blendphase: a volume weight", "[phase]") {
    PCG32 rng(5, 6);
    auto random_direction = [&] {
        return direction_around(Vec3(0.0f, 0.0f, 1.0f), 1.0f - 2.0f * rng.next_float(), TwoPi * rng.next_float());
    };
    // A constant volume is the float weight, sample by sample; 0 and 1 are the parts.
    Ref<PhaseFunction> by_volume = blend_with_volume(constant_volume(Spectrum(0.3f))), by_float = make_phase("blendphase", 0.3f);
    Ref<PhaseFunction> zero = blend_with_volume(constant_volume(Spectrum(0.0f))), one = blend_with_volume(constant_volume(Spectrum(1.0f)));
    Ref<PhaseFunction> iso = make_phase("isotropic"), hg7 = make_phase("hg", 0.7f);
    CHECK_FALSE(by_volume->varies_in_space());
    int differences = 0;
    for (int i = 0; i < 1000; ++i) {
        MediumInteraction mi{Vec3(rng.next_float(), rng.next_float(), rng.next_float()), random_direction()};
        Vec2 u(rng.next_float(), rng.next_float());
        PhaseSample a = by_volume->sample(mi, u), b = by_float->sample(mi, u);
        if (a.wo != b.wo || a.pdf != b.pdf || a.weight != b.weight) ++differences;
        Vec3 wo = random_direction();
        if (by_volume->eval(mi, wo) != by_float->eval(mi, wo) || by_volume->pdf(mi, wo) != by_float->pdf(mi, wo)) ++differences;
        if (zero->eval(mi, wo) != iso->eval(mi, wo) || one->eval(mi, wo) != Approx(hg7->eval(mi, wo))) ++differences;
        PhaseSample z = zero->sample(mi, u), zi = iso->sample(mi, u);
        if (z.wo != zi.wo) ++differences;
    }
    CHECK(differences == 0);
    // An rgb constant counts by its mean, as Mitsuba's eval_1 of a constvolume.
    Ref<PhaseFunction> rgb = blend_with_volume(constant_volume(Spectrum(0.1f, 0.3f, 0.5f)));
    Vec3 z(0.0f, 0.0f, 1.0f);
    CHECK(rgb->eval(at(z), -z) == Approx(by_float->eval(at(z), -z)));
}

TEST_CASE("blendphase: a grid weight is read at the scattering point and clamped", "[phase][volume]") {
    // Two voxels along x: 0.2 at x < 0.5 and 1.5 (clamped to 1) beyond, looked up nearest.
    auto dir = scratch_dir("blendphase-grid");
    write_vol(dir / "w.vol", glm::ivec3(2, 1, 1), 1, {0.2f, 1.5f});
    Properties grid("gridvolume", SourceLocation{"test", 1});
    grid.set_string("filename", (dir / "w.vol").string());
    grid.set_string("filter_type", "nearest");
    Ref<PhaseFunction> blend = blend_with_volume(create_plugin_as<Volume>(ObjectKind::Volume, grid));
    Ref<PhaseFunction> low = make_phase("blendphase", 0.2f), high = make_phase("blendphase", 1.0f);
    CHECK(blend->varies_in_space());
    PCG32 rng(8, 1);
    int mismatches = 0, inconsistent = 0;
    for (int i = 0; i < 1000; ++i) {
        MediumInteraction mi{Vec3(rng.next_float(), rng.next_float(), rng.next_float()), Vec3(0.0f, 0.0f, 1.0f)};
        Vec3 wo = direction_around(Vec3(0.0f, 0.0f, 1.0f), 1.0f - 2.0f * rng.next_float(), TwoPi * rng.next_float());
        const PhaseFunction& expected = mi.p.x < 0.5f ? *low : *high;
        if (blend->eval(mi, wo) != Approx(expected.eval(mi, wo))) ++mismatches;
        PhaseSample ps = blend->sample(mi, Vec2(rng.next_float(), rng.next_float()));
        float pdf = blend->pdf(mi, ps.wo);
        if (!ps.valid() || std::abs(ps.pdf - pdf) > 1e-5f * pdf || std::abs(ps.weight - blend->eval(mi, ps.wo) / pdf) > 1e-5f)
            ++inconsistent;
    }
    CHECK(mismatches == 0);
    CHECK(inconsistent == 0);
}
