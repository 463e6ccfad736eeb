// The polarized variant end to end: Malus' law through two polarisers, seen directly and
// through next-event estimation (shadow rays carry the crossed surfaces' matrices), with each
// integrator; Brewster's angle in the stokes integrator's S1 and behind a polariser; a
// quarter-wave plate making circular light; circular polarisers; a depolarising scene rendering as the spectral
// variant bit for bit; and stokes refused outside the variant.

#include "core/error.h"
#include "core/xml.h"
#include "integrators/estimators.h"
#include "materials/fresnel.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace candela;
using namespace candela::test;

namespace {

RenderResult render(const std::string& xml, const std::string& name, Variant variant = Variant::ScalarSpectralPolarized) {
    Ref<Scene> scene = load_scene_from_string(xml, scratch_dir("polarized_" + name).string() + "/scene.xml", {}, variant);
    return scene->integrator().render(*scene, RenderOptions());
}

std::string sensor(const std::string& origin, const std::string& up, float fov, int spp) {
    return R"(<sensor type="perspective"><float name="fov" value=")" + std::to_string(fov) +
           R"("/><transform name="to_world"><lookat origin=")" + origin + R"(" target="0, 0, 0" up=")" + up +
           R"("/></transform><sampler type="independent"><integer name="sample_count" value=")" + std::to_string(spp) +
           R"("/></sampler><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
           <rfilter type="box"/><string name="component_format" value="float32"/></film></sensor>)";
}

std::string sheet(float z, const std::string& bsdf) {
    return R"(<shape type="rectangle"><transform name="to_world"><scale value="50"/><translate z=")" + std::to_string(z) +
           R"("/></transform>)" + bsdf + "</shape>";
}

std::string polarizer(float degrees) {
    return R"(<bsdf type="polarizer"><float name="theta" value=")" + std::to_string(degrees) + R"("/></bsdf>)";
}

// The camera looks at an area light through two polarisers, the second turned by `degrees`.
std::string seen_through(const std::string& integrator, float degrees) {
    return R"(<scene version="3.0.0"><integrator type="stokes"><integrator type=")" + integrator + R"("/></integrator>)" +
           sensor("0, 0, 5", "0, 1, 0", 2, 4) +
           R"(<shape type="rectangle"><transform name="to_world"><scale value="50"/><translate z="-1"/></transform>
               <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)" +
           sheet(0, polarizer(0)) + sheet(1, polarizer(degrees)) + "</scene>";
}

// A diffuse floor lit through two polarisers (only next-event estimation and BSDF samples through
// the null sheets reach the light); the camera sits below them.
std::string lit_through(const std::string& integrator, float degrees) {
    return R"(<scene version="3.0.0"><integrator type=")" + integrator + R"("/>)" + sensor("0, 0, 1", "0, 1, 0", 20, 16) +
           R"(<shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="180"/><translate z="3"/></transform>
               <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)" +
           sheet(2, polarizer(0)) + sheet(1.5f, polarizer(degrees)) + sheet(0, R"(<bsdf type="diffuse"/>)") + "</scene>";
}

int channel(const Image& image, const std::string& name) {
    const auto& names = image.channels();
    for (size_t i = 0; i < names.size(); ++i)
        if (names[i] == name) return int(i);
    FAIL("no channel " << name);
    return -1;
}

}  // namespace

TEST_CASE("polarized: Malus' law, seen through two polarisers, with each integrator", "[render][polarized]") {
    // The same seed draws the same wavelengths: each pixel's ratio to the aligned pair is cos^2
    // up to rounding, and S1 / S0 = cos 2a, |S2| / S0 = sin 2a (light polarised along the second;
    // a narrow view, as the tilted polariser's axes and the camera's horizontal turn off axis).
    for (const char* integrator : {"path", "direct", "volpath", "volpathmis"}) {
        const RenderResult aligned = render(seen_through(integrator, 0), "malus");
        for (float degrees : {30.0f, 45.0f, 60.0f, 90.0f}) {
            const RenderResult turned = render(seen_through(integrator, degrees), "malus");
            const float a = glm::radians(degrees), expected = sqr(std::cos(a));
            const int s0 = channel(turned.image, "S0.G"), s1 = channel(turned.image, "S1.G"), s2 = channel(turned.image, "S2.G");
            INFO(integrator << " at " << degrees << " degrees");
            for (int y = 0; y < 8; ++y)
                for (int x = 0; x < 8; ++x) {
                    for (int c = 0; c < 3; ++c)
                        CHECK(turned.image.at(x, y, c) == Approx(expected * aligned.image.at(x, y, c)).margin(1e-6));
                    const float S0 = turned.image.at(x, y, s0);
                    if (S0 < 1e-3f) continue;
                    CHECK(turned.image.at(x, y, s1) / S0 == Approx(std::cos(2 * a)).margin(1e-4));
                    CHECK(std::abs(turned.image.at(x, y, s2)) / S0 == Approx(std::sin(2 * a)).margin(1e-4));
                }
        }
    }
}

