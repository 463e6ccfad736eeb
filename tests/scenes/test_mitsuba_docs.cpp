// Scenes behind Mitsuba 3's plugin documentation (mitsuba-data docs/scenes, see
// tests/scenes/mitsuba_docs/README.md), unchanged, load and render at 1 spp: a Cornell box with
// measured spectra found through a search folder, an analytic sphere light, B-spline curves, a
// conductor with wavelength:value spectra, two coloured spot lights, and the four motion-blur
// scenes (a moving instance, camera and spot light, and the rotation's slerp pose). The binary
// assets they name (matpreview.serialized, museum.exr, envmap.exr, bunny.ply, teapot.ply) are not
// in this repository: the test writes stand-ins of the same kind and name (the serialized writer
// of tests/, a sky gradient, small PLY spheres).
// Each check can fail: the light seen directly has exactly its emission's colour, the walls
// keep their colours, the spots light the scene in red and blue only.
// Six scenes more come from an older copy (mitsuba-data as forked by acdupont, see the README):
// they name their search folder with Mitsuba 2's <resource_path>, which Mitsuba 3 calls <path>;
// unchanged they stop at that line, and with it renamed (as mitsuba-data now writes it) they
// render: textured anisotropic roughness, PLY vertex and face colours, the aov integrator's
// channels, three polarisers and a textured analytic sphere.
// Under CANDELA_TEST_EFFORT below 1 (the sanitizer stage) the scratch copies' films are shrunk to
// that fraction of their pixels: the checks are per-pixel properties, means and fractions of the
// image, which hold at any size; what the sanitizers look at (loading, every plugin's code on the
// path) is the same.

#include "core/image.h"
#include "core/spectral.h"
#include "core/xml.h"
#include "tests/scoped_search_folders.h"
#include "tests/serialized_writer.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <regex>

using namespace candela;
using namespace candela::test;
namespace fs = std::filesystem;

namespace {

// A uv sphere of radius r about c, with normals and uvs.
TestMesh uv_sphere(float r, const Vec3& c, int nu, int nv) {
    TestMesh m;
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            float theta = Pi * float(j) / float(nv), phi = 2.0f * Pi * float(i) / float(nu);
            Vec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
            m.positions.push_back(c + r * n);
            m.normals.push_back(n);
            m.uvs.push_back(Vec2(float(i) / float(nu), float(j) / float(nv)));
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            uint32_t a = uint32_t(j * (nu + 1) + i), b = a + uint32_t(nu + 1);
            if (j > 0) m.triangles.push_back({a, b, a + 1});
            if (j < nv - 1) m.triangles.push_back({a + 1, b, b + 1});
        }
    return m;
}

// A mesh as an ASCII PLY file (positions and triangles).
std::string ascii_ply(const TestMesh& m) {
    std::string out = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(m.positions.size()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(m.triangles.size()) +
                      "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3& p : m.positions) out += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    for (const auto& t : m.triangles) out += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
    return out;
}

// A film side of `pixels` in the docs scenes as the test renders it: shrunk with the test effort
// so that the image has that fraction of the pixels.
int film_side(int pixels) { return std::max(8, int(std::lround(pixels * std::sqrt(test_effort())))); }

// Rewrites every film's literal width and height in the XML files under `dir` to film_side.
void shrink_films(const fs::path& dir) {
    const std::regex side(R"re((<integer name="(?:width|height)" value=")([0-9]+)("))re");
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
        if (entry.path().extension() != ".xml") continue;
        const std::string text = read_text(entry.path());
        std::string out;
        auto last = text.cbegin();
        for (std::sregex_iterator m(text.begin(), text.end(), side), end; m != end; ++m) {
            out.append(last, (*m)[0].first);
            out += (*m)[1].str() + std::to_string(film_side(std::stoi((*m)[2].str()))) + (*m)[3].str();
            last = (*m)[0].second;
        }
        out.append(last, text.cend());
        if (out != text) write_text(entry.path(), out);
    }
}

