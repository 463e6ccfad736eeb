// Every BSDF samples what it evaluates: chi-square goodness of fit of sample() against pdf() at
// several incident directions (grazing ones and, for dielectrics, from inside), delta lobes by
// their discrete probabilities, weight = eval / pdf, pdf integrating to at most one, directional
// albedo at most one (exactly one where lossless), and reciprocity of the reflection lobes.
// All statistical tests in this file together keep a family-wise significance of 1% (Sidak).

#include "core/rng.h"
#include "materials/fresnel.h"
#include "tests/bsdf_harness.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <functional>

using namespace candela;
using namespace candela::test;

namespace {

using DeltaFn = std::function<std::vector<DeltaExpectation>(const Vec3& wi)>;

struct Config {
    std::string name, xml;
    std::vector<float> cos_thetas;  // incident directions; negative = from the inside
    DeltaFn deltas;                 // discrete lobe probabilities (none when empty)
    bool lossless = false;          // directional albedo exactly one
    bool reciprocal = true;         // check reciprocity of reflection
};

const std::vector<float> Outside = {0.9f, 0.5f, 0.07f};
const std::vector<float> BothSides = {0.9f, 0.5f, 0.07f, -0.6f, -0.15f};
// A fibre has no preferred side; three directions (costly to evaluate) suffice.
const std::vector<float> Fibre = {0.8f, 0.2f, -0.5f};

std::vector<DeltaExpectation> fresnel_split(const Vec3& wi, float eta) {
    float F = fresnel_dielectric(wi.z, eta).F;
    return {{DeltaReflection, F}, {DeltaTransmission, 1.0 - F}};
}

const std::vector<Config>& configs() {
    static const std::vector<Config> list = {
        {"diffuse", R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.5, 0.2"/></bsdf>)", Outside, {}},
        {"twosided diffuse from the back", R"(<bsdf type="twosided"><bsdf type="diffuse"/></bsdf>)", {-0.8f, -0.2f}, {}, false, false},
        {"conductor", R"(<bsdf type="conductor"><rgb name="eta" value="0.2, 0.9, 1.1"/><rgb name="k" value="3.9, 2.4, 2.1"/></bsdf>)",
         Outside,
         [](const Vec3&) {
             return std::vector<DeltaExpectation>{{DeltaReflection, 1.0}};
         },
         false, false},
        {"conductor none", R"(<bsdf type="conductor"/>)", Outside,
         [](const Vec3&) {
             return std::vector<DeltaExpectation>{{DeltaReflection, 1.0}};
         },
         true, false},
        {"conductor eta 0 k 0", R"(<bsdf type="conductor"><rgb name="eta" value="0"/><rgb name="k" value="0"/></bsdf>)", Outside,
         [](const Vec3&) {
             return std::vector<DeltaExpectation>{{DeltaReflection, 1.0}};
         },
         true, false},
        {"roughconductor beckmann",
         R"(<bsdf type="roughconductor"><float name="alpha" value="0.3"/><string name="material" value="Au"/></bsdf>)",
         Outside,
         {}},
        {"roughconductor ggx",
         R"(<bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/></bsdf>)",
         Outside,
         {}},
        {"roughconductor ggx anisotropic",
         R"(<bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.4"/></bsdf>)",
         Outside,
         {}},
        {"roughconductor beckmann all normals",
         R"(<bsdf type="roughconductor"><float name="alpha" value="0.2"/><boolean name="sample_visible" value="false"/></bsdf>)",
         Outside,
         {}},
        {"roughconductor ggx all normals anisotropic",
         R"(<bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha_u" value="0.3"/><float name="alpha_v" value="0.15"/><boolean name="sample_visible" value="false"/></bsdf>)",
         Outside,
         {}},
        {"dielectric", R"(<bsdf type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>)", BothSides,
         [](const Vec3& wi) { return fresnel_split(wi, 1.5f); }, true, false},
        {"thindielectric", R"(<bsdf type="thindielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>)",
         BothSides,
         [](const Vec3& wi) {
             float r1 = fresnel_dielectric(std::abs(wi.z), 1.5f).F, R = 2 * r1 / (1 + r1);
             return std::vector<DeltaExpectation>{{DeltaReflection, R}, {Null, 1.0 - R}};
         },
         true, false},
        {"roughdielectric ggx",
         R"(<bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>)",
         BothSides,
         {},
         false,
         false},
        {"roughdielectric beckmann",
         R"(<bsdf type="roughdielectric"><float name="alpha" value="0.2"/><string name="int_ior" value="water"/></bsdf>)",
         BothSides,
         {},
         false,
         false},
        {"plastic",
         R"(<bsdf type="plastic"><rgb name="diffuse_reflectance" value="0.5"/><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>)",
         Outside,
         [](const Vec3& wi) {
             float Fi = fresnel_dielectric(wi.z, 1.5f).F, w = 1.0f / 1.5f;
             double ps = Fi * w / (Fi * w + (1 - Fi) * (1 - w));
             return std::vector<DeltaExpectation>{{DeltaReflection, ps}};
         },
         false, true},
        {"plastic nonlinear",
         R"(<bsdf type="plastic"><rgb name="diffuse_reflectance" value="0.9, 0.3, 0.1"/><boolean name="nonlinear" value="true"/></bsdf>)",
         Outside,
         [](const Vec3& wi) {
             float eta = 1.49f / 1.000277f;
             float Fi = fresnel_dielectric(wi.z, eta).F, w = 1.0f / (1.0f + (0.9f + 0.3f + 0.1f) / 3.0f);
             double ps = Fi * w / (Fi * w + (1 - Fi) * (1 - w));
             return std::vector<DeltaExpectation>{{DeltaReflection, ps}};
         },
         false, true},
        {"roughplastic ggx",
         R"(<bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/><rgb name="diffuse_reflectance" value="0.6, 0.2, 0.1"/></bsdf>)",
         Outside,
         {}},
        {"roughplastic beckmann nonlinear",
         R"(<bsdf type="roughplastic"><float name="alpha" value="0.3"/><boolean name="nonlinear" value="true"/></bsdf>)",
         Outside,
         {}},
        {"phong",
         R"(<bsdf type="phong"><rgb name="kd" value="0.4"/><rgb name="ks" value="0.5"/><float name="exponent" value="20"/></bsdf>)",
         Outside,
         {}},
        {"blinnphong",
         R"(<bsdf type="blinnphong"><rgb name="kd" value="0.3"/><rgb name="ks" value="0.6"/><float name="exponent" value="40"/></bsdf>)",
         Outside,
         {}},
        {"bumpmap over roughconductor",
         R"(<bsdf type="bumpmap"><texture type="checkerboard"><transform name="to_uv"><rotate z="1" angle="30"/></transform></texture><float name="scale" value="0.2"/>
            <bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha" value="0.25"/></bsdf></bsdf>)",
         {0.9f, 0.5f},
         {},
         false,
         false},
        // Issue 10: textured roughness.
        {"roughconductor textured alpha_u, alpha_v",
         R"(<bsdf type="roughconductor"><string name="distribution" value="ggx"/>
              <texture type="checkerboard" name="alpha_u"><rgb name="color0" value="0.05"/><rgb name="color1" value="0.3"/></texture>
              <texture type="checkerboard" name="alpha_v"><rgb name="color0" value="0.4"/><rgb name="color1" value="0.1"/></texture></bsdf>)",
         Outside,
         {}},
        {"roughdielectric textured alpha",
         R"(<bsdf type="roughdielectric"><texture type="checkerboard" name="alpha"><rgb name="color0" value="0.3"/><rgb name="color1" value="0.15"/></texture>
              <float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>)",
         BothSides,
         {},
         false,
         false},
        // principled: defaults; every lobe at once (both sides); textured; white limits.
        {"principled default", R"(<bsdf type="principled"/>)", Outside, {}},
        {"principled every lobe",
         R"(<bsdf type="principled"><rgb name="base_color" value="0.8, 0.5, 0.3"/><float name="metallic" value="0.3"/>
              <float name="specular" value="0.6"/><float name="roughness" value="0.35"/><float name="spec_tint" value="0.4"/>
              <float name="anisotropic" value="0.5"/><float name="sheen" value="0.3"/><float name="sheen_tint" value="0.2"/>
              <float name="clearcoat" value="0.6"/><float name="clearcoat_gloss" value="0.3"/><float name="spec_trans" value="0.4"/>
              <float name="flatness" value="0.5"/></bsdf>)",
         BothSides,
         {},
         false,
         false},
        {"principled textured",
         R"(<bsdf type="principled"><texture type="checkerboard" name="base_color"/><texture type="checkerboard" name="roughness"/>
              <texture type="checkerboard" name="metallic"><rgb name="color0" value="0.2"/><rgb name="color1" value="0.7"/></texture>
              <float name="eta" value="1.33"/><float name="clearcoat" value="1"/><float name="clearcoat_gloss" value="0.5"/></bsdf>)",
         Outside,
         {},
         false,
         true},
        {"principled white metal",
         R"(<bsdf type="principled"><rgb name="base_color" value="1"/><float name="metallic" value="1"/><float name="roughness" value="0.4"/></bsdf>)",
         Outside,
         {}},
        {"principled white glass",
         R"(<bsdf type="principled"><rgb name="base_color" value="1"/><float name="spec_trans" value="1"/><float name="roughness" value="0.5"/><float name="eta" value="1.5"/></bsdf>)",
         BothSides,
         {},
         false,
         false},
        {"principledthin",
         R"(<bsdf type="principledthin"><rgb name="base_color" value="0.7, 0.1, 0.1"/><float name="roughness" value="0.3"/>
              <float name="spec_tint" value="0.1"/><float name="anisotropic" value="0.5"/><float name="spec_trans" value="0.6"/>
              <float name="diff_trans" value="0.6"/><float name="eta" value="1.33"/><float name="sheen" value="0.5"/><float name="flatness" value="0.3"/></bsdf>)",
         BothSides,
         {},
         false,
         false},
        {"principledthin default", R"(<bsdf type="principledthin"/>)", BothSides, {}, false, false},
        {"principledthin white sheet",
         R"(<bsdf type="principledthin"><rgb name="base_color" value="1"/><float name="spec_trans" value="1"/><float name="roughness" value="0.6"/></bsdf>)",
         BothSides,
         {},
         false,
         false},
        // Composites and surfaces that let light pass.
        {"blendbsdf rough metal and diffuse",
         R"(<bsdf type="blendbsdf"><float name="weight" value="0.3"/><bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf>
              <bsdf type="diffuse"><rgb name="reflectance" value="0.9, 0.6, 0.3"/></bsdf></bsdf>)",
         Outside,
         {}},
        {"blendbsdf mirror and rough plastic",
         R"(<bsdf type="blendbsdf"><float name="weight" value="0.6"/><bsdf type="conductor"/><bsdf type="roughplastic"/></bsdf>)", Outside,
         [](const Vec3&) {
             return std::vector<DeltaExpectation>{{DeltaReflection, 0.4}};
         },
         false, false},
        {"blendbsdf mirror and glass",
         R"(<bsdf type="blendbsdf"><float name="weight" value="0.25"/><bsdf type="conductor"/><bsdf type="dielectric"/></bsdf>)", Outside,
         [](const Vec3& wi) {
             float F = fresnel_dielectric(wi.z, 1.5046f / 1.000277f).F;
             return std::vector<DeltaExpectation>{{DeltaReflection, 0.75 + 0.25 * F}, {DeltaTransmission, 0.25 * (1.0 - F)}};
         },
         true, false},
        {"mask over rough plastic",
         R"(<bsdf type="mask"><float name="opacity" value="0.3"/><bsdf type="roughplastic"><float name="alpha" value="0.2"/></bsdf></bsdf>)",
         BothSides,
         [](const Vec3&) {
             return std::vector<DeltaExpectation>{{Null, 0.7}};
         },
         false, false},
        {"mask over a mirror", R"(<bsdf type="mask"><float name="opacity" value="0.4"/><bsdf type="conductor"/></bsdf>)", Outside,
         [](const Vec3&) {
             return std::vector<DeltaExpectation>{{Null, 0.6}, {DeltaReflection, 0.4}};
         },
         true, false},
        {"null", R"(<bsdf type="null"/>)", BothSides,
         [](const Vec3&) {
             return std::vector<DeltaExpectation>{{Null, 1.0}};
         },
         true, false},
        {"polarizer", R"(<bsdf type="polarizer"><rgb name="transmittance" value="0.8"/></bsdf>)", BothSides,
         [](const Vec3&) {
             return std::vector<DeltaExpectation>{{Null, 1.0}};
         },
         false, false},
        {"circular", R"(<bsdf type="circular"><rgb name="transmittance" value="0.8"/></bsdf>)", BothSides,
         [](const Vec3&) {
             return std::vector<DeltaExpectation>{{Null, 1.0}};
         },
         false, false},
        // hair: pigmented, lossless (sigma_a = 0), and smooth with a strong tilt.
        {"hair", R"(<bsdf type="hair"/>)", Fibre, {}, false, false},
        {"hair lossless", R"(<bsdf type="hair"><rgb name="sigma_a" value="0"/></bsdf>)", Fibre, {}, true, false},
        {"hair smooth blonde",
         R"(<bsdf type="hair"><float name="eumelanin" value="0.2"/><float name="pheomelanin" value="0.4"/><float name="longitudinal_roughness" value="0.2"/>
              <float name="azimuthal_roughness" value="0.2"/><float name="scale_tilt" value="5"/></bsdf>)",
         Fibre,
         {},
         false,
         false},
        {"pplastic",
         R"(<bsdf type="pplastic"><rgb name="diffuse_reflectance" value="0.05, 0.03, 0.1"/><float name="alpha" value="0.06"/></bsdf>)",
         Outside,
         {}},
        {"pplastic ggx rough",
         R"(<bsdf type="pplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.4"/></bsdf>)",
         Outside,
         {}},
    };
    return list;
}

