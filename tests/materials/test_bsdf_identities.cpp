// Identities between BSDFs, checked point by point (eval and pdf over random direction pairs) or
// sample by sample: the limits in which principled and principledthin become other BSDFs, blends
// and masks at their extreme weights, textured roughness that is constant, pplastic's lobes, and
// the hair model's closed-form albedo against its own sampling. Deterministic unless stated; the
// statistical checks share a 1% family-wise level (Sidak).

#include "core/rng.h"
#include "core/warp.h"
#include "materials/fresnel.h"
#include "tests/bsdf_harness.h"

#include <catch2/catch.hpp>

#include <cstring>

using namespace candela;
using namespace candela::test;

namespace {

constexpr int Pairs = 20000;
// float32 evaluation along different code paths (rounding of alpha = roughness^2, Fresnel of a
// perfect mirror from eta = 0, k = 1, ...): agreement to this relative tolerance.
constexpr double Tolerance = 2e-4;

void check_same(const std::string& xml_a, const std::string& xml_b, bool both_sides, BSDFContext ctx = BSDFContext()) {
    BSDFUnderTest a = make_bsdf(xml_a), b = make_bsdf(xml_b);
    PointwiseDifference d = compare_pointwise(*a.bsdf, *b.bsdf, ctx, Pairs, 7, both_sides);
    INFO(xml_a << "\n  vs " << xml_b << "\n  eval " << d.eval << ", pdf " << d.pdf << " over " << d.nonzero << " non-zero pairs");
    CHECK(d.nonzero > Pairs / 10);  // the comparison covers the lobes, not just zeros
    CHECK(d.eval < Tolerance);
    CHECK(d.pdf < Tolerance);
}

// Samples drawn with the same random numbers must agree (direction, pdf, weight, lobe).
void check_same_samples(const BSDF& a, const BSDF& b, int n, bool both_sides) {
    PCG32 rng(3, 5);
    BSDFContext ctx;
    int valid = 0;
    for (int i = 0; i < n; ++i) {
        float u1 = rng.next_float(), u2 = rng.next_float(), ul = rng.next_float(), ux = rng.next_float(), uy = rng.next_float();
        Vec3 wi = both_sides ? warp::square_to_uniform_sphere(Vec2(u1, u2)) : warp::square_to_uniform_hemisphere(Vec2(u1, u2));
        SurfaceInteraction si = local_interaction(wi);
        BSDFSample sa = a.sample(ctx, si, ul, Vec2(ux, uy)), sb = b.sample(ctx, si, ul, Vec2(ux, uy));
        REQUIRE(sa.valid() == sb.valid());
        if (!sa.valid()) continue;
        ++valid;
        CHECK(sa.lobe == sb.lobe);
        CHECK(glm::length(sa.wo - sb.wo) < 1e-5f);
        CHECK(std::abs(sa.pdf - sb.pdf) <= Tolerance * std::max(sa.pdf, sb.pdf));
        CHECK(glm::length(sa.weight - sb.weight) <= Tolerance * std::max(glm::length(sa.weight), 1e-3f));
    }
    CHECK(valid > n / 4);  // (one-sided BSDFs seen from both sides fail half the time)
}

// Burley 2012's diffuse in its factored form, f = base / pi (1 + (F_D90 - 1) F_i)(1 + (F_D90 - 1) F_o),
// F_D90 = 1/2 + 2 r cos_d^2, F = (1 - cos)^5: an independent statement of what principled's
// diffuse lobe must evaluate to.
Spectrum burley_2012(const Spectrum& base, float roughness, const Vec3& wi, const Vec3& wo) {
    Vec3 h = glm::normalize(wi + wo);
    float cos_d = glm::dot(h, wo), fd90 = 0.5f + 2.0f * roughness * cos_d * cos_d;
    float Fi = std::pow(1.0f - wi.z, 5.0f), Fo = std::pow(1.0f - wo.z, 5.0f);
    return base * (InvPi * (1.0f + (fd90 - 1.0f) * Fi) * (1.0f + (fd90 - 1.0f) * Fo) * wo.z);
}

}  // namespace

