// volpath and volpathmis against closed forms, against each other and against path.
//   - Beer-Lambert: an orthographic camera looks at an emitter of radiance L through a slab of
//     thickness d of an absorbing medium (chromatic sigma_t), bounded by null surfaces or by
//     index-matched dielectrics, and through a sphere along its diameter: the image is
//     L exp(-sigma_t d).
//   - Through a slab bounded by thindielectric sheets (R = 2 r / (1 + r) per sheet at normal
//     incidence, r the Fresnel reflectance): the light passes each sheet as a Null lobe (as in
//     Mitsuba 3), no scattering event, so with max_depth 1 the image is L (1 - R)^2 exp(-sigma_t d),
//     and with unbounded depth the sheets' interreflections add up to
//     L (1 - R)^2 exp(-sigma_t d) / (1 - R^2 exp(-2 sigma_t d)).
//   - Furnace (scenes/furnace/medium_sphere.xml): a camera inside a closed sphere that emits 1
//     and reflects 0.5 diffusely, filled with a medium of albedo 1 (chromatic sigma_t, HG phase
//     function): every pixel is 1 / (1 - 0.5) = 2. Next-event estimation, phase sampling and MIS through the medium all
//     contribute; volpathmis's per-channel majorants are exercised by the chromatic sigma_t.
//   - A medium with sigma_t = 0 changes nothing: volpath renders what path renders without it.
//   - volpath and volpathmis agree on a heterogeneous, chromatic, scattering scene.
//   - A homogeneous medium with a grid albedo (Mitsuba 3 allows a spatially varying albedo with a
//     constant sigma_t; its docs scene medium_homogeneous_sss_textured) renders as the
//     heterogeneous medium with that albedo grid and a uniform sigma_t grid around the shape.
//   - path refuses a scene with media, naming volpath.
// Statistics: pixels of a box-filtered render are independent, so image and block means get their
// standard errors from the spread of the pixels; every comparison is a z-test, and all of them
// together keep a 1% family-wise level (Sidak over the count below).

#include "core/scene.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/support/vol_writer.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

// Channels times the z-tests: Beer-Lambert 5 cases x 2 integrators, the furnace 2 integrators,
// sigma_t = 0 one comparison, volpath vs volpathmis 1 image mean + 16 block means, homogeneous
// with a grid albedo vs heterogeneous the same 17.
const double Z = two_sided_z(sidak(0.01, 3 * (10 + 2 + 1 + 17 + 17)));

RenderResult render_xml(const std::string& xml, const std::string& name) {
    auto dir = scratch_dir(name);
    write_text(dir / "scene.xml", xml);
    Ref<Scene> scene = load_scene((dir / "scene.xml").string());
    return scene->integrator().render(*scene, RenderOptions());
}

std::string film(int size, int spp) { return box_film(size, spp); }

// Looking down -z at an emitter of radiance (1, 2, 3) in the plane z = 0 (black: it reflects
// nothing back up), through `between`.
std::string beer_lambert_scene(const std::string& integrator, const std::string& between, float view_scale, int max_depth = -1) {
    return scene_xml(R"(<integrator type=")" + integrator + R"("><integer name="max_depth" value=")" + std::to_string(max_depth) +
                     R"("/></integrator>
        <sensor type="orthographic"><transform name="to_world"><scale value=")" +
                     std::to_string(view_scale) + R"("/><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>)" +
                     film(16, 64) + R"(</sensor>
        <shape type="rectangle"><transform name="to_world"><scale value="10"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
            <emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter></shape>
        <medium type="homogeneous" id="absorber"><rgb name="sigma_t" value="0.5, 1, 2"/><float name="albedo" value="0"/></medium>)" +
                     between);
}

}  // namespace

