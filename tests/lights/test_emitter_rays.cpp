// Emitter::sample_ray, the start of every light path, for every emitter: the sampled directions
// and origins against the densities written independently here (chi-square), each sample's
// reported pdfs and weight against the same formulas, and the flux the weights carry against
// Emitter::power(). The statistical tests share a 1% family-wise level (Sidak).

#include "analysis/statistics.h"
#include "core/image.h"
#include "core/rng.h"
#include "core/xml.h"
#include "tests/stats.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

#include <functional>

using namespace candela;
using namespace candela::test;

namespace {

// 9 direction and 7 position histograms, 11 emitters x 3 channels of flux.
constexpr int RayTests = 9 + 7 + 33;
const double Alpha = sidak(0.01, RayTests);
const double Pi_d = 3.14159265358979323846;
// 2e5 rays per emitter (2e4 at the sanitizer run's CANDELA_TEST_EFFORT=0.1, tests/util.h: the
// same significance, less power). Power, by the noncentral chi-square: a direction or origin
// density off by 7% over a tenth of the sphere or disk is found with probability about 1/2 at 2e5
// rays, by 21% at 2e4.
const int Samples = effort_scaled(200000, 20000);

// A scene with one emitter and a unit cube (so that infinite emitters have bounds).
Ref<Scene> scene_with(const std::string& emitter) {
    auto dir = scratch_dir("emitter_rays");
    write_text(
        dir / "scene.xml",
        scene_xml(emitter + R"(<shape type="cube"><transform name="to_world"><translate x="0.5" y="-0.2" z="0.1"/></transform></shape>)"));
    return load_scene((dir / "scene.xml").string());
}

const Emitter& only_emitter(const Scene& scene) {
    REQUIRE(scene.emitters().size() == 1);
    return *scene.emitters()[0];
}

bool close(double a, double b) { return std::abs(a - b) <= 1e-3 * std::max(std::abs(a), std::abs(b)) + 1e-12; }

// What a test knows about an emitter, written from its definition and not from its code.
struct RayModel {
    std::function<double(const Vec3&)> direction_pdf;   // density of directions; empty: a delta
    std::function<Vec2(const EmitterRay&)> position;    // the origin mapped into [0,1]^2, uniform when the
                                                        // origin density is right; empty: a delta
    std::function<bool(const EmitterRay&)> consistent;  // the sample's pdfs, flags and weight
    double power_allowance = 1e-5;                      // relative: float rounding (or power()'s quadrature)
};

void check_rays(const char* what, const Emitter& emitter, const RayModel& model, uint64_t seed) {
    PCG32 rng(seed, 7);
    SphericalHistogram directions(10, 20);
    std::vector<double> positions(16 * 16, 0.0);
    double failed = 0.0, valid = 0.0;
    int inconsistent = 0;
    std::vector<double> flux[3];
    for (int i = 0; i < Samples; ++i) {
        Vec2 u_pos(rng.next_float(), rng.next_float()), u_dir(rng.next_float(), rng.next_float());
        EmitterRay r = emitter.sample_ray(u_pos, u_dir, nullptr, 0.0f);
        for (int c = 0; c < 3; ++c) flux[c].push_back(r.valid() ? r.weight[c] : 0.0);
        if (!r.valid()) {
            failed += 1.0;
            continue;
        }
        valid += 1.0;
        if (model.direction_pdf) directions.add(r.ray.d);
        if (model.position) {
            Vec2 q = glm::clamp(model.position(r), Vec2(0.0f), Vec2(0.99999f));
            positions[size_t(q.y * 16) * 16 + size_t(q.x * 16)] += 1.0;
        }
        if (!model.consistent(r) && ++inconsistent < 4)
            WARN(what << ": inconsistent sample, pdfs " << r.pdf_position << ", " << r.pdf_direction);
    }
    INFO(what);
    CHECK(inconsistent == 0);
    if (model.direction_pdf) {
        std::vector<double> expected = directions.expected(model.direction_pdf, Samples), observed = directions.counts;
        double total = 0.0;
        for (double e : expected) total += e;
        observed.push_back(failed);
        expected.push_back(std::max(0.0, Samples - total));
        ChiSquareResult chi = chi_square(observed, expected);
        INFO("directions: " << chi.details);
        CHECK(chi.p_value > Alpha);
    }
    if (model.position) {
        ChiSquareResult chi = chi_square(positions, std::vector<double>(positions.size(), valid / positions.size()));
        INFO("positions: " << chi.details);
        CHECK(chi.p_value > Alpha);
    }
    Spectrum power = emitter.power();
    double z = two_sided_z(Alpha);
    for (int c = 0; c < 3; ++c) {
        MeanAndError m = mean_and_error(flux[c]);
        INFO("flux channel " << c << ": " << m.mean << " +- " << m.std_error << ", power() " << power[c]);
        CHECK(std::abs(m.mean - power[c]) <= z * m.std_error + model.power_allowance * power[c]);
    }
}

// Where a ray from an infinite emitter starts on the scene's bounding disk across its direction,
// as (r^2 / R^2, phi / 2pi): uniform when the origin is uniform on the disk. NaN (failing the
// consistency check) when the origin is not on the disk's plane.
Vec2 disk_coordinates(const Scene& scene, const EmitterRay& r) {
    Vec3 center = scene.bbox().center();
    float radius = std::max(scene.bbox().bounding_radius(), 1e-3f);
    Vec3 q = r.ray.o - (center - r.ray.d * radius), s, t;
    coordinate_system(r.ray.d, s, t);
    float x = glm::dot(q, s) / radius, y = glm::dot(q, t) / radius;
    float phi = std::atan2(y, x);
    return Vec2(x * x + y * y, (phi < 0.0f ? phi + 2.0f * float(Pi_d) : phi) / (2.0f * float(Pi_d)));
}
bool on_disk_plane(const Scene& scene, const EmitterRay& r) {
    float radius = std::max(scene.bbox().bounding_radius(), 1e-3f);
    return std::abs(glm::dot(r.ray.o - scene.bbox().center(), r.ray.d) + radius) < 1e-4f * radius &&
           close(r.pdf_position, 1.0 / (Pi_d * radius * radius));
}

// A w x h float EXR whose texel (x, y) (row 0 on top) holds values[y * w + x].
std::string write_texture(const std::string& name, int w, int h, const std::vector<Spectrum>& values) {
    Image img = Image::rgb(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.set_rgb(x, y, values[size_t(y) * w + x]);
    std::string path = (scratch_dir("ray-texture-" + name) / name).string();
    write_exr(img, path, true);
    return path;
}
const std::vector<Spectrum> Texels = {{1, 2, 3},        {4, 5, 6},    {7, 8, 9}, {10, 11, 12},
                                      {0.5f, 0.25f, 2}, {3, 1, 0.5f}, {2, 2, 1}, {6, 0.5f, 4}};
std::string nearest_bitmap(const std::string& name, const std::string& path) {
    return R"(<texture type="bitmap" name=")" + name + R"("><string name="filename" value=")" + path +
           R"("/><string name="filter_type" value="nearest"/></texture>)";
}

}  // namespace

