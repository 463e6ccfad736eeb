// The lights of the local model, against the scene they come from: an area light's surface shows
// exactly its radiance; shadow maps and volumes leave out exactly the light's own shape, even
// when two area lights share a centre; Gouraud shading lights every vertex exactly once per
// light.

#include "core/registry.h"
#include "core/warp.h"
#include "core/xml.h"
#include "integrators/raster/raster.h"
#include "integrators/raster/raster_scene.h"
#include "integrators/raster/shadows.h"
#include "lights/point_source.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <map>
#include <mutex>
#include <tuple>

using namespace candela;
using namespace candela::raster;
using namespace candela::test;

namespace {

Ref<Scene> scene_from(const std::string& body) { return load_scene_xml("raster-lights", body); }

// A point light that records the reference point of every sample_direction call: the local
// model evaluates a delta light through sample_direction once per lighting evaluation.
std::mutex g_calls_mutex;
std::vector<Vec3> g_calls;

class RecordingPointEmitter final : public Emitter {
public:
    explicit RecordingPointEmitter(const Properties& props) {
        type_ = EmitterType::DeltaPosition;
        position_ = props.get_point("position");
        intensity_ = props.get_rgb("intensity", Spectrum(1.0f));
    }
    DirectionSample sample_direction(const SurfaceInteraction& ref, const Vec2&, Spectrum& weight) const override {
        {
            std::lock_guard<std::mutex> lock(g_calls_mutex);
            g_calls.push_back(ref.p);
        }
        DirectionSample ds = sample_point_source(position_, ref, this);
        weight = ds.dist > 0.0f ? intensity_ / (ds.dist * ds.dist) : Spectrum(0.0f);
        return ds;
    }
    float pdf_direction(const SurfaceInteraction&, const DirectionSample&) const override { return 0.0f; }
    Spectrum eval(const SurfaceInteraction&) const override { return Spectrum(0.0f); }
    Spectrum power() const override { return FourPi * intensity_; }
    EmitterRay sample_ray(const Vec2&, const Vec2& u_direction, Wavelengths*, float) const override {
        return point_source_ray(position_, warp::square_to_uniform_sphere(u_direction), InvFourPi, intensity_);
    }
    std::string to_string() const override { return "test_recording_point"; }

private:
    Vec3 position_;
    Spectrum intensity_;
};
CANDELA_REGISTER(RecordingPointEmitter, ObjectKind::Emitter, "test_recording_point");

using Key = std::tuple<float, float, float>;
Key key(const Vec3& p) { return {p.x, p.y, p.z}; }

}  // namespace

TEST_CASE("raster: an area light's surface shows exactly its radiance", "[raster][lights]") {
    // Shapes of very different areas, planar and not: the emission the rasterizer draws is the
    // emitter's radiance itself, not a point light's intensity divided back by an area.
    const Spectrum radiance(0.3f, 1.7f, 11.1f);
    const std::string emit = "<emitter type=\"area\"><rgb name=\"radiance\" value=\"0.3, 1.7, 11.1\"/></emitter>";
    const std::string black = "<bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"0\"/></bsdf>";
    Ref<Scene> scene = scene_from(
        "<shape type=\"rectangle\"><transform name=\"to_world\"><scale x=\"3.7\" y=\"2.3\"/><translate z=\"-1\"/></transform>" + black +
        emit + "</shape>" +
        "<shape type=\"sphere\"><point name=\"center\" x=\"9\" y=\"0\" z=\"0\"/><float name=\"radius\" value=\"0.37\"/>" + emit +
        "</shape>" + "<shape type=\"disk\"><transform name=\"to_world\"><scale value=\"0.13\"/><translate x=\"-9\"/></transform>" + emit +
        "</shape>" +
        "<shape type=\"cube\"><transform name=\"to_world\"><scale x=\"0.7\" y=\"3\" z=\"0.21\"/><translate y=\"9\"/></transform>" + emit +
        "</shape>" + pinhole_camera("0, 0, 2", "0, 0, 0", 16, 12, 30));
    RasterGeometry g = build_geometry(*scene, 32, false, 0);
    REQUIRE(g.shapes.size() == 4);
    for (const RasterShape& rs : g.shapes) {
        INFO(rs.shape->to_string());
        for (int k = 0; k < 3; ++k) CHECK(rs.emission[k] == radiance[k]);
    }
    // The rendered front of the (black) rectangle, which fills the view: radiance, bit for bit.
    RasterSettings s;
    s.shadows = RasterSettings::Shadows::None;
    Image img = RasterIntegrator(s).render(*scene, RenderOptions{}).image;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 16; ++x)
            for (int k = 0; k < 3; ++k) CHECK(img.rgb_at(x, y)[k] == radiance[k]);
}

