// sggx, the SGGX microflake phase function (media/sggx.cpp), and what media do with it.
//   - Chi-square: directions drawn by sample() against pdf() integrated over the cells of a
//     10 x 20 spherical grid, for four matrices S (identity, diagonal, a skewed one with all six
//     entries, and a flat "surface-like" one) at an oblique incident direction.
//   - Deterministic: each sample's pdf equals pdf(wi, wo), its weight is 1, eval = pdf.
//   - Normalisation: the Monte Carlo integral of p over the sphere (uniform directions) is 1
//     (z-test). The flat S is too peaked for uniform directions to estimate with power: its
//     normalisation is the chi-square's (expected counts come from the pdf's integrals).
//   - S = identity is the isotropic phase function with projected area 1; the projected area is
//     sqrt(w^T S w); microflake reciprocity sigma(wi) p(wi, wo) = sigma(wo) p(wo, wi) (Heitz et
//     al. 2015, eq. 6), while p alone is not symmetric.
//   - A 6-channel gridvolume gives S as the constvolume with the same six numbers does.
//   - Media: extinction is sigma_t sqrt(d^T S d): volpath's Beer-Lambert image through an
//     absorbing slab (homogeneous with a constant S: closed form; heterogeneous with a grid S:
//     the trace bound as majorant, null collisions), each compared with the closed form.
//   - A scattering scene with S = identity renders as the isotropic medium (block z-tests), and
//     one with a skewed grid S renders finite.
//   - Errors: no S, S of three channels, a constant S that is not positive definite, a 6-channel
//     volume where a colour is meant, and a blendphase with an sggx part.
// All statistical checks together keep a 1% family-wise level (Sidak over the count below).

#include "core/medium.h"
#include "core/phase.h"
#include "core/registry.h"
#include "core/rng.h"
#include "core/scene.h"
#include "core/volume.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/support/vol_writer.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

const char* const Identity = "1, 1, 1, 0, 0, 0";
const char* const Diagonal = "0.15, 1.0, 0.8, 0, 0, 0";
const char* const Skewed = "1.0, 0.35, 0.32, 0.52, 0.44, 0.2";
const char* const Flat = "0.05, 1.0, 0.05, 0.01, 0, 0.02";
const std::vector<const char*> Matrices = {Identity, Diagonal, Skewed, Flat};

// Statistical checks: chi-square 4, normalisation 3, the two media 2 x 3 channels x 2
// integrators, identity vs isotropic 3 x 17.
const double Alpha = sidak(0.01, 4 + 3 + 12 + 51);
const double Z = two_sided_z(Alpha);

Ref<Volume> constant_S(const std::string& values) {
    Properties props("constvolume", SourceLocation{"test", 1});
    props.set_string("value", values);
    return create_plugin_as<Volume>(ObjectKind::Volume, props);
}

Ref<PhaseFunction> make_sggx(const Ref<Volume>& S) {
    Properties props("sggx", SourceLocation{"test", 2});
    props.set_object("S", S, SourceLocation{"test", 3});
    return create_plugin_as<PhaseFunction>(ObjectKind::Phase, props);
}
Ref<PhaseFunction> make_sggx(const std::string& values) { return make_sggx(constant_S(values)); }

MediumInteraction at(const Vec3& wi) { return MediumInteraction{Vec3(0.0f), wi}; }

Vec3 uniform_direction(PCG32& rng) {
    float z = 1.0f - 2.0f * rng.next_float();
    return direction_around(Vec3(0.0f, 0.0f, 1.0f), z, TwoPi * rng.next_float());
}

std::vector<float> repeated(const std::vector<float>& six, int voxels) {
    std::vector<float> out;
    for (int i = 0; i < voxels; ++i) out.insert(out.end(), six.begin(), six.end());
    return out;
}

std::string film(int size, int spp) { return box_film(size, spp); }

RenderResult render_in(const std::filesystem::path& dir, const std::string& xml) {
    write_text(dir / "scene.xml", xml);
    Ref<Scene> scene = load_scene((dir / "scene.xml").string());
    return scene->integrator().render(*scene, RenderOptions());
}

}  // namespace

