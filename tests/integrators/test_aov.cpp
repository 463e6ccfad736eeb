// The aov and moment integrators. AOVs are checked against known geometry under an orthographic
// camera: a rectangle at a known depth and a sphere. Every AOV is filtered like the radiance, so a
// pixel holds the mean over its samples; the checks use what survives averaging exactly: values
// constant over a pixel (depth, normals and partials of the plane, indices), affine relations
// between AOVs (uv of the plane from its position, the sphere's normal from its position, depth
// from height), and positions that must lie within the pixel's footprint. The moments are checked
// against the variance layer: m2 - m1^2 = (n - 1) / n times the sample variance, exactly.

#include "core/scene.h"
#include "core/spectral.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstring>

using namespace candela;
using namespace candela::test;

namespace {

constexpr int Size = 16, Spp = 16;
const Vec3 SphereCentre(0.4f, -0.4f, 0.0f);
constexpr float SphereRadius = 0.45f, PlaneZ = -1.0f, NearPlaneZ = 5.0f - 0.01f;
// The rectangle: [-1, 1]^2 scaled by (0.6, 0.4) and moved to (-0.2, 0.5, PlaneZ).
const Vec2 RectScale(0.6f, 0.4f), RectCentre(-0.2f, 0.5f);

std::string aov_scene(const std::string& integrator) {
    return scene_xml(integrator + R"(
        <sensor type="orthographic"><transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value=")" +
                     std::to_string(Spp) + R"("/></sampler>
            <film type="hdrfilm"><integer name="width" value=")" +
                     std::to_string(Size) + R"("/><integer name="height" value=")" + std::to_string(Size) +
                     R"("/><rfilter type="box"/><string name="component_format" value="float32"/></film></sensor>
        <emitter type="point"><point name="position" value="0, 0, 3"/><rgb name="intensity" value="5"/></emitter>
        <shape type="rectangle"><transform name="to_world"><scale x="0.6" y="0.4"/><translate x="-0.2" y="0.5" z="-1"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.3, 0.5, 0.7"/></bsdf></shape>
        <shape type="sphere"><point name="center" value="0.4, -0.4, 0"/><float name="radius" value="0.45"/>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf></shape>)");
}

const std::string AllAovs =
    "al:albedo, dd:depth, pp:position, tex:uv, gn:geo_normal, sn:sh_normal, du:dp_du, dv:dp_dv, "
    "dx:duv_dx, dy:duv_dy, pi:prim_index, sh:shape_index";

struct Channels {
    const Image& img;
    Vec3 v3(int x, int y, const std::string& name, const char* s = "XYZ") const {
        return Vec3(at(x, y, name + "." + s[0]), at(x, y, name + "." + s[1]), at(x, y, name + "." + s[2]));
    }
    Vec2 v2(int x, int y, const std::string& name) const { return Vec2(at(x, y, name + ".U"), at(x, y, name + ".V")); }
    float at(int x, int y, const std::string& channel) const {
        int c = img.channel_index(channel);
        REQUIRE(c >= 0);
        return img.at(x, y, c);
    }
};

// The world-space box that pixel (x, y) covers on the plane z = PlaneZ (orthographic: the same
// x and y for every depth).
void pixel_footprint(const Scene& scene, int x, int y, Vec2& lo, Vec2& hi) {
    lo = Vec2(Infinity);
    hi = Vec2(-Infinity);
    for (Vec2 corner : {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(1, 1)}) {
        Ray r = scene.sensor().sample_ray(Vec2(float(x), float(y)) + corner, Vec2(0.5f));
        lo = glm::min(lo, Vec2(r.o));
        hi = glm::max(hi, Vec2(r.o));
    }
}

void check_within(const Vec3& p, const Vec2& lo, const Vec2& hi) {
    CHECK(p.x >= lo.x - 1e-5f);
    CHECK(p.x <= hi.x + 1e-5f);
    CHECK(p.y >= lo.y - 1e-5f);
    CHECK(p.y <= hi.y + 1e-5f);
}

}  // namespace

