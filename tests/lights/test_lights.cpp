// Lights: analytic irradiance through the estimators (with their own error bars), sampling of
// every emitter against its pdf (chi-square), the consistency MIS relies on, and the light
// tree's selection probabilities. The statistical tests here share a 1% family-wise level.

#include "core/rng.h"
#include "core/xml.h"
#include "integrators/estimators.h"
#include "lights/light_tree.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <functional>
#include <unordered_map>

using namespace candela;
using namespace candela::test;

namespace {

// The statistical tests of this file: 7 irradiance z-tests, 1 on the error bars' N^-1/2, 12
// emitter chi-squares and 2 solid-angle z-tests with 2 uv chi-squares, 5 + 3 light-tree chi-squares, 2 strategy z-tests.
constexpr int LightTests = 34;
const double Alpha = sidak(0.01, LightTests);

Ref<Scene> scene_from(const std::string& body) { return load_scene_xml("lights", body); }

void check_irradiance(const char* what, const std::string& body, Vec3 p, Vec3 n, double exact) {
    Ref<Scene> scene = scene_from(body);
    EstimatorOptions o;
    o.samples = 200000;
    o.seed = 3;
    Estimate e = estimate_irradiance(*scene, p, n, o);
    double z = two_sided_z(Alpha);
    INFO(what << ": " << e.mean.x << " +- " << e.std_error.x << " (95% [" << e.ci95_low().x << ", " << e.ci95_high().x << "]), exact "
              << exact);
    // Float32 evaluation allows a relative error of about 1e-5 where the estimator has no variance
    // (delta lights).
    CHECK(std::abs(e.mean.x - exact) <= z * e.std_error.x + 1e-5 * exact);
    CHECK(e.nonfinite == 0);
}

const char* Ground =
    R"(<shape type="rectangle"><transform name="to_world"><scale value="50"/><rotate x="1" angle="-90"/></transform></shape>)";

}  // namespace

TEST_CASE("irradiance: a point light gives I cos(theta) / r^2 (and the lecture's attenuation)", "[lights][estimate]") {
    double r2 = 1 + 4 + 1, cos_t = 2.0 / std::sqrt(r2);
    check_irradiance("point",
                     R"(<emitter type="point"><point name="position" x="1" y="2" z="-1"/><rgb name="intensity" value="5"/></emitter>)",
                     Vec3(0.0f), Vec3(0, 1, 0), 5.0 * cos_t / r2);
    double d = std::sqrt(r2);
    check_irradiance("attenuated point",
                     R"(<emitter type="point"><point name="position" x="1" y="2" z="-1"/><rgb name="intensity" value="5"/>
                        <float name="attenuation_constant" value="1"/><float name="attenuation_linear" value="0.5"/><float name="attenuation_quadratic" value="0.25"/></emitter>)",
                     Vec3(0.0f), Vec3(0, 1, 0), 5.0 * cos_t / (1 + 0.5 * d + 0.25 * r2));
}

TEST_CASE("irradiance: a directional light gives E cos(theta)", "[lights][estimate]") {
    Vec3 dir = glm::normalize(Vec3(1, -2, 0.5f));
    check_irradiance(
        "directional",
        R"(<emitter type="directional"><vector name="direction" x="1" y="-2" z="0.5"/><rgb name="irradiance" value="3"/></emitter>)",
        Vec3(0.3f, 0, 0.2f), Vec3(0, 1, 0), 3.0 * -dir.y);
}

TEST_CASE("irradiance: a uniform sky over an open plane gives pi L", "[lights][estimate]") {
    check_irradiance("sky", std::string(Ground) + R"(<emitter type="constant"><rgb name="radiance" value="0.7"/></emitter>)", Vec3(0.0f),
                     Vec3(0, 1, 0), 3.14159265358979 * 0.7);
}

