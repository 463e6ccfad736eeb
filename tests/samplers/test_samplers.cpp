// Samplers: every one is uniform (chi-square over the unit square and the 2D projections of its
// first dimensions), keeps the stratification it promises, renders the same image bit for bit
// with any number of threads, and reads its parameters as Mitsuba (or pbrt-v4) does.

#include "analysis/statistics.h"
#include "core/error.h"
#include "core/properties.h"
#include "core/registry.h"
#include "core/sampler.h"
#include "core/warning.h"
#include "core/xml.h"
#include "samplers/sequences.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <set>

using namespace candela;
using namespace candela::test;

namespace {

const std::vector<std::string> AllSamplers = {"independent", "stratified", "multijitter", "orthogonal", "ldsampler", "sobol", "zsobol"};

Ref<Sampler> make_sampler(const std::string& name, int spp, const Vec2i& film, uint64_t seed = 7) {
    Properties props(name, SourceLocation{});
    props.set_int("sample_count", spp);
    props.set_int("seed", int64_t(seed));
    Ref<Sampler> s = create_plugin_as<Sampler>(ObjectKind::Sampler, props);
    s->set_film(film, 0);
    return s;
}

// The first dimensions of one sample, drawn as a path draws them: a mix of 1D and 2D calls.
constexpr int Dims = 10;
std::array<float, Dims> draw(Sampler& s, const Vec2i& pixel, uint32_t index) {
    s.start(pixel, index);
    std::array<float, Dims> v{};
    Vec2 a = s.next_2d();
    v[0] = a.x, v[1] = a.y;
    v[2] = s.next_1d();
    Vec2 b = s.next_2d();
    v[3] = b.x, v[4] = b.y;
    v[5] = s.next_1d();
    v[6] = s.next_1d();
    Vec2 c = s.next_2d();
    v[7] = c.x, v[8] = c.y;
    v[9] = s.next_1d();
    return v;
}

int cell(float v, int n) { return std::min(n - 1, int(v * float(n))); }

// Whether the points (pairs in [0,1)^2) have exactly one point in every elementary interval of
// area 1/N (N points, a power of two): the (0, m, 2)-net property.
bool is_02_net(const std::vector<Vec2>& points) {
    const int n = int(points.size());
    int m = 0;
    while ((1 << m) < n) ++m;
    for (int a = 0; a <= m; ++a) {
        int nx = 1 << a, ny = 1 << (m - a);
        std::vector<int> count(size_t(n), 0);
        for (const Vec2& p : points)
            if (++count[size_t(cell(p.y, ny) * nx + cell(p.x, nx))] > 1) return false;
    }
    return true;
}

// Whether the values have one value in each of `n` equal strata.
bool one_per_stratum(const std::vector<float>& values, int n) {
    std::set<int> seen;
    for (float v : values) seen.insert(cell(v, n));
    return int(values.size()) == n && int(seen.size()) == n;
}

std::string scene_with_sampler(const std::string& sampler) {
    std::string scene = read_text(source_path("scenes/validation/cbox.xml"));
    const std::string from = "<sampler type=\"independent\">", to = "</sampler>";
    size_t a = scene.find(from), b = scene.find(to, a);
    return scene.substr(0, a) + sampler + scene.substr(b + to.size());
}

}  // namespace

