// Media and volumes: the .vol reader, interpolation, majorant grids, and the two transmittance
// estimators against closed forms.
//   - gridvolume returns the stored voxel values at voxel centres, interpolates trilinearly (or
//     picks the nearest voxel) between them, and rejects malformed files at the filename's line.
//   - Majorant segments cover exactly the part of a ray inside the volume, in order, and bound
//     sigma_t at every point of their span (checked at many random points; deterministic).
//   - Transmittance through a grid whose density is linear along x (different in each channel)
//     has the closed form exp(-tau); ratio tracking and delta tracking (the fraction of free
//     flights that pass, weighted as the integrators weight them) estimate it, with the majorant
//     grid and with one global majorant, and in a homogeneous medium too. Each estimate is
//     z-tested against the closed form with its own standard error; 1% family-wise (Sidak).
//   - A homogeneous medium answers exp(-sigma_t d) exactly.
// The spectral variant (sigma_t an unbounded spectrum, the albedo a reflectance, measured spectra
// per wavelength, majorants bounding sigma_t at every wavelength):
//   - A homogeneous slab whose sigma_t is a measured spectrum (wavelength:value pairs, linear
//     between them, zero beyond) transmits exp(-scale sigma_t(l) d) at each wavelength l, exactly
//     (Beer-Lambert); in scalar_rgb the same scene gets the spectrum's colour as an unbounded value
//     (not clamped to [0, 1]).
//   - Majorant segments bound sigma_t at every wavelength drawn, for a coloured grid (2 max(rgb)),
//     a grey grid and a measured constant (random points; deterministic).
//   - Ratio and delta tracking estimate the closed form per wavelength in heterogeneous media (a
//     measured constant, a grid of one colour), z-tested as above.

#include "core/medium.h"
#include "core/scene.h"
#include "core/spectral.h"
#include "core/volume.h"
#include "core/wavelengths.h"
#include "tests/stats.h"
#include "tests/support/vol_writer.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

// A scene with a null-BSDF unit cube whose interior is the medium declared (with id "m") in
// `medium_xml`; files the medium names go to the same folder, written by `prepare`.
struct MediumInScene {
    Ref<Scene> scene;
    const Medium* medium = nullptr;
};
MediumInScene load_medium(const std::string& name, const std::string& medium_xml,
                          const std::function<void(const std::filesystem::path&)>& prepare = {}, Variant variant = Variant::ScalarRGB) {
    auto dir = scratch_dir(name);
    if (prepare) prepare(dir);
    write_text(dir / "scene.xml",
               scene_xml(medium_xml + "\n<shape type=\"cube\"><bsdf type=\"null\"/><ref name=\"interior\" id=\"m\"/></shape>"));
    MediumInScene out;
    out.scene = load_scene((dir / "scene.xml").string(), {}, variant);
    out.medium = out.scene->shapes()[0]->interior();
    REQUIRE(out.medium);
    return out;
}

std::string grid_medium(const std::string& extra, const std::string& volume_extra = "") {
    return R"(<medium type="heterogeneous" id="m"><float name="albedo" value="0"/>)" + extra + R"(
        <volume type="gridvolume" name="sigma_t"><string name="filename" value="grid.vol"/>)" +
           volume_extra + R"(</volume></medium>)";
}

// A transmittance estimator and the value it estimates (per channel, or per wavelength of
// ray.wavelengths).
struct Estimator {
    std::string name;
    const Medium* medium;
    int mode;  // 0: ratio tracking, 1: delta tracking with a shared majorant, 2: per-channel majorants
    Vec3 expected;
};