TEST_CASE("irradiance: disk and sphere lights match their closed forms", "[lights][estimate]") {
    // A disk of radius R at height h, facing down, seen on its axis: E = pi L R^2 / (h^2 + R^2).
    check_irradiance(
        "disk",
        R"(<shape type="disk"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="1.5"/></transform>
                        <emitter type="area"><rgb name="radiance" value="3"/></emitter></shape>)",
        Vec3(0.0f), Vec3(0, 1, 0), 3.14159265358979 * 3 * 0.25 / (2.25 + 0.25));
    // A sphere of radius R at distance d, wholly above the horizon: E = pi L (R / d)^2 cos(theta).
    const char* sphere = R"(<shape type="sphere"><point name="center" x="1" y="2" z="0"/><float name="radius" value="0.3"/>
                            <emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>)";
    check_irradiance("sphere on axis", sphere, Vec3(1, 0, 0), Vec3(0, 1, 0), 3.14159265358979 * 2 * 0.09 / 4);
    check_irradiance("sphere off axis", sphere, Vec3(0.0f), Vec3(0, 1, 0), 3.14159265358979 * 2 * 0.09 / 5 * (2 / std::sqrt(5.0)));
}

TEST_CASE("irradiance: the error bars shrink as 1 / sqrt(N)", "[lights][estimate]") {
    Ref<Scene> scene = scene_from(std::string(Ground) + R"(<emitter type="constant"><rgb name="radiance" value="0.7"/></emitter>
        <shape type="sphere"><point name="center" x="0.5" y="0.6" z="0"/><float name="radius" value="0.4"/></shape>)");
    EstimatorOptions a, b;
    a.samples = 40000;
    b.samples = 160000;
    a.seed = 11;
    b.seed = 12;
    Estimate ea = estimate_irradiance(*scene, Vec3(0.0f), Vec3(0, 1, 0), a), eb = estimate_irradiance(*scene, Vec3(0.0f), Vec3(0, 1, 0), b);
    // sigma = SE sqrt(N) is the same quantity measured twice; the standard error of a sample
    // standard deviation is sigma sqrt((kurtosis - 1) / (4 N)).
    double sa = ea.luminance_std_error * std::sqrt(double(a.samples)), sb = eb.luminance_std_error * std::sqrt(double(b.samples));
    double kurt = 0.5 * (ea.luminance_kurtosis + eb.luminance_kurtosis);
    double se = 0.5 * (sa + sb) * std::sqrt((kurt - 1) / (4.0 * a.samples) + (kurt - 1) / (4.0 * b.samples));
    INFO("sigma " << sa << " vs " << sb << " (+- " << se << "), SE ratio " << eb.luminance_std_error / ea.luminance_std_error);
    CHECK(std::abs(sa - sb) <= two_sided_z(Alpha) * se);
    CHECK(eb.luminance_std_error < ea.luminance_std_error);
}

TEST_CASE("estimate: radiance along a ray sees emitters and the environment", "[lights][estimate]") {
    Ref<Scene> scene = scene_from(R"(<emitter type="constant"><rgb name="radiance" value="0.25, 0.5, 1"/></emitter>
        <shape type="rectangle"><transform name="to_world"><translate z="-3"/></transform><emitter type="area"><rgb name="radiance" value="4"/></emitter></shape>)");
    EstimatorOptions o;
    o.samples = 1000;
    Estimate sky = estimate_radiance(*scene, Vec3(0.0f), Vec3(0, 1, 0), o);
    CHECK(sky.mean == Spectrum(0.25f, 0.5f, 1.0f));
    Estimate lamp = estimate_radiance(*scene, Vec3(0.0f), Vec3(0, 0, -1), o);
    CHECK(lamp.mean.x == Approx(4.0f));
    Estimate back = estimate_radiance(*scene, Vec3(0, 0, -5), Vec3(0, 0, 1), o);  // the lamp's back: black
    CHECK(back.mean.x == Approx(0.0f));
}