TEST_CASE("emitter rays: point and spot lights emit over the sphere and the cone", "[lights][rays]") {
    Ref<Scene> point = scene_with(
        R"(<emitter type="point"><point name="position" x="0.2" y="1" z="-0.3"/><rgb name="intensity" value="2, 3, 5"/></emitter>)");
    RayModel m;
    m.direction_pdf = [](const Vec3&) { return 1.0 / (4.0 * Pi_d); };
    m.consistent = [](const EmitterRay& r) {
        return r.delta_position && !r.delta_direction && r.ray.o == Vec3(0.2f, 1, -0.3f) && close(r.pdf_direction, 1.0 / (4 * Pi_d)) &&
               close(r.weight.z, 5 * 4 * Pi_d);
    };
    check_rays("point", only_emitter(*point), m, 1);

    // A spot with Mitsuba's linear falloff ramp between beam_width and cutoff_angle.
    const float cutoff = 25.0f, beam = 10.0f;
    Transform to_world = Transform::look_at(Vec3(0.1f, 2, 0.3f), Vec3(0.6f, 0, 0.1f), Vec3(0, 0, 1));
    Transform to_local = to_world.inverse();
    auto spot_local = [&](const Vec3& w) { return glm::normalize(to_local.apply_vector(w)); };
    auto falloff = [&](const Vec3& local) {
        double theta = std::acos(std::clamp(double(local.z), -1.0, 1.0)), c = cutoff * Pi_d / 180, b = beam * Pi_d / 180;
        return theta >= c ? 0.0 : theta <= b ? 1.0 : (c - theta) / (c - b);
    };
    const double cos_cut = std::cos(cutoff * Pi_d / 180), cone_pdf = 1.0 / (2 * Pi_d * (1 - cos_cut));
    std::string spot_xml =
        R"(<emitter type="spot"><transform name="to_world"><lookat origin="0.1, 2, 0.3" target="0.6, 0, 0.1" up="0, 0, 1"/></transform>
        <float name="cutoff_angle" value="25"/><float name="beam_width" value="10"/><rgb name="intensity" value="4, 2, 1"/>)";
    Ref<Scene> spot = scene_with(spot_xml + "</emitter>");
    m.direction_pdf = [&](const Vec3& w) { return spot_local(w).z >= cos_cut ? cone_pdf : 0.0; };
    m.consistent = [&](const EmitterRay& r) {
        // (absolute tolerance: the ramp reaches 0 at the cutoff, where relative errors blow up)
        return r.delta_position && close(r.pdf_direction, cone_pdf) &&
               std::abs(r.weight.x - 4 * falloff(spot_local(r.ray.d)) / cone_pdf) < 1e-3 * 4 / cone_pdf;
    };
    check_rays("spot", only_emitter(*spot), m, 2);

    // With a texture over the cone: the flux still matches power() (its own quadrature).
    std::string tex = write_texture("spot.exr", 4, 2, Texels);
    Ref<Scene> textured = scene_with(spot_xml + nearest_bitmap("texture", tex) + "</emitter>");
    m.consistent = [&](const EmitterRay& r) { return r.delta_position && close(r.pdf_direction, cone_pdf); };
    m.power_allowance = 2e-3;  // power() integrates the nearest-neighbour texture by a 256 x 256 midpoint rule
    check_rays("textured spot", only_emitter(*textured), m, 3);
}

