// Projector, textured spot, textured area and directionalarea lights: irradiance against closed
// forms through the estimators (delta lights have no variance, so there the tolerance is float
// rounding), power against an independent quadrature or Monte Carlo estimate, and the light
// tree never missing a light that contributes. The statistical checks here share a 1%
// family-wise level (Sidak).

#include "analysis/statistics.h"
#include "core/image.h"
#include "core/rng.h"
#include "core/warp.h"
#include "core/xml.h"
#include "integrators/estimators.h"
#include "lights/light_tree.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

constexpr int StatisticalTests = 2 * 3 + 3;  // textured area light: 2 points x 3 channels; spot power: 3 channels
const double Alpha = sidak(0.01, StatisticalTests);
const double Pi_d = 3.14159265358979323846;

Ref<Scene> scene_from(const std::string& body) { return load_scene_xml("projected_lights", body); }

// A w x h float EXR whose texel (x, y) (row 0 on top) holds values[y * w + x].
std::string write_texture(const std::string& name, int w, int h, const std::vector<Spectrum>& values) {
    Image img = Image::rgb(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.set_rgb(x, y, values[size_t(y) * w + x]);
    std::string path = (scratch_dir("texture-" + name) / name).string();  // scratch_dir empties its folder
    write_exr(img, path, true);
    return path;
}

// Eight distinct texels in a 4 x 2 image.
const std::vector<Spectrum> Texels = {{1, 2, 3},        {4, 5, 6},    {7, 8, 9}, {10, 11, 12},
                                      {0.5f, 0.25f, 2}, {3, 1, 0.5f}, {2, 2, 1}, {6, 0.5f, 4}};
Spectrum texel(int x, int y) { return Texels[size_t(y) * 4 + x]; }

std::string bitmap(const std::string& name, const std::string& path, const std::string& filter) {
    return R"(<texture type="bitmap" name=")" + name + R"("><string name="filename" value=")" + path +
           R"("/><string name="filter_type" value=")" + filter + R"("/></texture>)";
}

// Irradiance from a delta light: the estimator has no variance, so all channels must agree
// with the closed form to float rounding.
void check_exact_irradiance(const char* what, const Scene& scene, Vec3 p, Vec3 n, Spectrum exact) {
    EstimatorOptions o;
    o.samples = 64;
    Estimate e = estimate_irradiance(scene, p, n, o);
    INFO(what << ": " << e.mean.x << ", " << e.mean.y << ", " << e.mean.z << " exact " << exact.x << ", " << exact.y << ", " << exact.z);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(e.mean[c] - exact[c]) <= 1e-5 * std::max(1.0f, exact[c]));
}

// The flux through z = 1 of a light's camera space (the frustum of a projector) by the midpoint
// rule: the irradiance on that plane is the facing irradiance times cos(theta).
Spectrum flux_through_image_plane(const Emitter& e, const Transform& to_world, float tan_x, float tan_y, int nx, int ny) {
    double sum[3] = {0.0, 0.0, 0.0};
    double dA = (2.0 * tan_x / nx) * (2.0 * tan_y / ny);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            Vec3 local(tan_x * (2.0f * (i + 0.5f) / nx - 1.0f), tan_y * (2.0f * (j + 0.5f) / ny - 1.0f), 1.0f);
            SurfaceInteraction ref;
            ref.p = to_world.apply_point(local);
            Spectrum w;
            e.sample_direction(ref, Vec2(0.5f), w);
            for (int c = 0; c < 3; ++c) sum[c] += w[c] * dA / glm::length(local);  // cos(theta) = 1 / |local|
        }
    return Spectrum(float(sum[0]), float(sum[1]), float(sum[2]));
}

}  // namespace

