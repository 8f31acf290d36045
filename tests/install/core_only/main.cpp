// Refines the icosahedron uniformly to level 3 and back with the installed rgbmesh::core, checks
// the mesh with validate() at each stage and prints what the install test compares.
#include <cstdio>
#include <string>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"

int main() {
  using namespace rgbmesh;
  const TriangleMeshData ico = icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  selective_refinement(mesh, UniformLevel(3));
  std::string problems = mesh.validate(true);
  std::printf("level 3: %zu vertices, %zu triangles, max level %d, %s\n", mesh.num_vertices(),
              mesh.num_triangles(), mesh.max_level(), problems.empty() ? "valid" : problems.c_str());
  if (!problems.empty()) return 1;
  selective_refinement(mesh, CoarsenAll());
  problems = mesh.validate(true);
  std::printf("coarsened: %zu vertices, %zu triangles, %s\n", mesh.num_vertices(), mesh.num_triangles(),
              problems.empty() ? "valid" : problems.c_str());
  std::printf("checked handles: %d\n", RGBMESH_CHECKED_HANDLES);
  return problems.empty() ? 0 : 1;
}