// Each estimator's mean over many tracks along `ray` to tmax, z-tested against its expectation
// with its own standard error (Sidak over all channels of all estimators).
void check_tracking(const std::vector<Estimator>& estimators, const Ray& ray, float tmax) {
    const double z = two_sided_z(sidak(0.01, 3 * int(estimators.size())));
    const int tracks = effort_scaled(100000, 20000);
    for (const Estimator& e : estimators) {
        INFO(e.name);
        PCG32 rng(42, 7);
        std::vector<double> samples[3];
        for (int i = 0; i < tracks; ++i) {
            Spectrum T;
            if (e.mode == 0) {
                T = ratio_tracking_transmittance(*e.medium, ray, tmax, rng);
            } else {
                TrackingWeights w;
                w.shared_majorant = e.mode == 1;
                w.channel = int(rng.next_bounded(3));
                float t;
                MediumPoint mp;
                // Albedo 0: a real collision ends the path; passing through keeps the weights.
                T = sample_free_flight(*e.medium, ray, tmax, rng, w, t, mp) ? Spectrum(0.0f) : w.estimate_weight();
            }
            for (int k = 0; k < 3; ++k) samples[k].push_back(T[k]);
        }
        for (int k = 0; k < 3; ++k) {
            MeanAndError m = mean_and_error(samples[k]);
            INFO("channel " << k << ": " << m.mean << " +- " << m.std_error << ", expected " << e.expected[k]);
            CHECK(std::abs(m.mean - e.expected[k]) < z * m.std_error);
            CHECK(m.std_error < 0.01);  // the test has power: errors of a few percent are seen
        }
    }
}

// The spectral tests' sigma_t, a measured spectrum (nm:value), and its closed form.
const char* const MeasuredSigmaT = "400:0.5, 500:2, 600:1, 700:3";
double measured_sigma_t(double lambda) {
    const double l[4] = {400, 500, 600, 700}, v[4] = {0.5, 2, 1, 3};
    if (lambda < l[0] || lambda > l[3]) return 0.0;
    for (int i = 0; i < 3; ++i)
        if (lambda <= l[i + 1]) return v[i] + (v[i + 1] - v[i]) * (lambda - l[i]) / (l[i + 1] - l[i]);
    return 0.0;
}

Wavelengths wavelengths(float a, float b, float c) {
    Wavelengths w;
    w.lambda = Vec3(a, b, c);
    w.pdf = Vec3(1.0f);
    return w;
}

}  // namespace

TEST_CASE("gridvolume: voxel values at their centres, trilinear and nearest lookups between", "[media][volume]") {
    // 3 x 2 x 2 voxels, one channel: value = 1 + x + 10 y + 100 z.
    std::vector<float> values;
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 3; ++x) values.push_back(float(1 + x + 10 * y + 100 * z));
    auto write = [&](const std::filesystem::path& dir) { write_vol(dir / "grid.vol", glm::ivec3(3, 2, 2), 1, values); };
    MediumInScene trilinear = load_medium("gridvolume-lookups", grid_medium(""), write);
    auto sigma = [&](const Medium* m, float x, float y, float z) { return m->coefficients(Vec3(x, y, z)).sigma_t.x; };
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 3; ++x)
                CHECK(sigma(trilinear.medium, (x + 0.5f) / 3.0f, (y + 0.5f) / 2.0f, (z + 0.5f) / 2.0f) == Approx(1 + x + 10 * y + 100 * z));
    // Halfway between voxel centres along x and y; clamped beyond the outer centres.
    CHECK(sigma(trilinear.medium, 1.0f / 3.0f, 0.25f, 0.25f) == Approx(1.5f));
    CHECK(sigma(trilinear.medium, 0.5f, 0.5f, 0.25f) == Approx(2.0f + 5.0f));
    CHECK(sigma(trilinear.medium, 0.01f, 0.01f, 0.01f) == Approx(1.0f));
    CHECK(sigma(trilinear.medium, 0.99f, 0.99f, 0.99f) == Approx(113.0f));
    MediumInScene nearest = load_medium("gridvolume-nearest", grid_medium("", R"(<string name="filter_type" value="nearest"/>)"), write);
    CHECK(sigma(nearest.medium, 0.32f, 0.4f, 0.6f) == Approx(1 + 0 + 0 + 100));
    CHECK(sigma(nearest.medium, 0.34f, 0.6f, 0.4f) == Approx(1 + 1 + 10 + 0));
    // The albedo 0 leaves nothing scattered.
    CHECK(trilinear.medium->coefficients(Vec3(0.5f)).sigma_s == Spectrum(0.0f));
}

