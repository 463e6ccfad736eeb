// hdrfilm's pixel formats, sample_border and format errors. Every render of a scene uses the same
// seed, so the pixel formats only re-express the same filtered RGB: the checks are identities
// (XYZ = M rgb with Mitsuba's matrix, Y its middle row, A the fraction of the filter weight from
// samples that hit a surface), not stored numbers.

#include "core/scene.h"
#include "core/spectral.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <regex>

using namespace candela;
using namespace candela::test;

namespace {

constexpr int Size = 20;

// A diffuse sphere lit by a point light, nothing behind it (no environment): pixels off the
// sphere see nothing (alpha 0). `film` is inserted into the hdrfilm element.
std::string film_scene(const std::string& film, const std::string& filter = "box", int width = Size, int height = Size) {
    return scene_xml(R"(<integrator type="path"/>
        <sensor type="perspective"><float name="fov" value="40"/>
            <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="8"/></sampler>
            <film type="hdrfilm"><integer name="width" value=")" +
                     std::to_string(width) + R"("/><integer name="height" value=")" + std::to_string(height) + R"("/>
                <rfilter type=")" +
                     filter + R"("/>)" +
                     (film.find("component_format") == std::string::npos ? "<string name=\"component_format\" value=\"float32\"/>" : "") +
                     film +
                     R"(</film></sensor>
        <emitter type="point"><point name="position" value="1, 2, 3"/><rgb name="intensity" value="20"/></emitter>
        <shape type="sphere"><float name="radius" value="0.8"/>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.4, 0.2"/></bsdf></shape>)");
}

Image render_scene(const std::string& xml) {
    Ref<Scene> scene = load_scene_from_string(xml, source_path("scenes/hdrfilm_test.xml"));
    RenderOptions options;
    options.seed = 17;
    return scene->integrator().render(*scene, options).image;
}

Image render_format(const std::string& format) {
    return render_scene(film_scene("<string name=\"pixel_format\" value=\"" + format + "\"/>"));
}

}  // namespace

TEST_CASE("hdrfilm: pixel formats re-express the same filtered RGB as Mitsuba names them", "[render][film]") {
    Image rgb = render_format("rgb");
    REQUIRE(rgb.channels() == std::vector<std::string>{"R", "G", "B"});
    Image rgba = render_format("RGBA");  // names are case-insensitive, as in Mitsuba
    REQUIRE(rgba.channels() == std::vector<std::string>{"R", "G", "B", "A"});
    Image y = render_format("luminance"), ya = render_format("luminance_alpha");
    REQUIRE(y.channels() == std::vector<std::string>{"Y"});
    REQUIRE(ya.channels() == std::vector<std::string>{"Y", "A"});
    Image xyz = render_format("xyz"), xyza = render_format("xyza");
    REQUIRE(xyz.channels() == std::vector<std::string>{"X", "Y", "Z"});
    REQUIRE(xyza.channels() == std::vector<std::string>{"X", "Y", "Z", "A"});

    int empty = 0, covered = 0, partial = 0;
    for (int py = 0; py < Size; ++py)
        for (int px = 0; px < Size; ++px) {
            INFO("pixel (" << px << ", " << py << ")");
            Spectrum c = rgb.rgb_at(px, py);
            CHECK(rgba.rgb_at(px, py) == c);  // colour is not divided by alpha
            Vec3d expected = linear_srgb_to_xyz(Vec3d(c));
            const double tolerance = 1e-6 * (1.0 + expected.y);
            CHECK(y.at(px, py, 0) == Approx(luminance(c)).margin(tolerance));
            CHECK(y.at(px, py, 0) == Approx(expected.y).margin(tolerance));
            CHECK(ya.at(px, py, 0) == y.at(px, py, 0));
            for (int k = 0; k < 3; ++k) {
                CHECK(xyz.at(px, py, k) == Approx(expected[k]).margin(tolerance));
                CHECK(xyza.at(px, py, k) == xyz.at(px, py, k));
            }
            // Alpha: the same in every format with one; 0 where no sample hit, 1 where all did.
            float a = rgba.at(px, py, 3);
            CHECK(ya.at(px, py, 1) == a);
            CHECK(xyza.at(px, py, 3) == a);
            CHECK(a >= 0.0f);
            CHECK(a <= 1.0f);
            if (a == 0.0f) {
                ++empty;
                CHECK(c == Spectrum(0.0f));
            } else if (a == 1.0f) {
                ++covered;
            } else {
                ++partial;
            }
        }
    // The sphere covers the middle, the corners see nothing, its outline is partly covered.
    CHECK(empty > 40);
    CHECK(covered > 40);
    CHECK(partial > 10);
    // A white pixel's XYZ is D65 white (Mitsuba's matrix rows sum to the white point).
    Vec3d white = linear_srgb_to_xyz(Vec3d(1.0));
    CHECK(white.x == Approx(0.950456).epsilon(1e-5));
    CHECK(white.y == Approx(1.0).epsilon(1e-5));
    CHECK(white.z == Approx(1.088754).epsilon(1e-5));
}