namespace {

// The density (solid angle) with which `emitter` would produce direction w from ref, found the
// way the path tracer finds it: by tracing the direction.
double emitter_pdf(const Scene& scene, const Emitter& emitter, const SurfaceInteraction& ref, const Vec3& w) {
    DirectionSample ds;
    ds.d = w;
    if (emitter.is_infinite()) {
        ds.dist = Infinity;
        return emitter.pdf_direction(ref, ds);
    }
    SurfaceInteraction si;
    if (!scene.intersect(Ray(ref.p, w), si) || si.shape->emitter() != &emitter) return 0.0;
    ds.p = si.p;
    ds.n = si.n;
    ds.dist = glm::length(si.p - ref.p);
    return emitter.pdf_direction(ref, ds);
}

void check_emitter_sampling(const char* what, const std::string& body, Vec3 ref_p, uint64_t seed) {
    Ref<Scene> scene = scene_from(body);
    REQUIRE(scene->emitters().size() == 1);
    const Emitter& emitter = *scene->emitters()[0];
    SurfaceInteraction ref = virtual_vertex(*scene, ref_p, Vec3(0, 1, 0));
    // 1e6 directions (1e5 at the sanitizer run's CANDELA_TEST_EFFORT=0.1, tests/util.h: the same
    // significance, less power). Power, by the noncentral chi-square over the 200 bins: a pdf
    // off by 3% over a tenth of the sphere is found with probability about 1/2 at 1e6, by 9% at 1e5.
    const int n = effort_scaled(1000000, 100000);
    PCG32 rng(seed, 5);
    SphericalHistogram hist(10, 20);
    double failed = 0.0;
    int inconsistent = 0;
    for (int i = 0; i < n; ++i) {
        float a = rng.next_float();
        Spectrum weight;
        DirectionSample ds = emitter.sample_direction(ref, Vec2(a, rng.next_float()), weight);
        if (!(ds.pdf > 0.0f)) {
            failed += 1.0;
            continue;
        }
        hist.add(ds.d);
        // MIS consistency: tracing the sampled direction finds the same density.
        if (i % 50 == 0) {
            double traced = emitter_pdf(*scene, emitter, ref, ds.d);
            if (std::abs(traced - ds.pdf) > 1e-3 * ds.pdf) ++inconsistent;
        }
    }
    std::vector<double> expected = hist.expected([&](const Vec3& w) { return emitter_pdf(*scene, emitter, ref, w); }, n);
    std::vector<double> observed = hist.counts;
    double total = 0.0;
    for (double e : expected) total += e;
    observed.push_back(failed);
    expected.push_back(std::max(0.0, n - total));
    ChiSquareResult r = chi_square(observed, expected);
    INFO(what << ": " << r.details << "; traced pdf disagreed " << inconsistent << " times");
    CHECK(r.p_value > Alpha);
    CHECK(inconsistent == 0);
}

// The solid angle a shape's triangles subtend from p (Van Oosterom & Strackee 1983, per triangle:
// tan(omega / 2) = |a . (b x c)| / (abc + (a.b)c + (a.c)b + (b.c)a) for the corners' offsets).
double subtended_solid_angle(const Shape& shape, const Vec3& p) {
    TriangleSoup soup;
    shape.tessellate(soup, 0);
    double omega = 0.0;
    for (const glm::uvec3& t : soup.triangles) {
        glm::dvec3 a = glm::dvec3(soup.positions[t.x] - p), b = glm::dvec3(soup.positions[t.y] - p),
                   c = glm::dvec3(soup.positions[t.z] - p);
        double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
        double numerator = std::abs(glm::dot(a, glm::cross(b, c)));
        double denominator = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
        omega += 2.0 * std::atan2(numerator, denominator);
    }
    return omega;
}

// Lights too small for the direction histogram (the area-sampled branch of a far rectangle):
// the mean of 1 / pdf over the samples (0 for a failed one) must be the subtended solid angle
// (E_q[1 / p] = the solid angle where q > 0 when the reported p is the density q), within a
// z-interval from the samples' own standard error; the points must be uniform by area (a
// chi-square over the uv that tracing finds there, the rectangle's affine parameterisation); tracing finds the same pdf.
void check_small_emitter_sampling(const char* what, const std::string& body, Vec3 ref_p, uint64_t seed) {
    Ref<Scene> scene = scene_from(body);
    const Emitter& emitter = *scene->emitters()[0];
    SurfaceInteraction ref = virtual_vertex(*scene, ref_p, Vec3(0, 1, 0));
    const int n = effort_scaled(400000, 40000);
    PCG32 rng(seed, 5);
    double sum = 0.0, sum2 = 0.0;
    int inconsistent = 0, valid = 0;
    constexpr int UvBins = 8;  // sampled points uniform by area: uv uniform over an 8 x 8 grid
    std::vector<double> uv_counts(UvBins * UvBins, 0.0);
    for (int i = 0; i < n; ++i) {
        float a = rng.next_float();
        Spectrum weight;
        DirectionSample ds = emitter.sample_direction(ref, Vec2(a, rng.next_float()), weight);
        double inv = ds.pdf > 0.0f ? 1.0 / ds.pdf : 0.0;
        sum += inv;
        sum2 += inv * inv;
        SurfaceInteraction hit;  // where the sampled point really is: the surface's own uv there
        if (ds.pdf > 0.0f && scene->intersect(Ray(ref.p, ds.d), hit)) {
            ++valid;
            int bx = std::clamp(int(hit.uv.x * UvBins), 0, UvBins - 1), by = std::clamp(int(hit.uv.y * UvBins), 0, UvBins - 1);
            uv_counts[size_t(by * UvBins + bx)] += 1.0;
        }
        if (ds.pdf > 0.0f && i % 50 == 0 && std::abs(emitter_pdf(*scene, emitter, ref, ds.d) - ds.pdf) > 1e-3 * ds.pdf) ++inconsistent;
    }
    double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1));
    double omega = subtended_solid_angle(*scene->shapes()[0], ref_p);
    INFO(what << ": mean 1/pdf " << mean << " +- " << se << ", solid angle " << omega << "; traced pdf disagreed " << inconsistent
              << " times");
    CHECK(omega < 0.1);  // the area-sampled branch
    CHECK(std::abs(mean - omega) <= two_sided_z(Alpha) * se + 1e-6 * omega);
    CHECK(inconsistent == 0);
    // E[1 / pdf] barely depends on where on a far light the points fall; their uv does.
    REQUIRE(valid > 0);
    ChiSquareResult uniform = chi_square(uv_counts, std::vector<double>(uv_counts.size(), double(valid) / uv_counts.size()));
    INFO("uv uniformity: " << uniform.details);
    CHECK(uniform.p_value > Alpha);
}

