// A test mesh with triangles of several levels: the RGB mesh of a base refined to a floor
// everywhere and deeper in a ball (the Loop-space tests grade their meshes so).
#pragma once

#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

namespace rgbmesh::testing {

// The RGB mesh of `base` refined to `floor` everywhere and to `peak` in a ball around the
// limit point of the base's first vertex (radius relative to the first base edge): triangles
// of several levels, with red and blue ones between them.
inline RgbMesh graded(const BaseMesh& base, int floor, int peak, double radius) {
  RgbMesh mesh = base.build();
  if (floor > 0) selective_refinement(mesh, AtLeastLevel(floor));
  const auto& t = base.triangles[0];
  const double edge =
      norm(base.points[static_cast<std::size_t>(t[0])] - base.points[static_cast<std::size_t>(t[1])]);
  mesh.compute_limits();
  selective_refinement(mesh, BallLevel(mesh.limit_position(VertexHandle(0)), radius * edge, peak));
  return mesh;
}

}  // namespace rgbmesh::testing
