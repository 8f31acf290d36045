// The base of a fit from its target: the choice between the target's faces and a reconstruction,
// and the topology checks shared by decimation and reconstruction (see base.hpp).

#include "rgbmesh/fit/base.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/statistics.hpp"

namespace rgbmesh::fit {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string plural(long n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", seconds);
  return text;
}

}  // namespace

std::string with_thousands(std::size_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string to_string(const Topology& t) {
  return plural(t.components, "component", "components") + ", genus " + std::to_string(t.genus) + ", " +
         plural(t.boundary_loops, "boundary loop", "boundary loops");
}

Topology topology_of(const TriangleMeshData& mesh) {
  const RgbMesh rgb = RgbMesh::from_triangles(mesh.points, mesh.triangles);
  const std::string problem = rgb.validate();
  if (!problem.empty()) throw InputError("not a valid RGB base mesh: " + problem);
  const MeshStatistics s = compute_statistics(rgb);
  Topology t;
  t.components = s.components;
  t.boundary_loops = s.boundary_loops;
  t.euler_characteristic = s.euler_characteristic;
  t.genus = s.genus;
  return t;
}

const char* to_string(BaseSource source) {
  switch (source) {
    case BaseSource::given:
      return "given";
    case BaseSource::target:
      return "target";
    case BaseSource::decimated:
      return "decimated";
    default:
      return "reconstructed";
  }
}

Base make_base(const PolygonSoup& target, const std::vector<Vec3>& normals, const BaseOptions& options) {
  Base base;
  TriangleMeshData surface;
  bool has_surface = false;
  std::string unusable_faces;  // why the target's faces were not used
  if (!target.faces.empty()) {
    try {
      SoupOptions soup_options;
      soup_options.triangulate = options.triangulate;
      surface = prepare_triangle_mesh(target, soup_options);
      topology_of(surface);
      has_surface = true;
      base.notes.insert(base.notes.end(), surface.notes.begin(), surface.notes.end());
    } catch (const InputError& e) {
      unusable_faces = e.what();
      base.notes.push_back("the target's faces are not a valid manifold surface (" + unusable_faces +
                           "): the base is reconstructed from its " + with_thousands(target.points.size()) +
                           " points");
    }
  }
  if (!has_surface) {
    const auto start = std::chrono::steady_clock::now();
    ReconstructionOptions reconstruction = options.reconstruction;
    reconstruction.faces = std::max(reconstruction.faces, 4 * options.faces);
    try {
      surface = reconstruct_surface(target.points, normals, reconstruction);
    } catch (const InputError& e) {
      // The faces' problem may be the one the user has to fix (polygons without --triangulate).
      if (unusable_faces.empty()) throw;
      throw InputError(std::string(e.what()) + " (the target's faces were not used: " + unusable_faces + ")");
    }
    base.reconstruction_seconds = seconds_since(start);
    base.notes.insert(base.notes.end(), surface.notes.begin(), surface.notes.end());
    base.notes.push_back("reconstructed a surface of " + with_thousands(surface.triangles.size()) +
                         " faces (" + to_string(topology_of(surface)) + ") in " +
                         seconds_text(base.reconstruction_seconds));
  }
  const auto start = std::chrono::steady_clock::now();
  base.mesh = decimate(surface, options.faces, has_surface ? "the target" : "the reconstructed surface");
  base.decimation_seconds = seconds_since(start);
  base.notes.insert(base.notes.end(), base.mesh.notes.begin(), base.mesh.notes.end());
  base.mesh.notes.clear();
  if (!has_surface)
    base.source = BaseSource::reconstructed;
  else
    base.source =
        base.mesh.triangles.size() < surface.triangles.size() ? BaseSource::decimated : BaseSource::target;
  base.topology = topology_of(base.mesh);
  return base;
}

}  // namespace rgbmesh::fit