// Runs every configuration whose name starts with `prefix`; there must be one.
void check_configs(const std::string& prefix);

int statistical_tests() {
    int n = 0;
    for (const Config& c : configs()) n += 3 * int(c.cos_thetas.size());  // chi-square, pdf integral, albedo
    return n;
}

// 1e6 samples per incidence (1e5 at the sanitizer run's CANDELA_TEST_EFFORT=0.1: the same
// significance, less power; tests/util.h).
const int Samples = effort_scaled(1000000, 100000);

void check_config(const Config& c) {
    BSDFUnderTest t = make_bsdf(c.xml);
    const double alpha = sidak(0.01, statistical_tests());
    const double z = normal_quantile(1.0 - alpha);  // one-sided bounds
    // Importance mode: the same sampling, without the eta^2 radiance scaling, so that albedos of
    // lossless interfaces are exactly one.
    BSDFContext ctx;
    ctx.mode = TransportMode::Importance;
    // `--rng-seed N` draws other samples (the default seed is 0).
    uint64_t seed = 1 + 1000 * uint64_t(Catch::rngSeed());
    for (float cos_theta : c.cos_thetas) {
        Vec3 wi = direction(cos_theta, 0.7f);
        SurfaceInteraction si = local_interaction(wi);
        INFO(c.name << ", cos theta_i = " << cos_theta);
        SamplingCheck check = check_sampling(*t.bsdf, si, ctx, Samples, c.deltas ? c.deltas(wi) : std::vector<DeltaExpectation>{}, seed++);
        for (const std::string& f : check.failures) FAIL_CHECK(f);
        INFO(check.chi2.details << " (per-test alpha " << alpha << ")");
        CHECK(check.chi2.p_value > alpha);
        MeanAndError integral = pdf_integral(*t.bsdf, si, ctx, effort_scaled(200000, 20000), seed++);
        INFO("pdf integral " << integral.mean << " +- " << integral.std_error);
        CHECK(integral.mean - z * integral.std_error <= 1.0);
        INFO("albedo " << check.albedo.mean << " +- " << check.albedo.std_error);
        if (c.lossless)
            CHECK(std::abs(check.albedo.mean - 1.0) < 1e-6);
        else
            CHECK(check.albedo.mean - z * check.albedo.std_error <= 1.0);
    }
    if (c.reciprocal) CHECK(reciprocity_error(*t.bsdf, 2000, 99) < 1e-4);  // float32 evaluation
}

