// The path tracer's wavefront (integrators/path_wave.cpp) against the path tracer one path at a
// time (RenderOptions::wavefront off): the same image bit for bit, and the same ray count, for
// every sampler and what a user can combine with it (settings, shapes that Embree calls back for
// a packet, instances, motion blur, environment maps, adaptive sampling, parts of a render, the
// --aov layers).

#include "core/integrator.h"
#include "core/rng.h"
#include "core/scene.h"
#include "core/sensor.h"
#include "core/variant.h"
#include "core/warp.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <regex>

using namespace candela;
using namespace candela::test;

namespace {

const std::vector<std::string> AllSamplers = {"independent", "stratified", "multijitter", "orthogonal", "ldsampler", "sobol", "zsobol"};

bool batched(const Scene& scene) {
    const auto* integrator = dynamic_cast<const SamplingIntegrator*>(&scene.integrator());
    return integrator && integrator->samples_in_batches(scene);
}

// Renders `scene` with `options` as a wavefront and one path at a time, and compares; returns
// the wavefront's.
RenderResult check_same_render(const Scene& scene, RenderOptions options) {
    options.wavefront = true;
    const RenderResult wave = scene.integrator().render(scene, options);
    options.wavefront = false;
    const RenderResult one = scene.integrator().render(scene, options);
    REQUIRE(wave.image.data().size() == one.image.data().size());
    size_t differing = 0;
    for (size_t i = 0; i < one.image.data().size(); ++i) differing += wave.image.data()[i] != one.image.data()[i];
    CHECK(differing == 0);
    CHECK(wave.stats.rays == one.stats.rays);
    CHECK(wave.stats.samples == one.stats.samples);
    CHECK(wave.stats.nonfinite == one.stats.nonfinite);
    double sum = 0.0;
    for (float v : one.image.data()) sum += v;
    CHECK(sum > 0.0);
    return wave;
}

RenderOptions with_sampler(const std::string& sampler, int spp = 5) {
    RenderOptions options;
    options.sampler = sampler;
    options.spp = spp;
    options.seed = 7;
    options.threads = 2;
    return options;
}

// Sets an environment variable for its lifetime, then restores what was there (or unsets it).
class ScopedEnvironment {
public:
    ScopedEnvironment(const char* name, const char* value) : name_(name) {
        if (const char* previous = std::getenv(name)) previous_ = previous, had_previous_ = true;
        setenv(name, value, 1);
    }
    ~ScopedEnvironment() {
        if (had_previous_)
            setenv(name_.c_str(), previous_.c_str(), 1);
        else
            unsetenv(name_.c_str());
    }
    ScopedEnvironment(const ScopedEnvironment&) = delete;
    ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

private:
    std::string name_, previous_;
    bool had_previous_ = false;
};

}  // namespace

TEST_CASE("path wavefront: the validation scenes render bit for bit as one path at a time with every sampler", "[render][wavefront]") {
    // Diffuse, conductors, plastics, rough glass, a thin dielectric (a Null lobe), textures, an
    // environment map, point, spot and directional lights, spheres (user geometry: Embree calls
    // it back for a whole packet).
    for (const char* name : {"cbox", "conductors", "envmap", "glass", "lights", "plastics", "roughglass", "textured"}) {
        Ref<Scene> scene = load_scene(source_path(std::string("scenes/validation/") + name + ".xml"), {{"res", "16"}, {"spp", "5"}});
        REQUIRE(batched(*scene));
        for (const std::string& sampler : AllSamplers) {
            INFO(name << " with " << sampler);
            check_same_render(*scene, with_sampler(sampler));
        }
    }
}