TEST_CASE("emitter rays: a projector emits through its image plane", "[lights][rays]") {
    std::string tex = write_texture("projector.exr", 4, 2, Texels);
    Ref<Scene> scene = scene_with(
        R"(<emitter type="projector"><transform name="to_world"><lookat origin="0, 2, 1" target="0.3, 0, 0" up="0, 1, 0"/></transform>
        <float name="fov" value="40"/><float name="scale" value="0.5"/>)" +
        nearest_bitmap("irradiance", tex) + "</emitter>");
    Transform to_local = Transform::look_at(Vec3(0, 2, 1), Vec3(0.3f, 0, 0), Vec3(0, 1, 0)).inverse();
    const double tx = std::tan(20.0 * Pi_d / 180), ty = tx / 2.0;  // a 4 x 2 image
    auto pdf = [&](const Vec3& w) {
        Vec3 l = glm::normalize(to_local.apply_vector(w));
        if (!(l.z > 0.0f)) return 0.0;
        double sx = 0.5 - 0.5 * l.x / (l.z * tx), sy = 0.5 - 0.5 * l.y / (l.z * ty);
        if (sx < 0 || sx > 1 || sy < 0 || sy > 1) return 0.0;
        return 1.0 / (4 * tx * ty * std::pow(double(l.z), 3.0));
    };
    RayModel m;
    m.direction_pdf = pdf;
    m.consistent = [&](const EmitterRay& r) { return r.delta_position && close(r.pdf_direction, pdf(r.ray.d)); };
    check_rays("projector", only_emitter(*scene), m, 4);
}