const char* AreaLight = R"(<emitter type="area"><rgb name="radiance" value="1"/></emitter>)";

}  // namespace

TEST_CASE("emitters: sampling matches pdf_direction for every kind of light", "[lights][sampling]") {
    std::string sphere =
        std::string(R"(<shape type="sphere"><point name="center" x="0.3" y="1.5" z="0.2"/><float name="radius" value="0.5"/>)") +
        AreaLight + "</shape>";
    check_emitter_sampling("sphere seen from outside (cone)", sphere, Vec3(0.0f), 1);
    check_emitter_sampling("sphere seen from inside (area)", sphere, Vec3(0.4f, 1.6f, 0.1f), 2);
    std::string rect =
        std::string(
            R"(<shape type="rectangle"><transform name="to_world"><scale x="0.8" y="0.3"/><rotate x="1" angle="70"/><rotate y="1" angle="20"/><translate x="0.2" y="1" z="-0.4"/></transform>)") +
        AreaLight + "</shape>";
    check_emitter_sampling("rectangle (spherical rectangle)", rect, Vec3(0.0f), 3);
    check_emitter_sampling("rectangle seen from behind", rect, Vec3(0.5f, 3.0f, -1.0f), 4);
    check_small_emitter_sampling("rectangle seen from afar (area)", rect, Vec3(2.0f, -4.0f, 3.0f), 10);
    // A mirroring to_world: Mitsuba's rectangle then faces along the transformed normal, -z here.
    std::string mirrored =
        std::string(R"(<shape type="rectangle"><transform name="to_world"><scale x="0.5" y="0.4" z="-1"/><translate z="1"/></transform>)") +
        AreaLight + "</shape>";
    check_emitter_sampling("mirrored rectangle, near (spherical rectangle)", mirrored, Vec3(0.1f, 0.0f, 0.2f), 11);
    check_small_emitter_sampling("mirrored rectangle, far (area)", mirrored, Vec3(0.3f, 0.2f, -5.0f), 12);
    std::string sheared =
        std::string(
            R"(<shape type="rectangle"><transform name="to_world"><matrix value="1 0.5 0 0  0 0 1 1  0 1 0 0  0 0 0 1"/></transform>)") +
        AreaLight + "</shape>";
    check_emitter_sampling("sheared rectangle (area)", sheared, Vec3(0.0f), 5);
    std::string disk =
        std::string(
            R"(<shape type="disk"><transform name="to_world"><scale x="0.6" y="0.3"/><rotate x="1" angle="90"/><translate y="1"/></transform>)") +
        AreaLight + "</shape>";
    check_emitter_sampling("elliptic disk", disk, Vec3(0.2f, 0, 0.1f), 6);
    std::string cube =
        std::string(R"(<shape type="cube"><transform name="to_world"><scale value="0.3"/><translate y="1.2"/></transform>)") + AreaLight +
        "</shape>";
    check_emitter_sampling("cube (mesh)", cube, Vec3(0.0f), 7);
    check_emitter_sampling("constant environment", R"(<emitter type="constant"/>)", Vec3(0.0f), 8);
    check_emitter_sampling(
        "environment map",
        R"(<emitter type="envmap"><string name="filename" value=")" + source_path("scenes/validation/textures/sky.exr") +
            R"("/><transform name="to_world"><rotate y="1" angle="60"/><rotate x="1" angle="20"/></transform></emitter>)",
        Vec3(0.0f), 9);
    // The sun and sky's sky alone (its sun's cone is too small for the histogram: the sun's
    // sampling is tested in test_sunsky.cpp), in a turned frame.
    check_emitter_sampling(
        "sun and sky, the sky",
        R"(<emitter type="sunsky"><float name="sun_scale" value="0"/><vector name="sun_direction" x="0.5" y="0.1" z="0.3"/>
                              <transform name="to_world"><rotate x="1" angle="-90"/></transform></emitter>)",
        Vec3(0.0f), 13);
    check_emitter_sampling("timed sun and sky, the sky",
                           R"(<emitter type="timed_sunsky"><float name="sun_scale" value="0"/><float name="window_start_time" value="11"/>
                              <transform name="to_world"><rotate x="1" angle="-90"/></transform></emitter>)",
                           Vec3(0.0f), 14);
}