TEST_CASE("principled: metallic 1 with a white base is roughconductor (ggx, alpha = roughness^2, a perfect mirror)", "[bsdf][principled]") {
    const char* metal =
        R"(<bsdf type="principled"><rgb name="base_color" value="1"/><float name="metallic" value="1"/><float name="roughness" value="0.5"/></bsdf>)";
    const char* rough = R"(<bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha" value="0.25"/></bsdf>)";
    check_same(metal, rough, false);
    // Anisotropic: alpha_u = r^2 / aspect, alpha_v = r^2 aspect with aspect = sqrt(1 - 0.9 a); for
    // r = 0.6, a = 0.5: aspect = sqrt(0.55).
    float aspect = std::sqrt(0.55f);
    check_same(
        R"(<bsdf type="principled"><rgb name="base_color" value="1"/><float name="metallic" value="1"/><float name="roughness" value="0.6"/>
                    <float name="anisotropic" value="0.5"/></bsdf>)",
        "<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha_u\" value=\"" +
            std::to_string(0.36f / aspect) + "\"/><float name=\"alpha_v\" value=\"" + std::to_string(0.36f * aspect) + "\"/></bsdf>",
        false);
    // Their samplers are the same visible-normal sampler: the same numbers give the same samples.
    BSDFUnderTest a = make_bsdf(metal), b = make_bsdf(rough);
    check_same_samples(*a.bsdf, *b.bsdf, 20000, false);
    // A coloured metal is the mirror times Schlick's Fresnel with F0 = base_color.
    const Spectrum base(0.9f, 0.6f, 0.2f);
    BSDFUnderTest gold = make_bsdf(
        R"(<bsdf type="principled"><rgb name="base_color" value="0.9, 0.6, 0.2"/><float name="metallic" value="1"/><float name="roughness" value="0.5"/></bsdf>)");
    BSDFContext ctx;
    PCG32 rng(67, 71);
    double worst = 0.0;
    for (int i = 0; i < Pairs; ++i) {
        float u1 = rng.next_float(), u2 = rng.next_float(), u3 = rng.next_float(), u4 = rng.next_float();
        Vec3 wi = warp::square_to_uniform_hemisphere(Vec2(u1, u2)), wo = warp::square_to_uniform_hemisphere(Vec2(u3, u4));
        SurfaceInteraction si = local_interaction(wi);
        float c = glm::dot(wi, glm::normalize(wi + wo));
        Spectrum expect = (base + (Spectrum(1.0f) - base) * std::pow(1.0f - c, 5.0f)) * b.bsdf->eval(ctx, si, wo);
        Spectrum f = gold.bsdf->eval(ctx, si, wo);
        worst = std::max(worst, double(max_component(glm::abs(f - expect)) / std::max(max_component(expect), 1e-3f)));
    }
    CHECK(worst < Tolerance);
}

TEST_CASE("principled: spec_trans 1 with a white base is roughdielectric (ggx, alpha = roughness^2), both sides, both transport modes",
          "[bsdf][principled]") {
    const char* glass =
        R"(<bsdf type="principled"><rgb name="base_color" value="1"/><float name="spec_trans" value="1"/><float name="roughness" value="0.4"/>
                             <float name="eta" value="1.5"/></bsdf>)";
    const char* rough = R"(<bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.16"/>
                             <float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>)";
    check_same(glass, rough, true);
    BSDFContext importance;
    importance.mode = TransportMode::Importance;
    check_same(glass, rough, true, importance);
    // specular = 0.08^-1 ((eta - 1) / (eta + 1))^2 is the same interface as eta.
    float specular = std::pow(0.5f / 2.5f, 2.0f) / 0.08f;
    check_same(
        "<bsdf type=\"principled\"><rgb name=\"base_color\" value=\"1\"/><float name=\"spec_trans\" value=\"1\"/><float name=\"roughness\" value=\"0.4\"/>"
        "<float name=\"specular\" value=\"" +
            std::to_string(specular) + "\"/></bsdf>",
        rough, true);
}