TEST_CASE("volpath: Beer-Lambert through slabs and a sphere", "[volpath][stats]") {
    const Vec3 L(1.0f, 2.0f, 3.0f), sigma(0.5f, 1.0f, 2.0f);
    struct Case {
        std::string name, between;
        float view_scale, distance;
        int max_depth = -1;
        float sheet_R = 0.0f;  // reflectance of each bounding thindielectric sheet
    };
    // thindielectric of relative index 1.5: r = 0.04 at normal incidence.
    const float r = 0.04f, sheet_R = 2.0f * r / (1.0f + r);
    const std::string thin_sheets =
        R"(<bsdf type="thindielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>)";
    const std::string slab_transform = R"(<transform name="to_world"><scale x="10" y="10" z="0.5"/><translate z="2"/></transform>)";
    const std::vector<Case> cases = {
        {"null slab", "<shape type=\"cube\">" + slab_transform + "<bsdf type=\"null\"/><ref name=\"interior\" id=\"absorber\"/></shape>",
         1.0f, 1.0f},
        {"index-matched dielectric slab",
         "<shape type=\"cube\">" + slab_transform +
             R"(<bsdf type="dielectric"><float name="int_ior" value="1"/><float name="ext_ior" value="1"/></bsdf><ref name="interior" id="absorber"/></shape>)",
         1.0f, 1.0f},
        // Along the diameter: the view is 0.02 across, so chords differ from 2 by under 1e-4.
        {"sphere", R"(<shape type="sphere"><point name="center" value="0, 0, 2"/><float name="radius" value="1"/><bsdf type="null"/>
            <ref name="interior" id="absorber"/></shape>)",
         0.01f, 2.0f},
        {"thindielectric slab, max_depth 1",
         "<shape type=\"cube\">" + slab_transform + thin_sheets + "<ref name=\"interior\" id=\"absorber\"/></shape>", 1.0f, 1.0f, 1,
         sheet_R},
        {"thindielectric slab, unbounded",
         "<shape type=\"cube\">" + slab_transform + thin_sheets + "<ref name=\"interior\" id=\"absorber\"/></shape>", 1.0f, 1.0f, -1,
         sheet_R},
    };
    for (const Case& c : cases)
        for (const char* integrator : {"volpath", "volpathmis"}) {
            INFO(c.name << ", " << integrator);
            RenderResult result = render_xml(beer_lambert_scene(integrator, c.between, c.view_scale, c.max_depth), "beer-lambert");
            for (int ch = 0; ch < 3; ++ch) {
                MeanAndError m = channel_mean(result.image, ch);
                const double T = std::exp(-double(sigma[ch]) * c.distance), R = c.sheet_R;
                double expected = L[ch] * (1.0 - R) * (1.0 - R) * T;
                if (c.max_depth < 0) expected /= 1.0 - R * R * T * T;
                INFO("channel " << ch << ": " << m.mean << " +- " << m.std_error << ", expected " << expected);
                CHECK(std::abs(m.mean - expected) < Z * m.std_error);
                CHECK(m.std_error < 0.03 * L[ch]);  // power: a 10% error would be seen
            }
        }
}

TEST_CASE("volpath: furnace, a closed emitting sphere filled with a medium of albedo 1", "[volpath][stats]") {
    for (const char* integrator : {"volpath", "volpathmis"}) {
        INFO(integrator);
        RenderResult r =
            render_file(source_path("scenes/furnace/medium_sphere.xml"), {{"integrator", integrator}, {"res", "16"}, {"spp", "64"}});
        for (int ch = 0; ch < 3; ++ch) {
            MeanAndError m = channel_mean(r.image, ch);
            INFO("channel " << ch << ": " << m.mean << " +- " << m.std_error);
            CHECK(std::abs(m.mean - 2.0) < Z * m.std_error);
            CHECK(m.std_error < 0.035);  // power: a 5% error would be seen
        }
    }
}

namespace {

// A floor, a sphere and an area light, seen in perspective; `extra` is added.
std::string small_scene(const std::string& integrator, const std::string& extra, int spp) {
    return scene_xml(R"(<integrator type=")" + integrator + R"("/>
        <sensor type="perspective"><float name="fov" value="45"/>
            <transform name="to_world"><lookat origin="0, 1.5, 4" target="0, 0.5, 0" up="0, 1, 0"/></transform>)" +
                     film(32, spp) + R"(</sensor>
        <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.5, 0.4"/></bsdf></shape>
        <shape type="sphere"><point name="center" value="0.3, 0.5, 0"/><float name="radius" value="0.5"/>
            <bsdf type="roughplastic"/></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="2.5"/></transform>
            <emitter type="area"><rgb name="radiance" value="10"/></emitter></shape>)" +
                     extra);
}

// Two independent 32 x 32 renders of one expectation agree: 51 z-tests by blocks.
void check_agree_by_blocks(const Image& a, const Image& b) {
    std::string where;
    double z = largest_block_z(a, b, &where);
    INFO(where);
    CHECK(z <= Z);
}

}  // namespace

TEST_CASE("volpath: a medium with sigma_t = 0 renders as vacuum, as path renders the scene", "[volpath][stats]") {
    const std::string clear_box = R"(<medium type="homogeneous" id="clear"><float name="sigma_t" value="0"/></medium>
        <shape type="cube"><transform name="to_world"><scale value="1.2"/><translate y="0.6"/></transform>
            <bsdf type="null"/><ref name="interior" id="clear"/></shape>)";
    RenderResult with_medium = render_xml(small_scene("volpath", clear_box, 32), "clear-medium");
    RenderResult vacuum = render_xml(small_scene("path", "", 32), "clear-vacuum");
    for (int ch = 0; ch < 3; ++ch) {
        std::vector<double> diff;
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) diff.push_back(double(with_medium.image.at(x, y, ch)) - vacuum.image.at(x, y, ch));
        MeanAndError d = mean_and_error(diff);
        MeanAndError level = channel_mean(vacuum.image, ch);
        INFO("channel " << ch << ": difference " << d.mean << " +- " << d.std_error << " of " << level.mean);
        CHECK(std::abs(d.mean) < Z * d.std_error);
        CHECK(d.std_error < 0.03 * level.mean);
    }
}