TEST_CASE("aov: every AOV type against a rectangle and a sphere of known geometry", "[render][aov]") {
    Ref<Scene> scene = load_scene_from_string(aov_scene("<integrator type=\"aov\"><string name=\"aovs\" value=\"" + AllAovs +
                                                        "\"/><integrator type=\"path\" name=\"img\"/></integrator>"),
                                              source_path("scenes/aov_test.xml"));
    RenderOptions options;
    options.seed = 3;
    Image img = scene->integrator().render(*scene, options).image;
    // Mitsuba's channel order: the film's, the nested image's R, G, B, A, then the AOVs in order.
    std::vector<std::string> expected = {"R",    "G",    "B",    "img.R", "img.G", "img.B", "img.A", "al.R", "al.G",
                                         "al.B", "dd.T", "pp.X", "pp.Y",  "pp.Z",  "tex.U", "tex.V", "gn.X", "gn.Y",
                                         "gn.Z", "sn.X", "sn.Y", "sn.Z",  "du.X",  "du.Y",  "du.Z",  "dv.X", "dv.Y",
                                         "dv.Z", "dx.U", "dx.V", "dy.U",  "dy.V",  "pi.I",  "sh.I"};
    REQUIRE(img.channels() == expected);
    Channels ch{img};
    const Shape* rect = scene->shapes()[0].get();
    const Shape* sphere = scene->shapes()[1].get();
    // One differential step: one pixel (orthographic: the offset of the ray origins) over sqrt(spp).
    Vec3 step_x = scene->sensor().sample_ray(Vec2(1.5f, 0.5f), Vec2(0.5f)).o - scene->sensor().sample_ray(Vec2(0.5f, 0.5f), Vec2(0.5f)).o;
    Vec3 step_y = scene->sensor().sample_ray(Vec2(0.5f, 1.5f), Vec2(0.5f)).o - scene->sensor().sample_ray(Vec2(0.5f, 0.5f), Vec2(0.5f)).o;
    const float scale = 1.0f / std::sqrt(float(Spp));
    int counts[3] = {0, 0, 0};
    for (int y = 0; y < Size; ++y)
        for (int x = 0; x < Size; ++x) {
            PixelView view = pixel_view(*scene, x, y);
            if (view.mixed) continue;
            INFO("pixel (" << x << ", " << y << ")");
            // The nested image is the film's image, and its alpha says what was hit.
            for (int c = 0; c < 3; ++c) CHECK(img.at(x, y, c) == img.at(x, y, 3 + c));
            CHECK(ch.at(x, y, "img.A") == (view.nothing() ? 0.0f : 1.0f));
            Vec2 lo, hi;
            pixel_footprint(*scene, x, y, lo, hi);
            Vec3 p = ch.v3(x, y, "pp");
            if (view.nothing()) {
                ++counts[0];
                for (int c = 7; c < img.channel_count(); ++c) CHECK(img.at(x, y, c) == 0.0f);
            } else if (view.shape == rect) {
                ++counts[1];
                CHECK(glm::length(ch.v3(x, y, "al", "RGB") - Vec3(0.3f, 0.5f, 0.7f)) <
                      1e-6f);  // a constant, up to float rounding of the filter sums
                CHECK(ch.at(x, y, "dd.T") == Approx(NearPlaneZ - PlaneZ).epsilon(1e-6));
                check_within(p, lo, hi);
                CHECK(p.z == Approx(PlaneZ).epsilon(1e-6));
                // uv = ((x_object + 1) / 2, (y_object + 1) / 2), affine in the position.
                Vec2 object = (Vec2(p) - RectCentre) / RectScale;
                CHECK(ch.v2(x, y, "tex").x == Approx((object.x + 1.0f) / 2.0f).margin(1e-5));
                CHECK(ch.v2(x, y, "tex").y == Approx((object.y + 1.0f) / 2.0f).margin(1e-5));
                CHECK(ch.v3(x, y, "gn") == Vec3(0, 0, 1));
                CHECK(ch.v3(x, y, "sn") == Vec3(0, 0, 1));
                // dp/du and dp/dv: the square's edges, 2 units long in object space.
                CHECK(glm::length(ch.v3(x, y, "du") - Vec3(2.0f * RectScale.x, 0, 0)) < 1e-5f);
                CHECK(glm::length(ch.v3(x, y, "dv") - Vec3(0, 2.0f * RectScale.y, 0)) < 1e-5f);
                // uv per differential step: the step's world length over the edge length.
                Vec2 dx = ch.v2(x, y, "dx"), dy = ch.v2(x, y, "dy");
                CHECK(dx.x == Approx(step_x.x * scale / (2.0f * RectScale.x)).margin(1e-6));
                CHECK(dx.y == Approx(step_x.y * scale / (2.0f * RectScale.y)).margin(1e-6));
                CHECK(dy.x == Approx(step_y.x * scale / (2.0f * RectScale.x)).margin(1e-6));
                CHECK(dy.y == Approx(step_y.y * scale / (2.0f * RectScale.y)).margin(1e-6));
                // Triangle 0 lies below the square's diagonal (y < x in object space), 1 above.
                Vec2 olo = (lo - RectCentre) / RectScale, ohi = (hi - RectCentre) / RectScale;
                if (ohi.y < olo.x) CHECK(ch.at(x, y, "pi.I") == 0.0f);
                if (olo.y > ohi.x) CHECK(ch.at(x, y, "pi.I") == 1.0f);
                CHECK(ch.at(x, y, "sh.I") == 1.0f);
            } else {
                REQUIRE(view.shape == sphere);
                ++counts[2];
                CHECK(glm::length(ch.v3(x, y, "al", "RGB") - Vec3(0.8f)) < 1e-6f);
                check_within(p, lo, hi);
                // Per sample n = (p - c) / r and t = z_near - p.z: affine, so the pixel means obey them too.
                CHECK(glm::length(ch.v3(x, y, "gn") - (p - SphereCentre) / SphereRadius) < 1e-5f);
                CHECK(glm::length(ch.v3(x, y, "sn") - ch.v3(x, y, "gn")) < 1e-5f);
                CHECK(ch.at(x, y, "dd.T") == Approx(NearPlaneZ - p.z).epsilon(1e-5));
                // Points on the sphere: their mean lies inside it, by at most the sag over a pixel.
                float d = glm::length(p - SphereCentre);
                CHECK(d <= SphereRadius * (1.0f + 1e-5f));
                CHECK(d >= SphereRadius * 0.98f);
                Vec2 uv = ch.v2(x, y, "tex");
                CHECK((uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f));
                CHECK(ch.at(x, y, "sh.I") == 2.0f);
            }
        }
    CHECK(counts[0] > 20);
    CHECK(counts[1] > 20);
    CHECK(counts[2] > 20);
}