TEST_CASE("principled: with metallic 0 and specular 0 only Burley's diffuse remains, it is Lambertian where its Fresnel weights vanish",
          "[bsdf][principled]") {
    // There is no exact Lambertian limit: Burley's retro-reflection term (1 + (F_D90 - 1) F_i)
    // (1 + (F_D90 - 1) F_o) is 1 only at normal incidence or normal exitance with F_D90 != 1.
    // So: pointwise against the 2012 factored form, and equal to `diffuse` at normal incidence.
    for (float roughness : {0.0f, 0.5f, 1.0f}) {
        BSDFUnderTest p = make_bsdf(
            "<bsdf type=\"principled\"><rgb name=\"base_color\" value=\"0.8, 0.5, 0.2\"/><float name=\"specular\" value=\"0\"/>"
            "<float name=\"roughness\" value=\"" +
            std::to_string(roughness) + "\"/></bsdf>");
        BSDFUnderTest d = make_bsdf(R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.5, 0.2"/></bsdf>)");
        BSDFContext ctx;
        PCG32 rng(11, 13);
        double worst = 0.0;
        for (int i = 0; i < Pairs; ++i) {
            float a = rng.next_float(), b = rng.next_float(), c = rng.next_float(), e = rng.next_float();
            Vec3 wi = warp::square_to_uniform_hemisphere(Vec2(a, b)), wo = warp::square_to_uniform_hemisphere(Vec2(c, e));
            Spectrum f = p.bsdf->eval(ctx, local_interaction(wi), wo), expect = burley_2012(Spectrum(0.8f, 0.5f, 0.2f), roughness, wi, wo);
            worst = std::max(worst, double(max_component(glm::abs(f - expect)) / std::max(max_component(expect), 1e-3f)));
        }
        INFO("roughness " << roughness << ": worst relative difference " << worst);
        CHECK(worst < Tolerance);
        // Normal incidence: F_i = 0, and then Lambertian in wo whenever F_o = 0, i.e. wo = n too.
        SurfaceInteraction normal = local_interaction(Vec3(0, 0, 1));
        Spectrum fp = p.bsdf->eval(ctx, normal, Vec3(0, 0, 1)), fd = d.bsdf->eval(ctx, normal, Vec3(0, 0, 1));
        CHECK(glm::length(fp - fd) < 1e-6f);
    }
}

TEST_CASE("principledthin: its diffuse lobe is principled's, diff_trans 2 is a Lambertian transmitter, it is the same from both sides",
          "[bsdf][principled]") {
    const char* base =
        R"(<rgb name="base_color" value="0.3, 0.6, 0.9"/><float name="roughness" value="0.7"/><float name="sheen" value="0.4"/>
                          <float name="sheen_tint" value="0.5"/><float name="flatness" value="0.3"/>)";
    // (With specular 0, principled's specular lobe is zero; sampling rate 0 stops sampling it too.)
    check_same(
        std::string("<bsdf type=\"principledthin\">") + base + "</bsdf>",
        std::string(
            "<bsdf type=\"principled\"><float name=\"specular\" value=\"0\"/><float name=\"main_specular_sampling_rate\" value=\"0\"/>") +
            base + "</bsdf>",
        false);

    BSDFUnderTest thin = make_bsdf(
        R"(<bsdf type="principledthin"><rgb name="base_color" value="0.3, 0.6, 0.9"/><float name="diff_trans" value="2"/></bsdf>)");
    BSDFUnderTest lambert = make_bsdf(R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.3, 0.6, 0.9"/></bsdf>)");
    BSDFUnderTest sheet =
        make_bsdf(R"(<bsdf type="principledthin"><rgb name="base_color" value="0.7, 0.4, 0.2"/><float name="spec_trans" value="0.5"/>
                                         <float name="diff_trans" value="0.8"/><float name="anisotropic" value="0.3"/><float name="eta" value="1.4"/></bsdf>)");
    BSDFContext ctx;
    PCG32 rng(17, 19);
    double worst = 0.0, worst_flip = 0.0;
    for (int i = 0; i < Pairs; ++i) {
        float a = rng.next_float(), b = rng.next_float(), c = rng.next_float(), e = rng.next_float();
        Vec3 wi = warp::square_to_uniform_hemisphere(Vec2(a, b)), wo = warp::square_to_uniform_hemisphere(Vec2(c, e));
        Vec3 wo_below(wo.x, wo.y, -wo.z);
        SurfaceInteraction si = local_interaction(wi);
        // Transmission to wo_below equals Lambertian reflection to wo; no reflection at all.
        Spectrum ft = thin.bsdf->eval(ctx, si, wo_below), fl = lambert.bsdf->eval(ctx, si, wo);
        worst = std::max(worst, double(max_component(glm::abs(ft - fl)) / std::max(max_component(fl), 1e-3f)));
        worst = std::max(worst, double(max_component(thin.bsdf->eval(ctx, si, wo))));
        // Seen from the back (wi and wo mirrored through the sheet), everything is the same.
        SurfaceInteraction back = local_interaction(-wi);
        for (const Vec3& w : {wo, wo_below}) {
            Spectrum f1 = sheet.bsdf->eval(ctx, si, w), f2 = sheet.bsdf->eval(ctx, back, -w);
            float p1 = sheet.bsdf->pdf(ctx, si, w), p2 = sheet.bsdf->pdf(ctx, back, -w);
            worst_flip = std::max({worst_flip, double(max_component(glm::abs(f1 - f2))), double(std::abs(p1 - p2))});
        }
    }
    CHECK(worst < Tolerance);
    CHECK(worst_flip == 0.0);
}