namespace {
std::string many_lights(int count, uint64_t seed) {
    PCG32 rng(seed, 1);
    std::string body = R"(<emitter type="constant"><rgb name="radiance" value="0.1"/></emitter>
                          <emitter type="directional"><vector name="direction" x="0.2" y="-1" z="0.1"/></emitter>)";
    for (int i = 0; i < count; ++i) {
        float x = 8 * rng.next_float() - 4, y = 0.5f + 3 * rng.next_float(), z = 8 * rng.next_float() - 4;
        float power = 0.1f + 5 * rng.next_float();
        std::string pos = std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z);
        switch (i % 4) {
            case 0:
                body += "<emitter type=\"point\"><point name=\"position\" value=\"" + pos + "\"/><rgb name=\"intensity\" value=\"" +
                        std::to_string(power) + "\"/></emitter>";
                break;
            case 1:
                body += "<emitter type=\"spot\"><transform name=\"to_world\"><lookat origin=\"" + pos + "\" target=\"" +
                        std::to_string(x + 0.3f) + ", 0, " + std::to_string(z) + "\"/></transform><rgb name=\"intensity\" value=\"" +
                        std::to_string(power) + "\"/></emitter>";
                break;
            case 2:
                body +=
                    "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"0.2\"/><rotate x=\"1\" angle=\"90\"/><translate value=\"" +
                    pos + "\"/></transform><emitter type=\"area\"><rgb name=\"radiance\" value=\"" + std::to_string(power) +
                    "\"/></emitter></shape>";
                break;
            default:
                body += "<shape type=\"sphere\"><point name=\"center\" value=\"" + pos +
                        "\"/><float name=\"radius\" value=\"0.1\"/><emitter type=\"area\"><rgb name=\"radiance\" value=\"" +
                        std::to_string(power) + "\"/></emitter></shape>";
        }
    }
    return body;
}
}  // namespace

