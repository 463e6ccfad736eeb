// The rasterizer against exact references: a closed mesh around the camera covers every sample
// exactly once (no gaps, no double hits along shared edges), perspective-correct uv on a steep
// plane equals the ray-cast uv, the z-buffer picks the triangle a ray caster picks, and with
// physical settings the local model equals the path tracer's direct illumination.

#include "analysis/image_metrics.h"
#include "core/xml.h"
#include "integrators/raster/environment.h"
#include "integrators/raster/raster.h"
#include "integrators/raster/raster_scene.h"
#include "integrators/raster/rasterizer.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::raster;
using namespace candela::test;

namespace {

Ref<Scene> scene_from(const std::string& body) { return load_scene_xml("raster", body); }

// Clip-space triangles of a scene's geometry as the raster integrator submits them.
std::vector<std::array<Vec4, 3>> clip_triangles(const RasterGeometry& g, const RasterCamera& cam) {
    std::vector<std::array<Vec4, 3>> out;
    for (const auto& t : g.triangles) out.push_back({cam.clip(g.positions[t.x]), cam.clip(g.positions[t.y]), cam.clip(g.positions[t.z])});
    return out;
}

}  // namespace

TEST_CASE("rasterizer: a closed mesh around the camera covers every sample exactly once", "[raster]") {
    // Inside a finely tessellated sphere and inside a cube: thousands of shared edges, many
    // passing through sample positions at every angle; with 4 samples per pixel and a crop.
    for (const char* shape :
         {"<shape type=\"sphere\"><float name=\"radius\" value=\"3\"/></shape>",
          "<shape type=\"cube\"><transform name=\"to_world\"><scale value=\"2\"/><rotate y=\"1\" angle=\"30\"/></transform></shape>"}) {
        Ref<Scene> scene = scene_from(std::string(shape) + pinhole_camera("0.3, 0.2, 0.1", "1, 0.5, 2", 97, 61, 100));
        RasterGeometry g = build_geometry(*scene, 57, false, 0);
        RasterCamera cam = RasterCamera::from_pinhole(*scene->sensor().pinhole());
        for (int spp : {1, 4}) {
            Rasterizer r(97, 61, sample_pattern(spp), Vec2i(97, 61));
            r.setup(clip_triangles(g, cam), true);
            std::vector<int> hits(size_t(97) * 61 * spp, 0);
            r.run([&](const Fragment& f) { ++hits[(size_t(f.y) * 97 + f.x) * spp + f.sample]; });
            int zero = 0, twice = 0;
            for (int h : hits) zero += h == 0, twice += h > 1;
            INFO(shape << " spp " << spp);
            CHECK(zero == 0);
            CHECK(twice == 0);
        }
    }
}

TEST_CASE("rasterizer: perspective-correct uv on a steep plane equals the ray-cast uv", "[raster]") {
    Ref<Scene> scene = scene_from(
        R"(<shape type="rectangle"><transform name="to_world"><scale x="2" y="20"/><rotate x="1" angle="-90"/><translate z="-19"/></transform></shape>)" +
        pinhole_camera("0, 0.3, 1", "0, 0, -5", 80, 60));
    RasterGeometry g = build_geometry(*scene, 32, false, 0);
    RasterCamera cam = RasterCamera::from_pinhole(*scene->sensor().pinhole());
    for (bool perspective : {true, false}) {
        Rasterizer r(80, 60, sample_pattern(1), Vec2i(80, 60));
        r.setup(clip_triangles(g, cam), perspective);
        std::vector<Vec2> uv(80 * 60, Vec2(-1.0f));
        r.run([&](const Fragment& f) {
            const glm::uvec3& t = g.triangles[f.triangle->id];
            uv[size_t(f.y) * 80 + f.x] = f.bary.x * g.uvs[t.x] + f.bary.y * g.uvs[t.y] + f.bary.z * g.uvs[t.z];
        });
        // Vertices snap to 1/256 pixel; near the horizon that perturbs the projective map of the
        // whole triangle, so compare against the uv footprint of one pixel: the interpolated uv
        // must lie within 1% of it (a perspective error would be a large part of it, as the
        // affine case shows).
        auto ray_uv = [&](float x, float y, Vec2& out) {
            SurfaceInteraction si;
            if (!scene->intersect(scene->sensor().sample_ray(Vec2(x, y), Vec2(0.5f)), si)) return false;
            out = si.uv;
            return true;
        };
        double worst_ratio = 0.0, worst = 0.0;
        int compared = 0;
        for (int y = 0; y < 60; ++y)
            for (int x = 0; x < 80; ++x) {
                Vec2 exact, dx, dy;
                if (!ray_uv(x + 0.5f, y + 0.5f, exact) || !ray_uv(x + 1.5f, y + 0.5f, dx) || !ray_uv(x + 0.5f, y + 1.5f, dy)) continue;
                REQUIRE(uv[size_t(y) * 80 + x].x >= 0.0f);  // covered by the rasterizer too
                double bound = 0.01 * (glm::length(dx - exact) + glm::length(dy - exact)) + 1e-5;
                double err = glm::length(uv[size_t(y) * 80 + x] - exact);
                worst = std::max(worst, err);
                worst_ratio = std::max(worst_ratio, err / bound);
                ++compared;
            }
        INFO((perspective ? "perspective-correct" : "affine")
             << ": largest uv error " << worst << " (" << worst_ratio << " of 1% of a pixel footprint) over " << compared << " pixels");
        CHECK(compared > 1000);
        if (perspective)
            CHECK(worst_ratio <= 1.0);
        else
            CHECK(worst > 0.05);  // the distortion affine interpolation shows on a steep plane
    }
}

