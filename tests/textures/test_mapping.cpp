// Texture mappings (core/texture.h): spherical mapping on a sphere, cylindrical on a cylinder and
// planar on a rectangle, each placed by the shape's own transform, reproduce the shape's own
// parameterisation, so the image equals the one with the uv mapping; in the path tracer and in
// the raster mode. A mapping in the wrong frame changes the image (the check has power).

#include "core/image.h"
#include "core/rng.h"
#include "core/texture.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <fstream>

using namespace candela;
using namespace candela::test;

namespace {

// A smooth random texture (bilinear, repeating), written as a float EXR.
void write_texture(const std::filesystem::path& path) {
    Image img = Image::rgb(16, 8);
    PCG32 rng(7, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x)
            img.set_rgb(x, y, Spectrum(0.2f) + 0.7f * Spectrum(rng.next_float(), rng.next_float(), rng.next_float()));
    write_exr(img, path.string(), true);
}

// An open cylinder of radius 1 from z = 0 to 1 with Mitsuba's cylinder uv (phi / 2pi, z), as
// an OBJ (v stored as 1 - v: the loader flips it back).
void write_cylinder_obj(const std::filesystem::path& path, int segments) {
    std::ofstream out(path);
    for (int k = 0; k <= segments; ++k) {
        double phi = 2.0 * 3.14159265358979323846 * k / segments;
        for (int z = 0; z <= 1; ++z) {
            out << "v " << std::cos(phi) << " " << std::sin(phi) << " " << z << "\n";
            out << "vt " << double(k) / segments << " " << 1 - z << "\n";
            out << "vn " << std::cos(phi) << " " << std::sin(phi) << " 0\n";
        }
    }
    for (int k = 0; k < segments; ++k) {
        int a = 2 * k + 1, b = a + 1, c = a + 2, d = a + 3;  // (k, 0), (k, 1), (k + 1, 0), (k + 1, 1)
        out << "f " << a << "/" << a << "/" << a << " " << c << "/" << c << "/" << c << " " << d << "/" << d << "/" << d << "\n";
        out << "f " << a << "/" << a << "/" << a << " " << d << "/" << d << "/" << d << " " << b << "/" << b << "/" << b << "\n";
    }
}

std::string integrator(bool raster) {
    return raster
               ? R"(<integrator type="raster"><string name="texture_filter" value="bilinear"/><string name="shadows" value="none"/></integrator>)"
               : R"(<integrator type="path"><integer name="max_depth" value="2"/></integrator>)";
}

// A diffuse shape with the texture, under a uniform sky, seen from `origin`.
Image render_textured(const std::filesystem::path& dir, bool raster, const std::string& shape, const std::string& mapping,
                      const std::string& origin) {
    std::string xml = scene_xml(integrator(raster) + R"(
        <sensor type="perspective"><float name="fov" value="45"/>
            <transform name="to_world"><lookat origin=")" +
                                origin + R"(" target="0, 0, 0" up="0, 1, 0"/></transform>
            <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
            <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="48"/><rfilter type="box"/></film>
        </sensor>
        <texture type="bitmap" id="tex"><string name="filename" value="tex.exr"/>)" +
                                mapping + R"(</texture>
        <shape type=")" + shape +
                                R"(<bsdf type="twosided"><bsdf type="diffuse"><ref name="reflectance" id="tex"/></bsdf></bsdf></shape>
        <emitter type="constant"><rgb name="radiance" value="1"/></emitter>)");
    write_text(dir / "scene.xml", xml);
    Ref<Scene> scene = load_scene((dir / "scene.xml").string());
    RenderOptions options;
    options.seed = 5;
    return scene->integrator().render(*scene, options).image;
}

// Largest per-pixel difference and mean absolute difference, relative to the mean value.
void differences(const Image& a, const Image& b, double& max_rel, double& mean_rel) {
    double sum = 0.0, diff = 0.0, worst = 0.0;
    for (size_t i = 0; i < a.data().size(); ++i) {
        double d = std::abs(double(a.data()[i]) - double(b.data()[i]));
        sum += a.data()[i];
        diff += d;
        worst = std::max(worst, d);
    }
    double mean = sum / double(a.data().size());
    max_rel = worst / mean;
    mean_rel = diff / double(a.data().size()) / mean;
}

struct Case {
    const char* name;
    std::string shape;    // the shape element's opening up to its placement, closed by the caller
    std::string mapping;  // mapping properties that reproduce the shape's uv
    std::string wrong;    // the same mapping in a frame turned by 90 degrees
    std::string origin;
};