TEST_CASE("raster: shadows leave out exactly the light's own shape, also when lights share a centre", "[raster][lights][shadows]") {
    // Two concentric emitting spheres, and two emitting rectangles at one place facing opposite
    // ways: every pair has the same centre, so only the shape's identity tells them apart. A
    // plain diffuse shape first, so that shape and light indices differ.
    const std::string emit = "<emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter>";
    Ref<Scene> scene = scene_from(
        "<shape type=\"cube\"><transform name=\"to_world\"><translate x=\"5\"/></transform></shape>"
        "<shape type=\"sphere\"><point name=\"center\" x=\"0\" y=\"2\" z=\"0\"/><float name=\"radius\" value=\"0.2\"/>" +
        emit + "</shape>" +
        "<shape type=\"sphere\"><point name=\"center\" x=\"0\" y=\"2\" z=\"0\"/><float name=\"radius\" value=\"0.5\"/>" + emit +
        "</shape>" +
        "<shape type=\"rectangle\"><transform name=\"to_world\"><rotate x=\"1\" angle=\"90\"/><translate y=\"-3\"/></transform>" + emit +
        "</shape>" +
        "<shape type=\"rectangle\"><transform name=\"to_world\"><rotate x=\"1\" angle=\"-90\"/><translate y=\"-3\"/></transform>" + emit +
        "</shape>" + pinhole_camera("0, 0, 8", "0, 0, 0", 16, 12));
    RasterGeometry g = build_geometry(*scene, 32, false, 0);
    LocalLights lights = collect_lights(*scene);
    REQUIRE(lights.lights.size() == 4);
    REQUIRE(scene->emitters().size() == 4);
    for (size_t k = 0; k < lights.lights.size(); ++k) {
        // collect_lights keeps the scene's emitter order; the expected shape carries emitter k.
        int expected = -1;
        for (size_t s = 0; s < g.shapes.size(); ++s)
            if (g.shapes[s].shape->emitter() == scene->emitters()[k].get()) expected = int(s);
        INFO("light " << k);
        REQUIRE(expected >= 1);
        CHECK(light_shape(lights.lights[k], g) == expected);
    }
}

TEST_CASE("raster: Gouraud shading lights every vertex exactly once per light", "[raster][lights][gouraud]") {
    // A closed sphere (each vertex shared by about six triangles) over an open floor. Lighting a
    // vertex once per triangle that uses it would write the same vertex from several threads at
    // once (a data race) and evaluate the light several times; the local model must evaluate it
    // once per vertex, at the vertex.
    Ref<Scene> scene = scene_from(R"(
        <shape type="sphere"><point name="center" x="0" y="0.5" z="0"/><float name="radius" value="0.5"/></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="2"/><rotate x="1" angle="-90"/></transform></shape>
        <emitter type="test_recording_point"><point name="position" x="0.3" y="2" z="0.4"/><rgb name="intensity" value="3"/></emitter>)" +
                                  pinhole_camera("0, 1.5, 3", "0, 0.3, 0", 40, 30));
    RasterSettings s;
    s.shading = RasterSettings::Shading::Gouraud;
    s.shadows = RasterSettings::Shadows::None;
    s.tessellation = 16;
    RasterGeometry g = build_geometry(*scene, s.tessellation, false, 0);
    std::map<Key, int> vertices;  // vertices at each position (seams and poles repeat positions)
    for (const Vec3& p : g.positions) ++vertices[key(p)];
    g_calls.clear();
    RasterIntegrator(s).render(*scene, RenderOptions{});
    std::map<Key, int> evaluations;
    for (const Vec3& p : g_calls) ++evaluations[key(p)];
    int wrong = 0;
    for (const auto& [p, n] : vertices) wrong += evaluations[p] != n;
    size_t at_vertices = 0;
    for (const auto& [p, n] : evaluations) at_vertices += vertices.count(p) ? size_t(n) : 0;
    INFO(g.positions.size() << " vertices, " << g.triangles.size() << " triangles; " << at_vertices << " light evaluations at vertices, "
                            << g_calls.size() << " in all");
    CHECK(wrong == 0);
    CHECK(at_vertices == g.positions.size());
}