TEST_CASE("path wavefront: Null surfaces (thin glass and masks) render bit for bit as one path at a time", "[render][wavefront]") {
    // A thin dielectric pane, a checkered mask over a diffuse card and a null box in front of
    // the light: paths cross them without a bounce (each crossing its own block of numbers, the
    // roulette's number drawn only behind a lobe that scatters), shadow rays take their
    // transmittance. Short paths and an early roulette reach the Null crossings at the last
    // allowed bounce and the roulette behind a Null-lobe BSDF.
    const std::string body = pinhole_camera("0, 1, 6", "0, 0.5, 0", 24, 16, 50) + R"(
        <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.5, 0.4"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><scale x="0.8" y="0.6"/><translate y="0.7" z="1.5"/></transform>
            <bsdf type="thindielectric"><float name="int_ior" value="1.5"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="0.7"/><translate x="-0.9" y="0.8"/></transform>
            <bsdf type="mask"><texture type="checkerboard" name="opacity"><transform name="to_uv"><scale value="4"/></transform></texture>
                <bsdf type="diffuse"/></bsdf></shape>
        <shape type="cube"><transform name="to_world"><scale value="0.4"/><translate x="0.9" y="2"/></transform>
            <bsdf type="null"/></shape>
        <shape type="sphere"><point name="center" value="0.8, 0.4, 0"/><float name="radius" value="0.4"/><bsdf type="roughconductor"/></shape>
        <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="90"/><translate y="3"/></transform>
            <emitter type="area"><rgb name="radiance" value="4"/></emitter></shape>
        <emitter type="constant"><rgb name="radiance" value="0.1"/></emitter>)";
    const std::vector<std::string> settings = {
        "",
        R"(<integer name="max_depth" value="2"/>)",
        R"(<integer name="max_depth" value="3"/><integer name="rr_depth" value="1"/>)",
        R"(<integer name="rr_depth" value="1"/><boolean name="hide_emitters" value="true"/>)",
    };
    for (const std::string& setting : settings) {
        const std::string xml = scene_xml("<integrator type=\"path\">" + setting + "</integrator>" + body);
        Ref<Scene> scene = load_scene_from_string(xml, source_path("scenes/validation/wave.xml"));
        REQUIRE(scene->has_null_surfaces());
        REQUIRE(batched(*scene));
        for (const std::string& sampler : AllSamplers) {
            INFO(setting << " with " << sampler);
            check_same_render(*scene, with_sampler(sampler, 6));
        }
    }
}

TEST_CASE("path wavefront: the spectral variant renders bit for bit as one path at a time, the polarized one path at a time",
          "[render][wavefront][spectral]") {
    // Each sample's wavelengths are drawn by the pixel loop after the camera's numbers and belong
    // to that sample (a dispersive glass terminates its secondary ones); the polarized variant's
    // Stokes sums are not batched.
    for (const char* name : {"cbox", "conductors", "glass", "roughglass", "textured", "envmap"}) {
        const std::string path = source_path(std::string("scenes/validation/") + name + ".xml");
        Ref<Scene> scene = load_scene(path, {{"res", "12"}, {"spp", "5"}}, Variant::ScalarSpectral);
        CHECK(batched(*scene));
        for (const char* sampler : {"independent", "ldsampler", "zsobol"}) {
            INFO(name << " with " << sampler);
            check_same_render(*scene, with_sampler(sampler));
        }
        CHECK_FALSE(batched(*load_scene(path, {{"res", "12"}, {"spp", "5"}}, Variant::ScalarSpectralPolarized)));
    }
}

TEST_CASE("path wavefront: path's settings, hidden emitters and short paths render bit for bit as one path at a time",
          "[render][wavefront]") {
    const std::string cbox = read_text(source_path("scenes/validation/cbox.xml"));
    const std::string envmap = read_text(source_path("scenes/validation/envmap.xml"));
    const std::vector<std::string> settings = {
        R"(<integer name="max_depth" value="1"/>)",
        R"(<integer name="max_depth" value="2"/>)",
        R"(<integer name="max_depth" value="3"/><integer name="rr_depth" value="1"/>)",
        R"(<integer name="max_depth" value="0"/>)",
        R"(<boolean name="hide_emitters" value="true"/>)",
        R"(<string name="light_sampler" value="uniform"/>)",
        R"(<string name="light_sampler" value="power"/>)",
    };
    for (const std::string* base : {&cbox, &envmap})
        for (const std::string& setting : settings) {
            const std::string xml = std::regex_replace(*base, std::regex(R"(<integrator type="path">[\s\S]*?</integrator>)"),
                                                       "<integrator type=\"path\">" + setting + "</integrator>");
            Ref<Scene> scene = load_scene_from_string(xml, source_path("scenes/validation/wave.xml"), {{"res", "16"}, {"spp", "5"}});
            REQUIRE(batched(*scene));
            INFO((base == &cbox ? "cbox" : "envmap") << " with " << setting);
            if (setting.find("\"0\"") != std::string::npos) {
                // Nothing at all: both renders black.
                RenderOptions options = with_sampler("independent");
                const RenderResult wave = scene->integrator().render(*scene, options);
                options.wavefront = false;
                CHECK(wave.image.data() == scene->integrator().render(*scene, options).image.data());
                continue;
            }
            for (const char* sampler : {"independent", "ldsampler"}) check_same_render(*scene, with_sampler(sampler));
        }
}