// The docs scenes copied to a scratch folder (mitsuba-data's layout: docs/scenes and common),
// with stand-ins for the binary assets: matpreview.serialized holds a unit plane (shape 0), an
// inner sphere (1) and the preview object, a unit sphere (2); the environment maps are a sky
// gradient, brighter above the horizon.
fs::path docs_folder() {
    fs::path dir = scratch_dir("mitsuba-docs");
    fs::copy(source_path("tests/scenes/mitsuba_docs"), dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    if (test_effort() < 1.0) shrink_films(dir);
    TestMesh plane;
    plane.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    plane.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    plane.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    plane.triangles = {{0, 1, 2}, {0, 2, 3}};
    write_text(dir / "common" / "meshes" / "matpreview.serialized",
               encode_file({plane, uv_sphere(0.6f, Vec3(0, 0, 0.85f), 16, 8), uv_sphere(1.0f, Vec3(0.0f), 32, 16)}, 4));
    fs::create_directories(dir / "common" / "textures");
    Image sky = Image::rgb(32, 16);
    for (int y = 0; y < sky.height(); ++y)
        for (int x = 0; x < sky.width(); ++x)
            sky.set_rgb(x, y, Spectrum(y < sky.height() / 2 ? 1.0f - float(y) / float(sky.height()) : 0.25f));
    for (const char* name : {"museum.exr", "envmap.exr"}) write_exr(sky, (dir / "common" / "textures" / name).string(), true);
    // The PLY meshes of the animation scenes: small spheres where the bunny (about 0.15 across,
    // scaled by 12) and the teapot (recentred by -0.215, scaled by 0.42) would stand.
    write_text(dir / "common" / "meshes" / "bunny.ply", ascii_ply(uv_sphere(0.05f, Vec3(0.0f, 0.0f, 0.05f), 16, 8)));
    write_text(dir / "common" / "meshes" / "teapot.ply", ascii_ply(uv_sphere(0.8f, Vec3(0.6f, 0.0f, 1.0f), 16, 8)));
    return dir;
}

// The older copies name their search folder as <resource_path value="..."/>; mitsuba-data now
// writes <path value="..."/>. Rewrites a scratch copy so.
void rename_resource_path(const fs::path& file) {
    std::string text = read_text(file);
    const std::string old_tag = "<resource_path ", new_tag = "<path ";
    for (size_t at = text.find(old_tag); at != std::string::npos; at = text.find(old_tag, at)) text.replace(at, old_tag.size(), new_tag);
    write_text(file, text);
}

Image render(const fs::path& scene_file, const std::vector<fs::path>& search = {}, SceneParameters defines = {},
             Variant variant = Variant::ScalarRGB) {
    INFO(scene_file.string());
    defines["spp"] = "1";
    ScopedSearchFolders folders(search);
    Ref<Scene> scene = load_scene(scene_file.string(), defines, variant);
    RenderOptions options;
    options.spp = 1;
    options.seed = 3;
    return scene->integrator().render(*scene, options).image;
}

struct Summary {
    Spectrum mean{0.0f}, max{0.0f};
    bool finite = true;
};

Summary summarize(const Image& img, int x0, int x1) {
    Summary s;
    for (int y = 0; y < img.height(); ++y)
        for (int x = x0; x < x1; ++x) {
            Spectrum v = img.rgb_at(x, y);
            s.finite = s.finite && all_finite(v);
            s.mean += v / float((x1 - x0) * img.height());
            s.max = glm::max(s.max, v);
        }
    return s;
}
Summary summarize(const Image& img) { return summarize(img, 0, img.width()); }

}  // namespace