TEST_CASE("aov: the nested integrator's image is the image it renders alone, bit for bit", "[render][aov]") {
    std::string path = source_path("scenes/aov_test.xml");
    Ref<Scene> alone = load_scene_from_string(aov_scene("<integrator type=\"path\"/>"), path);
    Ref<Scene> nested = load_scene_from_string(
        aov_scene("<integrator type=\"aov\"><string name=\"aovs\" value=\"d:depth\"/><integrator type=\"path\"/></integrator>"), path);
    RenderOptions options;
    options.seed = 11;
    Image a = alone->integrator().render(*alone, options).image, b = nested->integrator().render(*nested, options).image;
    REQUIRE(b.channel_count() == 3 + 4 + 1);
    CHECK(std::memcmp(a.data().data(), b.select_channels({"R", "G", "B"}).data().data(), a.data().size() * sizeof(float)) == 0);
}

TEST_CASE("aov: bad specifications are errors at the aovs property", "[render][aov][errors]") {
    for (const char* aovs : {"dd:depth, nn", "dd:deepness", ":depth", "a:b:c"}) {
        INFO(aovs);
        CHECK_THROWS_AS(load_scene_from_string(
                            aov_scene(std::string("<integrator type=\"aov\"><string name=\"aovs\" value=\"") + aovs + "\"/></integrator>"),
                            source_path("scenes/aov_errors.xml")),
                        SceneError);
    }
    CHECK_THROWS_WITH(
        load_scene_from_string(
            aov_scene(R"(<integrator type="aov"><string name="aovs" value="d:depth"/><integrator type="raster"/></integrator>)"),
            source_path("scenes/aov_errors.xml")),
        Catch::Contains("only sampling integrators"));
}