// 7 samplers x (45 pairs of the first 10 dimensions + the 10 single dimensions) chi-square tests
// at a family-wise level of 1% (Sidak). Each 2D test has 4096 points (16 x 16 pixels, 16 samples)
// in 8 x 8 cells, 64 expected per cell. Power: a pair of dimensions whose density is 25% too high
// over a quarter of the square (and correspondingly low elsewhere) has a noncentrality of
// 4096 * (16 * 0.25^2 + 48 * 0.083^2) / 64 = 85 on 63 dof and is rejected with probability about
// 0.9 at this level; identical or mirrored dimensions give chi2 in the thousands. 1D tests use 64
// strata.
TEST_CASE("samplers: uniform over the unit square and every 2D projection of the first dimensions", "[sampler][statistics]") {
    const Vec2i film(16, 16);
    const int spp = 16, bins = 8;
    const int tests = int(AllSamplers.size()) * (Dims * (Dims - 1) / 2 + Dims);
    const double level = sidak(0.01, tests);
    for (const std::string& name : AllSamplers) {
        Ref<Sampler> s = make_sampler(name, spp, film);
        std::vector<std::array<float, Dims>> points;
        for (int y = 0; y < film.y; ++y)
            for (int x = 0; x < film.x; ++x)
                for (int i = 0; i < s->sample_count(); ++i) points.push_back(draw(*s, Vec2i(x, y), uint32_t(i)));
        for (int d0 = 0; d0 < Dims; ++d0) {
            std::vector<double> observed(64, 0.0);
            for (const auto& p : points) {
                REQUIRE(p[size_t(d0)] >= 0.0f);
                REQUIRE(p[size_t(d0)] < 1.0f);
                observed[size_t(cell(p[size_t(d0)], 64))] += 1;
            }
            ChiSquareResult r = chi_square(observed, std::vector<double>(64, double(points.size()) / 64));
            INFO(name << " dimension " << d0 << ": chi2 " << r.chi2 << " dof " << r.dof);
            CHECK(r.p_value > level);
            for (int d1 = d0 + 1; d1 < Dims; ++d1) {
                std::vector<double> observed2(size_t(bins * bins), 0.0);
                for (const auto& p : points) observed2[size_t(cell(p[size_t(d1)], bins) * bins + cell(p[size_t(d0)], bins))] += 1;
                ChiSquareResult r2 = chi_square(observed2, std::vector<double>(size_t(bins * bins), double(points.size()) / (bins * bins)));
                INFO(name << " dimensions " << d0 << ", " << d1 << ": chi2 " << r2.chi2 << " dof " << r2.dof);
                CHECK(r2.p_value > level);
            }
        }
    }
}

TEST_CASE("samplers: stratified puts one sample in every stratum of each dimension, or at its centre without jitter", "[sampler]") {
    for (bool jitter : {true, false}) {
        Properties props("stratified", SourceLocation{});
        props.set_int("sample_count", 16);
        props.set_bool("jitter", jitter);
        Ref<Sampler> s = create_plugin_as<Sampler>(ObjectKind::Sampler, props);
        s->set_film(Vec2i(128), 0);
        for (Vec2i pixel : {Vec2i(0, 0), Vec2i(5, 3), Vec2i(100, 7)}) {
            std::vector<std::vector<float>> dims(Dims);
            std::vector<std::vector<Vec2>> pairs(3);
            for (uint32_t i = 0; i < 16; ++i) {
                auto v = draw(*s, pixel, i);
                for (int d = 0; d < Dims; ++d) dims[size_t(d)].push_back(v[size_t(d)]);
                pairs[0].push_back({v[0], v[1]}), pairs[1].push_back({v[3], v[4]}), pairs[2].push_back({v[7], v[8]});
            }
            for (int d : {2, 5, 6, 9}) {
                CHECK(one_per_stratum(dims[size_t(d)], 16));
                if (!jitter)
                    for (float v : dims[size_t(d)]) CHECK(std::fmod(v * 16.0f, 1.0f) == Approx(0.5f));
            }
            for (const auto& p : pairs) {
                std::set<int> cells;
                for (const Vec2& q : p) {
                    cells.insert(cell(q.y, 4) * 4 + cell(q.x, 4));
                    if (!jitter) CHECK(std::fmod(q.x * 4.0f, 1.0f) == Approx(0.5f));
                }
                CHECK(cells.size() == 16);
            }
        }
    }
}

