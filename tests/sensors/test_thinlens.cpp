// The thin lens camera: with a zero aperture it is the perspective camera, ray for ray and image
// for image; points on the focal plane stay sharp; elsewhere a film position's rays spread over
// the circle of confusion, of radius a |1 - z / f| at depth z (a: aperture radius, f: focus
// distance), uniformly (the aperture disk scaled).

#include "analysis/statistics.h"
#include "core/rng.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

const char* Lookat = R"(<transform name="to_world"><lookat origin="0.5, 1, 6" target="0, 0.2, 0" up="0, 1, 0"/></transform>)";

std::string camera(const std::string& type, const std::string& extra) {
    return "<sensor type=\"" + type + "\"><float name=\"fov\" value=\"35\"/>" + extra + Lookat +
           R"(<film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="32"/><rfilter type="box"/></film>
           <sampler type="independent"><integer name="sample_count" value="4"/></sampler></sensor>)";
}

const char* Objects = R"(<emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>
    <shape type="sphere"><float name="radius" value="0.8"/><bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.4, 0.2"/></bsdf></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/><translate y="-0.8"/></transform></shape>)";

Ref<Scene> load(const std::string& name, const std::string& body) {
    auto dir = scratch_dir("thinlens");
    write_text(dir / name, scene_xml(body));
    return load_scene((dir / name).string());
}

}  // namespace

TEST_CASE("thinlens: a zero aperture is the perspective camera", "[camera][thinlens]") {
    Ref<Scene> lens = load(
        "lens.xml", camera("thinlens", R"(<float name="aperture_radius" value="0"/><float name="focus_distance" value="3"/>)") + Objects);
    Ref<Scene> pinhole = load("pinhole.xml", camera("perspective", "") + Objects);
    PCG32 rng(7, 1);
    for (int i = 0; i < 1000; ++i) {
        Vec2 p(48.0f * rng.next_float(), 32.0f * rng.next_float()), u(rng.next_float(), rng.next_float());
        Ray a = lens->sensor().sample_ray(p, u), b = pinhole->sensor().sample_ray(p, u);
        REQUIRE(glm::length(a.o - b.o) < 1e-6f);
        REQUIRE(glm::length(a.d - b.d) < 1e-6f);
        REQUIRE(a.tmin == Approx(b.tmin).epsilon(1e-5));
        REQUIRE(a.tmax == Approx(b.tmax).epsilon(1e-5));
    }
    // The whole pipeline: the same image, pixel for pixel.
    RenderOptions options;
    Image x = lens->integrator().render(*lens, options).image, y = pinhole->integrator().render(*pinhole, options).image;
    REQUIRE(x.data().size() == y.data().size());
    double worst = 0.0;
    for (size_t i = 0; i < x.data().size(); ++i) worst = std::max(worst, double(std::abs(x.data()[i] - y.data()[i])));
    CHECK(worst < 1e-5);
    // Only a zero aperture leaves a pinhole for the rasterizer.
    CHECK(lens->sensor().pinhole().has_value());
    Ref<Scene> open_lens = load("open.xml", camera("thinlens", R"(<float name="aperture_radius" value="0.1"/>)") + Objects);
    CHECK(!open_lens->sensor().pinhole().has_value());
}

TEST_CASE("thinlens: the focal plane is sharp and defocus follows the circle of confusion", "[camera][thinlens]") {
    const float a = 0.15f, f = 4.0f;
    Ref<Scene> lens =
        load("coc.xml", camera("thinlens", R"(<float name="aperture_radius" value="0.15"/><float name="focus_distance" value="4"/>)"));
    Ref<Scene> pinhole = load("pin.xml", camera("perspective", ""));
    const Sensor& s = lens->sensor();
    const Transform& to_camera = s.to_world().inverse();
    // Depths z (camera space) and film positions; the statistical checks share a 1% level.
    const float depths[] = {1.5f, 3.0f, 4.0f, 7.0f, 20.0f};
    const Vec2 films[] = {Vec2(24, 16), Vec2(3.5f, 29.0f), Vec2(40.0f, 5.0f)};
    const double alpha = sidak(0.01, 3 * 4 * 3);  // three checks, four defocused depths, three positions
    PCG32 rng(11, 3);
    for (float z : depths) {
        for (Vec2 film : films) {
            // Where the pinhole's ray through this film position reaches depth z.
            Ray pr = pinhole->sensor().sample_ray(film, Vec2(0.5f));
            Vec3 pd = to_camera.apply_vector(pr.d);
            Vec3 centre = to_camera.apply_point(pr.o) + pd * (z / pd.z);
            float coc = a * std::abs(1.0f - z / f);
            INFO("depth " << z << ", film " << film.x << ", " << film.y << ", circle of confusion radius " << coc);
            const int n = 400000;
            std::vector<double> dx(n), dy(n), r2(n);
            double worst = 0.0;
            for (int i = 0; i < n; ++i) {
                Ray r = s.sample_ray(film, Vec2(rng.next_float(), rng.next_float()));
                Vec3 o = to_camera.apply_point(r.o), d = to_camera.apply_vector(r.d);
                Vec3 x = o + d * ((z - o.z) / d.z) - centre;
                dx[i] = x.x;
                dy[i] = x.y;
                r2[i] = x.x * x.x + x.y * x.y;
                worst = std::max(worst, std::sqrt(r2[i]));
            }
            // Every ray stays inside the circle; one through the aperture's rim reaches it.
            CHECK(worst <= coc * 1.0001 + 2e-5 * z);
            Ray rim = s.sample_ray(film, Vec2(1.0f, 0.3f));
            Vec3 ro = to_camera.apply_point(rim.o), rd = to_camera.apply_vector(rim.d);
            CHECK(glm::length(Vec2(ro + rd * ((z - ro.z) / rd.z) - centre)) == Approx(coc).margin(2e-5 * z));
            if (coc == 0.0f) continue;  // on the focal plane: all rays meet in one point
            // Uniform over the disk: mean (0, 0) and E[r^2] = coc^2 / 2, within the estimator's
            // own error.
            MeanAndError mx = mean_and_error(dx), my = mean_and_error(dy), mr = mean_and_error(r2);
            double zq = two_sided_z(alpha);
            CHECK(std::abs(mx.mean) <= zq * mx.std_error);
            CHECK(std::abs(my.mean) <= zq * my.std_error);
            CHECK(std::abs(mr.mean - 0.5 * coc * coc) <= zq * mr.std_error);
        }
    }
}
