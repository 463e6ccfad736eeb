// Polygon algorithms: ear clipping of concave and collinear polygons, the crossing test.

#include "geometry2d/polygon.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace candela;

TEST_CASE("polygons: ear clipping of concave and collinear polygons", "[polygon]") {
    struct Case {
        const char* name;
        std::vector<glm::dvec2> pts;
    };
    const std::vector<Case> cases = {
        {"L shape", {{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}}},
        {"comb", {{0, 0}, {5, 0}, {5, 3}, {4, 3}, {4, 1}, {3, 1}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}}},
        {"collinear square", {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}}},
        {"clockwise star", {{0, 3}, {1, 1}, {3, 1}, {1.5, -0.5}, {2, -3}, {0, -1.5}, {-2, -3}, {-1.5, -0.5}, {-3, 1}, {-1, 1}}},
        {"vertices on one scanline", {{0, 0}, {2, 0}, {2, 2}, {1.5, 1}, {1, 2}, {0.5, 1}, {0, 2}}},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        auto tris = triangulate_polygon(c.pts);
        double area = std::abs(0.5 * polygon_signed_area2(c.pts)), sum = 0.0;
        bool ccw = polygon_signed_area2(c.pts) > 0.0;
        for (auto& t : tris) {
            std::vector<glm::dvec2> tri = {c.pts[t[0]], c.pts[t[1]], c.pts[t[2]]};
            double a = 0.5 * polygon_signed_area2(tri);
            CHECK((a > 0.0) == ccw);  // wound like the polygon
            sum += std::abs(a);
            glm::dvec2 centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
            CHECK(point_in_polygon(c.pts, centroid));
        }
        CHECK(sum == Approx(area).epsilon(1e-12));
    }
}

TEST_CASE("polygons: crossing test counts vertices on the test line correctly", "[polygon]") {
    // A diamond whose left and right vertices lie exactly on y = 1, and a W shape with a
    // vertex touching y = 1 from below between two edges on one side.
    std::vector<glm::dvec2> diamond = {{1, 0}, {2, 1}, {1, 2}, {0, 1}};
    CHECK(point_in_polygon(diamond, {1.0, 1.0}));
    CHECK(!point_in_polygon(diamond, {-0.5, 1.0}));
    CHECK(!point_in_polygon(diamond, {2.5, 1.0}));
    std::vector<glm::dvec2> w = {{0, 0}, {4, 0}, {4, 2}, {3, 2}, {2, 1}, {1, 2}, {0, 2}};
    CHECK(point_in_polygon(w, {0.5, 1.0}));
    CHECK(point_in_polygon(w, {3.5, 1.0}));
    CHECK(point_in_polygon(w, {1.9, 1.0}));
    CHECK(!point_in_polygon(w, {2.0, 1.5}));
    CHECK(!point_in_polygon(w, {5.0, 1.0}));
}
