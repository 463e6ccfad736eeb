// Moving area lights: a shape with an area emitter and an animated to_world (Mitsuba 3's
// <animation name="to_world">). The loader moves the shape as a one-shape group and an animated
// instance; the emitter samples the still shape at the reference point's time.
//   - At a time t a moving light with a rigid motion samples as the static light at the pose
//     interpolated at t (same point, direction, pdf and weight); with a non-uniform scale, every
//     sample's pdf is what pdf_direction gives for it.
//   - Time average: a small rectangle light (non-uniformly scaled, facing down) crosses above a
//     diffuse plane during the shutter; an orthographic camera whose view is 0.002 across looks at
//     one point P of the plane. The image mean is (rho / pi) times the irradiance at P averaged
//     over the shutter, from Lambert's polygon formula E = L / 2 sum_i theta_i (n . u_i) at 4000
//     midpoint times (a smooth integrand: the quadrature error is far below 1e-6 relative), for
//     direct (MIS, and emitter sampling alone), path and volpath. Each is a z-test on the mean of
//     independent pixels, all at a 1% family-wise level (Sidak over 4 integrators x 3 channels),
//     with a power check (the standard error below 1.5% of the value).

#include "core/emitter.h"
#include "core/scene.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

std::string light(const std::string& placement) {
    return R"(<shape type="rectangle"><emitter type="area"><rgb name="radiance" value="4, 3, 2"/></emitter>)" + placement + "</shape>";
}

// The pose of the test light at time t in [0, 1]: scale (0.25, 0.15), turned to face -z, its
// centre moving from (-1, 0, 1) to (1, 0, 1).
std::string pose(float x, const std::string& scale = R"(<scale x="0.25" y="0.15"/>)") {
    return scale + R"(<rotate x="1" angle="180"/><translate x=")" + std::to_string(x) + R"(" z="1"/>)";
}

std::string moving_light(const std::string& scale) {
    return light(R"(<animation name="to_world"><transform time="0">)" + pose(-1.0f, scale) + R"(</transform><transform time="1">)" +
                 pose(1.0f, scale) + "</transform></animation>");
}

// Irradiance at P (normal +z) from a uniform Lambertian quadrilateral of radiance 1 (Lambert).
double polygon_irradiance(const std::vector<glm::dvec3>& corners, const glm::dvec3& P) {
    double sum = 0.0;
    for (size_t i = 0; i < corners.size(); ++i) {
        glm::dvec3 a = glm::normalize(corners[i] - P), b = glm::normalize(corners[(i + 1) % corners.size()] - P);
        glm::dvec3 c = glm::cross(a, b);
        double theta = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
        sum += theta * c.z / glm::length(c);
    }
    return 0.5 * std::abs(sum);
}

}  // namespace

TEST_CASE("area motion: at time t a moving area light samples as the static one at that pose", "[lights][animation]") {
    // A rigid motion with a uniform scale: solid angles are kept, samples agree one for one.
    const std::string uniform = R"(<scale value="0.3"/>)";
    Ref<Scene> moving = load_scene_xml("area-moving", moving_light(uniform));
    REQUIRE(moving->emitters().size() == 1);
    const Emitter& m = *moving->emitters()[0];
    CHECK(m.is_animated());
    CHECK(moving->is_animated());
    for (float t : {0.0f, 0.3f, 1.0f}) {
        Ref<Scene> still =
            load_scene_xml("area-still", light("<transform name=\"to_world\">" + pose(-1.0f + 2.0f * t, uniform) + "</transform>"));
        REQUIRE(still->emitters().size() == 1);
        const Emitter& s = *still->emitters()[0];
        for (Vec3 p : {Vec3(0.0f), Vec3(0.3f, -0.2f, 0.0f), Vec3(-1.5f, 0.4f, -0.1f)})
            for (Vec2 u : {Vec2(0.5f), Vec2(0.1f, 0.8f), Vec2(0.9f, 0.3f)}) {
                INFO("t " << t << ", reference " << p.x << ", " << p.y << ", " << p.z << ", u " << u.x << ", " << u.y);
                SurfaceInteraction ref;
                ref.p = p;
                ref.time = t;
                Spectrum wm, ws;
                DirectionSample dm = m.sample_direction(ref, u, wm), ds = s.sample_direction(ref, u, ws);
                REQUIRE(dm.pdf > 0.0f);
                CHECK(glm::length(dm.p - ds.p) < 1e-4f);
                CHECK(dm.pdf == Approx(ds.pdf).epsilon(1e-3));
                CHECK(wm.x == Approx(ws.x).epsilon(1e-3));
                CHECK(m.pdf_direction(ref, dm) == Approx(dm.pdf).epsilon(1e-3));
            }
    }
    // A non-uniform scale: each sample's pdf is pdf_direction's.
    Ref<Scene> squashed = load_scene_xml("area-squashed", moving_light(R"(<scale x="0.25" y="0.15"/>)"));
    REQUIRE(squashed->emitters().size() == 1);
    const Emitter& q = *squashed->emitters()[0];
    int inconsistent = 0;
    for (int i = 0; i < 200; ++i) {
        SurfaceInteraction ref;
        ref.p = Vec3(0.01f * float(i % 17) - 0.1f, 0.02f * float(i % 5), -0.2f);
        ref.time = float(i) / 199.0f;
        Spectrum w;
        DirectionSample d = q.sample_direction(ref, Vec2(float(i % 13) / 13.0f + 0.03f, float(i % 7) / 7.0f + 0.05f), w);
        if (!(d.pdf > 0.0f) || std::abs(q.pdf_direction(ref, d) - d.pdf) > 1e-3f * d.pdf) ++inconsistent;
    }
    CHECK(inconsistent == 0);
}