TEST_CASE("mitsuba docs scenes: the spectral Cornell box renders through a search folder", "[scenes][docs]") {
    fs::path dir = docs_folder();
    fs::path scene = dir / "docs" / "scenes" / "variants_cbox_spectral.xml";
    // It names meshes/cbox_*.obj without a <path>: Mitsuba renders it with common/ on the search path.
    CHECK_THROWS_AS(load_scene(scene.string(), {{"spp", "1"}}), SceneError);
    // With max_depth 1 only the luminaire is seen: through a box filter, exactly its emission
    // spectrum in RGB.
    Summary direct = summarize(render(scene, {dir / "common"}, {{"max_depth", "1"}}));
    CHECK(direct.finite);
    Spectrum light = spectrum_to_rgb(parse_spectrum_pairs("400:0, 500:8, 600:15.6, 700:18.4"), false, false);
    for (int c = 0; c < 3; ++c) CHECK(direct.max[c] == Approx(light[c]).epsilon(1e-4));
    Image img = render(scene, {dir / "common"});
    REQUIRE(img.width() == film_side(500));
    Summary all = summarize(img);
    CHECK(all.finite);
    CHECK(all.mean.x > direct.mean.x);
    // The red wall is on the image's left, the green one on its right (Mitsuba's camera looks
    // down +z with +x to the left).
    const int w = img.width();
    Summary left = summarize(img, w / 100, w * 12 / 100), right = summarize(img, w * 88 / 100, w * 99 / 100);
    CHECK(left.mean.x > 2.0f * left.mean.y);
    CHECK(right.mean.y > 1.5f * right.mean.x);
}

TEST_CASE("mitsuba docs scenes: analytic sphere light, B-spline curves, spectral gold, coloured spots", "[scenes][docs]") {
    fs::path dir = docs_folder();
    fs::path scenes = dir / "docs" / "scenes";
    {
        // An area-light sphere of radiance <spectrum value="20"/> (the equal-energy white, pink
        // against sRGB's white) over a rough plastic plane. Its default diffuse BSDF adds what it
        // reflects of the dim surroundings (a constant 0.1 environment): well under 0.15.
        Summary s = summarize(render(scenes / "shape_sphere_light_analytic.xml"));
        CHECK(s.finite);
        Spectrum emission = uniform_emission_rgb(20.0);
        for (int c = 0; c < 3; ++c) {
            CHECK(s.max[c] >= emission[c] * (1.0f - 1e-5f));
            CHECK(s.max[c] <= emission[c] + 0.15f);
        }
    }
    {
        Image curves = render(scenes / "shape_bsplinecurve_basic.xml");
        Summary s = summarize(curves);
        CHECK(curves.width() == film_side(960));
        CHECK(s.finite);
        CHECK(s.mean.z > 0.1f);
    }
    {
        // No <path>: found through the search folder; eta and k given as wavelength:value pairs.
        Summary s = summarize(render(scenes / "bsdf_conductor_gold.xml", {dir / "common"}));
        CHECK(s.finite);
        CHECK(s.mean.x > 0.1f);
    }
    {
        // Red and blue spots over a dim grey environment: much more red and blue than green.
        Summary s = summarize(render(scenes / "emitter_spot_no_texture.xml"));
        CHECK(s.finite);
        CHECK(s.mean.x > 2.0f * s.mean.y);
        CHECK(s.mean.z > 2.0f * s.mean.y);
    }
}

TEST_CASE("mitsuba docs scenes: the four motion-blur scenes render (moving instance, camera, spot light, slerp pose)",
          "[scenes][docs][animation]") {
    fs::path dir = docs_folder();
    fs::path scenes = dir / "docs" / "scenes";
    for (const char* name : {"animation_shape.xml", "animation_sensor.xml", "animation_emitter.xml"}) {
        INFO(name);
        Summary s = summarize(render(scenes / name));
        CHECK(s.finite);
        CHECK(s.mean.x > 0.0f);
        // The floor is lit: an environment of scale 3 (0.12 with the spot) and the spot.
        CHECK(s.max.x > 0.05f);
    }
    // The rotation scene's closed shutter at 0.23 (one pose), and its blurred version.
    Image still = render(scenes / "animation_rotation.xml");
    Image blurred = render(scenes / "animation_rotation.xml", {}, {{"shutter_open", "0"}, {"shutter_close", "1"}});
    CHECK(still.width() == film_side(720));
    CHECK(summarize(still).finite);
    CHECK(summarize(blurred).finite);
    double differing = 0;
    for (size_t i = 0; i < still.data().size(); ++i) differing += still.data()[i] != blurred.data()[i];
    CHECK(differing > 0);
    // photonmapper renders no motion: it stops and says so (ptracer and sppm render it:
    // tests/integrators/test_light_path_motion.cpp).
    CHECK_THROWS_WITH(render(scenes / "animation_shape.xml", {}, {{"integrator", "photonmapper"}}), Catch::Contains("motion blur"));
}