TEST_CASE("emitters: a mirrored rectangle emits on the side Mitsuba's transformed normal faces", "[lights][sampling]") {
    // scale z = -1 mirrors: the transformed normal of (0, 0, 1) is (0, 0, -1), while the
    // triangles' winding still turns counter-clockwise around +z.
    Ref<Scene> scene = scene_from(
        std::string(R"(<shape type="rectangle"><transform name="to_world"><scale x="0.5" y="0.4" z="-1"/><translate z="1"/></transform>)") +
        AreaLight + "</shape>");
    const Emitter& emitter = *scene->emitters()[0];
    SurfaceInteraction from_below, from_above;
    REQUIRE(scene->intersect(Ray(Vec3(0.0f), Vec3(0, 0, 1)), from_below));
    REQUIRE(scene->intersect(Ray(Vec3(0, 0, 2), Vec3(0, 0, -1)), from_above));
    CHECK(from_below.n.z < 0.0f);
    CHECK(luminance(emitter.eval(from_below)) > 0.0f);
    CHECK(luminance(emitter.eval(from_above)) == 0.0f);
    // Light sampling agrees: points below see the light, points above do not.
    Spectrum weight;
    CHECK(emitter.sample_direction(virtual_vertex(*scene, Vec3(0, 0, 0.5f), Vec3(0, 0, 1)), Vec2(0.3f, 0.6f), weight).pdf > 0.0f);
    CHECK(emitter.sample_direction(virtual_vertex(*scene, Vec3(0, 0, 1.5f), Vec3(0, 0, -1)), Vec2(0.3f, 0.6f), weight).pdf == 0.0f);
}

TEST_CASE("light tree: selection probabilities sum to one, match sampling, and miss no light", "[lights][tree]") {
    Ref<Scene> scene = scene_from(many_lights(60, 4));
    LightTree tree(*scene);
    const auto& emitters = scene->emitters();
    struct Point {
        Vec3 p, n;
    };
    const Point points[] = {
        {{0, 0, 0}, {0, 1, 0}}, {{2, 1, -1}, {0, 1, 0}}, {{-3, 0.2f, 3}, {1, 0, 0}}, {{0, 5, 0}, {0, -1, 0}}, {{1, 1, 1}, {0, 0, 0}}};
    for (const Point& pt : points) {
        SurfaceInteraction ref;
        ref.p = pt.p;
        ref.shading = pt.n == Vec3(0.0f) ? Frame() : Frame(glm::normalize(pt.n));
        if (pt.n == Vec3(0.0f)) ref.shading.n = Vec3(0.0f);
        double sum = 0.0;
        std::vector<double> pmf(emitters.size());
        for (size_t i = 0; i < emitters.size(); ++i) sum += pmf[i] = tree.pmf(ref, emitters[i].get());
        INFO("point " << pt.p.x << "," << pt.p.y << "," << pt.p.z << ": pmf sum " << sum);
        // Subtrees whose bounds rule out any contribution are never entered, so the sum may fall
        // short of one; unbiasedness needs only the check below.
        CHECK(sum <= 1.0 + 1e-4);
        CHECK(sum > 0.5);
        // Every light that can send light to p (ignoring occlusion) has a chance.
        for (size_t i = 0; i < emitters.size(); ++i) {
            bool contributes = false;
            for (int k = 0; k < 16 && !contributes; ++k) {
                Spectrum w;
                DirectionSample ds = emitters[i]->sample_direction(ref, Vec2((k % 4 + 0.5f) / 4, (k / 4 + 0.5f) / 4), w);
                bool faces = pt.n == Vec3(0.0f) || std::abs(glm::dot(ds.d, pt.n)) > 0.0f;
                contributes = ds.pdf > 0.0f && !is_black(w) && faces;
            }
            if (contributes) CHECK(pmf[i] > 0.0);
        }
        // Sampling frequencies follow pmf.
        const int n = 200000;
        std::vector<double> counts(emitters.size() + 1, 0.0), expected(emitters.size() + 1);
        PCG32 rng(77, 3);
        for (int s = 0; s < n; ++s) {
            float prob;
            const Emitter* e = tree.sample(ref, rng.next_float(), prob);
            if (!e) {
                counts.back() += 1.0;  // no light chosen
                continue;
            }
            for (size_t i = 0; i < emitters.size(); ++i)
                if (emitters[i].get() == e) {
                    counts[i] += 1.0;
                    REQUIRE(prob == Approx(pmf[i]).epsilon(1e-4));
                }
        }
        for (size_t i = 0; i < emitters.size(); ++i) expected[i] = pmf[i] * n;
        expected.back() = std::max(0.0, 1.0 - sum) * n;
        ChiSquareResult r = chi_square(counts, expected);
        INFO(r.details);
        CHECK(r.p_value > Alpha);
    }
}