TEST_CASE("area motion: a light crossing above a plane lights it by its time average", "[lights][animation][stats]") {
    const glm::dvec3 P(0.3, 0.1, 0.0);
    const double rho = 0.5;
    // The time-averaged irradiance per unit radiance at P: the corners of the light at time t.
    double E = 0.0;
    const int steps = 4000;
    for (int k = 0; k < steps; ++k) {
        double t = (k + 0.5) / steps, x = -1.0 + 2.0 * t;
        std::vector<glm::dvec3> corners = {{x - 0.25, -0.15, 1.0}, {x + 0.25, -0.15, 1.0}, {x + 0.25, 0.15, 1.0}, {x - 0.25, 0.15, 1.0}};
        E += polygon_irradiance(corners, P) / steps;
    }
    const Vec3 L(4.0f, 3.0f, 2.0f);
    // The camera looks at P from above along (0, -1, 1), clear of the light's path (|y| <= 0.15).
    const std::string scene_body = R"(
        <sensor type="orthographic"><float name="shutter_open" value="0"/><float name="shutter_close" value="1"/>
            <transform name="to_world"><scale value="0.001"/><lookat origin="0.3, -2.9, 3" target="0.3, 0.1, 0" up="0, 0, 1"/></transform>
            <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/>
                <string name="component_format" value="float32"/></film>
            <sampler type="independent"><integer name="sample_count" value="128"/></sampler></sensor>
        <shape type="rectangle"><transform name="to_world"><scale value="5"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>)" +
                                   moving_light(R"(<scale x="0.25" y="0.15"/>)");
    const double Z = two_sided_z(sidak(0.01, 4 * 3));
    for (const char* integrator :
         {R"(<integrator type="direct"/>)",
          R"(<integrator type="direct"><integer name="bsdf_samples" value="0"/><integer name="emitter_samples" value="1"/></integrator>)",
          R"(<integrator type="path"/>)", R"(<integrator type="volpath"/>)"}) {
        INFO(integrator);
        auto dir = scratch_dir("area-motion");
        write_text(dir / "scene.xml", scene_xml(integrator + scene_body));
        Ref<Scene> scene = load_scene((dir / "scene.xml").string());
        Image img = scene->integrator().render(*scene, RenderOptions()).image;
        for (int ch = 0; ch < 3; ++ch) {
            std::vector<double> v;
            for (int y = 0; y < img.height(); ++y)
                for (int x = 0; x < img.width(); ++x) v.push_back(img.at(x, y, ch));
            MeanAndError m = mean_and_error(v);
            double expected = rho / Pi * L[ch] * E;
            INFO("channel " << ch << ": " << m.mean << " +- " << m.std_error << ", expected " << expected);
            CHECK(std::abs(m.mean - expected) < Z * m.std_error);
            CHECK(m.std_error < 0.015 * expected);
        }
    }
}