TEST_CASE("mitsuba docs scenes from an older copy: resource_path stops and once renamed to path six more scenes render", "[scenes][docs]") {
    fs::path dir = docs_folder();
    fs::path scenes = dir / "docs" / "scenes";
    // The mesh-attribute scenes' PLY: the bunny stand-in's sphere, red at every vertex and blue
    // on every face (mitsuba-data's file holds random colours of both kinds).
    TestMesh bunny = uv_sphere(0.05f, Vec3(0.0f, 0.0f, 0.05f), 16, 8);
    std::string ply =
        "ply\nformat ascii 1.0\nelement vertex " + std::to_string(bunny.positions.size()) +
        "\nproperty float x\nproperty float y\nproperty float z\nproperty float r\nproperty float g\nproperty float b\nelement face " +
        std::to_string(bunny.triangles.size()) +
        "\nproperty list uchar int vertex_indices\nproperty float r\nproperty float g\nproperty float b\nend_header\n";
    for (const Vec3& p : bunny.positions) ply += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + " 1 0 0\n";
    for (const auto& t : bunny.triangles)
        ply += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + " 0 0 1\n";
    write_text(dir / "common" / "meshes" / "bunny_attribute_color.ply", ply);

    CHECK_THROWS_WITH(load_scene((scenes / "texture_mesh_attribute_vertex.xml").string(), {{"spp", "1"}}), Catch::Contains("<path value="));
    for (const char* name :
         {"bsdf_roughconductor_textured_carbon.xml", "texture_mesh_attribute_face.xml", "texture_mesh_attribute_vertex.xml",
          "integrator_aov.xml", "include/integrator_scene.xml", "bsdf_polarizer_middle.xml", "shape_sphere_parameterization.xml"})
        rename_resource_path(scenes / name);
    for (const char* name : {"bsdf_roughconductor_textured_carbon.xml", "bsdf_polarizer_middle.xml", "shape_sphere_parameterization.xml"}) {
        INFO(name);
        Summary s = summarize(render(scenes / name));
        CHECK(s.finite);
        CHECK(s.mean.x > 0.05f);
    }
    {
        // The same scene but for the attribute read: the vertex colours make the object red, the
        // face colours blue, everything else is equal (same seed, same paths).
        Summary vertex = summarize(render(scenes / "texture_mesh_attribute_vertex.xml"));
        Summary face = summarize(render(scenes / "texture_mesh_attribute_face.xml"));
        CHECK(vertex.finite);
        CHECK(face.finite);
        CHECK(vertex.mean.x > face.mean.x);
        CHECK(vertex.mean.z < face.mean.z);
    }
    {
        // aovs "nn:sh_normal, position:position, depth.y:depth" with the path tracer as "image":
        // Mitsuba's channel names, and unit normals wherever the depth says something was hit.
        Image aov = render(scenes / "integrator_aov.xml");
        for (const char* channel : {"R", "G", "B", "depth.y.T", "image.R", "nn.X", "nn.Y", "nn.Z", "position.X", "position.Z"})
            CHECK(aov.channel_index(channel) >= 0);
        int depth = aov.channel_index("depth.y.T"), nx = aov.channel_index("nn.X");
        REQUIRE(depth >= 0);
        REQUIRE(nx >= 0);
        int hits = 0;
        for (int y = 0; y < aov.height(); ++y)
            for (int x = 0; x < aov.width(); ++x) {
                if (aov.at(x, y, depth) <= 0.0f) continue;
                Vec3 n(aov.at(x, y, nx), aov.at(x, y, nx + 1), aov.at(x, y, nx + 2));
                hits += std::abs(glm::length(n) - 1.0f) < 0.02f;
            }
        CHECK(hits > aov.width() * aov.height() / 4);
    }
}