TEST_CASE("projector: irradiance is pi scale T(uv) / z^2 on planes across the axis (Mitsuba's convention)", "[lights][projector]") {
    // A constant image: a plane at depth 3 is lit evenly inside the frustum (fov 60 along x, a
    // constant counts as a square image), nothing outside.
    Ref<Scene> flat = scene_from(
        R"(<emitter type="projector"><rgb name="irradiance" value="2, 1, 0.5"/><float name="scale" value="1.5"/><float name="fov" value="60"/>
        <transform name="to_world"><lookat origin="0, 3, 0" target="0, 0, 0" up="0, 0, 1"/></transform></emitter>)");
    Spectrum plane = Spectrum(2, 1, 0.5f) * float(Pi_d * 1.5 / 9.0);
    check_exact_irradiance("on the axis", *flat, Vec3(0.0f), Vec3(0, 1, 0), plane);
    check_exact_irradiance("off the axis", *flat, Vec3(0.5f, 0, -0.7f), Vec3(0, 1, 0), plane);
    float edge = 3.0f * std::tan(radians(30.0f));
    check_exact_irradiance("just inside the frustum", *flat, Vec3(edge * 0.98f, 0, edge * 0.98f), Vec3(0, 1, 0), plane);
    check_exact_irradiance("outside the frustum", *flat, Vec3(edge * 1.02f, 0, 0), Vec3(0, 1, 0), Spectrum(0.0f));
    // A receiver facing the projector gets the facing irradiance, 1 / cos(theta) more.
    Vec3 p(1.0f, 0.0f, 0.4f), to_light = glm::normalize(Vec3(0, 3, 0) - p);
    check_exact_irradiance("facing the projector", *flat, p, to_light, plane / to_light.y);

    // An image: a 4 x 2 bitmap, so the frustum is twice as wide as high; fov 90 along x. Looking
    // down -z with +y up, world +x is the image's right, and texel (3, 0) (top right) lands at
    // uv (0.875, 0.25): camera-space (-0.75 z, 0.25 z, z), world (1.5, 0.5, -2) at depth 2.
    std::string tex = write_texture("projector.exr", 4, 2, Texels);
    Ref<Scene> image = scene_from(R"(<emitter type="projector">)" + bitmap("irradiance", tex, "nearest") + R"(<float name="fov" value="90"/>
        <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, -1" up="0, 1, 0"/></transform></emitter>)");
    float k = float(Pi_d / 4.0);
    check_exact_irradiance("texel (3, 0)", *image, Vec3(1.5f, 0.5f, -2.0f), Vec3(0, 0, 1), texel(3, 0) * k);
    check_exact_irradiance("texel (0, 1)", *image, Vec3(-1.5f, -0.5f, -2.0f), Vec3(0, 0, 1), texel(0, 1) * k);
    check_exact_irradiance("texel (1, 0)", *image, Vec3(-0.5f, 0.5f, -2.0f), Vec3(0, 0, 1), texel(1, 0) * k);
    check_exact_irradiance("above the 2:1 frustum", *image, Vec3(0.0f, 1.1f, -2.0f), Vec3(0, 0, 1), Spectrum(0.0f));

    // Power: pi scale mean(T) (2 tan_x)(2 tan_y) equals the flux through the image plane.
    const Emitter& e = *image->emitters()[0];
    Spectrum flux = flux_through_image_plane(e, Transform::look_at(Vec3(0.0f), Vec3(0, 0, -1), Vec3(0, 1, 0)), 1.0f, 0.5f, 400, 200);
    for (int c = 0; c < 3; ++c) CHECK(e.power()[c] == Approx(flux[c]).epsilon(1e-4));
    // The light tree sees the whole frustum.
    auto b = e.bounds();
    REQUIRE(b);
    CHECK(light_importance(*b, Vec3(1.9f, 0.9f, -2.0f), Vec3(0, 0, 1)) > 0.0f);
}