TEST_CASE("blendbsdf: weight 0 and 1 are its parts, sample by sample", "[bsdf]") {
    const char* first = R"(<bsdf type="roughconductor"><float name="alpha" value="0.2"/><string name="material" value="Cu"/></bsdf>)";
    const char* second = R"(<bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0.2, 0.4, 0.6"/></bsdf>)";
    for (int w = 0; w <= 1; ++w) {
        std::string blend =
            "<bsdf type=\"blendbsdf\"><float name=\"weight\" value=\"" + std::to_string(w) + "\"/>" + first + second + "</bsdf>";
        const char* part = w == 0 ? first : second;
        INFO("weight " << w);
        check_same(blend, part, false);
        BSDFUnderTest b = make_bsdf(blend), p = make_bsdf(part);
        check_same_samples(*b.bsdf, *p.bsdf, 20000, false);
    }
    // In between: the blend of the parts (a textured weight looked up per point).
    BSDFUnderTest half =
        make_bsdf(std::string(R"(<bsdf type="blendbsdf"><texture type="checkerboard" name="weight"><rgb name="color0" value="0.25"/>
                                                     <rgb name="color1" value="0.25"/></texture>)") +
                  first + second + "</bsdf>");
    BSDFUnderTest a = make_bsdf(first), c = make_bsdf(second);
    BSDFContext ctx;
    SurfaceInteraction si = local_interaction(direction(0.6f, 0.3f));
    Vec3 wo = direction(0.5f, 2.9f);
    Spectrum expect = 0.75f * a.bsdf->eval(ctx, si, wo) + 0.25f * c.bsdf->eval(ctx, si, wo);
    CHECK(glm::length(half.bsdf->eval(ctx, si, wo) - expect) < 1e-6f * glm::length(expect) + 1e-9f);
    CHECK(half.bsdf->pdf(ctx, si, wo) == Approx(0.75f * a.bsdf->pdf(ctx, si, wo) + 0.25f * c.bsdf->pdf(ctx, si, wo)).epsilon(1e-6));
}