TEST_CASE("sggx: sampling matches pdf (chi-square) and is exact", "[phase][sggx][stats]") {
    const Vec3 wi = glm::normalize(Vec3(0.3f, -0.5f, 0.8f));
    const int n = 200000;
    for (const char* values : Matrices) {
        INFO("S = " << values);
        Ref<PhaseFunction> phase = make_sggx(values);
        PCG32 rng(7, 11);
        SphericalHistogram hist(10, 20);
        int inconsistent = 0;
        for (int i = 0; i < n; ++i) {
            PhaseSample ps = phase->sample(at(wi), Vec2(rng.next_float(), rng.next_float()));
            REQUIRE(ps.valid());
            float pdf = phase->pdf(at(wi), ps.wo), f = phase->eval(at(wi), ps.wo);
            if (std::abs(ps.pdf - pdf) > 1e-3f * pdf || ps.weight != 1.0f || f != pdf || std::abs(glm::length(ps.wo) - 1.0f) > 1e-4f)
                ++inconsistent;
            hist.add(ps.wo);
        }
        CHECK(inconsistent == 0);
        ChiSquareResult chi2 = chi_square(hist.counts, hist.expected([&](const Vec3& wo) { return double(phase->pdf(at(wi), wo)); }, n));
        INFO(chi2.details);
        CHECK(chi2.p_value > Alpha);
    }
}

TEST_CASE("sggx: the phase function integrates to one over the sphere", "[phase][sggx][stats]") {
    const Vec3 wi = glm::normalize(Vec3(-0.2f, 0.1f, 0.9f));
    const int n = 400000;
    for (const char* values : {Identity, Diagonal, Skewed}) {
        INFO("S = " << values);
        Ref<PhaseFunction> phase = make_sggx(values);
        PCG32 rng(3, 5);
        std::vector<double> v(n);
        for (int i = 0; i < n; ++i) v[size_t(i)] = double(phase->eval(at(wi), uniform_direction(rng))) * 4.0 * Pi;
        MeanAndError m = mean_and_error(v);
        INFO(m.mean << " +- " << m.std_error);
        // S = identity is constant: then only float rounding separates it from 1.
        CHECK(std::abs(m.mean - 1.0) < Z * m.std_error + 1e-5);
        CHECK(m.std_error < 0.01);  // power: a 4% error would be seen
    }
}

TEST_CASE("sggx: identity is isotropic, the projected area, microflake reciprocity", "[phase][sggx]") {
    PCG32 rng(1, 2);
    Ref<PhaseFunction> identity = make_sggx(Identity), skewed = make_sggx(Skewed), diagonal = make_sggx(Diagonal);
    CHECK(identity->is_microflake());
    int isotropic_misses = 0, reciprocity_misses = 0, asymmetric = 0;
    for (int i = 0; i < 1000; ++i) {
        Vec3 wi = uniform_direction(rng), wo = uniform_direction(rng);
        if (std::abs(identity->eval(at(wi), wo) - InvFourPi) > 1e-5f * InvFourPi) ++isotropic_misses;
        if (std::abs(identity->projected_area(at(wi)) - 1.0f) > 1e-5f) ++isotropic_misses;
        float forward = skewed->projected_area(at(wi)) * skewed->eval(at(wi), wo);
        float backward = skewed->projected_area(at(wo)) * skewed->eval(at(wo), wi);
        if (std::abs(forward - backward) > 1e-4f * std::max(forward, backward)) ++reciprocity_misses;
        if (std::abs(skewed->eval(at(wi), wo) - skewed->eval(at(wo), wi)) > 1e-3f * forward) ++asymmetric;
    }
    CHECK(isotropic_misses == 0);
    CHECK(reciprocity_misses == 0);
    CHECK(asymmetric > 100);  // p alone is not reciprocal: the check above can fail
    // sigma(w) = sqrt(w^T S w): along the axes, the diagonal's square roots.
    CHECK(diagonal->projected_area(at(Vec3(1, 0, 0))) == Approx(std::sqrt(0.15)));
    CHECK(diagonal->projected_area(at(Vec3(0, -1, 0))) == Approx(1.0));
    CHECK(diagonal->projected_area(at(Vec3(0, 0, 1))) == Approx(std::sqrt(0.8)));
    Vec3 w = glm::normalize(Vec3(1, 1, 1));
    CHECK(skewed->projected_area(at(w)) == Approx(std::sqrt((1.0 + 0.35 + 0.32 + 2 * (0.52 + 0.44 + 0.2)) / 3.0)));
    // A constant S bounds the majorant by its exact projected area along the ray.
    CHECK(diagonal->max_projected_area(Vec3(0, 0, 2)) == Approx(std::sqrt(0.8)));
}