TEST_CASE("spot: a texture is projected over the cone as Mitsuba maps it", "[lights][spot]") {
    std::string tex = write_texture("spot.exr", 4, 2, Texels);
    const char* placement = R"(<float name="cutoff_angle" value="30"/><float name="beam_width" value="20"/><rgb name="intensity" value="4"/>
        <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, -1" up="0, 1, 0"/></transform>)";
    Ref<Scene> scene = scene_from(R"(<emitter type="spot">)" + bitmap("texture", tex, "nearest") + placement + "</emitter>");
    // uv = 0.5 + 0.5 (x, y) / (z tan 30): texel (2, 0) (uv (0.625, 0.25)) lies along local
    // (0.25 t, -0.5 t, 1), t = tan 30, 17.9 degrees off the axis (inside the full beam). Local +x
    // is world -x here.
    float t = std::tan(radians(30.0f));
    Vec3 d = Vec3(-0.25f * t, -0.5f * t, -1.0f);
    Vec3 p = 2.0f * d;
    float r2 = squared_length(p);
    check_exact_irradiance("texel (2, 0)", *scene, p, -glm::normalize(d), texel(2, 0) * (4.0f / r2));
    // Texel (0, 1) (uv (0.125, 0.75)): local (-0.75 t, 0.5 t, 1), 27.5 degrees, on the ramp.
    Vec3 d2 = Vec3(0.75f * t, 0.5f * t, -1.0f);
    float theta = degrees(std::acos(-d2.z / glm::length(d2)));
    check_exact_irradiance("texel (0, 1) on the ramp", *scene, d2, -glm::normalize(d2),
                           texel(0, 1) * (4.0f * (30.0f - theta) / 10.0f / squared_length(d2)));

    // Power: intensity times falloff times texture over the cone, against a Monte Carlo estimate
    // (uniform directions in the cone) with its own error bar. A bilinear texture keeps the
    // plugin's quadrature error far below that error bar.
    Ref<Scene> smooth = scene_from(R"(<emitter type="spot">)" + bitmap("texture", tex, "bilinear") + placement + "</emitter>");
    const Emitter& e = *smooth->emitters()[0];
    const float cos_cutoff = std::cos(radians(30.0f));
    const int n = 200000;
    PCG32 rng(5, 9);
    std::vector<double> samples[3];
    for (int i = 0; i < n; ++i) {
        Vec3 local = warp::square_to_uniform_cone(Vec2(rng.next_float(), rng.next_float()), cos_cutoff);
        SurfaceInteraction ref;
        ref.p = Vec3(-local.x, local.y, -local.z);  // unit distance along the local direction
        Spectrum w;
        e.sample_direction(ref, Vec2(0.5f), w);
        for (int c = 0; c < 3; ++c) samples[c].push_back(w[c] / warp::square_to_uniform_cone_pdf(local, cos_cutoff));
    }
    for (int c = 0; c < 3; ++c) {
        MeanAndError m = mean_and_error(samples[c]);
        INFO("channel " << c << ": power " << e.power()[c] << ", Monte Carlo " << m.mean << " +- " << m.std_error);
        CHECK(std::abs(e.power()[c] - m.mean) <= two_sided_z(Alpha) * m.std_error);
    }
    // As in Mitsuba, a texture must vary in space.
    CHECK_THROWS_WITH(scene_from(R"(<emitter type="spot"><rgb name="texture" value="0.5"/></emitter>)"), Catch::Contains("texture"));
}

namespace {
// Form factor from a point to a parallel a x b rectangle with one corner straight above it at
// height 1 (times pi: the irradiance under radiance 1).
double corner_irradiance(double a, double b) {
    double sa = std::sqrt(1 + a * a), sb = std::sqrt(1 + b * b);
    return 0.5 * (a / sa * std::atan(b / sa) + b / sb * std::atan(a / sb));
}
}  // namespace

TEST_CASE("area: a textured radiance is looked up by uv, in light sampling and in BSDF hits alike", "[lights][area]") {
    // A 2w x 2h rectangle at height 1 facing down, its left half (u < 0.5, world x < 0) of
    // radiance La, its right half Lb (a 2 x 1 bitmap, nearest). Under x0, the halves split into
    // corner rectangles: E = 2 [La (C(w + x0, h) - C(x0, h)) + Lb (C(x0, h) + C(w - x0, h))].
    const Spectrum La(1.0f, 2.0f, 0.5f), Lb(5.0f, 1.0f, 3.0f);
    std::string tex = write_texture("area.exr", 2, 1, {La, Lb});
    const double w = 0.8, h = 0.5;
    Ref<Scene> scene = scene_from(
        R"(<shape type="rectangle"><transform name="to_world"><scale x="0.8" y="0.5"/><rotate x="1" angle="90"/><translate y="1"/></transform>
        <emitter type="area">)" +
        bitmap("radiance", tex, "nearest") + "</emitter></shape>");
    for (double x0 : {0.0, 0.3}) {
        EstimatorOptions o;
        o.samples = 200000;
        o.seed = 17;
        Estimate e = estimate_irradiance(*scene, Vec3(float(x0), 0, 0), Vec3(0, 1, 0), o);
        double left = corner_irradiance(w + x0, h) - corner_irradiance(x0, h),
               right = corner_irradiance(x0, h) + corner_irradiance(w - x0, h);
        for (int c = 0; c < 3; ++c) {
            double exact = 2.0 * (La[c] * left + Lb[c] * right);
            INFO("x0 " << x0 << ", channel " << c << ": " << e.mean[c] << " +- " << e.std_error[c] << ", exact " << exact);
            CHECK(std::abs(e.mean[c] - exact) <= two_sided_z(Alpha) * e.std_error[c]);
        }
    }
}