TEST_CASE("hdrfilm: sample_border makes a crop window's edge pixels those of the full film", "[render][film]") {
    // With a gaussian filter (radius 2: a border of 2 pixels), the pixels of a crop window get
    // samples from their neighbours outside it only with sample_border. Samples depend only on
    // (seed, pixel, index), so the cropped render with sample_border equals the full render
    // inside the window, up to the order of float sums; without it, the window's edge differs.
    const std::string crop = R"(<integer name="crop_offset_x" value="5"/><integer name="crop_offset_y" value="4"/>
        <integer name="crop_width" value="9"/><integer name="crop_height" value="11"/>)";
    Image full = render_scene(film_scene("", "gaussian"));
    Image bordered = render_scene(film_scene(crop + "<boolean name=\"sample_border\" value=\"true\"/>", "gaussian"));
    Image plain = render_scene(film_scene(crop, "gaussian"));
    REQUIRE(bordered.width() == 9);
    REQUIRE(bordered.height() == 11);
    int edge_differs = 0;
    for (int y = 0; y < 11; ++y)
        for (int x = 0; x < 9; ++x) {
            INFO("crop pixel (" << x << ", " << y << ")");
            bool interior = x >= 2 && y >= 2 && x < 9 - 2 && y < 11 - 2;
            for (int c = 0; c < 3; ++c) {
                float f = full.at(x + 5, y + 4, c);
                CHECK(bordered.at(x, y, c) == Approx(f).epsilon(1e-5).margin(1e-7));
                if (interior)
                    CHECK(plain.at(x, y, c) == Approx(f).epsilon(1e-5).margin(1e-7));
                else if (std::abs(plain.at(x, y, c) - f) > 1e-3f * (1.0f + f))
                    ++edge_differs;
            }
        }
    CHECK(edge_differs > 20);  // without sample_border the edge pixels miss their outer samples
    // A box filter reaches no neighbour: sample_border changes nothing, bit for bit.
    Image box = render_scene(film_scene(crop)),
          box_border = render_scene(film_scene(crop + "<boolean name=\"sample_border\" value=\"true\"/>"));
    CHECK(std::memcmp(box.data().data(), box_border.data().data(), box.data().size() * sizeof(float)) == 0);
}

TEST_CASE("hdrfilm: every reconstruction filter keeps a uniform image uniform and a sharp edge finite", "[render][film]") {
    // The film divides each pixel's weighted sum by its sum of weights, so where every sample has
    // the same value the pixel has it too, whatever the weights, negative lobes (mitchell,
    // catmullrom, lanczos) included, in a crop window and at the film's edges. Then the lit sphere's
    // silhouette: negative lobes ring (pixels may dip below zero, as in Mitsuba), never to NaN.
    const std::string uniform = scene_xml(R"(<integrator type="path"/>
        <sensor type="perspective"><float name="fov" value="40"/>
            <sampler type="independent"><integer name="sample_count" value="3"/></sampler>
            <film type="hdrfilm"><integer name="width" value="13"/><integer name="height" value="9"/>
                <string name="component_format" value="float32"/><rfilter type="$filter"/>$crop</film></sensor>
        <emitter type="constant"><rgb name="radiance" value="0.25, 0.5, 2"/></emitter>)");
    const std::string crop = R"(<integer name="crop_offset_x" value="3"/><integer name="crop_width" value="7"/>
        <boolean name="sample_border" value="true"/>)";
    for (const char* filter : {"box", "tent", "gaussian", "mitchell", "catmullrom", "lanczos"}) {
        for (const std::string& window : {std::string(), crop}) {
            std::string xml = std::regex_replace(uniform, std::regex("\\$filter"), filter);
            xml = std::regex_replace(xml, std::regex("\\$crop"), window);
            INFO(filter << (window.empty() ? "" : ", crop window with sample_border"));
            const Image image = render_scene(xml);
            REQUIRE(image.width() == (window.empty() ? 13 : 7));
            for (int y = 0; y < image.height(); ++y)
                for (int x = 0; x < image.width(); ++x) {
                    CHECK(image.at(x, y, 0) == Approx(0.25).epsilon(1e-5));
                    CHECK(image.at(x, y, 1) == Approx(0.5).epsilon(1e-5));
                    CHECK(image.at(x, y, 2) == Approx(2.0).epsilon(1e-5));
                }
        }
        const Image edge = render_scene(film_scene("", filter));
        bool finite = true;
        for (float v : edge.data()) finite = finite && std::isfinite(v);
        CHECK(finite);
    }
}

TEST_CASE("hdrfilm: unsupported formats are errors at their property", "[film][errors]") {
    auto fails = [](const std::string& film, const std::string& message) {
        INFO(film);
        try {
            render_scene(film_scene(film));
            FAIL_CHECK("expected an error");
        } catch (const SceneError& e) {
            CHECK_THAT(std::string(e.what()), Catch::Contains(message));
        }
    };
    fails(R"(<string name="pixel_format" value="rgbw"/>)", "pixel_format");
    fails(R"(<string name="component_format" value="uint32"/>)", "uint32");
    fails(R"(<string name="file_format" value="pfm"/>)", "OpenEXR");
    fails(R"(<boolean name="sample_border" value="true"/><boolean name="high_quality_edges" value="true"/>)", "not both");
}