TEST_CASE("sggx: a 6-channel gridvolume gives S as a constvolume does", "[phase][sggx][volume]") {
    auto dir = scratch_dir("sggx-grid");
    std::vector<float> six = {1.0f, 0.35f, 0.32f, 0.52f, 0.44f, 0.2f};
    write_vol(dir / "S.vol", glm::ivec3(2, 2, 2), 6, repeated(six, 8));
    Properties props("gridvolume", SourceLocation{"test", 1});
    props.set_string("filename", (dir / "S.vol").string());
    Ref<Volume> grid = create_plugin_as<Volume>(ObjectKind::Volume, props);
    REQUIRE(grid->channel_count() == 6);
    Ref<PhaseFunction> from_grid = make_sggx(grid), from_constant = make_sggx(Skewed);
    CHECK(from_grid->varies_in_space());
    CHECK_FALSE(from_constant->varies_in_space());
    PCG32 rng(9, 9);
    for (int i = 0; i < 100; ++i) {
        MediumInteraction mi{Vec3(rng.next_float(), rng.next_float(), rng.next_float()), uniform_direction(rng)};
        Vec3 wo = uniform_direction(rng);
        CHECK(from_grid->eval(mi, wo) == Approx(from_constant->eval(mi, wo)).epsilon(1e-4));
        CHECK(from_grid->projected_area(mi) == Approx(from_constant->projected_area(mi)).epsilon(1e-5));
    }
    // The trace bound covers every direction.
    CHECK(from_grid->max_projected_area(Vec3(1, 0, 0)) >= from_constant->max_projected_area(glm::normalize(Vec3(1, 1, 1))));
}

TEST_CASE("sggx: media take extinction sigma_t sqrt(d^T S d) (Beer-Lambert through a slab)", "[volpath][sggx][stats]") {
    // Looking down -z at an emitter of radiance (1, 2, 3) through a slab 1 thick of an absorbing
    // medium with sigma_t (0.5, 1, 2): along z the projected area is sqrt(S_zz) = 0.6.
    auto dir = scratch_dir("sggx-slab");
    std::vector<float> six = {0.25f, 1.0f, 0.36f, 0.1f, 0.05f, -0.2f};
    write_vol(dir / "S.vol", glm::ivec3(2, 2, 2), 6, repeated(six, 8));
    const std::string constant_S =
        R"(<volume type="constvolume" name="S"><string name="value" value="0.25, 1, 0.36, 0.1, 0.05, -0.2"/></volume>)";
    const std::string grid_S = R"(<volume type="gridvolume" name="S"><string name="filename" value="S.vol"/></volume>)";
    const std::string slab = R"(<transform name="to_world"><scale x="10" y="10" z="0.5"/><translate z="2"/></transform>)";
    struct Case {
        std::string name, medium;
    };
    const std::vector<Case> cases = {
        {"homogeneous, constant S", R"(<medium type="homogeneous" id="absorber"><rgb name="sigma_t" value="0.5, 1, 2"/>
            <float name="albedo" value="0"/><phase type="sggx">)" +
                                        constant_S + "</phase></medium>"},
        {"heterogeneous, grid S", R"(<medium type="heterogeneous" id="absorber"><volume type="constvolume" name="sigma_t">
            <rgb name="value" value="0.5, 1, 2"/><transform name="to_world"><scale x="20" y="20" z="1"/><translate x="-10" y="-10" z="1.5"/></transform></volume>
            <float name="albedo" value="0"/><phase type="sggx">)" +
                                      grid_S + "</phase></medium>"},
    };
    const Vec3 L(1.0f, 2.0f, 3.0f), sigma(0.5f, 1.0f, 2.0f);
    for (const Case& c : cases)
        for (const char* integrator : {"volpath", "volpathmis"}) {
            INFO(c.name << ", " << integrator);
            RenderResult r = render_in(dir, scene_xml(std::string(R"(<integrator type=")") + integrator + R"("/>
                <sensor type="orthographic"><transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>)" +
                                                      film(16, 64) + R"(</sensor>
                <shape type="rectangle"><transform name="to_world"><scale value="10"/></transform>
                    <emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter></shape>
                <shape type="cube">)" + slab + R"(<bsdf type="null"/><ref name="interior" id="absorber"/></shape>)" +
                                                      c.medium));
            for (int ch = 0; ch < 3; ++ch) {
                MeanAndError m = channel_mean(r.image, ch);
                double expected = L[ch] * std::exp(-double(sigma[ch]) * 0.6);
                INFO("channel " << ch << ": " << m.mean << " +- " << m.std_error << ", expected " << expected);
                CHECK(std::abs(m.mean - expected) < Z * m.std_error);
                CHECK(m.std_error < 0.03 * L[ch]);  // power: a 10% error would be seen
            }
        }
}