TEST_CASE("polarized: Malus' law in light that reaches a floor through two polarisers", "[render][polarized]") {
    // ptracer's light paths carry the Stokes vector through the sheets to the floor (the same
    // random numbers for every angle, so its ratio is exact too).
    for (const char* integrator : {"path", "direct", "volpath", "ptracer"}) {
        const RenderResult aligned = render(lit_through(integrator, 0), "malus_nee");
        for (float degrees : {45.0f, 60.0f, 90.0f}) {
            const RenderResult turned = render(lit_through(integrator, degrees), "malus_nee");
            const float expected = sqr(std::cos(glm::radians(degrees)));
            INFO(integrator << " at " << degrees << " degrees");
            for (int c = 0; c < 3; ++c) {
                const double ratio = channel_mean(turned.image, c).mean / channel_mean(aligned.image, c).mean;
                CHECK(ratio == Approx(expected).margin(1e-5));
            }
            CHECK(channel_mean(aligned.image, 1).mean > 0.05);
        }
    }
}

TEST_CASE("polarized: the irradiance estimate under two polarisers follows Malus' law", "[render][polarized][estimate]") {
    // The `estimate` command's estimator, at the floor below the polarisers (the same seed for
    // every angle: the ratio is exact but for rounding).
    auto irradiance = [](float degrees) {
        Ref<Scene> scene = load_scene_from_string(lit_through("path", degrees), scratch_dir("polarized_estimate").string() + "/scene.xml",
                                                  {}, Variant::ScalarSpectralPolarized);
        EstimatorOptions options;
        options.samples = 4096;
        return estimate_irradiance(*scene, Vec3(0.0f), Vec3(0, 0, 1), options).mean;
    };
    const Spectrum aligned = irradiance(0.0f);
    REQUIRE(aligned.y > 0.1f);
    for (float degrees : {45.0f, 60.0f, 90.0f}) {
        const Spectrum turned = irradiance(degrees);
        for (int c = 0; c < 3; ++c) CHECK(turned[c] == Approx(sqr(std::cos(glm::radians(degrees))) * aligned[c]).margin(1e-5));
    }
}

TEST_CASE("polarized: light reflected at Brewster's angle, arctan(n), is s-polarised", "[render][polarized]") {
    // The camera sees a large light in a glass plane (n = 1.5) at incidence theta, up = the
    // normal: s (perpendicular to the plane of incidence) is the camera's horizontal, so
    // S1 / S0 = (R_s - R_p) / (R_s + R_p), 1 at Brewster's angle. Behind a small polariser in
    // front of the camera, what passes when it passes p over what passes when it passes s is
    // R_p / R_s, 0 at Brewster's angle. (Ratios within one render, or between renders that draw
    // the same numbers: the glass picks reflection at random, too rarely for a mean to be exact.)
    const float n = 1.5f;
    auto scene = [&](float theta, float filter_degrees) {
        const float s = std::sin(theta), c = std::cos(theta);
        char camera[64], light[64], between[64];
        std::snprintf(camera, sizeof camera, "0, %f, %f", -5 * s, 5 * c);
        std::snprintf(between, sizeof between, "0, %f, %f", -2.5f * s, 2.5f * c);
        std::snprintf(light, sizeof light, "0, %f, %f", 10 * s, 10 * c);
        // The p-passing filter: a polariser across the camera's view whose absorbing axis (its v)
        // is horizontal, the world x axis.
        const std::string filter =
            filter_degrees >= 0.0f
                ? R"(<shape type="rectangle"><transform name="to_world"><scale value="0.3"/>
            <rotate z="1" angle="90"/><lookat origin=")" +
                      std::string(between) +
                      R"(" target="0, 0, 0" up="0, 0, 1"/></transform><bsdf type="polarizer"><float name="theta" value=")" +
                      std::to_string(filter_degrees) + R"("/></bsdf></shape>)"
                : "";
        return R"(<scene version="3.0.0"><integrator type="stokes"><integrator type="path"/></integrator>)" +
               sensor(camera, "0, 0, 1", 1, 4) + R"(<shape type="rectangle"><transform name="to_world"><scale value="50"/></transform>
               <bsdf type="dielectric"><float name="int_ior" value="1.5"/></bsdf></shape>
               <shape type="rectangle"><transform name="to_world"><scale value="8"/><lookat origin=")" +
               light +
               R"(" target="0, 0, 0" up="0, 0, 1"/></transform><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)" +
               filter + "</scene>";
    };
    for (float degrees : {20.0f, 45.0f, glm::degrees(std::atan(n)), 70.0f}) {
        const float theta = glm::radians(degrees);
        float rs, rp;
        fresnel_dielectric_polarized(std::cos(theta), n, rs, rp);
        const RenderResult r = render(scene(theta, -1.0f), "brewster");
        const double S0 = channel_mean(r.image, channel(r.image, "S0.G")).mean, S1 = channel_mean(r.image, channel(r.image, "S1.G")).mean;
        INFO("incidence " << degrees << " degrees: S1 / S0 = " << S1 / S0);
        CHECK(S0 > 1e-3);
        CHECK(S1 / S0 == Approx((rs - rp) / (rs + rp)).margin(0.01));  // the 1 degree field of view spreads the angle
        // The filter's absorbing axis (its v) is horizontal (s) at theta 0, vertical at 90.
        const double p = channel_mean(render(scene(theta, 0.0f), "brewster_p").image, 1).mean;
        const double s = channel_mean(render(scene(theta, 90.0f), "brewster_s").image, 1).mean;
        INFO("through the filter: p " << p << ", s " << s);
        CHECK(s > 1e-3);
        CHECK(p / s == Approx(rp / rs).margin(0.01));
    }
}