TEST_CASE("directionalarea: a beam of irradiance L with the shape's cross-section, black to the eye", "[lights][directionalarea]") {
    // A 1 x 1 rectangle at height 2 facing down, its halves of radiance 1 and 4 (2 x 1 bitmap).
    std::string tex = write_texture("beam.exr", 2, 1, {Spectrum(1.0f), Spectrum(4.0f, 3.0f, 2.0f)});
    std::string light =
        R"(<shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="2"/></transform>
        <emitter type="directionalarea">)" +
        bitmap("radiance", tex, "nearest") + "</emitter></shape>";
    Ref<Scene> scene = scene_from(light);
    check_exact_irradiance("in the beam, left half", *scene, Vec3(-0.25f, 0, 0.1f), Vec3(0, 1, 0), Spectrum(1.0f));
    check_exact_irradiance("in the beam, right half", *scene, Vec3(0.3f, 0, -0.4f), Vec3(0, 1, 0), Spectrum(4.0f, 3.0f, 2.0f));
    check_exact_irradiance("tilted receiver", *scene, Vec3(0.3f, 0, -0.4f), glm::normalize(Vec3(1, 1, 0)),
                           Spectrum(4.0f, 3.0f, 2.0f) * std::sqrt(0.5f));
    check_exact_irradiance("far below, still in the beam", *scene, Vec3(-0.2f, -40.0f, 0.3f), Vec3(0, 1, 0), Spectrum(1.0f));
    check_exact_irradiance("beside the beam", *scene, Vec3(0.6f, 0, 0), Vec3(0, 1, 0), Spectrum(0.0f));
    check_exact_irradiance("above the light", *scene, Vec3(0.0f, 3.0f, 0.0f), Vec3(0, -1, 0), Spectrum(0.0f));
    Ref<Scene> shadowed =
        scene_from(light + R"(<shape type="sphere"><point name="center" x="0.2" y="1" z="0"/><float name="radius" value="0.2"/></shape>)");
    check_exact_irradiance("under an occluder", *shadowed, Vec3(0.2f, 0, 0), Vec3(0, 1, 0), Spectrum(0.0f));

    // Seen directly it is black (Mitsuba's eval is zero too); its flux is L times the area.
    EstimatorOptions o;
    o.samples = 64;
    CHECK(estimate_radiance(*scene, Vec3(0.0f), Vec3(0, 1, 0), o).mean == Spectrum(0.0f));
    const Emitter& e = *scene->emitters()[0];
    CHECK(e.power().x == Approx(0.5f * 1.0f + 0.5f * 4.0f));

    // The light tree never rules out a point of the beam.
    auto b = e.bounds();
    REQUIRE(b);
    PCG32 rng(3, 3);
    int missed = 0;
    for (int i = 0; i < 10000; ++i) {
        Vec3 p(rng.next_float() - 0.5f, 2.0f - 100.0f * rng.next_float() * rng.next_float(), rng.next_float() - 0.5f);
        Vec3 n = warp::square_to_uniform_sphere(Vec2(rng.next_float(), rng.next_float()));
        if (n.y < 0.0f) n = -n;
        if (!(light_importance(*b, p, n) > 0.0f)) ++missed;
    }
    CHECK(missed == 0);

    // Curved shapes are refused: their beams cross.
    CHECK_THROWS_WITH(scene_from(R"(<shape type="sphere"><emitter type="directionalarea"/></shape>)"), Catch::Contains("planar"));
}
