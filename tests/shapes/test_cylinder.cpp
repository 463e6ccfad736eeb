// cylinder: exact hits with Mitsuba's uv and normal conventions, the transforms it accepts, and
// two identities against a finely tessellated tube written independently here: the same render
// (same random numbers) and the same irradiance as an area light (within the estimators' error
// bars). As an area light: positions uniform by area (chi-square over uv cells) and the density
// the path tracer finds by tracing a sampled direction equal to the sampled one.

#include "core/emitter.h"
#include "core/rng.h"
#include "core/xml.h"
#include "integrators/estimators.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <sstream>

using namespace candela;
using namespace candela::test;

namespace {

SurfaceInteraction trace(const Scene& scene, Vec3 o, Vec3 d) {
    SurfaceInteraction si;
    scene.intersect(Ray(o, glm::normalize(d)), si);
    return si;
}

// The unit-radius tube around z from 0 to 1 (Mitsuba's default cylinder) as n quads, with radial
// vertex normals and Mitsuba's uv (u = phi / 2pi from +x toward +y, v = z), seam duplicated.
std::string tessellated_tube_obj(int n) {
    std::ostringstream obj;
    obj.precision(9);
    for (int j = 0; j <= n; ++j) {
        double phi = 2.0 * 3.14159265358979323846 * (j % n) / n;
        for (int k = 0; k < 2; ++k) obj << "v " << std::cos(phi) << " " << std::sin(phi) << " " << k << "\n";
        obj << "vn " << std::cos(phi) << " " << std::sin(phi) << " 0\n";
        for (int k = 0; k < 2; ++k) obj << "vt " << double(j) / n << " " << k << "\n";
    }
    for (int j = 0; j < n; ++j) {
        int a = 2 * j + 1, b = a + 1, c = a + 2, d = a + 3;  // a, c at z = 0 (1-based)
        int na = j + 1, nc = j + 2;
        auto corner = [](int v, int n_) { return std::to_string(v) + "/" + std::to_string(v) + "/" + std::to_string(n_); };
        obj << "f " << corner(a, na) << " " << corner(c, nc) << " " << corner(d, nc) << "\n";
        obj << "f " << corner(a, na) << " " << corner(d, nc) << " " << corner(b, na) << "\n";
    }
    return obj.str();
}

constexpr int CylinderTests = 2;  // statistical checks in this file (Sidak, 1% family-wise)

}  // namespace

TEST_CASE("cylinder: exact hits, outward normals and Mitsuba's uv", "[cylinder]") {
    auto dir = scratch_dir("cylinder");
    Ref<Scene> s = load_scene_xml_in(dir, R"(<shape type="cylinder"/>)");
    SurfaceInteraction si = trace(*s, Vec3(3, 0, 0.25f), Vec3(-1, 0, 0));
    REQUIRE(si.is_valid());
    CHECK(si.t == Approx(2.0f));
    CHECK(glm::length(si.p - Vec3(1, 0, 0.25f)) < 1e-6f);
    CHECK(glm::length(si.n - Vec3(1, 0, 0)) < 1e-6f);
    CHECK(si.uv.x == Approx(0.0f).margin(1e-6));
    CHECK(si.uv.y == Approx(0.25f));
    si = trace(*s, Vec3(0, 3, 0.5f), Vec3(0, -1, 0));
    CHECK(si.uv.x == Approx(0.25f));
    CHECK(glm::length(si.dpdu - Vec3(-TwoPi, 0, 0)) < 1e-4f);  // 2 pi (-y, x, 0)
    CHECK(glm::length(si.dpdv - Vec3(0, 0, 1)) < 1e-6f);
    // From inside the tube: the far wall, its normal still pointing out.
    si = trace(*s, Vec3(0, 0, 0.5f), Vec3(1, 0, 0));
    CHECK(si.t == Approx(1.0f));
    CHECK(si.n.x == Approx(1.0f));
    CHECK(Frame::cos_theta(si.wi) < 0.0f);  // seen from the back
    // Open ends: along the axis, or past the end, nothing.
    CHECK(!trace(*s, Vec3(0, 0, -2), Vec3(0, 0, 1)).is_valid());
    CHECK(!trace(*s, Vec3(3, 0, 1.2f), Vec3(-1, 0, 0)).is_valid());
    // Entering at z = 0.5 through a slanted ray.
    si = trace(*s, Vec3(3, 0, 1.5f), Vec3(-2, 0, -1));
    CHECK(glm::length(si.p - Vec3(1, 0, 0.5f)) < 1e-5f);
    REQUIRE(s->shapes().size() == 1);
    CHECK(s->shapes()[0]->surface_area() == Approx(TwoPi));
}