TEST_CASE("gridvolume: malformed files are errors at the filename's line", "[media][volume][errors]") {
    struct Case {
        std::string what;
        std::function<void(const std::filesystem::path&)> write;
        const char* message;
    };
    const std::vector<Case> cases = {
        {"truncated", [](const std::filesystem::path& p) { write_text(p, "VOL"); }, "shorter than the 48-byte header"},
        {"magic", [](const std::filesystem::path& p) { write_text(p, std::string(60, 'x')); }, "does not start with \"VOL\""},
        {"short data",
         [](const std::filesystem::path& p) {
             write_vol(p, glm::ivec3(2, 2, 2), 1, std::vector<float>(8, 1.0f));
             std::filesystem::resize_file(p, 48 + 7 * 4);
         },
         "the header promises 8 values"},
        {"five channels", [](const std::filesystem::path& p) { write_vol(p, glm::ivec3(1, 1, 1), 5, std::vector<float>(5, 1.0f)); },
         "5 channels"},
        {"not finite", [](const std::filesystem::path& p) { write_vol(p, glm::ivec3(1, 1, 1), 1, {std::nanf("")}); }, "not finite"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        auto dir = scratch_dir("gridvolume-bad");
        c.write(dir / "grid.vol");
        write_text(dir / "scene.xml", scene_xml("<medium type=\"heterogeneous\" id=\"m\">\n<volume type=\"gridvolume\" name=\"sigma_t\">\n"
                                                "<string name=\"filename\" value=\"grid.vol\"/>\n</volume>\n</medium>"));
        try {
            load_scene((dir / "scene.xml").string());
            FAIL("no error");
        } catch (const SceneError& e) {
            CHECK_THAT(e.message(), Catch::Contains(c.message));
            CHECK(e.location.line == 4);
        }
    }
}

TEST_CASE("majorant grid: segments cover the ray inside the volume and bound sigma_t", "[media][majorant]") {
    // A random grid, rotated and scaled into the world.
    PCG32 rng(1, 2);
    const glm::ivec3 res(19, 7, 12);
    std::vector<float> values(size_t(res.x * res.y * res.z));
    for (float& v : values) v = rng.next_float() < 0.7f ? 0.0f : 5.0f * rng.next_float();
    MediumInScene m = load_medium("majorant-cover", grid_medium(R"(<integer name="majorant_resolution_factor" value="4"/>)", R"(
        <transform name="to_world"><scale x="2" y="1" z="0.5"/><rotate x="1" y="1" z="0" angle="30"/><translate x="-0.5"/></transform>)"),
                                  [&](const std::filesystem::path& dir) { write_vol(dir / "grid.vol", res, 1, values); });
    // The volume's to_world above: scale, then rotate, then translate.
    const Transform to_world = Transform::translate(Vec3(-0.5f, 0.0f, 0.0f)) * Transform::rotate(Vec3(1.0f, 1.0f, 0.0f), 30.0f) *
                               Transform::scale(Vec3(2.0f, 1.0f, 0.5f));
    int violations = 0, gaps = 0, rays_inside = 0;
    for (int r = 0; r < 2000; ++r) {
        Vec3 o = Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 6.0f - Vec3(3.0f);
        // Toward a point inside the volume, so that every ray crosses it.
        Vec3 target = to_world.apply_point(Vec3(rng.next_float(), rng.next_float(), rng.next_float()));
        Ray ray(o, glm::normalize(target - o));
        MajorantIterator it = m.medium->majorants(ray, 20.0f);
        MajorantSegment seg;
        float previous_end = -1.0f;
        bool any = false;
        while (it.next(seg)) {
            if (previous_end >= 0.0f && std::abs(seg.t0 - previous_end) > 1e-5f * (1.0f + previous_end)) ++gaps;
            previous_end = seg.t1;
            any = true;
            for (int k = 0; k < 8; ++k) {
                float t = seg.t0 + (seg.t1 - seg.t0) * rng.next_float();
                if (m.medium->eval(ray(t), ray.d).sigma_t.x > seg.sigma_maj.x * (1.0f + 1e-5f) + 1e-6f) ++violations;
            }
        }
        rays_inside += any;
    }
    CHECK(rays_inside == 2000);  // every ray crosses the volume: the check has content
    CHECK(gaps == 0);
    CHECK(violations == 0);
}

TEST_CASE("transmittance: ratio and delta tracking agree with the closed form of a linear density", "[media][stats]") {
    // Channel k: sigma_t(x) = a_k + b_k x in the volume's unit cube, stretched to x in [0, 2]. The
    // voxel centres carry exact samples of the line; trilinear lookups are linear between the
    // outer centres and constant beyond them (clamp), which the closed form accounts for.
    const int n = 16;
    const Vec3 a(0.5f, 0.2f, 1.0f), b(3.0f, 0.5f, 0.0f);
    std::vector<float> values;
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < n; ++x)
                for (int k = 0; k < 3; ++k) values.push_back(a[k] + b[k] * (x + 0.5f) / n);
    auto write = [&](const std::filesystem::path& dir) { write_vol(dir / "grid.vol", glm::ivec3(n, 2, 2), 3, values); };
    const std::string stretch = R"(<transform name="to_world"><scale x="2"/></transform>)";
    MediumInScene grid = load_medium("linear-grid", grid_medium("", stretch), write);
    MediumInScene global =
        load_medium("linear-global", grid_medium(R"(<integer name="majorant_resolution_factor" value="0"/>)", stretch), write);
    MediumInScene homogeneous =
        load_medium("linear-homogeneous", R"(<medium type="homogeneous" id="m"><rgb name="sigma_t" value="0.3, 0.8, 1.5"/>
        <float name="albedo" value="0"/></medium>)");
    // tau = 2 * integral over the unit cube's x of the clamped line.
    const double h = 0.5 / n;
    Vec3 expected, expected_homogeneous;
    for (int k = 0; k < 3; ++k) {
        double v0 = a[k] + b[k] * h, v1 = a[k] + b[k] * (1.0 - h);
        double middle = a[k] * (1.0 - 2.0 * h) + 0.5 * b[k] * ((1.0 - h) * (1.0 - h) - h * h);
        expected[k] = float(std::exp(-2.0 * (v0 * h + middle + v1 * h)));
        expected_homogeneous[k] = float(std::exp(-Vec3(0.3f, 0.8f, 1.5f)[k] * 4.0));
    }
    Ray ray(Vec3(-1.0f, 0.4f, 0.6f), Vec3(1.0f, 0.0f, 0.0f));
    const float tmax = 4.0f;  // from x = -1 to x = 3: through the whole volume
    // The homogeneous medium answers exactly.
    PCG32 unused;
    Spectrum exact = homogeneous.medium->transmittance(ray, tmax, unused);
    for (int k = 0; k < 3; ++k) CHECK(exact[k] == Approx(expected_homogeneous[k]).epsilon(1e-5));

    const std::vector<Estimator> estimators = {
        {"ratio, majorant grid", grid.medium, 0, expected},
        {"ratio, global majorant", global.medium, 0, expected},
        {"delta shared, majorant grid", grid.medium, 1, expected},
        {"delta per channel, majorant grid", grid.medium, 2, expected},
        {"delta shared, global majorant", global.medium, 1, expected},
        {"ratio, homogeneous", homogeneous.medium, 0, expected_homogeneous},
        {"delta shared, homogeneous", homogeneous.medium, 1, expected_homogeneous},
        {"delta per channel, homogeneous", homogeneous.medium, 2, expected_homogeneous},
    };
    check_tracking(estimators, ray, tmax);
}