TEST_CASE("mitsuba docs scenes: polarisation in scalar_spectral_polarized (stokes on pplastic and a Cornell box, three polarisers)",
          "[scenes][docs][polarized]") {
    fs::path dir = docs_folder();
    fs::path scenes = dir / "docs" / "scenes";
    // The older copy names the Cornell box meshes meshes/cbox/<part>.obj.
    fs::create_directories(dir / "common" / "meshes" / "cbox");
    for (const char* part : {"luminaire", "floor", "ceiling", "back", "greenwall", "redwall"})
        fs::copy_file(dir / "common" / "meshes" / ("cbox_" + std::string(part) + ".obj"),
                      dir / "common" / "meshes" / "cbox" / (std::string(part) + ".obj"), fs::copy_options::overwrite_existing);
    for (const char* name : {"integrator_stokes_cbox.xml", "bsdf_polarizer_middle.xml"}) rename_resource_path(scenes / name);
    const Variant polarized = Variant::ScalarSpectralPolarized;
    // The mean |S_k| / S0 over the image: how polarised its light is.
    auto polarisation = [](const Image& img, int k) {
        const int s0 = img.channel_index("S0.G"), sk = img.channel_index("S" + std::to_string(k) + ".G");
        REQUIRE(s0 >= 0);
        REQUIRE(sk >= 0);
        double sum0 = 0.0, sumk = 0.0;
        for (int y = 0; y < img.height(); ++y)
            for (int x = 0; x < img.width(); ++x) {
                sum0 += img.at(x, y, s0);
                sumk += std::abs(img.at(x, y, sk));
            }
        return sumk / sum0;
    };
    // A specular pplastic polarises what it reflects (Fresnel); with only its diffuse part, the
    // light leaves through the coating, much less polarised.
    const Image specular = render(scenes / "bsdf_pplastic_specular_stokes.xml", {}, {}, polarized);
    const Image diffuse = render(scenes / "bsdf_pplastic_diffuse_stokes.xml", {}, {}, polarized);
    CHECK(summarize(specular).finite);
    CHECK(summarize(diffuse).finite);
    for (const char* channel : {"S0.R", "S1.G", "S2.B", "S3.R"}) CHECK(specular.channel_index(channel) >= 0);
    CHECK(polarisation(specular, 1) + polarisation(specular, 2) > 0.01);
    CHECK(polarisation(diffuse, 1) + polarisation(diffuse, 2) < 0.5 * (polarisation(specular, 1) + polarisation(specular, 2)));
    // The Cornell box of the stokes docs (glass and metal spheres): the conductor's complex index
    // turns linear into elliptical light, so S3 is not 0 either.
    const Image cbox = render(scenes / "integrator_stokes_cbox.xml", {}, {{"res", "64"}}, polarized);
    CHECK(summarize(cbox).finite);
    CHECK(polarisation(cbox, 1) + polarisation(cbox, 2) > 0.005);
    CHECK(polarisation(cbox, 3) > 0.0);
    // In RGB the stokes scenes stop at the integrator's line and name the variant.
    CHECK_THROWS_WITH(render(scenes / "integrator_stokes_cbox.xml", {}, {{"res", "64"}}), Catch::Contains("scalar_spectral_polarized"));
    // Three polarisers (0, 45 about the view and 90 degrees), as the docs' picture shows them:
    // where only those at 0 and 90 degrees overlap nothing passes (unpolarised, a quarter does);
    // where the middle one lies between them an eighth passes either way. The same seed draws the
    // same numbers in both spectral variants.
    const Image unpolarised = render(scenes / "bsdf_polarizer_middle.xml", {}, {}, Variant::ScalarSpectral);
    const Image crossed = render(scenes / "bsdf_polarizer_middle.xml", {}, {}, polarized);
    CHECK(summarize(crossed).finite);
    int blackened = 0;
    for (int y = 0; y < crossed.height(); ++y)
        for (int x = 0; x < crossed.width(); ++x)
            blackened += unpolarised.at(x, y, 1) > 0.02f && crossed.at(x, y, 1) < 0.01f * unpolarised.at(x, y, 1);
    INFO(blackened << " of " << crossed.width() * crossed.height() << " pixels blackened");
    CHECK(blackened > crossed.width() * crossed.height() / 140);  // 0.7%: 5000 of 960 x 720
}