namespace {
// `count` point lights of intensities 1..7 at positions from `position(i)`.
std::string point_lights(int count, const std::function<Vec3(int)>& position) {
    std::string body;
    for (int i = 0; i < count; ++i) {
        Vec3 p = position(i);
        body += "<emitter type=\"point\"><point name=\"position\" x=\"" + std::to_string(p.x) + "\" y=\"" + std::to_string(p.y) +
                "\" z=\"" + std::to_string(p.z) + "\"/><rgb name=\"intensity\" value=\"" + std::to_string(1 + i % 7) + "\"/></emitter>";
    }
    return body;
}
}  // namespace

TEST_CASE("light tree: thousands of lights on a line or at one point are all pickable with their pmf", "[lights][tree]") {
    // Collinear point lights have bounds of zero area, so every split ties at cost zero and cuts off
    // a single bucket: the tree grows far deeper than 64 levels. Coincident lights split in halves.
    struct Config {
        const char* what;
        std::function<Vec3(int)> position;
    };
    const Config configs[] = {{"2000 lights on a line", [](int i) { return Vec3(0.01f * float(i) - 10.0f, 1.0f, 0.0f); }},
                              {"2000 lights at one point", [](int) { return Vec3(0.3f, 2.0f, -0.2f); }}};
    for (const Config& config : configs) {
        Ref<Scene> scene = scene_from(point_lights(2000, config.position));
        LightTree tree(*scene);
        const auto& emitters = scene->emitters();
        std::unordered_map<const Emitter*, size_t> index;
        for (size_t i = 0; i < emitters.size(); ++i) index[emitters[i].get()] = i;
        const Vec3 receivers[] = {{0.0f, 0.0f, 0.0f}, {7.0f, -0.5f, 1.0f}};
        for (const Vec3& p : receivers) {
            if (config.what[5] == 'a' && p.x != 0.0f) continue;  // one receiver suffices for coincident lights
            SurfaceInteraction ref;
            ref.p = p;
            ref.shading = Frame(Vec3(0, 1, 0));
            // Every light is above the receiver and lights it: each must have a positive pmf, and
            // the pmfs must sum to one.
            std::vector<double> pmf(emitters.size());
            double sum = 0.0;
            int unpickable = 0;
            for (size_t i = 0; i < emitters.size(); ++i) {
                sum += pmf[i] = tree.pmf(ref, emitters[i].get());
                unpickable += pmf[i] <= 0.0;
            }
            INFO(config.what << ", receiver " << p.x << "," << p.y << "," << p.z << ": " << unpickable << " lights with pmf 0, pmf sum "
                             << sum);
            CHECK(unpickable == 0);
            CHECK(sum == Approx(1.0).epsilon(1e-4));
            // Sampling picks each light as often as its pmf says, and reports that pmf.
            const int n = 200000;
            std::vector<double> counts(emitters.size(), 0.0), expected(emitters.size());
            int disagreements = 0, missing = 0;
            PCG32 rng(91, 7);
            for (int s = 0; s < n; ++s) {
                float prob;
                const Emitter* e = tree.sample(ref, rng.next_float(), prob);
                if (!e) {
                    ++missing;
                    continue;
                }
                size_t i = index.at(e);
                counts[i] += 1.0;
                disagreements += std::abs(prob - pmf[i]) > 1e-4 * pmf[i];
            }
            for (size_t i = 0; i < emitters.size(); ++i) expected[i] = pmf[i] / sum * n;
            ChiSquareResult r = chi_square(counts, expected);
            INFO(r.details << "; sample() and pmf() disagreed " << disagreements << " times");
            CHECK(missing == 0);
            CHECK(disagreements == 0);
            CHECK(r.p_value > Alpha);
        }
    }
}