TEST_CASE("mask: opacity 1 is its nested BSDF sample by sample, opacity 0 passes everything, a texture sets it per point", "[bsdf]") {
    const char* nested = R"(<bsdf type="roughplastic"><float name="alpha" value="0.3"/></bsdf>)";
    BSDFUnderTest opaque = make_bsdf(std::string("<bsdf type=\"mask\"><float name=\"opacity\" value=\"1\"/>") + nested + "</bsdf>");
    BSDFUnderTest plain = make_bsdf(nested);
    check_same(std::string("<bsdf type=\"mask\"><float name=\"opacity\" value=\"1\"/>") + nested + "</bsdf>", nested, true);
    check_same_samples(*opaque.bsdf, *plain.bsdf, 20000, true);
    SurfaceInteraction si = local_interaction(direction(0.7f, 1.0f));
    CHECK(opaque.bsdf->null_transmission(si) == Spectrum(0.0f));

    BSDFUnderTest clear = make_bsdf(std::string("<bsdf type=\"mask\"><float name=\"opacity\" value=\"0\"/>") + nested + "</bsdf>");
    BSDFContext ctx;
    PCG32 rng(23, 29);
    for (int i = 0; i < 1000; ++i) {
        float ul = rng.next_float(), ux = rng.next_float(), uy = rng.next_float();
        BSDFSample bs = clear.bsdf->sample(ctx, si, ul, Vec2(ux, uy));
        REQUIRE(bs.valid());
        CHECK(bs.lobe == Null);
        CHECK(bs.wo == -si.wi);
        CHECK(bs.weight == Spectrum(1.0f));
        CHECK(clear.bsdf->eval(ctx, si, direction(2.0f * ux - 1.0f, uy * TwoPi)) == Spectrum(0.0f));
    }
    CHECK(clear.bsdf->null_transmission(si) == Spectrum(1.0f));

    // Checkerboard opacity: at uv (0.3, 0.6) the scalar lookup takes color0 (checkerboard.cpp:
    // scalar lookups use the opposite parity, as in Mitsuba).
    BSDFUnderTest textured =
        make_bsdf(std::string(R"(<bsdf type="mask"><texture type="checkerboard" name="opacity"><rgb name="color0" value="0.35"/>
                                                        <rgb name="color1" value="0.8"/></texture>)") +
                  nested + "</bsdf>");
    float t = textured.bsdf->null_transmission(si).x;
    CHECK(t == Approx(0.65f).epsilon(1e-6));
    Vec3 wo = direction(0.4f, 4.0f);
    CHECK(glm::length(textured.bsdf->eval(ctx, si, wo) - (1.0f - t) * plain.bsdf->eval(ctx, si, wo)) < 1e-6f);
}