TEST_CASE("path wavefront: instances, analytic shapes and motion blur render bit for bit as one path at a time", "[render][wavefront]") {
    // A shape group of a sphere and a cube instanced twice (Embree's instance ids in a packet),
    // a disk and a cylinder (user geometry), one instance moving while the shutter is open (each
    // lane's own time).
    const std::string body = pinhole_camera("0, 1, 6", "0, 0, 0", 24, 16, 45) + R"(
        <shape type="shapegroup" id="group">
            <shape type="sphere"><float name="radius" value="0.5"/><bsdf type="diffuse"/></shape>
            <shape type="cube"><transform name="to_world"><scale value="0.3"/><translate x="1"/></transform>
                <bsdf type="roughconductor"/></shape>
        </shape>
        <shape type="instance"><ref id="group"/><transform name="to_world"><translate x="-1.2"/></transform></shape>
        <shape type="instance"><ref id="group"/>
            <animation name="to_world"><transform time="0"><translate x="0.8"/></transform>
                <transform time="1"><translate x="1.2" y="0.3"/></transform></animation></shape>
        <shape type="disk"><transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/><translate y="-0.6"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.5, 0.4"/></bsdf></shape>
        <shape type="cylinder"><point name="p0" value="0, -0.6, -1.5"/><point name="p1" value="0, 1, -1.5"/>
            <float name="radius" value="0.3"/><bsdf type="plastic"/></shape>
        <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="90"/><translate y="3"/></transform>
            <emitter type="area"><rgb name="radiance" value="3"/></emitter></shape>
        <emitter type="constant"><rgb name="radiance" value="0.2"/></emitter>)";
    std::string xml = scene_xml(body);
    xml = std::regex_replace(xml, std::regex(R"(<sensor type="perspective">)"),
                             R"(<sensor type="perspective"><float name="shutter_open" value="0"/><float name="shutter_close" value="1"/>)");
    Ref<Scene> scene = load_scene_from_string(xml, source_path("scenes/validation/wave.xml"));
    REQUIRE(scene->is_animated());
    REQUIRE(scene->sensor().shutter_open_time() > 0.0f);
    REQUIRE(batched(*scene));
    for (const std::string& sampler : AllSamplers) {
        INFO(sampler);
        check_same_render(*scene, with_sampler(sampler, 6));
    }
}

TEST_CASE("path wavefront: adaptive sampling, parts of a render, --aov layers and one thread give what one path at a time gives",
          "[render][wavefront]") {
    Ref<Scene> scene = load_scene(source_path("scenes/validation/cbox.xml"), {{"res", "24"}, {"spp", "8"}});
    RenderOptions adaptive = with_sampler("independent", 64);
    adaptive.adaptive.threshold = 0.05f;
    adaptive.adaptive.min_spp = 8;
    check_same_render(*scene, adaptive);
    RenderOptions part = with_sampler("sobol", 16);
    part.samples = SampleRange{3, 11};
    part.region = ImageRect{Vec2i(5, 7), Vec2i(13, 9)};
    check_same_render(*scene, part);
    RenderOptions layers = with_sampler("stratified", 9);
    layers.aovs = {"albedo", "normal", "depth", "variance", "samples"};
    const RenderResult with_layers = check_same_render(*scene, layers);
    CHECK(with_layers.image.channels().size() > 3 + 3 + 3 + 1);
    RenderOptions one_thread = with_sampler("zsobol", 8);
    one_thread.threads = 1;
    check_same_render(*scene, one_thread);
}

TEST_CASE("path wavefront: Embree's kernels for machines without AVX-512 answer its part-filled packets", "[render][wavefront]") {
    // Without AVX-512 the wave asks for 8-ray packets (Accel::intersect_packet), which the SSE4.2
    // kernels split again into 4-ray ones; a split asserted (and aborted) on the unused lanes of a
    // packet the wave had left unwritten. CANDELA_EMBREE_CONFIG selects those kernels on any
    // machine that has them.
    struct Isa {
        const char* config;
        bool supported;
    };
    const Isa isas[] = {{"isa=sse4.2", bool(__builtin_cpu_supports("sse4.2"))},
                        {"isa=avx", bool(__builtin_cpu_supports("avx"))},
                        {"isa=avx2", bool(__builtin_cpu_supports("avx2"))}};
    for (const Isa& isa : isas) {
        if (!isa.supported) continue;
        INFO(isa.config);
        ScopedEnvironment config("CANDELA_EMBREE_CONFIG", isa.config);
        for (const char* name : {"cbox", "lights", "envmap"}) {
            INFO(name);
            Ref<Scene> scene = load_scene(source_path(std::string("scenes/validation/") + name + ".xml"), {{"res", "16"}, {"spp", "5"}});
            REQUIRE(batched(*scene));
            check_same_render(*scene, with_sampler("independent"));
        }
    }
}