TEST_CASE("emitter rays: directional, constant and envmap light enters through the scene's bounding disk", "[lights][rays]") {
    Ref<Scene> directional = scene_with(
        R"(<emitter type="directional"><vector name="direction" x="1" y="-2" z="0.5"/><rgb name="irradiance" value="3, 2, 1"/></emitter>)");
    Vec3 d = glm::normalize(Vec3(1, -2, 0.5f));
    RayModel m;
    m.position = [&](const EmitterRay& r) { return disk_coordinates(*directional, r); };
    m.consistent = [&](const EmitterRay& r) {
        return r.delta_direction && glm::length(r.ray.d - d) < 1e-6f && on_disk_plane(*directional, r);
    };
    check_rays("directional", only_emitter(*directional), m, 5);

    Ref<Scene> constant = scene_with(R"(<emitter type="constant"><rgb name="radiance" value="0.5, 1, 2"/></emitter>)");
    m.direction_pdf = [](const Vec3&) { return 1.0 / (4 * Pi_d); };
    m.position = [&](const EmitterRay& r) { return disk_coordinates(*constant, r); };
    m.consistent = [&](const EmitterRay& r) {
        return !r.delta_direction && close(r.pdf_direction, 1 / (4 * Pi_d)) && on_disk_plane(*constant, r);
    };
    check_rays("constant", only_emitter(*constant), m, 6);

    // The environment map's directions: the density next-event estimation uses toward the map,
    // reversed (the light travels inward).
    Ref<Scene> envmap =
        scene_with(R"(<emitter type="envmap"><string name="filename" value=")" + source_path("scenes/validation/textures/sky.exr") +
                   R"("/><transform name="to_world"><rotate y="1" angle="60"/></transform></emitter>)");
    const Emitter& env = only_emitter(*envmap);
    auto env_pdf = [&](const Vec3& w) {
        DirectionSample ds;
        ds.d = -w;
        ds.dist = Infinity;
        return double(env.pdf_direction(SurfaceInteraction(), ds));
    };
    m.direction_pdf = env_pdf;
    m.position = [&](const EmitterRay& r) { return disk_coordinates(*envmap, r); };
    m.consistent = [&](const EmitterRay& r) {
        return close(r.pdf_direction, env_pdf(r.ray.d)) && on_disk_plane(*envmap, r) &&
               close(r.weight.y, env.eval_environment(-r.ray.d, nullptr, 0.0f).y / r.pdf_direction * (1.0 / r.pdf_position));
    };
    m.power_allowance = 2e-3;  // power() integrates the bilinear map by the midpoint rule
    check_rays("envmap", env, m, 7);
}