std::vector<Case> cases(const std::filesystem::path& dir) {
    write_cylinder_obj(dir / "cylinder.obj", 256);
    const std::string sphere_placement = R"(<rotate x="1" angle="70"/><rotate z="1" angle="30"/><scale value="1.2"/><translate x="0.1"/>)";
    const std::string cylinder_placement = R"(<scale x="0.6" y="0.6" z="1.6"/><rotate x="1" angle="-80"/><translate y="-0.8"/>)";
    const std::string rectangle_placement = R"(<scale x="1.4" y="0.8"/><rotate z="1" angle="20"/><rotate x="1" angle="-30"/>)";
    // The rectangle's uv is ((x + 1) / 2, (y + 1) / 2): the mapping's unit square goes on [-1, 1]^2.
    const std::string square_to_rectangle = R"(<scale x="2" y="2"/><translate x="-1" y="-1"/>)";
    auto frame = [](const std::string& kind, const std::string& placement) {
        return R"(<string name="mapping" value=")" + kind + R"("/><transform name="mapping_to_world">)" + placement + "</transform>";
    };
    const std::string turn = R"(<rotate z="1" angle="90"/>)";
    return {
        {"spherical on a sphere", R"(sphere"><transform name="to_world">)" + sphere_placement + "</transform>",
         frame("spherical", sphere_placement), frame("spherical", turn + sphere_placement), "0, 0.5, 4"},
        {"cylindrical on a cylinder",
         R"(obj"><string name="filename" value="cylinder.obj"/><transform name="to_world">)" + cylinder_placement + "</transform>",
         frame("cylindrical", cylinder_placement), frame("cylindrical", turn + cylinder_placement), "0.3, 0.4, 3.5"},
        {"planar on a rectangle", R"(rectangle"><transform name="to_world">)" + rectangle_placement + "</transform>",
         frame("planar", square_to_rectangle + rectangle_placement), frame("planar", square_to_rectangle + turn + rectangle_placement),
         "0, 0, 3"},
    };
}

// Renders every case with the uv mapping, the reproducing mapping and the turned one, and
// bounds the differences between the first two (largest pixel and mean, relative to the mean).
void check_mappings(const std::string& name, bool raster, double max_tolerance, double mean_tolerance) {
    auto dir = scratch_dir(name);
    write_texture(dir / "tex.exr");
    for (const Case& c : cases(dir)) {
        Image uv = render_textured(dir, raster, c.shape, "", c.origin);
        Image mapped = render_textured(dir, raster, c.shape, c.mapping, c.origin);
        Image wrong = render_textured(dir, raster, c.shape, c.wrong, c.origin);
        double max_rel, mean_rel, wrong_max, wrong_mean;
        differences(uv, mapped, max_rel, mean_rel);
        differences(uv, wrong, wrong_max, wrong_mean);
        INFO(c.name << ": max " << max_rel << " mean " << mean_rel << "; turned frame: mean " << wrong_mean);
        CHECK(max_rel < max_tolerance);
        CHECK(mean_rel < mean_tolerance);
        CHECK(wrong_mean > 0.05);
    }
}

}  // namespace

TEST_CASE("mapping: projections reproduce the shapes' own parameterisations in the path tracer", "[texture][mapping]") {
    // The same random numbers and texture values that differ only by float rounding in the
    // mapping (a few ulps of uv; the cylinder mesh's chords add about 1e-5 of a turn).
    check_mappings("mapping-path", false, 1e-3, 1e-5);
}

TEST_CASE("mapping: projections reproduce the shapes' own parameterisations in the raster mode", "[texture][mapping][raster]") {
    // The rasterizer interpolates vertex uvs linearly across the tessellation's flat triangles,
    // while the mapping projects the interpolated position: on curved shapes they differ by the
    // chord error of the tessellation (96 segments per turn).
    check_mappings("mapping-raster", true, 0.02, 1e-3);
}

TEST_CASE("mapping: parameters are checked", "[texture][mapping]") {
    auto dir = scratch_dir("mapping-errors");
    write_texture(dir / "tex.exr");
    auto load = [&](const std::string& texture_props) {
        write_text(dir / "bad.xml",
                   scene_xml(R"(<texture type="bitmap" id="t"><string name="filename" value="tex.exr"/>)" + texture_props +
                             R"(</texture><shape type="sphere"><bsdf type="diffuse"><ref name="reflectance" id="t"/></bsdf></shape>)"));
        return load_scene((dir / "bad.xml").string());
    };
    CHECK_THROWS_WITH(load(R"(<string name="mapping" value="cubic"/>)"), Catch::Contains("bad.xml:") && Catch::Contains("mapping must be"));
    CHECK_THROWS_WITH(load(R"(<transform name="mapping_to_world"><scale value="2"/></transform>)"), Catch::Contains("needs a planar"));
    CHECK_THROWS_WITH(load(R"(<string name="mapping" value="planar"/><transform name="mapping_to_world"><scale z="0"/></transform>)"),
                      Catch::Contains("bad.xml:") && Catch::Contains("singular"));
    // Seams: differences of s wrap the shorter way round for the periodic mappings only.
    TextureMapping m;
    m.kind = TextureMapping::Kind::Spherical;
    CHECK(m.difference(Vec2(0.98f, 0.5f), Vec2(0.01f, 0.5f)).x == Approx(0.03f));
    m.kind = TextureMapping::Kind::Planar;
    CHECK(m.difference(Vec2(0.98f, 0.5f), Vec2(0.01f, 0.5f)).x == Approx(-0.97f));
}
