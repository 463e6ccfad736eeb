#pragma once
// Planar polygon algorithms shared by the mesh loaders and the rasterizer: signed area, the
// point-in-polygon crossing test, and ear-clipping triangulation of simple (possibly concave)
// polygons.

#include "core/math.h"

#include <array>
#include <vector>

namespace candela {

// Twice the signed area (positive for counter-clockwise vertex order): the shoelace formula.
double polygon_signed_area2(const std::vector<glm::dvec2>& pts);

// Even-odd crossing test (Shimrat 1962 with the half-open vertex rule of Haines 1994: an edge
// counts when one endpoint is strictly above the test line and the other is on or below it, so a
// vertex lying exactly on the horizontal line is counted once, or twice when both of its edges
// lie on the same side).
bool point_in_polygon(const std::vector<glm::dvec2>& pts, const glm::dvec2& p);

// Triangulates a simple polygon (no self-intersections; concave allowed; collinear and repeated
// vertices allowed) by ear clipping (Meisters 1975). Returns triangles as indices into `pts`,
// wound like the input. Degenerate polygons give fewer than n - 2 triangles.
std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<glm::dvec2>& pts);

// Triangulates a planar polygon in 3D by projecting it onto the plane of its Newell normal.
std::vector<std::array<int, 3>> triangulate_polygon_3d(const std::vector<Vec3>& pts);

}  // namespace candela