TEST_CASE("polarized: ptracer's light paths and path's camera paths see the same polarisation", "[render][polarized][ptracer]") {
    // Light through a polariser falls on a rough gold sphere and a rough pplastic floor, whose
    // Fresnel terms depend on the light's polarisation: turning the polariser from 30 to 120
    // degrees changes the image by about 5%. Camera paths (Mueller products toward the light) and
    // light paths (Stokes vectors toward the camera, matrices with directions swapped) must agree
    // at both angles: whole-image means over independent seeds, z-tests at 1% (Sidak over 2).
    auto scene = [](const std::string& integrator, float degrees) {
        return R"(<scene version="3.0.0"><integrator type=")" + integrator + R"("/>
    <sensor type="perspective"><transform name="to_world"><lookat origin="0, -4, 2" target="0, 0, 0" up="0, 0, 1"/></transform>
        <sampler type="independent"><integer name="sample_count" value="32"/></sampler>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/><string name="component_format" value="float32"/></film></sensor>
    <shape type="rectangle"><transform name="to_world"><scale value="0.7"/><rotate x="1" angle="180"/><translate z="3"/></transform>
        <emitter type="area"><rgb name="radiance" value="10"/></emitter></shape>
    <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="180"/><translate z="2.5"/></transform>
        <bsdf type="polarizer"><float name="theta" value=")" +
               std::to_string(degrees) + R"("/></bsdf></shape>
    <shape type="sphere"><transform name="to_world"><translate z="0.5"/><scale value="0.6"/></transform>
        <bsdf type="roughconductor"><string name="material" value="Au"/><float name="alpha" value="0.3"/></bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="3"/></transform>
        <bsdf type="pplastic"><float name="alpha" value="0.3"/></bsdf></shape>
</scene>)";
    };
    const int seeds = 12;
    auto image_mean = [&](const std::string& integrator, float degrees) {
        Ref<Scene> s = load_scene_from_string(scene(integrator, degrees), scratch_dir("polarized_ptracer").string() + "/scene.xml", {},
                                              Variant::ScalarSpectralPolarized);
        std::vector<double> means;
        for (int k = 0; k < seeds; ++k) {
            RenderOptions options;
            options.seed = 2000 + k;
            means.push_back(channel_mean(s->integrator().render(*s, options).image, 1).mean);
        }
        return mean_and_error(means);
    };
    const double z = two_sided_z(sidak(0.01, 2));
    MeanAndError at30 = image_mean("path", 30.0f), at120 = image_mean("path", 120.0f);
    for (float degrees : {30.0f, 120.0f}) {
        const MeanAndError path = degrees == 30.0f ? at30 : at120, light = image_mean("ptracer", degrees);
        const double error = std::sqrt(path.std_error * path.std_error + light.std_error * light.std_error);
        INFO(degrees << " degrees: path " << path.mean << " +- " << path.std_error << ", ptracer " << light.mean << " +- "
                     << light.std_error);
        CHECK(std::abs(path.mean - light.mean) <= z * error);
        CHECK(error < 0.01 * path.mean);  // power: a disagreement of 1% would show
    }
    // The polarisation matters here: the two angles differ by far more than the error.
    const double between = std::sqrt(at30.std_error * at30.std_error + at120.std_error * at120.std_error);
    INFO("30 degrees " << at30.mean << ", 120 degrees " << at120.mean);
    CHECK(std::abs(at30.mean - at120.mean) > 5.0 * between);
}

