// Sensor::sample_direction, the connection of light paths to the camera, for the perspective
// (with a shifted principal point), thinlens and orthographic (scaled) cameras: it inverts
// sample_ray (same lens point, same film position, same ray), and its importance is the Jacobian
// of the camera's map from film to scene: integrated over a tilted wall that fills the view it
// gives the film's area in pixels, and wall points kept with probability proportional to it land
// uniformly on the film (chi-square). The statistical tests share a 1% family-wise level (Sidak).

#include "analysis/statistics.h"
#include "core/rng.h"
#include "core/xml.h"
#include "tests/util.h"

#include <catch2/catch.hpp>

using namespace candela;
using namespace candela::test;

namespace {

constexpr int ConnectionTests = 3 * 2;  // three cameras: the integral and the chi-square
const double Alpha = sidak(0.01, ConnectionTests);
constexpr int Width = 48, Height = 32;

const char* Lookat = R"(<lookat origin="0.5, 1, 6" target="0, 0.2, 0" up="0, 1, 0"/>)";

Ref<Scene> camera_scene(const std::string& name, const std::string& sensor) {
    auto dir = scratch_dir("sensor_connection");
    write_text(
        dir / (name + ".xml"),
        scene_xml(sensor + R"(<film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="32"/></film></sensor>
        <shape type="sphere"><float name="radius" value="0.5"/></shape>)"));
    return load_scene((dir / (name + ".xml")).string());
}

struct Camera {
    const char* name;
    Ref<Scene> scene;
};

std::vector<Camera> cameras() {
    return {{"perspective", camera_scene("perspective", std::string(R"(<sensor type="perspective"><float name="fov" value="35"/>
                 <float name="principal_point_offset_x" value="0.1"/><float name="principal_point_offset_y" value="-0.05"/><transform name="to_world">)") +
                                                            Lookat + "</transform>")},
            {"thinlens",
             camera_scene("thinlens",
                          std::string(R"(<sensor type="thinlens"><float name="fov" value="35"/><float name="aperture_radius" value="0.3"/>
                 <float name="focus_distance" value="4"/><transform name="to_world">)") +
                              Lookat + "</transform>")},
            {"orthographic",
             camera_scene("orthographic", std::string(R"(<sensor type="orthographic"><transform name="to_world"><scale x="2" y="1.5"/>)") +
                                              Lookat + "</transform>")}};
}

}  // namespace

TEST_CASE("sensor connection: sample_direction inverts sample_ray", "[camera][lighttracing]") {
    for (const Camera& c : cameras()) {
        const Sensor& sensor = c.scene->sensor();
        PCG32 rng(17, 3);
        int checked = 0, wrong = 0;
        for (int i = 0; i < 2000; ++i) {
            Vec2 film(rng.next_float() * Width, rng.next_float() * Height), lens(rng.next_float(), rng.next_float());
            Ray ray = sensor.sample_ray(film, lens);
            Vec3 x = ray(ray.tmin + 0.5f + 8.0f * rng.next_float());
            SensorSample ss = sensor.sample_direction(x, lens, 0.0f);
            ++checked;
            bool ok = ss.pdf > 0.0f && glm::length(ss.film_pos - film) < 2e-3f && glm::length(ss.d + ray.d) < 1e-4f &&
                      glm::length(ss.p - ray(ray.tmin)) < 1e-4f * (1.0f + glm::length(ss.p)) &&
                      std::abs(ss.dist - glm::length(x - ss.p)) < 1e-4f * ss.dist;
            if (!ok && ++wrong < 4)
                WARN(c.name << ": film (" << film.x << ", " << film.y << ") came back as (" << ss.film_pos.x << ", " << ss.film_pos.y
                            << "), pdf " << ss.pdf);
        }
        INFO(c.name << ": " << wrong << " of " << checked << " connections did not retrace their camera ray");
        CHECK(wrong == 0);
        // Points behind the camera or outside the view have no connection.
        CHECK(sensor.sample_direction(Vec3(0.5f, 1, 9), Vec2(0.5f), 0.0f).pdf == 0.0f);
        CHECK(sensor.sample_direction(Vec3(30, 1, 0), Vec2(0.5f), 0.0f).pdf == 0.0f);
    }
}

TEST_CASE("sensor connection: importance is the film's Jacobian (integral and uniform landing)", "[camera][lighttracing]") {
    // A wall through the target, tilted by 30 degrees, 10 x 10 units: larger than the view.
    const Vec3 center(0, 0.2f, 0);
    const Vec3 axis_u = glm::normalize(Vec3(1, 0, 0)),
               axis_v = glm::normalize(Vec3(0, std::cos(radians(30.0f)), -std::sin(radians(30.0f))));
    const Vec3 normal = glm::normalize(glm::cross(axis_u, axis_v));
    const float half = 5.0f, area = 4 * half * half;
    const int n = 300000;
    for (const Camera& c : cameras()) {
        const Sensor& sensor = c.scene->sensor();
        PCG32 rng(23, 9);
        std::vector<double> weights(n, 0.0);
        std::vector<Vec2> landed(n);
        for (int i = 0; i < n; ++i) {
            Vec3 x = center + axis_u * half * (2 * rng.next_float() - 1) + axis_v * half * (2 * rng.next_float() - 1);
            SensorSample ss = sensor.sample_direction(x, Vec2(rng.next_float(), rng.next_float()), 0.0f);
            if (!(ss.pdf > 0.0f)) continue;
            weights[i] = ss.weight * std::abs(glm::dot(normal, ss.d));
            landed[i] = ss.film_pos;
        }
        MeanAndError m = mean_and_error(weights);
        INFO(c.name << ": integral of the importance over the wall " << m.mean * area << " +- " << m.std_error * area << ", film area "
                    << Width * Height);
        CHECK(std::abs(m.mean * area - Width * Height) <= two_sided_z(Alpha) * m.std_error * area);
        // Keep each point with probability weight / max: the kept film positions are uniform.
        double w_max = *std::max_element(weights.begin(), weights.end());
        std::vector<double> cells(12 * 8, 0.0);
        double kept = 0.0;
        for (int i = 0; i < n; ++i) {
            if (!(weights[i] > 0.0) || rng.next_float() * w_max >= weights[i]) continue;
            Vec2 q = glm::clamp(landed[i] / Vec2(Width, Height), Vec2(0.0f), Vec2(0.99999f));
            cells[size_t(q.y * 8) * 12 + size_t(q.x * 12)] += 1.0;
            kept += 1.0;
        }
        ChiSquareResult chi = chi_square(cells, std::vector<double>(cells.size(), kept / cells.size()));
        INFO("kept " << kept << " points: " << chi.details);
        CHECK(chi.p_value > Alpha);
    }
}
