// End-to-end fuzz target for one mesh format (RGBMESH_FUZZ_EXTENSION): the file is read as the
// tool reads it (read_polygon_soup, through a per-process scratch file), and whatever reads is
// taken on as far as an RGB mesh goes: prepare_triangle_mesh, RgbMesh::from_triangles,
// validate(). Each stage may refuse the input with an InputError, except from_triangles: what
// prepare_triangle_mesh makes is a clean triangle mesh, and refusing it is a finding, like a
// mesh that validate() finds broken.

#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/soup.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  PolygonSoup soup;
  {
    const fuzz::ScratchInput input(RGBMESH_FUZZ_EXTENSION, data, size);
    if (!fuzz::accepted([&] { soup = read_polygon_soup(input.path()); })) return 0;
  }
  // Triangulating: a soup of triangles gives the same mesh as without, and polygons go on too.
  SoupOptions options;
  options.triangulate = true;
  TriangleMeshData prepared;
  if (!fuzz::accepted([&] { prepared = prepare_triangle_mesh(soup, options); })) return 0;
  RgbMesh mesh;
  try {
    mesh = RgbMesh::from_triangles(prepared.points, prepared.triangles);
  } catch (const InputError& e) {
    fuzz::finding(std::string("RgbMesh::from_triangles refuses what prepare_triangle_mesh made: ") +
                  e.what());
  }
  if (mesh.num_vertices() != prepared.points.size() || mesh.num_triangles() != prepared.triangles.size())
    fuzz::finding("RgbMesh::from_triangles made " + std::to_string(mesh.num_vertices()) + " vertices and " +
                  std::to_string(mesh.num_triangles()) + " triangles of " +
                  std::to_string(prepared.points.size()) + " and " +
                  std::to_string(prepared.triangles.size()));
  const std::string problem = mesh.validate();
  if (!problem.empty()) fuzz::finding("validate() on the mesh of an accepted file: " + problem);
  return 0;
}