TEST_CASE("spectral media: a homogeneous slab transmits Beer-Lambert of its measured sigma_t at each wavelength", "[media][spectral]") {
    const std::string xml = std::string(R"(<medium type="homogeneous" id="m"><spectrum name="sigma_t" value=")") + MeasuredSigmaT +
                            R"("/><float name="scale" value="2"/><float name="albedo" value="0.5"/></medium>)";
    MediumInScene m = load_medium("spectral-slab", xml, {}, Variant::ScalarSpectral);
    const float d = 0.7f;
    PCG32 unused;
    for (Vec3 lambda : {Vec3(380.0f, 400.0f, 450.0f), Vec3(530.0f, 650.0f, 700.0f), Vec3(760.0f, 555.5f, 499.0f)}) {
        Wavelengths w = wavelengths(lambda.x, lambda.y, lambda.z);
        Ray ray(Vec3(0.2f, -1.0f, 0.1f), glm::normalize(Vec3(0.3f, 1.0f, -0.2f)));
        ray.wavelengths = &w;
        const Spectrum T = m.medium->transmittance(ray, d, unused);
        const MediumPoint mp = m.medium->coefficients(Vec3(0.1f), &w);
        for (int j = 0; j < 3; ++j) {
            const double sigma = 2.0 * measured_sigma_t(lambda[j]);
            INFO("wavelength " << lambda[j] << " nm");
            CHECK(mp.sigma_t[j] == Approx(sigma).epsilon(1e-6).margin(1e-7));
            CHECK(mp.sigma_s[j] == Approx(0.5 * sigma).epsilon(1e-6).margin(1e-7));
            CHECK(T[j] == Approx(std::exp(-sigma * d)).epsilon(1e-5));
        }
        // Its majorant is sigma_t itself, wavelength by wavelength.
        MajorantIterator it = m.medium->majorants(ray, d);
        MajorantSegment seg;
        REQUIRE(it.next(seg));
        for (int j = 0; j < 3; ++j) CHECK(seg.sigma_maj[j] == mp.sigma_t[j]);
    }
    // scalar_rgb: the spectrum's colour, unbounded (sigma_t is one of Mitsuba's unbounded
    // spectra): weighted by D65, not clamped to [0, 1].
    MediumInScene rgb = load_medium("spectral-slab-rgb", xml);
    SampledSpectrum s{{400, 500, 600, 700}, {0.5, 2, 1, 3}};
    const Spectrum colour = spectrum_to_rgb(s, true, false) * 2.0f;
    CHECK(max_component(colour) > 2.0f);
    const Spectrum sigma_t = rgb.medium->coefficients(Vec3(0.0f)).sigma_t;
    for (int k = 0; k < 3; ++k) CHECK(sigma_t[k] == Approx(colour[k]).epsilon(1e-6));
}