namespace {

// A ball of scattering medium over a floor, lit by an area light; `phase` is the medium's.
std::string scattering_scene(const std::string& phase, const std::string& medium_type = "homogeneous", int spp = 64) {
    return scene_xml(R"(<integrator type="volpath"/>
        <sensor type="perspective"><float name="fov" value="45"/>
            <transform name="to_world"><lookat origin="0, 1.5, 4" target="0, 0.5, 0" up="0, 1, 0"/></transform>)" +
                     film(32, spp) + R"(</sensor>
        <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.5, 0.4"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="2.5"/></transform>
            <emitter type="area"><rgb name="radiance" value="10"/></emitter></shape>
        <medium type=")" +
                     medium_type + R"(" id="fog"><rgb name="sigma_t" value="2, 3, 4"/><float name="albedo" value="0.9"/>)" + phase +
                     R"(</medium>
        <shape type="sphere"><point name="center" value="0, 0.6, 0"/><float name="radius" value="0.6"/><bsdf type="null"/>
            <ref name="interior" id="fog"/></shape>)");
}

}  // namespace

TEST_CASE("sggx: S = identity renders as the isotropic medium, a grid S renders finite", "[volpath][sggx][stats]") {
    auto dir = scratch_dir("sggx-render");
    Image iso = render_in(dir, scattering_scene(R"(<phase type="isotropic"/>)")).image;
    Image sggx =
        render_in(dir,
                  scattering_scene(std::string(R"(<phase type="sggx"><volume type="constvolume" name="S"><string name="value" value=")") +
                                   Identity + R"("/></volume></phase>)"))
            .image;
    std::string where;
    double z = largest_block_z(iso, sggx, &where);
    INFO(where);
    CHECK(z <= Z);
    // A skewed S that varies over a grid (two matrices), in a heterogeneous medium.
    std::vector<float> values = repeated({1.0f, 0.35f, 0.32f, 0.52f, 0.44f, 0.2f}, 4);
    std::vector<float> flat = repeated({0.05f, 1.0f, 0.05f, 0.01f, 0.0f, 0.02f}, 4);
    values.insert(values.end(), flat.begin(), flat.end());
    write_vol(dir / "S.vol", glm::ivec3(2, 2, 2), 6, values);
    Image grid =
        render_in(dir, scattering_scene(R"(<phase type="sggx"><volume type="gridvolume" name="S"><string name="filename" value="S.vol"/>
        <transform name="to_world"><scale value="1.2"/><translate x="-0.6" y="0" z="-0.6"/></transform></volume></phase>)",
                                        "homogeneous", 8))
            .image;
    double sum = 0.0;
    bool finite = true;
    for (int y = 0; y < grid.height(); ++y)
        for (int x = 0; x < grid.width(); ++x)
            for (int ch = 0; ch < 3; ++ch) {
                finite = finite && std::isfinite(grid.at(x, y, ch));
                sum += grid.at(x, y, ch);
            }
    CHECK(finite);
    CHECK(sum > 0.0);
}

TEST_CASE("sggx: bad S and misuse are errors at their line", "[phase][sggx][errors]") {
    CHECK_THROWS_WITH(create_plugin_as<PhaseFunction>(ObjectKind::Phase, Properties("sggx", SourceLocation{"test", 1})),
                      Catch::Contains("needs its matrix S"));
    CHECK_THROWS_WITH(make_sggx("1, 1, 1"), Catch::Contains("six values"));
    CHECK_THROWS_WITH(make_sggx("1, 1, 1, 2, 0, 0"), Catch::Contains("positive definite"));
    CHECK_THROWS_WITH(make_sggx("1, 1, 1, 0, 0"), Catch::Contains("1, 3 or 6"));
    // A 6-channel volume where a colour is meant.
    CHECK_THROWS_WITH(load_scene_xml("sggx-sigma", R"(<medium type="homogeneous" id="m"><volume type="constvolume" name="sigma_t">
        <string name="value" value="1, 1, 1, 0, 0, 0"/></volume></medium>)"),
                      Catch::Contains("six channels holds a matrix"));
    // A blend with a microflake part has no projected area to give the medium.
    Properties blend("blendphase", SourceLocation{"test", 4});
    blend.set_object("first", make_sggx(Identity), SourceLocation{"test", 5});
    blend.set_object("second", create_plugin_as<PhaseFunction>(ObjectKind::Phase, Properties("isotropic", SourceLocation{"test", 6})),
                     SourceLocation{"test", 6});
    CHECK_THROWS_WITH(create_plugin_as<PhaseFunction>(ObjectKind::Phase, blend), Catch::Contains("microflake"));
}