TEST_CASE("volpath and volpathmis agree on a heterogeneous chromatic medium", "[volpath][stats]") {
    auto dir = scratch_dir("volpath-vs-mis");
    PCG32 rng(5, 9);
    const glm::ivec3 res(12, 12, 12);
    std::vector<float> density;
    for (int i = 0; i < res.x * res.y * res.z; ++i) {
        float v = rng.next_float() < 0.5f ? 0.0f : 6.0f * rng.next_float();
        density.insert(density.end(), {v, 0.5f * v, 0.2f * v});
    }
    write_vol(dir / "smoke.vol", res, 3, density);
    const std::string smoke = R"(<medium type="heterogeneous" id="smoke"><rgb name="albedo" value="0.9, 0.7, 0.8"/>
            <volume type="gridvolume" name="sigma_t"><string name="filename" value="smoke.vol"/>
                <transform name="to_world"><scale value="1.4"/><translate x="-0.9" y="0.01" z="-0.5"/></transform></volume>
            <phase type="hg"><float name="g" value="0.5"/></phase></medium>
        <shape type="cube"><transform name="to_world"><scale value="0.7"/><translate x="-0.2" y="0.71" z="0.2"/></transform>
            <bsdf type="null"/><ref name="interior" id="smoke"/></shape>)";
    Image images[2];
    int i = 0;
    for (const char* integrator : {"volpath", "volpathmis"}) {
        write_text(dir / "scene.xml", small_scene(integrator, smoke, 32));
        Ref<Scene> scene = load_scene((dir / "scene.xml").string());
        images[i++] = scene->integrator().render(*scene, RenderOptions()).image;
    }
    check_agree_by_blocks(images[0], images[1]);
}

TEST_CASE("homogeneous: a grid albedo renders as the heterogeneous medium with that albedo and a uniform sigma_t", "[volpath][stats]") {
    auto dir = scratch_dir("homogeneous-grid-albedo");
    PCG32 rng(7, 3);
    const glm::ivec3 res(6, 6, 6);
    std::vector<float> albedo, uniform;
    // Half the voxels absorb only: a medium that used one albedo everywhere would be brighter.
    for (int i = 0; i < res.x * res.y * res.z; ++i) {
        float a = rng.next_float() < 0.5f ? 0.0f : rng.next_float();
        albedo.insert(albedo.end(), {a, 0.8f * a, a * a});
        uniform.insert(uniform.end(), {3.0f, 1.5f, 0.75f});
    }
    write_vol(dir / "albedo.vol", res, 3, albedo);
    write_vol(dir / "sigma_t.vol", res, 3, uniform);
    // Both grids cover the cube that holds the medium (as in the volpath-vs-mis case).
    const std::string box = R"(<transform name="to_world"><scale value="1.4"/><translate x="-0.9" y="0.01" z="-0.5"/></transform>)";
    const std::string grid_albedo =
        R"(<volume type="gridvolume" name="albedo"><string name="filename" value="albedo.vol"/>)" + box + "</volume>";
    const std::string cube =
        R"(<shape type="cube"><transform name="to_world"><scale value="0.7"/><translate x="-0.2" y="0.71" z="0.2"/></transform>
            <bsdf type="null"/><ref name="interior" id="m"/></shape>)";
    const std::string media[2] = {
        R"(<medium type="homogeneous" id="m"><rgb name="sigma_t" value="0.75, 0.375, 0.1875"/><float name="scale" value="4"/>)" +
            grid_albedo + R"(<phase type="hg"><float name="g" value="0.5"/></phase></medium>)",
        R"(<medium type="heterogeneous" id="m"><volume type="gridvolume" name="sigma_t"><string name="filename" value="sigma_t.vol"/>)" +
            box + "</volume>" + grid_albedo + R"(<phase type="hg"><float name="g" value="0.5"/></phase></medium>)"};
    Image images[2];
    for (int i = 0; i < 2; ++i) {
        write_text(dir / "scene.xml", small_scene("volpath", media[i] + cube, 32));
        Ref<Scene> scene = load_scene((dir / "scene.xml").string());
        images[i] = scene->integrator().render(*scene, RenderOptions()).image;
    }
    check_agree_by_blocks(images[0], images[1]);
}

TEST_CASE("path refuses a scene with media and names volpath", "[volpath][errors]") {
    auto dir = scratch_dir("path-refuses-media");
    write_text(dir / "scene.xml",
               beer_lambert_scene("path", R"(<shape type="sphere"><bsdf type="null"/><ref name="interior" id="absorber"/></shape>)", 1.0f));
    Ref<Scene> scene = load_scene((dir / "scene.xml").string());
    try {
        scene->integrator().render(*scene, RenderOptions());
        FAIL("path rendered a scene with media");
    } catch (const SceneError& e) {
        CHECK_THAT(e.message(), Catch::Contains("volpath"));
    }
}