void check_configs(const std::string& prefix) {
    int found = 0;
    for (const Config& c : configs())
        if (c.name.compare(0, prefix.size(), prefix) == 0) {
            check_config(c);
            ++found;
        }
    REQUIRE(found > 0);
}

}  // namespace

TEST_CASE("bsdf: diffuse and twosided", "[bsdf]") {
    check_config(configs()[0]);
    check_config(configs()[1]);
}
TEST_CASE("bsdf: smooth conductors", "[bsdf]") {
    for (int i = 2; i <= 4; ++i) check_config(configs()[i]);
}
TEST_CASE("bsdf: rough conductors", "[bsdf]") {
    for (int i = 5; i <= 9; ++i) check_config(configs()[i]);
}
TEST_CASE("bsdf: smooth and thin dielectrics", "[bsdf]") {
    for (int i = 10; i <= 11; ++i) check_config(configs()[i]);
}
TEST_CASE("bsdf: rough dielectrics", "[bsdf]") {
    for (int i = 12; i <= 13; ++i) check_config(configs()[i]);
}
TEST_CASE("bsdf: plastics", "[bsdf]") {
    for (int i = 14; i <= 17; ++i) check_config(configs()[i]);
}
TEST_CASE("bsdf: phong, blinnphong and bump mapping", "[bsdf]") {
    for (int i = 18; i <= 20; ++i) check_config(configs()[i]);
}
TEST_CASE("bsdf: textured roughness", "[bsdf]") {
    check_configs("roughconductor textured");
    check_configs("roughdielectric textured");
}
TEST_CASE("bsdf: principled", "[bsdf][principled]") { check_configs("principled "); }
TEST_CASE("bsdf: principledthin", "[bsdf][principled]") { check_configs("principledthin"); }
TEST_CASE("bsdf: blendbsdf", "[bsdf]") { check_configs("blendbsdf"); }
TEST_CASE("bsdf: mask, null, polarizer and circular", "[bsdf]") {
    check_configs("mask");
    check_configs("null");
    check_configs("polarizer");
    check_configs("circular");
}
TEST_CASE("bsdf: hair", "[bsdf][hair]") { check_configs("hair"); }
TEST_CASE("bsdf: pplastic", "[bsdf]") { check_configs("pplastic"); }
TEST_CASE("bsdf: the configuration table is covered exactly", "[bsdf]") { CHECK(configs().size() == 44); }