TEST_CASE("polarized: a quarter-wave plate at 45 degrees makes linear light circular", "[render][polarized]") {
    // At normal incidence (a narrow view: oblique rays see less retardance, as in Mitsuba).
    const std::string xml =
        R"(<scene version="3.0.0"><integrator type="stokes"><integrator type="path"/></integrator>)" + sensor("0, 0, 5", "0, 1, 0", 2, 4) +
        R"(<shape type="rectangle"><transform name="to_world"><scale value="50"/><translate z="-1"/></transform>
               <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)" +
        sheet(0, polarizer(0)) +
        sheet(1, R"(<bsdf type="retarder"><float name="theta" value="45"/><float name="delta" value="90"/></bsdf>)") + "</scene>";
    const RenderResult r = render(xml, "quarter_wave");
    const int s0 = channel(r.image, "S0.G"), s1 = channel(r.image, "S1.G"), s3 = channel(r.image, "S3.G");
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const float S0 = r.image.at(x, y, s0);
            REQUIRE(S0 > 0.1f);
            CHECK(std::abs(r.image.at(x, y, s3)) / S0 == Approx(1.0f).margin(1e-4));
            CHECK(std::abs(r.image.at(x, y, s1)) / S0 < 1e-3f);  // 0.3 degrees less retardance 1 degree off axis
        }
}

TEST_CASE("polarized: a depolarising scene renders as the spectral variant, bit for bit", "[render][polarized][spectral]") {
    const std::string xml = R"(<scene version="3.0.0"><integrator type="path"/>)" + sensor("0, 0, 4", "0, 1, 0", 40, 8) +
                            R"(<emitter type="constant"><rgb name="radiance" value="0.8, 0.6, 0.4"/></emitter>
        <shape type="sphere"><bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0.2, 0.5, 0.7"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="5"/><translate z="-1.5"/></transform><bsdf type="diffuse"/></shape>
        </scene>)";
    const RenderResult spectral = render(xml, "depolarising", Variant::ScalarSpectral);
    const RenderResult polarized = render(xml, "depolarising");
    REQUIRE(spectral.image.channels() == polarized.image.channels());
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            for (int c = 0; c < 3; ++c) CHECK(spectral.image.at(x, y, c) == polarized.image.at(x, y, c));
}

TEST_CASE("polarized: stokes needs the variant and one nested integrator", "[render][polarized][errors]") {
    const std::string body = sensor("0, 0, 4", "0, 1, 0", 40, 1) + R"(<shape type="sphere"/></scene>)";
    for (Variant v : {Variant::ScalarRGB, Variant::ScalarSpectral}) {
        try {
            render(R"(<scene version="3.0.0"><integrator type="stokes"><integrator type="path"/></integrator>)" + body, "refused", v);
            FAIL("stokes rendered in " << variant_name(v));
        } catch (const SceneError& e) {
            CHECK_THAT(e.what(), Catch::Contains("stokes renders only in variant scalar_spectral_polarized"));
        }
    }
    CHECK_THROWS_WITH(render(R"(<scene version="3.0.0"><integrator type="stokes"/>)" + body, "refused"),
                      Catch::Contains("exactly one nested integrator"));
}

TEST_CASE("polarized: circular polarisers pass half of one hand, nothing of the other, a quarter of linear light", "[render][polarized]") {
    // The camera looks at an area light through a right-handed circular polariser and then
    // `second`. The same seed draws the same wavelengths: the ratios are exact up to rounding.
    auto through_right = [](const std::string& second) {
        const std::string xml = R"(<scene version="3.0.0"><integrator type="stokes"><integrator type="path"/></integrator>)" +
                                sensor("0, 0, 5", "0, 1, 0", 2, 4) +
                                R"(<shape type="rectangle"><transform name="to_world"><scale value="50"/><translate z="-1"/></transform>
               <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)" +
                                sheet(0, R"(<bsdf type="circular"/>)") + (second.empty() ? "" : sheet(1, second)) + "</scene>";
        return render(xml, "circular");
    };
    const RenderResult one = through_right("");
    const RenderResult same = through_right(R"(<bsdf type="circular"/>)");
    const RenderResult opposite = through_right(R"(<bsdf type="circular"><boolean name="left_handed" value="true"/></bsdf>)");
    const RenderResult linear = through_right(polarizer(30));
    const int s0 = channel(one.image, "S0.G"), s3 = channel(one.image, "S3.G");
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            const float S0 = one.image.at(x, y, s0);
            REQUIRE(S0 > 0.1f);
            // Light seen through one is circular; a second of the same hand passes it all.
            CHECK(std::abs(one.image.at(x, y, s3)) / S0 == Approx(1.0f).margin(1e-4));
            for (int c = 0; c < 3; ++c) {
                CHECK(same.image.at(x, y, c) == Approx(one.image.at(x, y, c)).margin(1e-6));
                CHECK(opposite.image.at(x, y, c) == Approx(0.0f).margin(1e-6));
                CHECK(linear.image.at(x, y, c) == Approx(0.5f * one.image.at(x, y, c)).margin(1e-6));
            }
        }
}