TEST_CASE("samplers: multijitter stratifies each 2D dimension in its grid and in N strata along each axis", "[sampler]") {
    Ref<Sampler> s = make_sampler("multijitter", 12, Vec2i(8));  // 3 rows x 4 columns
    REQUIRE(s->sample_count() == 12);
    for (Vec2i pixel : {Vec2i(0, 0), Vec2i(3, 6)}) {
        std::vector<std::vector<float>> dims(Dims);
        for (uint32_t i = 0; i < 12; ++i) {
            auto v = draw(*s, pixel, i);
            for (int d = 0; d < Dims; ++d) dims[size_t(d)].push_back(v[size_t(d)]);
        }
        for (int d = 0; d < Dims; ++d) CHECK(one_per_stratum(dims[size_t(d)], 12));
        for (int d : {0, 3, 7}) {
            std::set<int> cells;
            for (int i = 0; i < 12; ++i) cells.insert(cell(dims[size_t(d + 1)][size_t(i)], 3) * 4 + cell(dims[size_t(d)][size_t(i)], 4));
            CHECK(cells.size() == 12);
        }
    }
}

TEST_CASE("samplers: orthogonal (strength 2) stratifies every pair of its p + 1 columns in p x p cells and each dimension in p^2 strata",
          "[sampler]") {
    Ref<Sampler> s = make_sampler("orthogonal", 25, Vec2i(8));  // p = 5: 6 distinct columns
    REQUIRE(s->sample_count() == 25);
    for (Vec2i pixel : {Vec2i(0, 0), Vec2i(7, 2)}) {
        std::vector<std::vector<float>> dims(6);
        for (uint32_t i = 0; i < 25; ++i) {
            s->start(pixel, i);
            for (auto& d : dims) d.push_back(s->next_1d());
        }
        for (size_t a = 0; a < dims.size(); ++a) {
            CHECK(one_per_stratum(dims[a], 25));
            for (size_t b = a + 1; b < dims.size(); ++b) {
                std::set<int> cells;
                for (int i = 0; i < 25; ++i) cells.insert(cell(dims[b][size_t(i)], 5) * 5 + cell(dims[a][size_t(i)], 5));
                INFO("columns " << a << ", " << b);
                CHECK(cells.size() == 25);
            }
        }
    }
}

TEST_CASE("samplers: ldsampler's 2D dimensions are (0, m, 2)-nets and its 1D dimensions stratified", "[sampler]") {
    for (int spp : {4, 16, 64}) {
        Ref<Sampler> s = make_sampler("ldsampler", spp, Vec2i(8));
        REQUIRE(s->sample_count() == spp);
        std::vector<std::vector<float>> dims(Dims);
        for (uint32_t i = 0; i < uint32_t(spp); ++i) {
            auto v = draw(*s, Vec2i(3, 5), i);
            for (int d = 0; d < Dims; ++d) dims[size_t(d)].push_back(v[size_t(d)]);
        }
        for (int d : {2, 5, 6, 9}) CHECK(one_per_stratum(dims[size_t(d)], spp));
        for (int d : {0, 3, 7}) {
            std::vector<Vec2> pts;
            for (int i = 0; i < spp; ++i) pts.push_back({dims[size_t(d)][size_t(i)], dims[size_t(d + 1)][size_t(i)]});
            INFO("spp " << spp << " dimension " << d);
            CHECK(is_02_net(pts));
        }
    }
}

TEST_CASE("samplers: the first two Sobol' dimensions form a (0, 2)-sequence", "[sampler]") {
    // Every block of 2^m points starting at a multiple of 2^m is a (0, m, 2)-net.
    for (int m = 0; m <= 10; ++m)
        for (uint64_t block : {0ull, 1ull, 5ull, 1000ull}) {
            std::vector<Vec2> pts;
            for (uint64_t i = block << m; i < (block + 1) << m; ++i)
                pts.push_back({bits_to_unit(sobol_bits(i, 0)), bits_to_unit(sobol_bits(i, 1))});
            INFO("m " << m << " block " << block);
            CHECK(is_02_net(pts));
        }
    // Owen scrambling keeps it.
    std::vector<Vec2> pts;
    for (uint64_t i = 0; i < 256; ++i)
        pts.push_back({bits_to_unit(owen_scramble(sobol_bits(i, 0), 17)), bits_to_unit(owen_scramble(sobol_bits(i, 1), 99))});
    CHECK(is_02_net(pts));
}

