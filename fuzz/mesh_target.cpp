// End-to-end fuzz target for one mesh format (RGBMESH_FUZZ_EXTENSION): the file is read as the
// tool reads it (read_polygon_soup, through a per-process scratch file), and whatever reads is
// taken on as far as an RGB mesh goes: prepare_triangle_mesh, RgbMesh::from_triangles,
// validate(); for VTP and VTU also read_rgb_mesh, which restores a saved RGB state. Each stage
// may refuse the input with an InputError, except from_triangles: what prepare_triangle_mesh
// makes is a clean triangle mesh, and refusing it is a finding, like a mesh that validate()
// finds broken. Every soup also goes through the repair (check_repaired).

#include <cstdint>
#include <filesystem>
#include <string>

#include "fuzz_support.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/soup.hpp"
#include "rgbmesh/vtk_io.hpp"
#if defined(RGBMESH_FUZZ_REPAIR)
#include "rgbmesh/repair/repair.hpp"
#endif

using namespace rgbmesh;

namespace {

// The soup through the repair (rgbmesh::repair, CGAL), as `--repair --triangulate` reads it: a
// refusal (InputError) is fine, anything else escaping is a finding (a CGAL assertion included:
// the fuzz build keeps them on), and so is a repaired mesh that from_triangles refuses or
// validate() finds broken.
void check_repaired(const PolygonSoup& soup) {
#if defined(RGBMESH_FUZZ_REPAIR)
  TriangleMeshData repaired;
  const SoupOptions options = repair::soup_options(true, true);
  if (!fuzz::accepted([&] { repaired = prepare_triangle_mesh(soup, options); })) return;
  RgbMesh mesh;
  try {
    mesh = RgbMesh::from_triangles(repaired.points, repaired.triangles, repaired.sharp);
  } catch (const InputError& e) {
    fuzz::finding(std::string("RgbMesh::from_triangles refuses what the repair made: ") + e.what());
  }
  const std::string problem = mesh.validate();
  if (!problem.empty()) fuzz::finding("validate() on a repaired mesh: " + problem);
#else
  (void)soup;
#endif
}

// VTK XML files may carry a saved RGB state (rgb_state_io.cpp): read_rgb_mesh restores it, or
// refuses it as inconsistent. What it accepts must be a valid, stable RGB mesh.
void restore_saved_state(const std::filesystem::path& file) {
  const std::string extension = RGBMESH_FUZZ_EXTENSION;
  if (extension != ".vtp" && extension != ".vtu") return;
  RgbMeshFile read;
  if (!fuzz::accepted([&] { read = read_rgb_mesh(file); })) return;
  const std::string problem = read.mesh.validate(read.restored);
  if (!problem.empty())
    fuzz::finding(std::string("validate() on the mesh read_rgb_mesh ") + (read.restored ? "restored: " : "built: ") +
                  problem);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  PolygonSoup soup;
  {
    const fuzz::ScratchInput input(RGBMESH_FUZZ_EXTENSION, data, size);
    restore_saved_state(input.path());
    if (!fuzz::accepted([&] { soup = read_polygon_soup(input.path()); })) return 0;
  }
  check_repaired(soup);
  // Triangulating: a soup of triangles gives the same mesh as without, and polygons go on too.
  SoupOptions options;
  options.triangulate = true;
  TriangleMeshData prepared;
  if (!fuzz::accepted([&] { prepared = prepare_triangle_mesh(soup, options); })) return 0;
  RgbMesh mesh;
  try {
    mesh = RgbMesh::from_triangles(prepared.points, prepared.triangles, prepared.sharp);
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
  // Sharp features (OBJ tags): two levels of refinement keep every invariant and give finite
  // limit positions, whatever the tags were.
  if (mesh.has_sharp_features() && mesh.num_triangles() <= 2000) {
    selective_refinement(mesh, UniformLevel(2));
    const std::string refined = mesh.validate(true);
    if (!refined.empty()) fuzz::finding("validate() on a creased mesh refined twice: " + refined);
    mesh.compute_limits();
    for (const VertexHandle v : mesh.vertices())
      if (!is_finite(mesh.limit_position(v))) fuzz::finding("a creased mesh has a non-finite limit position");
  }
  return 0;
}