TEST_CASE("emitter rays: area lights emit cosine-weighted from points uniform by area", "[lights][rays]") {
    const char* rect_transform =
        R"(<transform name="to_world"><scale x="0.8" y="0.3"/><rotate x="1" angle="70"/><rotate y="1" angle="20"/><translate x="0.2" y="1" z="-0.4"/></transform>)";
    auto rect_scene = [&](const std::string& emitter) {
        return scene_with(std::string(R"(<shape type="rectangle">)") + rect_transform + emitter + "</shape>");
    };
    Ref<Scene> rect = rect_scene(R"(<emitter type="area"><rgb name="radiance" value="2, 1, 0.5"/></emitter>)");
    const Shape& shape = *rect->emitters()[0]->shape();
    Transform to_world = Transform::rotate(Vec3(0, 1, 0), 20) * Transform::rotate(Vec3(1, 0, 0), 70);
    to_world = Transform::translate(Vec3(0.2f, 1, -0.4f)) * to_world * Transform::scale(Vec3(0.8f, 0.3f, 1));
    Transform to_local = to_world.inverse();
    Vec3 n = glm::normalize(to_world.apply_normal(Vec3(0, 0, 1)));
    const double area = shape.surface_area();
    REQUIRE(area == Approx(4 * 0.8 * 0.3));
    RayModel m;
    m.direction_pdf = [&](const Vec3& w) { return std::max(0.0, double(glm::dot(w, n))) / Pi_d; };
    m.position = [&](const EmitterRay& r) { return Vec2(0.5f) + 0.5f * Vec2(to_local.apply_point(r.ray.o)); };
    m.consistent = [&](const EmitterRay& r) {
        double cos_theta = glm::dot(r.ray.d, n);
        return !r.delta_position && !r.delta_direction && close(r.pdf_position, 1 / area) && close(r.pdf_direction, cos_theta / Pi_d) &&
               close(r.weight.x, 2 * cos_theta / (r.pdf_position * r.pdf_direction)) && glm::length(r.n - n) < 1e-5f;
    };
    check_rays("rectangle", only_emitter(*rect), m, 8);

    // A textured radiance: the same rays, weighted by the texture at the origin's uv.
    std::string tex = write_texture("area.exr", 4, 2, Texels);
    Ref<Scene> textured = rect_scene(R"(<emitter type="area">)" + nearest_bitmap("radiance", tex) + "</emitter>");
    m.consistent = [&](const EmitterRay& r) {
        return close(r.pdf_position, 1 / area) && close(r.pdf_direction, glm::dot(r.ray.d, n) / Pi_d);
    };
    check_rays("textured rectangle", only_emitter(*textured), m, 9);

    // A sphere: origins uniform on it; over all its normals the cosine lobes add up to uniform.
    Ref<Scene> sphere = scene_with(R"(<shape type="sphere"><point name="center" x="0.3" y="1.5" z="0.2"/><float name="radius" value="0.5"/>
        <emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter></shape>)");
    m.direction_pdf = [](const Vec3&) { return 1.0 / (4 * Pi_d); };
    m.position = [](const EmitterRay& r) {
        Vec3 q = (r.ray.o - Vec3(0.3f, 1.5f, 0.2f)) / 0.5f;
        float phi = std::atan2(q.y, q.x);
        return Vec2(0.5f * (1.0f - q.z), (phi < 0 ? phi + 2 * float(Pi_d) : phi) / (2 * float(Pi_d)));
    };
    m.consistent = [](const EmitterRay& r) {
        Vec3 normal = (r.ray.o - Vec3(0.3f, 1.5f, 0.2f)) / 0.5f;
        double cos_theta = glm::dot(r.ray.d, normal);
        return close(r.pdf_position, 1 / (Pi_d)) && cos_theta > 0 && close(r.pdf_direction, cos_theta / Pi_d) &&
               glm::length(r.n - normal) < 1e-4f;
    };
    check_rays("sphere", only_emitter(*sphere), m, 10);

    // directionalarea: the same origins, all leaving along the normal.
    Ref<Scene> beam = rect_scene(R"(<emitter type="directionalarea"><rgb name="radiance" value="2, 1, 0.5"/></emitter>)");
    RayModel b;
    b.position = [&](const EmitterRay& r) { return Vec2(0.5f) + 0.5f * Vec2(to_local.apply_point(r.ray.o)); };
    b.consistent = [&](const EmitterRay& r) {
        return r.delta_direction && glm::length(r.ray.d - n) < 1e-5f && close(r.pdf_position, 1 / area) && close(r.weight.x, 2 * area);
    };
    check_rays("directionalarea", only_emitter(*beam), b, 11);
}

