// The BSDFs' Mueller matrices (BSDF::eval_mueller, the polarized variant): physical (no output
// more than fully polarised, S0 >= 0) for every sampled and evaluated direction; their (0, 0)
// elements agree with the unpolarised eval() and sample(); the world-basis form keeps the degree
// of polarisation; depolarising BSDFs say so.

#include "core/mueller.h"
#include "core/rng.h"
#include "materials/fresnel.h"
#include "tests/bsdf_harness.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

Stokes random_polarised(PCG32& rng) {
    const float u = 2.0f * rng.next_float() - 1.0f, phi = 6.2831853f * rng.next_float();
    const float r = std::sqrt(std::max(0.0f, 1.0f - u * u));
    return Stokes(1.0f, r * std::cos(phi), r * std::sin(phi), u);
}

Vec3 random_direction(PCG32& rng, bool both_sides) {
    const float cos_theta = both_sides ? 2.0f * rng.next_float() - 1.0f : rng.next_float();
    return direction(cos_theta, 6.2831853f * rng.next_float());
}

struct PolarizedCase {
    const char* xml;
    bool both_sides;  // wi from the whole sphere (transmissive, two-sided)
};

const PolarizedCase Cases[] = {
    {R"(<bsdf type="conductor"><string name="material" value="Au"/></bsdf>)", false},
    {R"(<bsdf type="roughconductor"><string name="material" value="Cu"/><float name="alpha" value="0.3"/></bsdf>)", false},
    {R"(<bsdf type="dielectric"/>)", true},
    {R"(<bsdf type="roughdielectric"><float name="alpha" value="0.2"/></bsdf>)", true},
    {R"(<bsdf type="thindielectric"/>)", true},
    {R"(<bsdf type="plastic"/>)", false},
    {R"(<bsdf type="pplastic"><float name="alpha" value="0.2"/></bsdf>)", false},
    {R"(<bsdf type="polarizer"><float name="theta" value="30"/></bsdf>)", true},
    {R"(<bsdf type="circular"><boolean name="left_handed" value="true"/></bsdf>)", true},
    {R"(<bsdf type="retarder"><float name="theta" value="20"/><float name="delta" value="120"/></bsdf>)", true},
    {R"(<bsdf type="twosided"><bsdf type="conductor"/></bsdf>)", true},
    {R"(<bsdf type="blendbsdf"><float name="weight" value="0.4"/><bsdf type="roughconductor"/><bsdf type="diffuse"/></bsdf>)", false},
    {R"(<bsdf type="mask"><float name="opacity" value="0.6"/><bsdf type="conductor"/></bsdf>)", true},
    {R"(<bsdf type="normalmap"><texture type="rawconstant" name="normalmap"><vector name="value" value="0.7, 0.4, 0.9"/></texture>
        <bsdf type="roughconductor"/></bsdf>)",
     false},
};

// Checks one matrix per wavelength against random fully polarised inputs; counts the checks.
int check_physical(const MuellerSpectrum& M, PCG32& rng, const std::string& what) {
    int checked = 0;
    for (int k = 0; k < 3; ++k) {
        const Mueller& m = M.w[k];
        INFO(what << " wavelength " << k << " M00 " << m(0, 0));
        CHECK(std::isfinite(m(0, 0)));
        for (int trial = 0; trial < 4; ++trial) {
            const Stokes out = m * random_polarised(rng);
            const float scale = std::max(std::abs(m(0, 0)), 1e-6f);
            CHECK(out[0] >= -1e-5f * scale);
            if (out[0] > 1e-2f * scale) {  // the degree of nearly extinguished light is ill-conditioned
                CHECK(degree_of_polarization(out) <= 1.0f + 2e-4f);
                ++checked;
            }
        }
    }
    return checked;
}

}  // namespace

TEST_CASE("polarized BSDFs: Mueller matrices are physical for sampled and evaluated directions", "[mueller][bsdf]") {
    for (const PolarizedCase& c : Cases) {
        const std::string xml = c.xml;
        BSDFUnderTest t = make_bsdf(xml);
        PCG32 rng(2026, 12);
        int physical = 0, polarizing = 0;
        for (int i = 0; i < 400; ++i) {
            const SurfaceInteraction si = local_interaction(random_direction(rng, c.both_sides));
            const float u_lobe = rng.next_float();
            const Vec2 u(rng.next_float(), rng.next_float());
            const BSDFSample bs = t.bsdf->sample(BSDFContext(), si, u_lobe, u);
            MuellerSpectrum M;
            if (bs.valid() && t.bsdf->eval_mueller(BSDFContext(), si, bs.wo, bs.lobe, M)) {
                ++polarizing;
                physical += check_physical(M, rng, xml + " sampled");
                for (int k = 0; k < 3; ++k)
                    if (bs.weight[k] > 0.0f) CHECK(M.w[k](0, 0) > 0.0f);
            }
            const Vec3 wo = random_direction(rng, true);
            const Spectrum f = t.bsdf->eval(BSDFContext(), si, wo);
            if (t.bsdf->eval_mueller(BSDFContext(), si, wo, BSDFNone, M)) {
                physical += check_physical(M, rng, xml + " evaluated");
                for (int k = 0; k < 3; ++k)
                    if (f[k] > 0.0f) CHECK(M.w[k](0, 0) > 0.0f);
            }
        }
        INFO(xml);
        CHECK(polarizing > 100);  // every case has a polarising lobe that is sampled often
        CHECK(physical > 1000);
    }
}