TEST_CASE("samplers: Divisor's quotient and remainder are the division's for every 32-bit numerator", "[sampler]") {
    PCG32 rng;
    std::vector<uint32_t> divisors = {1,   2,     3,     5,     6,           7,           36,          100,
                                      121, 32771, 65535, 65536, 0x7fffffffu, 0x80000001u, 0xfffffffeu, 0xffffffffu};
    for (int k = 0; k < 200; ++k) divisors.push_back(1 + (rng.next_uint() >> (k % 32)));
    for (uint32_t n : divisors) {
        const Divisor d(n);
        std::vector<uint32_t> numerators = {0, 1, n - 1, n, n + 1, 0x7fffffffu, 0x80000000u, 0xfffffffeu, 0xffffffffu, 0xffffffffu - n};
        for (int k = 0; k < 2000; ++k) numerators.push_back(rng.next_uint() >> (k % 32));
        for (uint32_t x : numerators) {
            INFO(x << " / " << n);
            REQUIRE(d.quotient(x) == x / n);
            REQUIRE(d.remainder(x) == x % n);
        }
    }
}

TEST_CASE("samplers: the reversed Sobol' matrices give the reversed digits", "[sampler]") {
    PCG32 rng;
    for (int dim : {0, 1, 2, 17, 256}) {
        for (int k = 0; k < 1000; ++k) {
            uint64_t index = (uint64_t(rng.next_uint()) << 32 | rng.next_uint()) >> (k % 40);
            REQUIRE(sobol_bits_reversed(index, dim) == reverse_bits(sobol_bits(index, dim)));
        }
    }
}

TEST_CASE("samplers: Sobol' dimension 1 from its byte tables is the generator matrix's XOR", "[sampler]") {
    // Indices below 2^32 take the byte tables; the matrix's columns of the set bits are the definition.
    PCG32 rng;
    std::vector<uint64_t> indices = {0, 1, 255, 256, 65535, 65536, 0xffffffffu, uint64_t(1) << 32, (uint64_t(1) << 32) + 5};
    for (int k = 0; k < 2000; ++k) indices.push_back(uint64_t(rng.next_uint()) >> (k % 32));
    const uint32_t* columns = sobol_matrix(1);
    for (uint64_t index : indices) {
        uint32_t expected = 0;
        for (int j = 0; j < 52; ++j)
            if ((index >> j) & 1u) expected ^= columns[j];
        INFO(index);
        REQUIRE(sobol_bits(index, 1) == expected);
        REQUIRE(sobol_bits_reversed(index, 1) == reverse_bits(expected));
    }
}

TEST_CASE("samplers: sobol's samples in a pixel are a (0, m, 2)-net over the pixel, zsobol's in every 2D dimension", "[sampler]") {
    for (int spp : {8, 16, 64}) {
        for (Vec2i pixel : {Vec2i(0, 0), Vec2i(13, 2), Vec2i(19, 30)}) {
            Ref<Sampler> sobol = make_sampler("sobol", spp, Vec2i(20, 32));
            Ref<Sampler> zsobol = make_sampler("zsobol", spp, Vec2i(20, 32));
            std::vector<Vec2> in_pixel;
            std::vector<std::vector<Vec2>> z(3);
            for (uint32_t i = 0; i < uint32_t(spp); ++i) {
                sobol->start(pixel, i);
                in_pixel.push_back(sobol->next_2d());
                auto v = draw(*zsobol, pixel, i);
                z[0].push_back({v[0], v[1]}), z[1].push_back({v[3], v[4]}), z[2].push_back({v[7], v[8]});
            }
            INFO("spp " << spp << " pixel " << pixel.x << ", " << pixel.y);
            CHECK(is_02_net(in_pixel));
            for (const auto& p : z) CHECK(is_02_net(p));
        }
    }
}

