// Turning a polygon soup into a clean, consistently oriented, manifold triangle mesh. The checks
// of the triangles are shared with RgbMesh::from_triangles (triangle_checks.hpp); this file adds
// what only a file can hold: faces that are not triangles, and the repairs.

#include "rgbmesh/soup.hpp"

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "triangle_checks.hpp"

namespace rgbmesh {
namespace {

using detail::plural;
using detail::Triangle;

void check_faces(const PolygonSoup& soup) {
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (soup.faces[f].size() < 3)
      throw InputError("face " + std::to_string(f) + " has " +
                       plural(soup.faces[f].size(), "vertex", "vertices") + "; a face needs at least 3");
  }
  detail::check_indices(soup.faces, soup.points.size(), detail::file_wording);
}

// Triangles in face order; polygons are fan-split from their first vertex when allowed.
// source_face stays empty when every face is a triangle (then triangle i is face i).
std::vector<Triangle> triangles_of(const PolygonSoup& soup, const SoupOptions& options,
                                   std::vector<std::int64_t>& source_face, std::vector<std::string>& notes) {
  std::uint64_t total = 0, polygons = 0;
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const std::size_t n = soup.faces[f].size();
    if (n > 3) {
      if (!options.triangulate)
        throw InputError("face " + std::to_string(f) + " has " + std::to_string(n) +
                         " vertices; only triangles are supported (use --triangulate to fan-split polygons)");
      ++polygons;
    }
    total += n - 2;
  }
  detail::check_triangle_count(total);

  std::vector<Triangle> triangles;
  triangles.reserve(total);
  if (polygons > 0) source_face.reserve(total);
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const auto& face = soup.faces[f];
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      triangles.push_back({static_cast<std::int32_t>(face[0]), static_cast<std::int32_t>(face[i]),
                           static_cast<std::int32_t>(face[i + 1])});
      if (polygons > 0) source_face.push_back(static_cast<std::int64_t>(f));
    }
  }
  if (polygons > 0)
    notes.push_back("fan-split " + plural(polygons, "polygon", "polygons") + " into triangles (" +
                    plural(total, "triangle", "triangles") + " in all)");
  return triangles;
}

}  // namespace

TriangleMeshData prepare_triangle_mesh(const PolygonSoup& soup, const SoupOptions& options) {
  detail::check_points(soup.points, soup.faces.size(), detail::file_wording);
  check_faces(soup);

  TriangleMeshData out;
  std::vector<std::int64_t> source_face;
  std::vector<Triangle> triangles = triangles_of(soup, options, source_face, out.notes);
  const detail::TriangleNames name(source_face);
  const detail::SurfaceCheck surface =
      detail::check_surface(soup.points, triangles, name, detail::AreaCheck::zero_area_is_degenerate);

  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (surface.flip[t]) std::swap(triangles[t][1], triangles[t][2]);
  }
  if (surface.flips > 0)
    out.notes.push_back("re-oriented " + plural(surface.flips, "triangle", "triangles") +
                        " for a consistent orientation");

  // Drop unreferenced vertices, keeping the others in file order.
  constexpr std::int32_t unused = -1;
  std::vector<std::int32_t> new_index(soup.points.size(), unused);
  for (const Triangle& t : triangles)
    for (const std::int32_t v : t) new_index[v] = 0;
  std::size_t dropped = 0, first_dropped = 0;
  for (std::size_t v = 0; v < soup.points.size(); ++v) {
    if (new_index[v] == unused) {
      if (dropped++ == 0) first_dropped = v;
      continue;
    }
    new_index[v] = static_cast<std::int32_t>(out.points.size());
    out.points.push_back(soup.points[v]);
  }
  if (dropped > 0)
    out.notes.push_back("dropped " + plural(dropped, "unreferenced vertex", "unreferenced vertices") +
                        " (first: " + std::to_string(first_dropped) + ")");
  for (Triangle& t : triangles)
    for (std::int32_t& v : t) v = new_index[v];
  out.triangles = std::move(triangles);
  return out;
}

}  // namespace rgbmesh
