// The base of a fit from its target: the choice between the target's faces and a reconstruction,
// and the topology checks shared by decimation and reconstruction (see base.hpp).

#include "rgbmesh/fit/base.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/statistics.hpp"
#include "rgbmesh/timing.hpp"
#include "reconstruction_methods.hpp"

namespace rgbmesh::fit {
namespace {

std::string plural(long n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", seconds);
  return text;
}

// Each triangle split into four at its edges' midpoints: the same surface, four times the faces.
TriangleMeshData split_in_four(const TriangleMeshData& mesh) {
  TriangleMeshData out;
  out.points = mesh.points;
  std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> midpoint;
  const auto middle = [&](std::int32_t a, std::int32_t b) {
    const auto key = std::minmax(a, b);
    const auto [it, inserted] = midpoint.emplace(key, static_cast<std::int32_t>(out.points.size()));
    if (inserted) out.points.push_back((mesh.points[a] + mesh.points[b]) * 0.5);
    return it->second;
  };
  for (const auto& t : mesh.triangles) {
    const std::int32_t ab = middle(t[0], t[1]), bc = middle(t[1], t[2]), ca = middle(t[2], t[0]);
    out.triangles.push_back({t[0], ab, ca});
    out.triangles.push_back({ab, t[1], bc});
    out.triangles.push_back({ca, bc, t[2]});
    out.triangles.push_back({ab, bc, ca});
  }
  // A sharp edge's halves keep its sharpness (the split surface is the same surface); corners
  // stay where they are.
  out.sharp.method = mesh.sharp.method;
  out.sharp.vertices = mesh.sharp.vertices;
  for (const SharpEdge& e : mesh.sharp.edges) {
    const auto it = midpoint.find(std::minmax(e.a, e.b));
    if (it == midpoint.end()) continue;
    out.sharp.edges.push_back({e.a, it->second, e.sharpness});
    out.sharp.edges.push_back({it->second, e.b, e.sharpness});
  }
  return out;
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

Base make_base(const PolygonSoup& target, const std::vector<Vec3>& normals, const BaseOptions& options,
               const StageControl& control) {
  Base base;
  TriangleMeshData surface;
  const bool has_surface = !target.faces.empty() && !options.ignore_faces;
  std::size_t given = 0;  // a surface target's triangles
  if (has_surface) {
    // A mesh target is a surface as it is, or a refusal that says how to make it one (the
    // checks' messages name --triangulate for polygons; the caller adds --repair's hint): a
    // reconstruction from its vertices alone would silently drop what its faces say (a
    // genus-3 quad mesh came back a genus-0 blob).
    surface = prepare_triangle_mesh(target, options.soup);
    topology_of(surface);
    base.notes.insert(base.notes.end(), surface.notes.begin(), surface.notes.end());
    surface.notes.clear();
    // A target coarser than the base asked for is split, not used as it is: its flat triangles
    // stay the same surface, and a finer control net lets the smooth limit surface follow its
    // edges and corners more closely (a 446-face CAD part: surface-to-target 0.8% of the
    // diagonal as it was).
    given = surface.triangles.size();
    while (4 * surface.triangles.size() <= 2 * options.faces) surface = split_in_four(surface);
    if (surface.triangles.size() > given)
      base.notes.push_back("the target has " + with_thousands(given) + " faces, fewer than the " +
                           with_thousands(options.faces) + " asked for: its triangles are split into " +
                           with_thousands(surface.triangles.size() / given) + " (" +
                           with_thousands(surface.triangles.size()) + " faces, the same surface)");
  } else {
    if (options.soup.sharp_angle > 0)
      base.notes.push_back("the sharp angle keeps the edges of a target's faces; a point cloud has none, so the "
                           "base is smooth");
    ReconstructionOptions reconstruction = options.reconstruction;
    reconstruction.faces = std::max(reconstruction.faces, 4 * options.faces);
    Reconstruction r = reconstruct_surface(target.points, normals, reconstruction, control);
    surface = std::move(r.mesh);
    base.reconstruction_seconds = r.seconds;
    base.reconstruction = r.method;
    base.unsupported = r.unsupported;
    base.notes.insert(base.notes.end(), surface.notes.begin(), surface.notes.end());
    surface.notes.clear();
    base.notes.push_back("reconstructed a surface of " + with_thousands(surface.triangles.size()) + " faces (" +
                         to_string(topology_of(surface)) + ") by " +
                         (r.method == ReconstructionMethod::poisson ? "Poisson reconstruction" : "advancing front") +
                         " in " + seconds_text(base.reconstruction_seconds));
  }
  // An open scan: the base follows the points' border, not the reconstruction's bridges and
  // caps over what the scan did not see. Trimmed at the reconstruction's resolution, before the
  // decimation (which keeps the border): trimming the coarse base instead cut away covered parts
  // where its large triangles leave the points (CGAL's hippo2: 28% of the area, targets 17% of
  // the diagonal from the surface).
  if (!has_surface && (base.reconstruction == ReconstructionMethod::advancing_front || base.unsupported > 0)) {
    base.trimmed = detail::trim_unsupported(surface, target.points, 4.0);
    if (base.trimmed > 0) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "trimmed %.2g%% of the reconstructed surface's area where no points lie (over parts the scan "
                    "did not see): the surface is open there",
                    100 * base.trimmed);
      base.notes.push_back(text);
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const bool split = has_surface && surface.triangles.size() > given;
  base.mesh = split ? surface
                    : decimate(surface, options.faces, has_surface ? "the target" : "the reconstructed surface", control);
  base.decimation_seconds = seconds_since(start);
  base.notes.insert(base.notes.end(), base.mesh.notes.begin(), base.mesh.notes.end());
  base.mesh.notes.clear();
  // The decimation moves the border's vertices too: its triangles are peeled back to the points.
  if (base.trimmed > 0) detail::trim_unsupported(base.mesh, target.points, 4.0, true);
  if (!has_surface)
    base.source = BaseSource::reconstructed;
  else
    base.source = base.mesh.triangles.size() < surface.triangles.size() ? BaseSource::decimated : BaseSource::target;
  base.topology = topology_of(base.mesh);
  return base;
}

}  // namespace rgbmesh::fit