TEST_CASE("polarized BSDFs: the (0, 0) element is the unpolarised value", "[mueller][bsdf]") {
    PCG32 rng(5, 5);
    BSDFUnderTest pplastic = make_bsdf(R"(<bsdf type="pplastic"><float name="alpha" value="0.2"/></bsdf>)");
    BSDFUnderTest conductor = make_bsdf(R"(<bsdf type="conductor"><string name="material" value="Au"/></bsdf>)");
    BSDFUnderTest glass =
        make_bsdf(R"(<bsdf type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>)");
    for (int i = 0; i < 200; ++i) {
        const SurfaceInteraction si = local_interaction(random_direction(rng, false));
        const Vec3 wo = random_direction(rng, false);
        MuellerSpectrum M;
        // pplastic returns its matrix at eval()'s scale (Mitsuba's).
        REQUIRE(pplastic.bsdf->eval_mueller(BSDFContext(), si, wo, BSDFNone, M));
        const Spectrum f = pplastic.bsdf->eval(BSDFContext(), si, wo);
        for (int k = 0; k < 3; ++k) CHECK(M.w[k](0, 0) == Approx(f[k]).epsilon(1e-3).margin(1e-7));  // float Fresnel by two routes
        // The mirror's matrix is its Fresnel reflectance, the sample's weight.
        const BSDFSample bs = conductor.bsdf->sample(BSDFContext(), si, 0.5f, Vec2(0.5f));
        REQUIRE(conductor.bsdf->eval_mueller(BSDFContext(), si, bs.wo, bs.lobe, M));
        for (int k = 0; k < 3; ++k) CHECK(M.w[k](0, 0) == Approx(bs.weight[k]).epsilon(1e-4));
        // Glass: R00 = F and T00 = 1 - F, from either side.
        const SurfaceInteraction any_side = local_interaction(random_direction(rng, true));
        const DielectricFresnel fr = fresnel_dielectric(Frame::cos_theta(any_side.wi), 1.5f);
        for (float u_lobe : {0.0f, 0.999999f}) {
            const BSDFSample g = glass.bsdf->sample(BSDFContext(), any_side, u_lobe, Vec2(0.5f));
            if (!g.valid()) continue;
            REQUIRE(glass.bsdf->eval_mueller(BSDFContext(), any_side, g.wo, g.lobe, M));
            CHECK(M.w[0](0, 0) == Approx(g.lobe == DeltaReflection ? fr.F : 1.0f - fr.F)
                                      .margin(2e-4));  // refraction near the critical angle is ill-conditioned in float
        }
    }
}

TEST_CASE("polarized BSDFs: world bases keep the degree of polarisation and depolarisers say so", "[mueller][bsdf]") {
    BSDFUnderTest conductor = make_bsdf(R"(<bsdf type="roughconductor"><string name="material" value="Al"/></bsdf>)");
    PCG32 rng(9, 9);
    for (int i = 0; i < 200; ++i) {
        SurfaceInteraction si = local_interaction(random_direction(rng, false));
        si.shading = Frame(glm::normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f)));
        const Vec3 wo = random_direction(rng, false);
        MuellerSpectrum local, world;
        if (!conductor.bsdf->eval_mueller(BSDFContext(), si, wo, BSDFNone, local)) continue;
        REQUIRE(normalized_world_mueller(*conductor.bsdf, BSDFContext(), si, wo, BSDFNone, world));
        const Stokes a = local.w[1] * Stokes(1, 0, 0, 0), b = world.w[1] * Stokes(1, 0, 0, 0);
        CHECK(degree_of_polarization(b) == Approx(degree_of_polarization(a)).margin(1e-4));
        CHECK(world.w[1](0, 0) == Approx(1.0f).margin(1e-6));
    }
    MuellerSpectrum M;
    for (const char* xml : {R"(<bsdf type="diffuse"/>)", R"(<bsdf type="roughplastic"/>)", R"(<bsdf type="principled"/>)"}) {
        BSDFUnderTest t = make_bsdf(xml);
        CHECK_FALSE(t.bsdf->eval_mueller(BSDFContext(), local_interaction(Vec3(0, 0.3f, 1)), Vec3(0.2f, 0, 1), DiffuseReflection, M));
    }
}