TEST_CASE("samplers: a sample's numbers depend only on (seed, pixel, index), and the render not on the thread count",
          "[sampler][determinism]") {
    auto dir = scratch_dir("sampler-threads");
    for (const std::string& name : AllSamplers) {
        INFO(name);
        // Out of order and repeated starts give the same numbers.
        Ref<Sampler> s = make_sampler(name, 16, Vec2i(16));
        auto first = draw(*s, Vec2i(4, 9), 5);
        draw(*s, Vec2i(2, 1), 11);
        CHECK(draw(*s, Vec2i(4, 9), 5) == first);
        Ref<Sampler> copy = s->clone();
        CHECK(draw(*copy, Vec2i(4, 9), 5) == first);
        // Another seed changes them.
        Ref<Sampler> other = make_sampler(name, 16, Vec2i(16), 8);
        CHECK(draw(*other, Vec2i(4, 9), 5) != first);
        // What a sampler keeps for the pixel's other samples follows a new seed, count or film on
        // the same pixel (the pixel loop's samplers are reseeded and resized in place).
        s->set_seed(8);
        CHECK(draw(*s, Vec2i(4, 9), 5) == draw(*other, Vec2i(4, 9), 5));
        s->set_seed(7);
        s->set_sample_count(64);
        CHECK(draw(*s, Vec2i(4, 9), 5) == draw(*make_sampler(name, 64, Vec2i(16)), Vec2i(4, 9), 5));
        s->set_film(Vec2i(40, 24), 0);
        CHECK(draw(*s, Vec2i(4, 9), 5) == draw(*make_sampler(name, 64, Vec2i(40, 24)), Vec2i(4, 9), 5));
        // Dimensions beyond the kept ones (64) and beyond the Sobol' table (257) as well.
        for (uint32_t dim : {60u, 70u, 300u}) {
            Ref<Sampler> fresh = make_sampler(name, 64, Vec2i(40, 24));
            draw(*s, Vec2i(4, 9), 6);
            s->set_dimension(dim);
            draw(*fresh, Vec2i(4, 9), 6);
            fresh->set_dimension(dim);
            CHECK(s->next_2d() == fresh->next_2d());
            CHECK(s->next_1d() == fresh->next_1d());
        }

        write_text(dir / "scene.xml",
                   scene_with_sampler("<sampler type=\"" + name + "\"><integer name=\"sample_count\" value=\"16\"/></sampler>"));
        RenderResult one = render_file((dir / "scene.xml").string(), {{"res", "24"}}, 1);
        RenderResult three = render_file((dir / "scene.xml").string(), {{"res", "24"}}, 3);
        REQUIRE(one.image.data().size() == three.image.data().size());
        CHECK(std::memcmp(one.image.data().data(), three.image.data().data(), one.image.data().size() * sizeof(float)) == 0);
    }
}

TEST_CASE("samplers: skip_1d passes over one number and leaves every later number as drawing it would", "[sampler][determinism]") {
    // The path integrator skips the lobe choice of a one-lobe BSDF and the light choice of a
    // one-light scene; its images must not change by it.
    for (const std::string& name : AllSamplers) {
        INFO(name);
        Ref<Sampler> drawn = make_sampler(name, 16, Vec2i(16)), skipped = make_sampler(name, 16, Vec2i(16));
        for (uint32_t index : {0u, 5u, 15u}) {
            drawn->start(Vec2i(3, 12), index);
            skipped->start(Vec2i(3, 12), index);
            for (uint32_t start : {0u, 7u, 70u}) {
                drawn->set_dimension(start);
                skipped->set_dimension(start);
                drawn->next_2d();
                skipped->next_2d();
                drawn->next_1d();
                skipped->skip_1d();
                CHECK(drawn->dimension() == skipped->dimension());
                CHECK(drawn->next_2d() == skipped->next_2d());
                CHECK(drawn->next_1d() == skipped->next_1d());
            }
        }
    }
}

