// Dispersion (not in Mitsuba 3): a dielectric whose index follows a named glass's Sellmeier
// equation refracts each wavelength by Snell's law at its own index, so a prism splits white light.

#include "core/wavelengths.h"
#include "materials/ior.h"
#include "tests/bsdf_harness.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace candela;
using namespace candela::test;

TEST_CASE("dispersion: the named glasses have their catalogue indices at the d line", "[spectral][dispersion]") {
    // n_d at 587.56 nm from the makers' catalogues (Schott; Malitson 1965 for fused silica).
    const std::pair<const char*, double> catalogue[] = {
        {"glass-BK7", 1.5168}, {"glass-BAF10", 1.6700}, {"glass-F2", 1.6200}, {"glass-SF11", 1.7847}, {"glass-fused-silica", 1.4585}};
    for (auto [name, nd] : catalogue) {
        const SellmeierGlass* g = named_glass(name);
        REQUIRE(g);
        INFO(name);
        CHECK(g->ior(587.56) == Approx(nd).margin(2e-4));
        // Normal dispersion: blue bends more than red.
        CHECK(g->ior(450.0) > g->ior(650.0));
    }
    CHECK(named_glass("GLASS-bk7"));  // names ignore case
    CHECK(!named_glass("bk7"));       // Mitsuba's constant bk7 stays constant
    CHECK(*named_ior("bk7") == 1.5046f);
}

namespace {

// Rotates v by `angle` about +y.
Vec3 rotate_y(const Vec3& v, double angle) {
    double c = std::cos(angle), s = std::sin(angle);
    return Vec3(float(c * v.x + s * v.z), v.y, float(-s * v.x + c * v.z));
}

// The world direction after the smooth dielectric refracts `d` (world) at a surface whose normal
// (outward, world) is `n`, at the wavelengths `w`: the BSDF's transmission sample.
Vec3 refract_through(const BSDF& bsdf, const Vec3& n, const Vec3& d, Wavelengths& w, bool* dispersed) {
    SurfaceInteraction si;
    si.n = n;
    si.shading = Frame(n);
    si.wavelengths = &w;
    si.wi = si.to_local(-d);
    BSDFContext ctx;
    ctx.lobes = DeltaTransmission;
    BSDFSample bs = bsdf.sample(ctx, si, 0.5f, Vec2(0.5f));
    REQUIRE(bs.valid());
    REQUIRE(bs.lobe == DeltaTransmission);
    *dispersed = bs.dispersed;
    return si.to_world(bs.wo);
}

}  // namespace

TEST_CASE("dispersion: a prism deviates each wavelength by the angle Snell's law gives", "[spectral][dispersion]") {
    BSDFUnderTest glass = make_bsdf(R"(<bsdf type="dielectric"><string name="int_ior" value="glass-SF11"/>
                                        <float name="ext_ior" value="1"/></bsdf>)");
    const SellmeierGlass& sf11 = *named_glass("glass-SF11");
    // A prism of apex angle A (45 degrees) in the xz plane: the entry face's outward normal points along -x
    // tilted by -A/2, the exit face's along +x tilted by +A/2 (rotations about y).
    const double A = 45.0 * Pi / 180.0, incidence = 55.0 * Pi / 180.0;
    const Vec3 entry_normal = rotate_y(Vec3(-1, 0, 0), A / 2), exit_normal = rotate_y(Vec3(1, 0, 0), -A / 2);
    // The incoming ray makes `incidence` with the entry face's inward normal.
    const Vec3 d_in = glm::normalize(rotate_y(-entry_normal, -incidence));
    double previous_deviation = 0.0;
    for (float lambda : {400.0f, 486.1f, 550.0f, 587.6f, 656.3f, 800.0f}) {
        Wavelengths w = Wavelengths::at(Vec3(lambda, 700.0f, 500.0f));
        bool dispersed = false;
        Vec3 inside = refract_through(*glass.bsdf, entry_normal, d_in, w, &dispersed);
        CHECK(dispersed);
        Vec3 out = refract_through(*glass.bsdf, exit_normal, glm::normalize(inside), w, &dispersed);
        // The textbook prism: sin t2 = sin t1 / n, t3 = A - t2, sin t4 = n sin t3, deviation t1 + t4 - A.
        const double n = sf11.ior(lambda);
        const double t2 = std::asin(std::sin(incidence) / n), t3 = A - t2, t4 = std::asin(n * std::sin(t3));
        const double expected = incidence + t4 - A;
        const double deviation = std::acos(std::clamp(double(glm::dot(d_in, glm::normalize(out))), -1.0, 1.0));
        INFO("lambda " << lambda << " n " << n << ": deviation " << deviation * 180 / Pi << " expected " << expected * 180 / Pi);
        CHECK(deviation == Approx(expected).margin(2e-5));  // float directions: about 1e-6 rad per refraction
        // Shorter wavelengths are deviated more.
        if (previous_deviation > 0.0) CHECK(deviation < previous_deviation);
        previous_deviation = deviation;
    }
}

TEST_CASE("dispersion: without wavelengths (RGB) a named glass is its index at 589.3 nm", "[spectral][dispersion]") {
    BSDFUnderTest glass = make_bsdf(R"(<bsdf type="dielectric"><string name="int_ior" value="glass-F2"/>
                                        <float name="ext_ior" value="1"/></bsdf>)");
    SurfaceInteraction si = local_interaction(direction(std::cos(0.7f), 0.3f));
    BSDFContext ctx;
    ctx.lobes = DeltaTransmission;
    BSDFSample bs = glass.bsdf->sample(ctx, si, 0.5f, Vec2(0.5f));
    REQUIRE(bs.valid());
    CHECK(!bs.dispersed);
    CHECK(bs.eta == Approx(named_glass("glass-F2")->ior(589.3)).epsilon(1e-6));
}