TEST_CASE("bsdf: a BSDF that says it does not read u_lobe samples the same for every u_lobe", "[bsdf]") {
    // The path integrator skips the number of such a BSDF (BSDF::reads_lobe_sample).
    int skipping = 0;
    for (const Config& c : configs()) {
        BSDFUnderTest t = make_bsdf(c.xml);
        if (t.bsdf->reads_lobe_sample()) continue;
        ++skipping;
        INFO(c.name);
        PCG32 rng(5, 9);
        for (float cos_theta : c.cos_thetas) {
            const SurfaceInteraction si = local_interaction(direction(cos_theta, 0.7f));
            for (int i = 0; i < 2000; ++i) {
                const float ux = rng.next_float();
                const Vec2 u(ux, rng.next_float());
                const BSDFSample a = t.bsdf->sample(BSDFContext(), si, 0.02f, u), b = t.bsdf->sample(BSDFContext(), si, 0.97f, u);
                REQUIRE(a.wo == b.wo);
                REQUIRE(a.pdf == b.pdf);
                REQUIRE(a.eta == b.eta);
                REQUIRE(a.lobe == b.lobe);
                REQUIRE(a.weight == b.weight);
            }
        }
    }
    // diffuse, twosided diffuse, the conductors and rough conductors, null, bump-mapped ones.
    CHECK(skipping >= 10);
}