TEST_CASE("moment: second moment minus first squared is the variance the variance layer reports", "[render][moment]") {
    // Inside the closed furnace sphere every sample is grey (R = G = B), so Y = R and the variance
    // of Y is that of each channel; X and Z are fixed multiples.
    std::string text = read_text(source_path("scenes/furnace/closed_sphere.xml"));
    std::string plain = "<integrator type=\"path\"><integer name=\"max_depth\" value=\"$max_depth\"/></integrator>";
    REQUIRE(text.find(plain) != std::string::npos);
    std::string moment = text;
    moment.replace(moment.find(plain), plain.size(),
                   "<integrator type=\"moment\"><integrator type=\"aov\" name=\"a\"><string name=\"aovs\" value=\"d:depth\"/>"
                   "<integrator type=\"path\" name=\"p\"/></integrator></integrator>");
    const int n = 64;
    SceneParameters params = {{"res", "8"}, {"spp", std::to_string(n)}};
    Ref<Scene> scene = load_scene_from_string(moment, source_path("scenes/furnace/closed_sphere_moment.xml"), params);
    RenderOptions options;
    options.aovs = {"variance"};
    options.seed = 5;
    Image img = scene->integrator().render(*scene, options).image;
    std::vector<std::string> first = {"a.p.R", "a.p.G", "a.p.B", "a.p.A", "a.d.T", "a.X", "a.Y", "a.Z"};
    std::vector<std::string> expected = {"R", "G", "B"};
    expected.insert(expected.end(), first.begin(), first.end());
    for (const std::string& c : first) expected.push_back("m2_" + c);
    for (const char* c : {"variance.R", "variance.G", "variance.B"}) expected.push_back(c);
    REQUIRE(img.channels() == expected);
    // The film's image is the path tracer's alone, bit for bit.
    Ref<Scene> alone = load_scene_from_string(text, source_path("scenes/furnace/closed_sphere.xml"), params);
    Image plain_img = alone->integrator().render(*alone, options).image;
    Channels ch{img};
    const Vec3d white = linear_srgb_to_xyz(Vec3d(1.0));
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            INFO("pixel (" << x << ", " << y << ")");
            CHECK(img.at(x, y, 0) == plain_img.at(x, y, 0));
            for (int k = 0; k < 3; ++k) {
                double m1 = ch.at(x, y, std::string("a.") + "XYZ"[k]), m2 = ch.at(x, y, std::string("m2_a.") + "XYZ"[k]);
                double sample_variance_of_mean = (m2 - m1 * m1) / (n - 1);
                double layer = ch.at(x, y, "variance.G") * white[k] * white[k];
                CHECK(layer > 0.0);
                CHECK(sample_variance_of_mean == Approx(layer).margin(1e-4 * m2 / (n - 1)));
            }
            // The camera sits at the centre: every ray meets the sphere at distance 1, and its depth
            // is that less the near plane's 0.01 / cos(theta) (where Mitsuba's camera rays start;
            // theta under 55 degrees here): no variance to speak of.
            double d = ch.at(x, y, "a.d.T");
            CHECK(d < 1.0 - 0.01);
            CHECK(d > 1.0 - 0.01 / std::cos(55.0 * Pi / 180.0));
            CHECK(ch.at(x, y, "m2_a.d.T") - d * d == Approx(0.0).margin(1e-5));
            CHECK(ch.at(x, y, "m2_a.p.A") == 1.0f);
        }
}

TEST_CASE("depth: the depth integrator and the aov depth measure from the near plane, as Mitsuba's camera rays start there",
          "[render][aov]") {
    // A perspective camera 5 units in front of a plane, near_clip 0.5, every sample at its pixel's
    // centre: a ray at angle theta to the axis meets the plane at 5 / cos(theta) from the eye and
    // enters the view at 0.5 / cos(theta), so its depth is 4.5 / cos(theta). The plane covers only
    // the left part of the view: pixels that see nothing have depth 0 and alpha 0.
    const std::string camera = R"(<sensor type="perspective"><float name="fov" value="40"/><float name="near_clip" value="0.5"/>
            <boolean name="jitter" value="false"/>
            <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="2"/></sampler>
            <film type="hdrfilm"><integer name="width" value="9"/><integer name="height" value="9"/><rfilter type="box"/>
                <string name="pixel_format" value="rgba"/><string name="component_format" value="float32"/></film></sensor>
        <shape type="rectangle"><transform name="to_world"><scale x="1" y="3"/><translate x="1.1"/></transform></shape>)";
    auto render = [&](const std::string& integrator) {
        Ref<Scene> scene = load_scene_from_string(scene_xml(integrator + camera), source_path("scenes/depth_test.xml"));
        return scene->integrator().render(*scene, RenderOptions()).image;
    };
    const Image depth = render(R"(<integrator type="depth"/>)");
    const Image aov = render(R"(<integrator type="aov"><string name="aovs" value="dd:depth"/></integrator>)");
    const float tan_half = std::tan(20.0f * Pi / 180.0f);
    int hits = 0, misses = 0;
    for (int y = 0; y < 9; ++y)
        for (int x = 0; x < 9; ++x) {
            // Camera space (Mitsuba's): +x toward the image's left, which is world -x here.
            const Vec3 d((1.0f - 2.0f * (x + 0.5f) / 9.0f) * tan_half, (1.0f - 2.0f * (y + 0.5f) / 9.0f) * tan_half, 1.0f);
            const float world_x = -5.0f * d.x;
            const bool hit = world_x > 0.1f && world_x < 2.1f;
            const float expected = hit ? 4.5f * glm::length(d) : 0.0f;
            INFO("pixel " << x << ", " << y);
            CHECK(depth.at(x, y, 0) == Approx(expected).epsilon(1e-5).margin(1e-6));
            CHECK(depth.at(x, y, 3) == (hit ? 1.0f : 0.0f));
            CHECK(aov.at(x, y, aov.channel_index("dd.T")) == Approx(expected).epsilon(1e-5).margin(1e-6));
            (hit ? hits : misses)++;
        }
    CHECK(hits >= 18);
    CHECK(misses >= 18);
}