TEST_CASE("rasterizer: the z-buffer resolves interpenetrating triangles as a ray caster does", "[raster]") {
    // Two large triangles crossing each other (and a third through both), seen obliquely.
    Ref<Scene> scene = scene_from(R"(
        <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="35"/></transform></shape>
        <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="-30"/><rotate y="1" angle="20"/></transform></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="0.7"/><rotate y="1" angle="70"/><translate x="0.2"/></transform></shape>)" +
                                  pinhole_camera("0.5, 0.4, 3", "0, 0, 0", 120, 100, 50));
    RasterGeometry g = build_geometry(*scene, 32, false, 0);
    RasterCamera cam = RasterCamera::from_pinhole(*scene->sensor().pinhole());
    Rasterizer r(120, 100, sample_pattern(1), Vec2i(120, 100));
    r.setup(clip_triangles(g, cam), true);
    std::vector<double> depth(120 * 100, Infinity);
    std::vector<int> shape(120 * 100, -1);
    r.run([&](const Fragment& f) {
        size_t i = size_t(f.y) * 120 + f.x;
        if (f.w < depth[i]) {
            depth[i] = f.w;
            shape[i] = int(g.triangle_shape[f.triangle->id]);
        }
    });
    int agree = 0, disagree_far = 0;
    for (int y = 0; y < 100; ++y)
        for (int x = 0; x < 120; ++x) {
            Ray ray = scene->sensor().sample_ray(Vec2(x + 0.5f, y + 0.5f), Vec2(0.5f));
            SurfaceInteraction si;
            int expected = -1;
            if (scene->intersect(ray, si))
                for (size_t s = 0; s < scene->shapes().size(); ++s)
                    if (scene->shapes()[s].get() == si.shape) expected = int(s);
            if (shape[size_t(y) * 120 + x] == expected) {
                ++agree;
                continue;
            }
            // A disagreement is allowed only where the two surfaces are at (nearly) the same
            // depth: on their intersection line, within float precision.
            SurfaceInteraction other;
            Ray r2 = ray;
            r2.tmin = si.t * (1.0f + 1e-4f);
            bool near_line = scene->intersect(r2, other) && other.t < si.t * 1.001f;
            if (!near_line) ++disagree_far;
        }
    INFO(agree << " pixels agree");
    CHECK(disagree_far == 0);
    CHECK(agree > 11000);
}