TEST_CASE("bsdf: one-sided BSDFs are black from behind, transmissive ones are not", "[bsdf]") {
    BSDFContext ctx;
    SurfaceInteraction back = local_interaction(direction(-0.5f, 0.3f));
    for (const char* xml : {R"(<bsdf type="diffuse"/>)", R"(<bsdf type="roughconductor"/>)", R"(<bsdf type="plastic"/>)",
                            R"(<bsdf type="roughplastic"/>)", R"(<bsdf type="conductor"/>)", R"(<bsdf type="phong"/>)"}) {
        BSDFUnderTest t = make_bsdf(xml);
        INFO(xml);
        CHECK(!t.bsdf->sample(ctx, back, 0.5f, Vec2(0.3f, 0.6f)).valid());
        CHECK(t.bsdf->eval(ctx, back, direction(-0.7f, 1.0f)) == Spectrum(0.0f));
    }
    BSDFUnderTest glass = make_bsdf(R"(<bsdf type="roughdielectric"/>)");
    CHECK(glass.bsdf->sample(ctx, back, 0.9f, Vec2(0.3f, 0.6f)).valid());
}

TEST_CASE("bsdf: bad parameters are errors", "[bsdf][errors]") {
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="dielectric"><string name="int_ior" value="unobtainium"/></bsdf>)"),
                      Catch::Contains("unknown index of refraction"));
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="conductor"><string name="material" value="Xx"/></bsdf>)"),
                      Catch::Contains("unknown conductor"));
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="roughconductor"><string name="distribution" value="phong"/></bsdf>)"),
                      Catch::Contains("beckmann or ggx"));
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="phong"><rgb name="kd" value="0.8"/><rgb name="ks" value="0.5"/></bsdf>)"),
                      Catch::Contains("exceeds 1"));
    CHECK_THROWS_WITH(
        make_bsdf(R"(<bsdf type="roughplastic"><float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.2"/></bsdf>)"),
        Catch::Contains("isotropic"));
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="twosided"><bsdf type="dielectric"/></bsdf>)"), Catch::Contains("transmissive"));
}
