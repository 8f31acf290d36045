#pragma once
/// \file
/// Consistent orientation of a triangle soup, with the splits that make it a surface: the rule of
/// CGAL's Polygon_mesh_processing::orient_polygon_soup (CGAL 5.5), which gives the same triangles
/// and the same new points for the same input (tests/test_repair_orient.cpp compares them on
/// random soups), in time linear in the soup's size where CGAL's maps of sets take several times
/// longer on a large export.
///
/// The rule: an edge of more than two triangles is non-manifold and not crossed. Starting from
/// the first triangle not yet visited, a depth-first walk crosses every other edge of two
/// triangles, reversing the triangle it enters when it runs the edge the same way; an edge
/// between two triangles already visited that disagree is cut (not crossed again). Afterwards,
/// a vertex whose triangles form several fans across the edges that were crossed keeps the fan
/// of its first triangle; each other fan gets a copy of the vertex, numbered after the existing
/// points in the order of the vertices and of their fans' first triangles.

#include <array>
#include <cstddef>
#include <vector>

namespace rgbmesh::repair {

struct SoupOrientation {
  std::size_t non_manifold_edges = 0;  ///< edges of more than two triangles
  std::size_t reversed_triangles = 0;  ///< triangles whose corners were reversed
  /// Edges of two triangles that the walk cut (the surface could not be oriented across them);
  /// the triangles no longer share them once the vertices are split, unless the vertices'
  /// fans still join them elsewhere (then the result is no surface: a twisted strip too narrow
  /// to cut).
  std::size_t cut_edges = 0;
  std::size_t split_vertices = 0;  ///< vertices whose triangles made several fans
  std::size_t vertex_copies = 0;   ///< the fans they made (so the vertices they became)
  /// New point `point_count + i` is a copy of point `copied_from[i]`.
  std::vector<std::size_t> copied_from;
};

/// Orients `triangles` (three distinct corners each, all below `point_count`) in place and
/// renumbers the corners that moved to copies of their vertex.
SoupOrientation orient_triangles(std::vector<std::array<std::size_t, 3>>& triangles, std::size_t point_count);

}  // namespace rgbmesh::repair
