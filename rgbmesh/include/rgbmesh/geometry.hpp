#pragma once
/// \file
/// Small geometric queries used by level-of-detail criteria.

#include <vector>

#include "rgbmesh/vec3.hpp"

namespace rgbmesh {

/// The point of triangle (a, b, c) closest to p (Voronoi regions of vertices, edges, face).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// The length of the diagonal of the points' axis-aligned bounding box (0 if there are none):
/// the scale that relative tolerances and errors refer to.
double bounding_box_diagonal(const std::vector<Vec3>& points);

inline double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return distance(p, closest_point_on_triangle(p, a, b, c));
}

}  // namespace rgbmesh