TEST_CASE("cylinder: p0, p1, radius and to_world place it, flip_normals turns it inside out", "[cylinder]") {
    auto dir = scratch_dir("cylinder-placed");
    Ref<Scene> s = load_scene_xml_in(dir, R"(<shape type="cylinder"><point name="p0" x="1" y="2" z="3"/><point name="p1" x="1" y="2" z="5"/>
        <float name="radius" value="0.5"/><transform name="to_world"><scale value="2"/></transform></shape>)");
    // Axis from (2, 4, 6) to (2, 4, 10), radius 1.
    SurfaceInteraction si = trace(*s, Vec3(5, 4, 8), Vec3(-1, 0, 0));
    CHECK(si.t == Approx(2.0f));
    CHECK(si.uv.y == Approx(0.5f));
    CHECK(s->shapes()[0]->surface_area() == Approx(TwoPi * 4.0f));
    // A tilted axis: the hit lies at distance radius from it.
    Ref<Scene> tilted =
        load_scene_xml_in(dir, R"(<shape type="cylinder"><point name="p1" x="1" y="1" z="1"/><float name="radius" value="0.3"/>
        <boolean name="flip_normals" value="true"/></shape>)");
    si = trace(*tilted, Vec3(2, -1, 0.5f), Vec3(-1, 1, 0.2f));
    REQUIRE(si.is_valid());
    Vec3 axis = glm::normalize(Vec3(1, 1, 1));
    Vec3 radial = si.p - axis * glm::dot(si.p, axis);
    CHECK(glm::length(radial) == Approx(0.3f).epsilon(1e-5));
    CHECK(glm::dot(si.n, glm::normalize(radial)) == Approx(-1.0f).epsilon(1e-5));  // flipped: inward
    CHECK(glm::dot(si.p, axis) / std::sqrt(3.0f) == Approx(si.uv.y).epsilon(1e-4));
}

TEST_CASE("cylinder: a to_world that shears it or squashes its cross-section is an error", "[cylinder][errors]") {
    auto dir = scratch_dir("cylinder-bad");
    for (const char* t : {R"(<scale x="2" y="1" z="1"/>)", R"(<matrix value="1 0.5 0 0  0 1 0 0  0 0 1 0  0 0 0 1"/>)"}) {
        INFO(t);
        CHECK_THROWS_AS(
            load_scene_xml_in(dir, std::string("<shape type=\"cylinder\"><transform name=\"to_world\">") + t + "</transform></shape>"),
            SceneError);
    }
    // Stretching along the axis is allowed.
    Ref<Scene> s = load_scene_xml_in(dir, R"(<shape type="cylinder"><transform name="to_world"><scale z="3"/></transform></shape>)");
    CHECK(s->shapes()[0]->surface_area() == Approx(TwoPi * 3.0f));
    CHECK_THROWS_AS(load_scene_xml_in(dir, R"(<shape type="cylinder"><float name="radius" value="0"/></shape>)"), SceneError);
    CHECK_THROWS_AS(load_scene_xml_in(dir, R"(<shape type="cylinder"><point name="p1" x="0" y="0" z="0"/></shape>)"), SceneError);
}