namespace {
const char* PhysicsScene = R"(
    <bsdf type="diffuse" id="grey"><rgb name="reflectance" value="0.6, 0.6, 0.6"/></bsdf>
    <shape type="rectangle"><transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/></transform><ref id="grey"/></shape>
    <shape type="rectangle"><transform name="to_world"><scale x="4" y="2"/><translate y="2" z="-2"/></transform><ref id="grey"/></shape>
    <shape type="cube"><transform name="to_world"><scale value="0.4"/><rotate y="1" angle="30"/><translate x="1" y="0.4" z="0.2"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.5, 0.7"/></bsdf></shape>
    <shape type="sphere"><point name="center" x="-1" y="0.5" z="0"/><float name="radius" value="0.5"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.3, 0.2"/></bsdf></shape>
    <emitter type="point"><point name="position" x="-1.2" y="2" z="1.2"/><rgb name="intensity" value="4, 3.5, 3"/></emitter>
    <emitter type="spot"><transform name="to_world"><lookat origin="1.5, 3, 1.5" target="0.8, 0, 0"/></transform>
        <rgb name="intensity" value="25, 25, 30"/><float name="cutoff_angle" value="25"/><float name="beam_width" value="15"/></emitter>
    <emitter type="directional"><vector name="direction" x="0.3" y="-1" z="-0.4"/><rgb name="irradiance" value="0.6, 0.55, 0.5"/></emitter>)";
}

TEST_CASE("raster: physical settings match the path tracer's direct illumination", "[raster][physics]") {
    // Diffuse only, point, spot and directional lights, Phong shading, inverse-square attenuation,
    // shadow maps, no ambient; the path tracer at max_depth 2 computes the same quantity exactly.
    const int W = 160, H = 128;
    Ref<Scene> scene = scene_from(std::string(PhysicsScene) + pinhole_camera("0, 2.2, 5", "0, 0.3, 0", W, H, 45) +
                                  R"(<integrator type="path"><integer name="max_depth" value="2"/></integrator>)");
    RenderOptions path_options;
    path_options.spp = 256;
    RenderResult path = scene->integrator().render(*scene, path_options);
    RasterSettings s;
    s.shading = RasterSettings::Shading::Phong;
    s.shadows = RasterSettings::Shadows::Map;
    s.shadow_map_resolution = 2048;
    s.aa = 16;
    s.tessellation = 256;
    RasterIntegrator raster(s);
    RenderResult local = raster.render(*scene, RenderOptions{});
    ImageComparison c = compare_images(local.image, path.image);
    INFO("whole-image means " << 100 * c.mean_relative_difference.x << "% " << 100 * c.mean_relative_difference.y << "% "
                              << 100 * c.mean_relative_difference.z << "%");
    for (int k = 0; k < 3; ++k) CHECK(std::abs(c.mean_relative_difference[k]) < 0.01);
    // Blocks away from shadow edges: no pixel of the block sees a light's visibility change
    // (ray-cast visibility at each pixel's visible point, for each light).
    const int B = 16;
    double sum = 0.0;
    int used = 0, skipped = 0;
    for (int by = 0; by < H; by += B)
        for (int bx = 0; bx < W; bx += B) {
            bool edge = false;
            std::vector<int> first;
            double lt = 0, lr = 0;
            for (int y = by; y < by + B; ++y)
                for (int x = bx; x < bx + B; ++x) {
                    lt += luminance(local.image.rgb_at(x, y));
                    lr += luminance(path.image.rgb_at(x, y));
                    SurfaceInteraction si;
                    if (!scene->intersect(scene->sensor().sample_ray(Vec2(x + 0.5f, y + 0.5f), Vec2(0.5f)), si)) continue;
                    std::vector<int> vis;
                    for (const auto& e : scene->emitters()) {
                        Spectrum w;
                        DirectionSample ds = e->sample_direction(si, Vec2(0.5f), w);
                        Ray shadow = std::isinf(ds.dist) ? si.spawn_ray(ds.d) : si.spawn_ray_to(ds.p);
                        vis.push_back(!is_black(w) && glm::dot(ds.d, si.n) > 0.0f && !scene->occluded(shadow));
                    }
                    if (first.empty())
                        first = vis;
                    else if (vis != first)
                        edge = true;
                }
            if (edge || lr <= 0.0) {
                ++skipped;
                continue;
            }
            sum += std::abs(lt - lr) / lr;
            ++used;
        }
    double block_mare = sum / used;
    INFO("blocks away from shadow edges: mean absolute relative difference " << 100 * block_mare << "% over " << used << " blocks ("
                                                                             << skipped << " skipped)");
    CHECK(used >= 20);
    CHECK(block_mare < 0.03);
}