TEST_CASE("spectral media: majorants bound sigma_t at every wavelength", "[media][spectral]") {
    PCG32 rng(11, 5);
    const glm::ivec3 res(10, 8, 6);
    std::vector<float> colour, grey;
    // Saturated colours (one channel far above the others) are where the upsampled spectrum
    // peaks highest relative to the colour.
    for (int i = 0; i < res.x * res.y * res.z; ++i) {
        const float v = rng.next_float() < 0.5f ? 0.0f : 5.0f * rng.next_float();
        const int hot = int(rng.next_bounded(3));
        for (int k = 0; k < 3; ++k) colour.push_back(k == hot ? v : 0.05f * v * rng.next_float());
        grey.push_back(v);
    }
    auto write = [&](const std::filesystem::path& dir) {
        write_vol(dir / "colour.vol", res, 3, colour);
        write_vol(dir / "grey.vol", res, 1, grey);
    };
    auto grid = [](const char* file) {
        return std::string(R"(<medium type="heterogeneous" id="m"><float name="albedo" value="0"/>
            <integer name="majorant_resolution_factor" value="2"/>
            <volume type="gridvolume" name="sigma_t"><string name="filename" value=")") +
               file + R"("/></volume></medium>)";
    };
    const std::string measured = std::string(R"(<medium type="heterogeneous" id="m"><float name="albedo" value="0"/>
        <float name="scale" value="1.5"/><spectrum name="sigma_t" value=")") +
                                 MeasuredSigmaT + R"("/></medium>)";
    struct Case {
        const char* name;
        MediumInScene m;
    };
    const Case cases[] = {{"colour grid", load_medium("spectral-majorant-colour", grid("colour.vol"), write, Variant::ScalarSpectral)},
                          {"grey grid", load_medium("spectral-majorant-grey", grid("grey.vol"), write, Variant::ScalarSpectral)},
                          {"measured constant", load_medium("spectral-majorant-measured", measured, {}, Variant::ScalarSpectral)}};
    for (const Case& c : cases) {
        INFO(c.name);
        int violations = 0, points = 0;
        float tightest = Infinity;  // the smallest majorant / sigma_t seen where sigma_t > 0
        for (int r = 0; r < 1000; ++r) {
            Wavelengths w = sample_visible_wavelengths(rng.next_float());
            Vec3 o = Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 4.0f - Vec3(1.5f);
            Vec3 target(rng.next_float(), rng.next_float(), rng.next_float());
            Ray ray(o, glm::normalize(target - o));
            ray.wavelengths = &w;
            MajorantIterator it = c.m.medium->majorants(ray, 20.0f);
            MajorantSegment seg;
            while (it.next(seg)) {
                for (int k = 0; k < 6; ++k) {
                    const float t = seg.t0 + (seg.t1 - seg.t0) * rng.next_float();
                    const Spectrum sigma_t = c.m.medium->eval(ray(t), ray.d, &w).sigma_t;
                    for (int j = 0; j < 3; ++j) {
                        ++points;
                        if (sigma_t[j] > seg.sigma_maj[j] * (1.0f + 1e-5f) + 1e-6f) ++violations;
                        if (sigma_t[j] > 0.0f) tightest = std::min(tightest, seg.sigma_maj[j] / sigma_t[j]);
                    }
                }
            }
        }
        INFO("tightest majorant / sigma_t " << tightest);
        CHECK(points > 10000);
        CHECK(violations == 0);
        CHECK(tightest >= 1.0f - 1e-5f);
    }
}