TEST_CASE("cylinder: renders like a finely tessellated tube (same random numbers)", "[cylinder][render]") {
    auto dir = scratch_dir("cylinder-render");
    const int segments = 1024;
    write_text(dir / "tube.obj", tessellated_tube_obj(segments));
    const char* rest =
        R"(<emitter type="directional"><vector name="direction" x="-1" y="2" z="-0.5"/><rgb name="irradiance" value="3"/></emitter>
        <emitter type="constant"><rgb name="radiance" value="0.2"/></emitter>
        <integrator type="path"><integer name="max_depth" value="3"/></integrator>
        <sensor type="perspective"><float name="fov" value="45"/>
            <transform name="to_world"><lookat origin="0.5, -4, 1.5" target="0, 0, 0.5" up="0, 0, 1"/></transform>
            <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
            <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="64"/><rfilter type="box"/></film></sensor>)";
    const char* material =
        R"(<bsdf type="diffuse"><texture type="checkerboard" name="reflectance"><rgb name="color0" value="0.8, 0.3, 0.1"/>
        <rgb name="color1" value="0.1, 0.4, 0.7"/><transform name="to_uv"><scale x="8" y="4"/></transform></texture></bsdf>)";
    std::vector<Image> images;
    for (std::string shape :
         {std::string("<shape type=\"cylinder\">") + material + "</shape>",
          std::string(
              "<shape type=\"obj\"><string name=\"filename\" value=\"tube.obj\"/><boolean name=\"flip_tex_coords\" value=\"false\"/>") +
              material + "</shape>"}) {
        write_text(dir / "scene.xml", scene_xml(shape + rest));
        images.push_back(render_file((dir / "scene.xml").string(), {}).image);
    }
    // The tube's chords are within r (1 - cos(pi / n)) = 5e-6 r of the circle, and its
    // interpolated normals and uvs match the exact ones to the same order: with the same random
    // numbers, a sample can only change where it lands within that distance of a silhouette or
    // a checker edge (a fraction ~ 1e-4 of the samples of the pixels those cross). So all but a
    // few pixels must agree to float precision, and the image means to 1e-3.
    int differing = 0, covered = 0;
    double sum[2] = {0, 0};
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            float a = luminance(images[0].rgb_at(x, y)), b = luminance(images[1].rgb_at(x, y));
            sum[0] += a;
            sum[1] += b;
            if (std::abs(a - b) > 1e-3f * std::max(a, b) + 1e-6f) ++differing;
            if (a > 0.25f) ++covered;  // brighter than the sky alone: the tube
        }
    INFO(differing << " of 4096 pixels differ; means " << sum[0] / 4096 << " vs " << sum[1] / 4096 << "; tube covers " << covered);
    CHECK(covered > 400);
    CHECK(differing <= 40);
    CHECK(std::abs(sum[0] - sum[1]) <= 1e-3 * sum[0]);
}

TEST_CASE("cylinder: as an area light it gives the irradiance of the tessellated tube", "[cylinder][estimate]") {
    auto dir = scratch_dir("cylinder-light");
    write_text(dir / "tube.obj", tessellated_tube_obj(2048));
    const char* light = R"(<emitter type="area"><rgb name="radiance" value="2"/></emitter>)";
    const char* place =
        R"(<transform name="to_world"><scale x="0.4" y="0.4" z="1.5"/><rotate x="1" angle="-70"/><translate x="0.3" y="1" z="-0.4"/></transform>)";
    EstimatorOptions o;
    o.samples = 400000;
    std::vector<Estimate> e;
    for (std::string shape :
         {std::string("<shape type=\"cylinder\">") + place + light + "</shape>",
          std::string("<shape type=\"obj\"><string name=\"filename\" value=\"tube.obj\"/>") + place + light + "</shape>"}) {
        Ref<Scene> scene = load_scene_xml_in(dir, shape);
        o.seed += 17;
        e.push_back(estimate_irradiance(*scene, Vec3(0.0f), Vec3(0, 1, 0), o));
    }
    // Discretisation: the tessellated tube's area is sin(2 pi / n) / (2 pi / n) = 1 - 4e-7 of the
    // tube's, far below the statistical error.
    double z = two_sided_z(sidak(0.01, CylinderTests));
    double se = std::hypot(e[0].luminance_std_error, e[1].luminance_std_error);
    INFO("cylinder " << e[0].luminance << " +- " << e[0].luminance_std_error << ", mesh " << e[1].luminance << " +- "
                     << e[1].luminance_std_error);
    CHECK(e[0].luminance > 0.1);
    CHECK(std::abs(e[0].luminance - e[1].luminance) <= z * se);
}