TEST_CASE("path wavefront: packets traced as coherent find the hits single rays find however their rays run", "[render][wavefront]") {
    // The wave asks Embree to trace its camera rays' packets as coherent ones (a frustum
    // traversal, RTC_INTERSECT_CONTEXT_FLAG_COHERENT) when the sensor's rays run together. Only
    // speed may depend on it: every lane must get the closest hit that one ray at a time gets,
    // for one pixel's rays, for a row of pixels' rays, for rays that scatter every way from
    // anywhere (the worst case for a frustum: every octant in one packet) and for part-filled
    // packets. A mesh of 2048 triangles, a cube and a floor (triangles: Embree's frustum path).
    const std::string body = pinhole_camera("0, 2.5, 4", "0, 0, 0", 32, 32, 50) + R"(
        <shape type="obj"><string name="filename" value="meshes/torus.obj"/><bsdf type="diffuse"/></shape>
        <shape type="cube"><transform name="to_world"><scale value="0.35"/><translate y="0.2"/></transform></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="5"/><rotate x="1" angle="-90"/><translate y="-0.5"/></transform></shape>
        <emitter type="constant"/>)";
    Ref<Scene> scene = load_scene_from_string(scene_xml(body), source_path("scenes/validation/coherent.xml"));
    const Sensor& sensor = scene->sensor();
    REQUIRE(sensor.rays_coherent());
    PCG32 rng(11, 5);
    auto next_2d = [&] {
        const float a = rng.next_float();
        return Vec2(a, rng.next_float());
    };
    std::vector<Ray> rays;
    std::vector<size_t> packet_sizes;
    // One pixel's 16 rays (the wave's packets at 16 spp and more), then rows of 16 pixels, one ray
    // each (at 1 spp).
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            packet_sizes.push_back(16);
            for (int s = 0; s < 16; ++s) rays.push_back(sensor.sample_ray(Vec2(float(x), float(y)) + next_2d(), Vec2(0.5f)));
        }
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            if (x % 16 == 0) packet_sizes.push_back(16);
            rays.push_back(sensor.sample_ray(Vec2(float(x), float(y)) + next_2d(), Vec2(0.5f)));
        }
    // Rays from anywhere in the scene's bounds in any direction, in packets of 1 to 16.
    const BoundingBox b = scene->bbox();
    for (int k = 0; k < 600; ++k) {
        const size_t size = 1 + rng.next_uint() % 16;
        packet_sizes.push_back(size);
        for (size_t i = 0; i < size; ++i) {
            const Vec3 o = b.min + Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * (b.max - b.min);
            rays.push_back(Ray(o, warp::square_to_uniform_sphere(next_2d())));
        }
    }
    size_t first = 0, hits = 0, differing = 0;
    for (size_t size : packet_sizes) {
        const Ray* packet[Accel::PacketSize];
        SurfaceInteraction batch[Accel::PacketSize];
        SurfaceInteraction* answers[Accel::PacketSize];
        bool found[Accel::PacketSize];
        for (size_t i = 0; i < size; ++i) packet[i] = &rays[first + i], answers[i] = &batch[i];
        scene->intersect_batch(packet, answers, found, size, true);
        for (size_t i = 0; i < size; ++i) {
            SurfaceInteraction single;
            const bool single_found = scene->intersect(rays[first + i], single);
            hits += single_found;
            const bool same = found[i] == single_found &&
                              (!single_found || (batch[i].shape == single.shape && batch[i].prim_index == single.prim_index &&
                                                 batch[i].t == single.t && batch[i].p == single.p && batch[i].prim_uv == single.prim_uv));
            differing += !same;
        }
        first += size;
    }
    INFO(rays.size() << " rays, " << hits << " hits");
    CHECK(differing == 0);
    CHECK(hits > rays.size() / 2);
}