TEST_CASE("spectral media: ratio and delta tracking estimate Beer-Lambert per wavelength", "[media][spectral][stats]") {
    // Through the unit cube along x: d = 1. A measured constant sigma_t (its majorant the largest
    // sample, 3 * scale) and a 2^3 grid of one colour (majorant 2 max(rgb)).
    const Spectrum rgb(0.4f, 2.5f, 1.0f);
    std::vector<float> values;
    for (int i = 0; i < 8; ++i) values.insert(values.end(), {rgb.x, rgb.y, rgb.z});
    auto write = [&](const std::filesystem::path& dir) { write_vol(dir / "grid.vol", glm::ivec3(2), 3, values); };
    MediumInScene measured = load_medium("spectral-tracking-measured",
                                         std::string(R"(<medium type="heterogeneous" id="m"><float name="albedo" value="0"/>
        <float name="scale" value="0.5"/><spectrum name="sigma_t" value=")") +
                                             MeasuredSigmaT + R"("/></medium>)",
                                         {}, Variant::ScalarSpectral);
    MediumInScene grid = load_medium("spectral-tracking-grid", R"(<medium type="heterogeneous" id="m"><float name="albedo" value="0"/>
        <volume type="gridvolume" name="sigma_t"><string name="filename" value="grid.vol"/></volume></medium>)",
                                     write, Variant::ScalarSpectral);
    Wavelengths w = wavelengths(430.0f, 575.0f, 690.0f);
    const Spectrum grid_sigma = rgb_at_wavelengths(rgb, SpectrumRole::Unbounded, &w);
    Vec3 expected_measured, expected_grid;
    for (int j = 0; j < 3; ++j) {
        expected_measured[j] = float(std::exp(-0.5 * measured_sigma_t(w.lambda[j])));
        expected_grid[j] = std::exp(-grid_sigma[j]);
    }
    Ray ray(Vec3(-1.0f, 0.4f, 0.6f), Vec3(1.0f, 0.0f, 0.0f));
    ray.wavelengths = &w;
    const float tmax = 3.0f;
    const std::vector<Estimator> estimators = {
        {"ratio, measured", measured.medium, 0, expected_measured},
        {"delta shared, measured", measured.medium, 1, expected_measured},
        {"delta per wavelength, measured", measured.medium, 2, expected_measured},
        {"ratio, grid", grid.medium, 0, expected_grid},
        {"delta shared, grid", grid.medium, 1, expected_grid},
        {"delta per wavelength, grid", grid.medium, 2, expected_grid},
    };
    check_tracking(estimators, ray, tmax);
}