TEST_CASE("light samplers: every strategy renders the same expected image", "[lights][tree]") {
    // Unbiasedness of the three strategies on a many-light scene: the image means of uniform,
    // power and tree renders agree within their Monte Carlo error. The renders use independent
    // seeds; with the box filter each pixel is the mean of its own samples and pixels are
    // independent, so the variance of the image mean is the sum of the variance AOV (the variance
    // of each pixel mean) over the pixels, divided by their count squared. Every light and surface
    // is grey, so one channel (G) carries the whole image.
    auto dir = scratch_dir("strategies");
    std::string body = std::string(Ground) + many_lights(40, 9);
    std::vector<MeanAndError> means;
    uint64_t seed = 100;
    for (const char* strategy : {"uniform", "power", "tree"}) {
        write_text(dir / "scene.xml",
                   scene_xml(body + R"(<integrator type="path"><integer name="max_depth" value="3"/><string name="light_sampler" value=")" +
                             strategy +
                             R"("/></integrator><sensor type="perspective"><float name="fov" value="60"/>
            <transform name="to_world"><lookat origin="0, 6, 6" target="0, 0, 0" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="96"/></sampler>
            <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="48"/><rfilter type="box"/></film></sensor>)"));
        Ref<Scene> scene = load_scene((dir / "scene.xml").string());
        RenderOptions options;
        options.seed = seed++;
        options.aovs = {"variance"};
        RenderResult r = scene->integrator().render(*scene, options);
        const int g = 1, var_g = r.image.channel_index("variance.G");
        REQUIRE(var_g > 0);
        double sum = 0.0, variance = 0.0, pixels = double(r.image.width()) * r.image.height();
        for (int y = 0; y < r.image.height(); ++y)
            for (int x = 0; x < r.image.width(); ++x) {
                sum += r.image.at(x, y, g);
                variance += r.image.at(x, y, var_g);
            }
        means.push_back({sum / pixels, std::sqrt(variance) / pixels});
    }
    const double z = two_sided_z(Alpha);
    // Power: a strategy whose expected value is off by `detectable` of the mean is detected with
    // probability at least 0.99 (that error exceeds the threshold by 2.33 standard errors of the
    // difference). The tree is compared at 10% (a lost or doubly counted light among the 40 is of
    // that order); power sampling is noisy here (the sky and the sun carry most of the flux, so
    // the small lights are rarely picked and come with large weights), and with this budget it is
    // compared at 20%.
    const double z_power = normal_quantile(0.99);
    const double detectable_of[3] = {0.0, 0.20, 0.10};  // uniform (the reference), power, tree
    for (int i = 1; i < 3; ++i) {
        double se = std::hypot(means[i].std_error, means[0].std_error), diff = means[i].mean - means[0].mean;
        const double detectable = detectable_of[i];
        INFO("strategy " << i << ": " << means[i].mean << " +- " << means[i].std_error << " vs uniform " << means[0].mean << " +- "
                         << means[0].std_error << "; |difference| " << std::abs(diff) / se << " standard errors, threshold " << z << "; a "
                         << detectable * 100 << "% error is " << detectable * means[0].mean / se << " standard errors");
        CHECK(std::abs(diff) <= z * se);
        CHECK(detectable * means[0].mean >= (z + z_power) * se);
        // And this very draw, off by that much, would have failed.
        CHECK(std::abs(diff + detectable * means[i].mean) > z * se);
        CHECK(std::abs(diff - detectable * means[i].mean) > z * se);
    }
}