TEST_CASE("samplers: restore() continues a saved sample bit for bit, with other samples drawn in between", "[sampler][determinism]") {
    // A wavefront advances many samples in turn through one sampler: each lane saves where its
    // sample stands and restores it before its next numbers (as bench_floor's generic wave does).
    for (const std::string& name : AllSamplers) {
        INFO(name);
        Ref<Sampler> s = make_sampler(name, 16, Vec2i(16));
        const auto a = draw(*s, Vec2i(4, 9), 5), b = draw(*s, Vec2i(11, 2), 15);
        // The two samples drawn in turn, saved and restored between every call (draw()'s order).
        SamplerState state_a, state_b;
        s->start(Vec2i(4, 9), 5);
        s->save(state_a);
        s->start(Vec2i(11, 2), 15);
        s->save(state_b);
        std::array<float, Dims> got_a{}, got_b{};
        auto step = [&](SamplerState& state, std::array<float, Dims>& got, int k) {
            s->restore(state);
            if (k == 0 || k == 3 || k == 7) {
                Vec2 v = s->next_2d();
                got[size_t(k)] = v.x, got[size_t(k) + 1] = v.y;
            } else {
                got[size_t(k)] = s->next_1d();
            }
            s->save(state);
        };
        for (int k : {0, 2, 3, 5, 6, 7, 9}) {
            step(state_a, got_a, k);
            step(state_b, got_b, k);
        }
        CHECK(got_a == a);
        CHECK(got_b == b);
        // A clone restores what another sampler saved, and a restored sample goes on at any
        // dimension (the path's layout jumps), beyond the kept ones too.
        for (uint32_t dim : {3u, 70u, 300u}) {
            Ref<Sampler> copy = s->clone();
            Ref<Sampler> fresh = make_sampler(name, 16, Vec2i(16));
            fresh->start(Vec2i(4, 9), 5);
            s->start(Vec2i(4, 9), 5);
            s->next_2d();
            s->save(state_a);
            fresh->next_2d();
            copy->restore(state_a);
            CHECK(copy->dimension() == fresh->dimension());
            copy->set_dimension(dim);
            fresh->set_dimension(dim);
            CHECK(copy->next_2d() == fresh->next_2d());
            CHECK(copy->next_1d() == fresh->next_1d());
        }
    }
}

TEST_CASE("samplers: sample counts round as Mitsuba (pbrt-v4 for sobol and zsobol) does, with a warning at the sampler", "[sampler]") {
    struct Case {
        std::string xml;
        int rounded;
    };
    const std::vector<Case> cases = {
        {R"(<sampler type="stratified"><integer name="sample_count" value="5"/><boolean name="jitter" value="false"/><integer name="seed" value="3"/></sampler>)",
         9},
        {R"(<sampler type="multijitter"><integer name="sample_count" value="5"/><boolean name="jitter" value="true"/></sampler>)", 6},
        {R"(<sampler type="orthogonal"><integer name="sample_count" value="16"/><integer name="strength" value="2"/></sampler>)", 25},
        {R"(<sampler type="ldsampler"><integer name="sample_count" value="17"/></sampler>)", 64},
        {R"(<sampler type="sobol"><integer name="sample_count" value="9"/><string name="randomization" value="permutedigits"/></sampler>)",
         16},
        {R"(<sampler type="zsobol"><integer name="sample_count" value="33"/></sampler>)", 64},
        {R"(<sampler type="stratified"><integer name="sample_count" value="4"/></sampler>)", 4},
    };
    auto dir = scratch_dir("sampler-rounding");
    for (const Case& c : cases) {
        INFO(c.xml);
        std::vector<std::string> warnings;
        WarningSink previous = set_warning_sink([&](const std::string& line) { warnings.push_back(line); });
        write_text(dir / "scene.xml", scene_with_sampler(c.xml));
        Ref<Scene> scene = load_scene((dir / "scene.xml").string(), {{"res", "8"}});
        set_warning_sink(previous);
        CHECK(scene->sensor().sampler().sample_count() == c.rounded);
        if (c.xml.find("value=\"" + std::to_string(c.rounded) + "\"") == std::string::npos) {
            REQUIRE(warnings.size() == 1);
            CHECK_THAT(warnings[0], Catch::Contains("scene.xml:") && Catch::Contains("rounded up to " + std::to_string(c.rounded)));
        } else {
            CHECK(warnings.empty());
        }
    }
}