TEST_CASE("path wavefront: every kind of sensor renders bit for bit as one path at a time whether its rays run together or not",
          "[render][wavefront]") {
    // The wave traces camera rays as coherent packets for the sensors that say their rays run
    // together (Sensor::rays_coherent) and as scattered ones otherwise; the image must not tell.
    const std::string film = R"(<film type="hdrfilm"><integer name="width" value="12"/><integer name="height" value="10"/>
        <rfilter type="box"/></film>)";
    const std::string pose = R"(<transform name="to_world"><lookat origin="0, 1, 5" target="0, 0, 0" up="0, 1, 0"/></transform>)";
    const std::string world = R"(
        <shape type="obj"><string name="filename" value="meshes/torus.obj"/><bsdf type="diffuse"/></shape>
        <shape type="cube"><transform name="to_world"><scale value="0.3"/><translate x="1" y="0.3"/></transform>
            <bsdf type="roughconductor"/></shape>
        <shape type="rectangle" id="floor"><transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/><translate y="-0.6"/></transform>
            <bsdf type="diffuse"/>%s</shape>
        <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="90"/><translate y="3"/></transform>
            <emitter type="area"><rgb name="radiance" value="4"/></emitter></shape>
        <emitter type="constant"><rgb name="radiance" value="0.3"/></emitter>)";
    auto with_floor_sensor = [&](const std::string& floor_sensor) {
        std::string body = world;
        body.replace(body.find("%s"), 2, floor_sensor);
        return body;
    };
    // The meters measure one value: a 1 x 1 film, and more samples.
    const std::string meter_film = R"(<film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/>
        <rfilter type="box"/></film>)";
    struct Case {
        const char* name;
        std::string body;
        bool coherent;
        int spp = 20;
    };
    const std::string perspective = R"(<sensor type="perspective"><float name="fov" value="50"/>)" + pose + film + "</sensor>";
    const std::string orthographic_pose = R"(<transform name="to_world"><scale x="2" y="2"/>
            <lookat origin="0, 1, 5" target="0, 0, 0" up="0, 1, 0"/></transform>)";
    const std::vector<Case> cases = {
        {"perspective", perspective + with_floor_sensor(""), true},
        {"thinlens",
         R"(<sensor type="thinlens"><float name="fov" value="50"/><float name="aperture_radius" value="0.2"/>
            <float name="focus_distance" value="4"/>)" +
             pose + film + "</sensor>" + with_floor_sensor(""),
         true},
        {"orthographic", R"(<sensor type="orthographic">)" + orthographic_pose + film + "</sensor>" + with_floor_sensor(""), true},
        {"radiancemeter",
         R"(<sensor type="radiancemeter"><point name="origin" value="0, 1, 5"/><vector name="direction" value="0, -0.2, -1"/>)" +
             meter_film + "</sensor>" + with_floor_sensor(""),
         true, 400},
        {"distant",
         R"(<sensor type="distant"><vector name="direction" value="0.2, -1, 0.1"/>)" + meter_film + "</sensor>" + with_floor_sensor(""),
         false, 400},
        {"irradiancemeter", with_floor_sensor(R"(<sensor type="irradiancemeter">)" + meter_film + "</sensor>"), false, 400},
        {"batch of a perspective and an orthographic camera",
         R"(<sensor type="batch"><sensor type="perspective"><float name="fov" value="50"/>)" + pose +
             R"(</sensor><sensor type="orthographic">)" + orthographic_pose + R"(</sensor>
            <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="10"/><rfilter type="box"/></film></sensor>)" +
             with_floor_sensor(""),
         true},
        {"batch of a radiance meter and an irradiance meter",
         R"(<sensor type="batch"><sensor type="radiancemeter"><point name="origin" value="0, 1, 5"/>
            <vector name="direction" value="0, -0.2, -1"/>)" +
             meter_film + R"(</sensor><ref id="floor"/>
            <film type="hdrfilm"><integer name="width" value="2"/><integer name="height" value="1"/><rfilter type="box"/></film></sensor>)" +
             with_floor_sensor(R"(<sensor type="irradiancemeter">)" + meter_film + "</sensor>"),
         false, 400},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        Ref<Scene> scene = load_scene_from_string(scene_xml(c.body), source_path("scenes/validation/sensors.xml"));
        REQUIRE(batched(*scene));
        CHECK(scene->sensor().rays_coherent() == c.coherent);
        for (const char* sampler : {"independent", "ldsampler"}) {
            INFO(sampler);
            check_same_render(*scene, with_sampler(sampler, c.spp));
        }
    }
}
