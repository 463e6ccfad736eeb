#pragma once
// The form factor from a differential area to a polygon, in closed form: the fraction of the
// power leaving a Lambertian differential area at x (unit normal n) that lands on the polygon,
// ignoring occlusion. It is the polygon's projected solid angle over pi, which Lambert's contour
// integral gives exactly (Baum, Rushmeier & Winget 1989 use it for radiosity form factors):
//
//   F = 1 / (2 pi) * | sum_k  gamma_k  n . (r_k x r_k+1) / |r_k x r_k+1| |
//
// with r_k the polygon's vertices relative to x and gamma_k the angle between r_k and r_k+1.
// The formula holds for the part of the polygon above x's tangent plane, so the polygon is
// clipped to that half-space first (Sutherland-Hodgman against one plane).

#include "core/math.h"

namespace candela {

// `vertices` in order around a planar convex polygon (at most 8). Double precision: receivers
// close to the polygon's edges take differences of nearly equal angles.
double point_polygon_form_factor(const Vec3d& x, const Vec3d& n, const Vec3d* vertices, int count);

}  // namespace candela