TEST_CASE("samplers: bad parameters name the file and line", "[sampler][errors]") {
    auto dir = scratch_dir("sampler-errors");
    struct Case {
        std::string xml;
        const char* message;
    };
    const std::vector<Case> cases = {
        {"<sampler type=\"stratified\"><float name=\"jitter\" value=\"1\"/></sampler>", "has type float, expected boolean"},
        {"<sampler type=\"ldsampler\"><boolean name=\"jitter\" value=\"true\"/></sampler>", "unused property \"jitter\""},
        {"<sampler type=\"orthogonal\"><integer name=\"strength\" value=\"1\"/></sampler>", "strength must be at least 2"},
        {"<sampler type=\"multijitter\"><integer name=\"sample_count\" value=\"0\"/></sampler>", "sample count must be at least 1 (got 0)"},
        {"<sampler type=\"stratified\"><integer name=\"sample_count\" value=\"1073741825\"/></sampler>",
         "sample count must be at most 2^30 = 1073741824 (got 1073741825)"},
        {"<sampler type=\"sobol\"><integer name=\"sample_count\" value=\"4294967297\"/></sampler>",
         "sample_count = 4294967297 lies beyond the integers Candela reads"},
        {"<sampler type=\"independent\"><integer name=\"sample_count\" value=\"-3\"/></sampler>",
         "sample count must be at least 1 (got -3)"},
        {"<sampler type=\"sobol\"><string name=\"randomization\" value=\"fast\"/></sampler>", "unknown randomization \"fast\""},
        {"<sampler type=\"halton\"/>", "unknown sampler type \"halton\""},
    };
    for (const Case& c : cases) {
        INFO(c.xml);
        write_text(dir / "scene.xml", scene_with_sampler(c.xml));
        CHECK_THROWS_WITH(load_scene((dir / "scene.xml").string()), Catch::Contains("scene.xml:") && Catch::Contains(c.message));
    }
}

TEST_CASE("samplers: start() checks its contract: an index below the count, a pixel inside the film and its sampled border", "[sampler]") {
    // Before issue 28 an index at the count walked a permutation's cycle forever (stratified,
    // multijitter, orthogonal, ldsampler) and a pixel left of the film shifted bits past sobol's
    // tables.
    for (const std::string& name : AllSamplers) {
        INFO(name);
        Ref<Sampler> s = make_sampler(name, 9, Vec2i(16, 8));
        s->set_film(Vec2i(16, 8), 2);
        const uint32_t n = uint32_t(s->sample_count());
        CHECK_NOTHROW(s->start(Vec2i(-2, -2), n - 1));
        CHECK_NOTHROW(s->start(Vec2i(17, 9), 0));
        CHECK_THROWS_AS(s->start(Vec2i(0, 0), n), InternalError);
        CHECK_THROWS_AS(s->start(Vec2i(-3, 0), 0), InternalError);
        CHECK_THROWS_AS(s->start(Vec2i(0, 10), 0), InternalError);
        CHECK_THROWS_WITH(s->start(Vec2i(18, 0), 0), Catch::Contains(name + " sampler asked for sample 0 of pixel (18, 0)"));
    }
}

TEST_CASE("samplers: sobol and zsobol give every pixel of a 2^m film and its sampled border a part of the sequence of its own",
          "[sampler]") {
    // A film exactly 2^m wide is where the ring's pixels (x = -1, x = 2^m) fell outside the
    // sequence's square: sobol read past its table (ASan: heap-buffer-overflow) and zsobol's
    // Morton codes of negative coordinates aliased other pixels'.
    for (const std::string& name : {std::string("sobol"), std::string("zsobol")})
        for (int border : {1, 3}) {
            INFO(name << ", border " << border);
            Ref<Sampler> s = make_sampler(name, 4, Vec2i(16));
            s->set_film(Vec2i(16), border);
            std::set<std::pair<float, float>> first_points;
            int pixels = 0;
            for (int y = -border; y < 16 + border; ++y)
                for (int x = -border; x < 16 + border; ++x, ++pixels) {
                    s->start(Vec2i(x, y), 0);
                    s->set_dimension(2);  // dimensions 2 and 3: the sequence's own, not the pixel's position
                    const Vec2 u = s->next_2d();
                    CHECK(u.x >= 0.0f);
                    CHECK(u.x < 1.0f);
                    first_points.insert({u.x, u.y});
                }
            CHECK(int(first_points.size()) == pixels);
        }
}