TEST_CASE("textured roughness equal to a constant gives exactly the constant's BSDF", "[bsdf]") {
    auto checker = [](const char* name, const char* value) {
        return std::string("<texture type=\"checkerboard\" name=\"") + name + "\"><rgb name=\"color0\" value=\"" + value +
               "\"/><rgb name=\"color1\" value=\"" + value + "\"/></texture>";
    };
    struct Case {
        std::string textured, constant;
        bool both_sides;
    };
    std::vector<Case> cases = {
        {"<bsdf type=\"roughconductor\">" + checker("alpha", "0.3") + "</bsdf>",
         R"(<bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf>)", false},
        {"<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/>" + checker("alpha_u", "0.1") +
             checker("alpha_v", "0.35") + "</bsdf>",
         R"(<bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.35"/></bsdf>)",
         false},
        {"<bsdf type=\"roughdielectric\">" + checker("alpha", "0.2") + "</bsdf>",
         R"(<bsdf type="roughdielectric"><float name="alpha" value="0.2"/></bsdf>)", true},
    };
    BSDFContext ctx;
    for (const Case& c : cases) {
        INFO(c.textured);
        BSDFUnderTest t = make_bsdf(c.textured), k = make_bsdf(c.constant);
        PointwiseDifference d = compare_pointwise(*t.bsdf, *k.bsdf, ctx, Pairs, 41, c.both_sides);
        CHECK(d.nonzero > Pairs / 10);
        CHECK(d.eval == 0.0);  // bit for bit
        CHECK(d.pdf == 0.0);
        PCG32 rng(43, 47);
        for (int i = 0; i < 5000; ++i) {
            float a = rng.next_float(), b = rng.next_float(), ul = rng.next_float(), ux = rng.next_float(), uy = rng.next_float();
            SurfaceInteraction si = local_interaction(warp::square_to_uniform_hemisphere(Vec2(a, b)));
            BSDFSample s1 = t.bsdf->sample(ctx, si, ul, Vec2(ux, uy)), s2 = k.bsdf->sample(ctx, si, ul, Vec2(ux, uy));
            // Bit for bit, member by member (the struct's padding bytes are not part of the sample).
            REQUIRE(std::memcmp(&s1.wo, &s2.wo, sizeof(s1.wo)) == 0);
            REQUIRE(std::memcmp(&s1.pdf, &s2.pdf, sizeof(s1.pdf)) == 0);
            REQUIRE(std::memcmp(&s1.eta, &s2.eta, sizeof(s1.eta)) == 0);
            REQUIRE(s1.lobe == s2.lobe);
            REQUIRE(std::memcmp(&s1.weight, &s2.weight, sizeof(s1.weight)) == 0);
            REQUIRE(s1.dispersed == s2.dispersed);
        }
    }
    // A non-constant texture is looked up per point: the checkerboard's scalar colour at uv
    // (0.3, 0.6) is color0.
    BSDFUnderTest varying =
        make_bsdf(R"(<bsdf type="roughconductor"><texture type="checkerboard" name="alpha"><rgb name="color0" value="0.05"/>
                                             <rgb name="color1" value="0.5"/></texture></bsdf>)");
    BSDFUnderTest smooth = make_bsdf(R"(<bsdf type="roughconductor"><float name="alpha" value="0.05"/></bsdf>)");
    BSDFUnderTest rough = make_bsdf(R"(<bsdf type="roughconductor"><float name="alpha" value="0.5"/></bsdf>)");
    SurfaceInteraction si = local_interaction(direction(0.8f, 0.2f));
    Vec3 wo = reflect(si.wi);
    Spectrum f = varying.bsdf->eval(ctx, si, wo);
    CHECK(f == smooth.bsdf->eval(ctx, si, wo));
    CHECK(smooth.bsdf->eval(ctx, si, wo) != rough.bsdf->eval(ctx, si, wo));
}

TEST_CASE("pplastic: its specular lobe is roughplastic's, its diffuse lobe is plastic's without the coating's internal reflections",
          "[bsdf]") {
    BSDFContext glossy;
    glossy.lobes = GlossyReflection;
    check_same(
        R"(<bsdf type="pplastic"><float name="alpha" value="0.15"/><rgb name="specular_reflectance" value="0.9, 0.7, 0.5"/></bsdf>)",
        R"(<bsdf type="roughplastic"><float name="alpha" value="0.15"/><rgb name="specular_reflectance" value="0.9, 0.7, 0.5"/></bsdf>)",
        false, glossy);
    // plastic's diffuse term is rho / (1 - Fdr_int) (1 - F_i)(1 - F_o) cos / (pi eta^2), so
    // pplastic's is plastic's times eta^2 (1 - Fdr_int) for the same rho.
    BSDFUnderTest pp = make_bsdf(R"(<bsdf type="pplastic"><rgb name="diffuse_reflectance" value="0.6, 0.3, 0.1"/></bsdf>)");
    BSDFUnderTest pl = make_bsdf(R"(<bsdf type="plastic"><rgb name="diffuse_reflectance" value="0.6, 0.3, 0.1"/></bsdf>)");
    BSDFContext diffuse;
    diffuse.lobes = DiffuseReflection;
    float eta = 1.49f / 1.000277f, scale = eta * eta * (1.0f - fresnel_diffuse_reflectance(1.0f / eta));
    PCG32 rng(53, 59);
    double worst = 0.0;
    for (int i = 0; i < Pairs; ++i) {
        float a = rng.next_float(), b = rng.next_float(), c = rng.next_float(), e = rng.next_float();
        SurfaceInteraction si = local_interaction(warp::square_to_uniform_hemisphere(Vec2(a, b)));
        Vec3 wo = warp::square_to_uniform_hemisphere(Vec2(c, e));
        Spectrum f = pp.bsdf->eval(diffuse, si, wo), expect = pl.bsdf->eval(diffuse, si, wo) * scale;
        worst = std::max(worst, double(max_component(glm::abs(f - expect)) / std::max(max_component(expect), 1e-3f)));
    }
    CHECK(worst < Tolerance);
}