TEST_CASE("cylinder: area-light samples are uniform by area and their densities match tracing", "[cylinder][sampling]") {
    auto dir = scratch_dir("cylinder-sampling");
    Ref<Scene> scene = load_scene_xml_in(
        dir, R"(<shape type="cylinder"><point name="p0" x="-0.5" y="1" z="0.2"/><point name="p1" x="0.6" y="1.3" z="-0.3"/>
        <float name="radius" value="0.3"/><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)");
    const Shape& shape = *scene->shapes()[0];
    const Emitter& emitter = *scene->emitters()[0];
    Vec3 p0(-0.5f, 1, 0.2f), axis = Vec3(0.6f, 1.3f, -0.3f) - p0;
    float length = glm::length(axis);
    axis /= length;
    CHECK(shape.surface_area() == Approx(TwoPi * 0.3f * length));
    // Uniform by area means uniform in (phi, z), i.e. in uv: equal expected counts per cell.
    const int n = 200000, cells_u = 16, cells_v = 8;
    std::vector<double> counts(cells_u * cells_v, 0.0), expected(counts.size(), double(n) / double(counts.size()));
    PCG32 rng(5, 1);
    int off_surface = 0;
    for (int i = 0; i < n; ++i) {
        PositionSample ps = shape.sample_position(Vec2(rng.next_float(), rng.next_float()));
        Vec3 radial = ps.p - p0 - axis * glm::dot(ps.p - p0, axis);
        if (std::abs(glm::length(radial) - 0.3f) > 1e-5f || glm::dot(ps.n, glm::normalize(radial)) < 0.99999f ||
            std::abs(glm::dot(ps.p - p0, axis) / length - ps.uv.y) > 1e-5f || ps.pdf != 1.0f / shape.surface_area())
            ++off_surface;
        int cu = std::min(int(ps.uv.x * cells_u), cells_u - 1), cv = std::min(int(ps.uv.y * cells_v), cells_v - 1);
        counts[size_t(cv * cells_u + cu)] += 1.0;
    }
    ChiSquareResult r = chi_square(counts, expected);
    INFO(r.details << "; samples off the surface or with a wrong normal, uv or pdf: " << off_surface);
    CHECK(off_surface == 0);
    CHECK(r.p_value > sidak(0.01, CylinderTests));
    // Next-event estimation's density must be what the path tracer finds when it traces the
    // direction (MIS). Away from the silhouette: there d^2 / (A |cos|) turns the float error of
    // the traced hit point into a relative error of order 1e-7 / cos^2.
    SurfaceInteraction ref = virtual_vertex(*scene, Vec3(0.1f, 0, 0.1f), Vec3(0, 1, 0));
    int checked = 0, inconsistent = 0;
    for (int i = 0; i < 20000; ++i) {
        Spectrum weight;
        DirectionSample ds = emitter.sample_direction(ref, Vec2(rng.next_float(), rng.next_float()), weight);
        if (!(ds.pdf > 0.0f) || std::abs(glm::dot(ds.n, ds.d)) < 0.05f) continue;
        SurfaceInteraction si;
        REQUIRE(scene->intersect(Ray(ref.p, ds.d), si));
        DirectionSample traced;
        traced.p = si.p;
        traced.n = si.n;
        traced.d = ds.d;
        traced.dist = glm::length(si.p - ref.p);
        ++checked;
        if (std::abs(emitter.pdf_direction(ref, traced) - ds.pdf) > 1e-3f * ds.pdf) ++inconsistent;
    }
    INFO(checked << " directions traced");
    CHECK(checked > 5000);
    CHECK(inconsistent == 0);
}