TEST_CASE("raster: cube map faces round-trip directions and load from images", "[raster]") {
    for (int face = 0; face < 6; ++face)
        for (float s : {0.1f, 0.5f, 0.93f})
            for (float t : {0.2f, 0.5f, 0.77f}) {
                Vec3 d = EnvironmentLookup::face_to_direction(face, s, t);
                int f2;
                float s2, t2;
                EnvironmentLookup::direction_to_face(d, f2, s2, t2);
                CHECK(f2 == face);
                CHECK(s2 == Approx(s).margin(1e-5));
                CHECK(t2 == Approx(t).margin(1e-5));
            }
    // Six constant-colour faces loaded from files: a lookup returns the face it points into.
    auto dir = scratch_dir("cubemap");
    const char* names[6] = {"px", "nx", "py", "ny", "pz", "nz"};
    for (int f = 0; f < 6; ++f) {
        Image img = Image::rgb(4, 4);
        for (float& v : img.data()) v = 0.1f * float(f + 1);
        write_exr(img, (dir / (std::string("sky_") + names[f] + ".exr")).string(), true);
    }
    Ref<Scene> scene = scene_from(pinhole_camera("0, 0, 0", "0, 0, 1", 8, 8));
    EnvironmentLookup cube(*scene, EnvironmentLookup::Mode::Cube, 8, (dir / "sky_{face}.exr").string());
    CHECK(cube.lookup(Vec3(1, 0.2f, 0.1f), 0.0f).x == Approx(0.1f));
    CHECK(cube.lookup(Vec3(0.1f, -1, 0.3f), 0.0f).x == Approx(0.4f));
    CHECK(cube.lookup(Vec3(0.2f, 0.1f, -1), 0.0f).x == Approx(0.6f));
}

TEST_CASE("raster: the cube_map property names six face images relative to the scene file", "[raster]") {
    // A perfect mirror facing the camera reflects the +z face; a pattern whose faces are missing,
    // or that has no {face}, is an error at the property's line.
    auto dir = scratch_dir("cubemap-property");
    const char* names[6] = {"px", "nx", "py", "ny", "pz", "nz"};
    std::filesystem::create_directories(dir / "sky");
    for (int f = 0; f < 6; ++f) {
        Image img = Image::rgb(4, 4);
        for (float& v : img.data()) v = 0.1f * float(f + 1);
        write_exr(img, (dir / "sky" / (std::string(names[f]) + ".exr")).string(), true);
    }
    auto scene_with = [&](const std::string& pattern) {
        write_text(dir / "scene.xml", scene_xml("<integrator type=\"raster\">\n<string name=\"cube_map\" value=\"" + pattern +
                                                "\"/>\n</integrator><shape type=\"rectangle\"><bsdf type=\"conductor\"/></shape>" +
                                                pinhole_camera("0, 0, 3", "0, 0, 0", 8, 8, 20)));
        return load_scene((dir / "scene.xml").string());
    };
    Ref<Scene> scene = scene_with("sky/{face}.exr");
    RenderResult r = scene->integrator().render(*scene, RenderOptions{});
    for (int k = 0; k < 3; ++k) CHECK(r.image.rgb_at(4, 4)[k] == Approx(0.5f));
    CHECK_THROWS_WITH(scene_with("sky/{face}.png"), Catch::Contains("scene.xml:") && Catch::Contains("file not found"));
    CHECK_THROWS_WITH(scene_with("sky/pz.exr"), Catch::Contains("scene.xml:") && Catch::Contains("must contain {face}"));
}

TEST_CASE("raster: pixels beyond 1e30 or not finite are blacked out and counted, as the pixel loop drops such samples", "[raster]") {
    // A point light of intensity 1e35 (a float) lights the sphere to about 1e34: past what a film
    // stores (core/film.h, storable_sample_value). The frame holds only storable values.
    Ref<Scene> scene = scene_from(R"(<integrator type="raster"/>
        <sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
                <string name="component_format" value="float32"/></film></sensor>
        <emitter type="point"><point name="position" value="0, 0, 3"/><rgb name="intensity" value="1e35"/></emitter>
        <shape type="sphere"><bsdf type="diffuse"/></shape>)");
    const RenderResult r = scene->integrator().render(*scene, RenderOptions{});
    CHECK(r.stats.nonfinite > 0);
    for (float v : r.image.data()) CHECK(storable_sample_value(v));
}