TEST_CASE("hair: the closed-form albedo sum A_p equals the mean sample weight, lossless fibres reflect everything", "[bsdf][hair]") {
    // Two estimators of the directional albedo: albedo() sums the attenuations A_p (M_p and N_p
    // are normalised), sample() draws directions and returns f cos / pdf. Six z-tests (three
    // directions, two fibres) at a 1% family-wise level.
    const double z = two_sided_z(sidak(0.01, 6));
    for (const char* xml :
         {R"(<bsdf type="hair"/>)", R"(<bsdf type="hair"><float name="eumelanin" value="0.3"/><float name="pheomelanin" value="0.1"/>
                                                        <float name="longitudinal_roughness" value="0.2"/><float name="scale_tilt" value="4"/></bsdf>)"}) {
        BSDFUnderTest t = make_bsdf(xml);
        for (float c : {0.9f, 0.3f, -0.5f}) {
            SurfaceInteraction si = local_interaction(direction(c, 1.3f));
            SamplingCheck check = check_sampling(*t.bsdf, si, BSDFContext(), 200000, {}, 61);
            double closed = average(t.bsdf->albedo(si));
            INFO(xml << " cos " << c << ": sum A_p " << closed << ", sampled " << check.albedo.mean << " +- " << check.albedo.std_error);
            CHECK(std::abs(check.albedo.mean - closed) <= z * check.albedo.std_error + 1e-6);
            CHECK(check.albedo.std_error < 0.01 * closed);  // power: a 3% error would show
        }
    }
    BSDFUnderTest clear = make_bsdf(R"(<bsdf type="hair"><rgb name="sigma_a" value="0"/></bsdf>)");
    for (float c : {0.99f, 0.5f, 0.01f, -0.7f})
        CHECK(max_abs_component(clear.bsdf->albedo(local_interaction(direction(c, 0.4f))) - Spectrum(1.0f)) < 1e-6f);
}

TEST_CASE("new BSDFs: bad parameters are errors", "[bsdf][errors]") {
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="principled"><float name="eta" value="1.5"/><float name="specular" value="0.5"/></bsdf>)"),
                      Catch::Contains("either eta or specular"));
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="hair"><rgb name="sigma_a" value="1"/><float name="eumelanin" value="0.5"/></bsdf>)"),
                      Catch::Contains("not both"));
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="hair"><float name="azimuthal_roughness" value="1.5"/></bsdf>)"), Catch::Contains("[0, 1]"));
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="blendbsdf"><bsdf type="diffuse"/></bsdf>)"), Catch::Contains("exactly two"));
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="mask"><float name="opacity" value="0.5"/></bsdf>)"), Catch::Contains("exactly one"));
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="twosided"><bsdf type="mask"><bsdf type="diffuse"/></bsdf></bsdf>)"),
                      Catch::Contains("inside it"));
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="roughconductor"><float name="alpha_u" value="0.1"/></bsdf>)"),
                      Catch::Contains("both alpha_u and alpha_v"));
    // alpha = 0 is accepted (raised to 1e-4, as Mitsuba does: tests/integrators/test_robustness.cpp).
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="roughconductor"><float name="alpha" value="-0.1"/></bsdf>)"),
                      Catch::Contains("must not be negative"));
    CHECK_THROWS_WITH(make_bsdf(R"(<bsdf type="roughplastic"><float name="alpha" value="-0.1"/></bsdf>)"),
                      Catch::Contains("must not be negative"));
    CHECK_THROWS_WITH(
        make_bsdf(R"(<bsdf type="principledthin"><float name="spec_trans" value="0.5"/><float name="metallic" value="0.5"/></bsdf>)"),
        Catch::Contains("metallic"));  // not a parameter of the thin BSDF
}