// Issue 31 (found by reading lights/area.cpp): a light path's start must see the emitter a camera
// path sees. (1) A radiance texture with a mapping other than uv (here a planar checkerboard
// whose uv the surface point decides) is looked up with that mapping in sample_ray, as where a
// path hits the light. (2) On a smooth-shaded mesh light (vertex normals far from the faces'),
// sampling decides the emitting side and converts area to solid angle with the normal a hit sees
// (the shading normal, as Mitsuba 3 does): for a point sampled on the light, the ray from a
// receiver hits that very point with the same normal, and the emitter's pdf of that hit equals
// the density of the sample.
TEST_CASE("emitter rays: area lights look up mapped radiance and choose their side as a hit does", "[lights][rays]") {
    {
        Ref<Scene> scene = scene_with(R"(<shape type="rectangle"><transform name="to_world"><scale value="2"/><translate z="3"/></transform>
            <emitter type="area"><texture type="checkerboard" name="radiance"><string name="mapping" value="planar"/>
                <rgb name="color0" value="1, 2, 3"/><rgb name="color1" value="0.1"/><transform name="to_uv"><scale value="3"/></transform></texture>
            </emitter></shape>)");
        const Emitter& light = *scene->emitters()[0];
        PCG32 rng(3, 7);
        int disagreements = 0;
        for (int i = 0; i < 2000; ++i) {
            EmitterRay r =
                light.sample_ray(Vec2(rng.next_float(), rng.next_float()), Vec2(rng.next_float(), rng.next_float()), nullptr, 0.0f);
            REQUIRE(r.valid());
            // What a camera path finds there: the hit's emission toward the ray's direction.
            SurfaceInteraction hit;
            REQUIRE(scene->intersect(Ray(r.ray.o + 0.5f * r.ray.d, -r.ray.d), hit));
            hit.wi = hit.to_local(r.ray.d);
            const Spectrum seen = light.eval(hit);
            const Spectrum sent = r.weight * (r.pdf_position / Pi);  // Le = weight pdf_pos pdf_dir / cos
            if (max_abs_component(seen - sent) > 1e-4f * max_component(seen)) ++disagreements;
        }
        CHECK(disagreements == 0);
    }
    {
        // A coarse smooth sphere (an octahedron with its corners' normals): shading normals up to
        // 55 degrees from the faces'.
        auto dir = scratch_dir("emitter_side");
        write_text(dir / "octa.obj", R"(v 1 0 0
v -1 0 0
v 0 1 0
v 0 -1 0
v 0 0 1
v 0 0 -1
vn 1 0 0
vn -1 0 0
vn 0 1 0
vn 0 -1 0
vn 0 0 1
vn 0 0 -1
f 1//1 3//3 5//5
f 3//3 2//2 5//5
f 2//2 4//4 5//5
f 4//4 1//1 5//5
f 3//3 1//1 6//6
f 2//2 3//3 6//6
f 4//4 2//2 6//6
f 1//1 4//4 6//6
)");
        write_text(dir / "scene.xml", scene_xml(R"(<shape type="obj"><string name="filename" value="octa.obj"/>
            <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)"));
        Ref<Scene> scene = load_scene((dir / "scene.xml").string());
        const Emitter& light = *scene->emitters()[0];
        SurfaceInteraction receiver;
        receiver.p = Vec3(2.5f, 0.7f, 0.4f);
        PCG32 rng(5, 7);
        int sampled = 0, mismatched_side = 0, mismatched_pdf = 0;
        for (int i = 0; i < 4000; ++i) {
            Spectrum weight;
            DirectionSample ds = light.sample_direction(receiver, Vec2(rng.next_float(), rng.next_float()), weight);
            if (!(ds.pdf > 0.0f)) continue;
            SurfaceInteraction hit;
            if (!scene->intersect(Ray(receiver.p, ds.d), hit) || glm::length(hit.p - ds.p) > 1e-3f) continue;  // the far side
            ++sampled;
            hit.wi = hit.to_local(-ds.d);
            if (is_black(light.eval(hit))) ++mismatched_side;
            DirectionSample at_hit = ds;
            at_hit.n = hit.shading.n;
            // (Grazing samples are left out of this one: there the hit's barycentrics, a float
            // rounding away from the sample's, move the cosine by a large fraction of itself.)
            const bool grazing = std::abs(glm::dot(ds.n, ds.d)) < 0.05f;
            if (!grazing && std::abs(light.pdf_direction(receiver, at_hit) - ds.pdf) > 1e-3f * ds.pdf) ++mismatched_pdf;
        }
        INFO(sampled << " samples seen from the receiver");
        CHECK(sampled > 500);
        CHECK(mismatched_side == 0);
        CHECK(mismatched_pdf == 0);
    }
}
