#pragma once
/// \file
/// Summary figures of a mesh, for `rgbmesh info` and reports.

#include <array>
#include <cstddef>
#include <map>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

struct MeshStatistics {
  std::size_t vertices = 0, edges = 0, triangles = 0;
  int components = 0;
  int boundary_loops = 0;
  long euler_characteristic = 0;
  /// Sum over the components of their genus, from χ = 2c − b − 2g (every RGB mesh is an
  /// oriented manifold).
  int genus = 0;
  int max_level = 0;
  std::size_t red_edges = 0;
  std::map<int, std::size_t> valence_histogram;   ///< valence -> vertices
  std::map<int, std::size_t> vertices_per_level;  ///< insertion level -> vertices
  /// triangles_per_level[level][color]: color 0 green, 1 red, 2 blue.
  std::map<int, std::array<std::size_t, 3>> triangles_per_level;
  double shortest_edge = 0, longest_edge = 0;
  /// The axis-aligned bounding box of the control points shown (zero for an empty mesh).
  Vec3 bbox_min, bbox_max;
  double bbox_diagonal = 0;
  /// Sharp features (sharpness.hpp) of the current mesh: interior edges with sharpness above 0
  /// (those below 10 also counted as semi-sharp), and the vertices whose rule at their shown
  /// level is dart, crease (boundary vertices, creases by Loop's rules, not counted) or
  /// corner.
  std::size_t sharp_edges = 0, semi_sharp_edges = 0;
  std::size_t darts = 0, crease_vertices = 0, corners = 0;
};

MeshStatistics compute_statistics(const RgbMesh& mesh);

/// How far the Loop limit surface strays from the base mesh's own vertices: the largest
/// distance between a base vertex and its limit position, and that vertex. A lower bound of
/// the distance between the limit surface and the input surface, cheap to compute: where it
/// is a percent of the diagonal or more, edges and corners of the input are being rounded.
struct LimitDeviation {
  double distance = 0;
  VertexHandle vertex;
};
LimitDeviation limit_deviation(const RgbMesh& mesh);

}  // namespace rgbmesh
