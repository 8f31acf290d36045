// Turning a polygon soup into a clean, consistently oriented, manifold triangle mesh. The checks
// of the triangles are shared with RgbMesh::from_triangles (triangle_checks.hpp); this file adds
// what only a file can hold: faces that are not triangles, and the repairs.

#include "rgbmesh/soup.hpp"

#include <algorithm>
#include <cstddef>
#include <iomanip>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "rgbmesh/polygons.hpp"
#include "triangle_checks.hpp"

namespace rgbmesh {
namespace {

using detail::plural;
using detail::Triangle;

// The sharp features' vertices are the soup's, and their edges the triangles' (the tags count
// vertices from 0, as OpenSubdiv's do).
void check_sharp_tags(const PolygonSoup& soup, const std::vector<Triangle>& triangles) {
  const auto n = static_cast<std::int64_t>(soup.points.size());
  const auto range = [n](const std::string& what, std::int64_t v) {
    if (v < 0 || v >= n)
      throw InputError(what + " names vertex " + std::to_string(v) + ", outside 0.." + std::to_string(n - 1) +
                       " (tags count vertices from 0)");
  };
  for (std::size_t i = 0; i < soup.sharp.vertices.size(); ++i)
    range("corner tag " + std::to_string(i), soup.sharp.vertices[i].v);
  if (soup.sharp.edges.empty()) return;
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  edges.reserve(3 * triangles.size());
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) edges.emplace_back(std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < soup.sharp.edges.size(); ++i) {
    const SharpEdge& e = soup.sharp.edges[i];
    const std::string what =
        "crease tag " + std::to_string(i) + " (" + std::to_string(e.a) + ", " + std::to_string(e.b) + ")";
    range(what, e.a);
    range(what, e.b);
    if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(std::min(e.a, e.b), std::max(e.a, e.b))))
      throw InputError(what + " is not an edge of the mesh (tags count vertices from 0)");
  }
}

// The tags in the numbering of the prepared mesh: new_vertex(v) is v's new index or -1 (gone).
// Tags whose edge is no longer an edge of `triangles` are dropped, with a note.
template <class NewVertex>
SharpFeatures renumbered_tags(const SharpFeatures& in, NewVertex new_vertex, const std::vector<Triangle>& triangles,
                              std::vector<std::string>& notes) {
  SharpFeatures out;
  out.method = in.method;
  if (in.edges.empty() && in.vertices.empty()) return out;
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) edges.emplace_back(std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  std::size_t lost = 0;
  for (const SharpEdge& e : in.edges) {
    const std::int32_t a = new_vertex(e.a), b = new_vertex(e.b);
    if (a < 0 || b < 0 || a == b ||
        !std::binary_search(edges.begin(), edges.end(), std::make_pair(std::min(a, b), std::max(a, b)))) {
      ++lost;
      continue;
    }
    out.edges.push_back({a, b, e.sharpness});
  }
  for (const SharpVertex& v : in.vertices) {
    const std::int32_t w = new_vertex(v.v);
    if (w < 0) {
      ++lost;
      continue;
    }
    out.vertices.push_back({w, v.sharpness});
  }
  if (lost > 0)
    notes.push_back("dropped " + plural(lost, "sharpness tag", "sharpness tags") +
                    " whose edge or vertex the repairs removed");
  return out;
}

// SoupOptions::sharp_angle: the detected features added to the tags, and a note.
void add_detected_features(TriangleMeshData& out, double angle) {
  if (angle == 0.0) return;
  if (!(angle > 0.0 && angle < 180.0))
    throw InputError("the sharp angle must be between 0 and 180 degrees, not " + std::to_string(angle));
  const SharpFeatures detected = detect_sharp_features(out.points, out.triangles, angle);
  out.sharp = merged(out.sharp, detected);
  std::ostringstream note;
  note << "edges sharper than " << angle << " degrees: " << plural(detected.edges.size(), "crease edge", "crease edges")
       << ", " << plural(detected.vertices.size(), "corner", "corners") << " where creases turn";
  out.notes.push_back(note.str());
}

// 't interpolateboundary ... 1': boundary vertices of a single triangle become corners.
void add_boundary_corners(TriangleMeshData& out) {
  std::vector<int> triangles_at(out.points.size(), 0);
  for (const Triangle& t : out.triangles)
    for (const std::int32_t v : t) ++triangles_at[static_cast<std::size_t>(v)];
  // A vertex of one triangle is on the boundary (its two edges there have one side).
  for (std::size_t v = 0; v < triangles_at.size(); ++v)
    if (triangles_at[v] == 1) out.sharp.vertices.push_back({static_cast<std::int32_t>(v), kInfiniteSharpness});
}

void check_faces(const PolygonSoup& soup) {
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (soup.faces[f].size() < 3)
      throw InputError("face " + std::to_string(f) + " has " +
                       plural(soup.faces[f].size(), "vertex", "vertices") + "; a face needs at least 3");
  }
  detail::check_indices(soup.faces, soup.points.size(), detail::file_wording);
}

// Triangles in face order; polygons are split when allowed (triangulate_polygon: fans for
// planar convex ones, ears for the others, self-crossing ones refused with the face named).
// source_face stays empty when every face is a triangle (then triangle i is face i).
std::vector<Triangle> triangles_of(const PolygonSoup& soup, const SoupOptions& options,
                                   std::vector<std::int64_t>& source_face, std::vector<std::string>& notes) {
  std::uint64_t total = 0, polygons = 0;
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const std::size_t n = soup.faces[f].size();
    if (n > 3) {
      if (!options.triangulate)
        throw InputError("face " + std::to_string(f) + " has " + std::to_string(n) +
                         " vertices; only triangles are supported (use --triangulate to split polygons" +
                         (options.repair ? "; a repair needs it too)" : ")"));
      ++polygons;
    }
    total += n - 2;
  }
  detail::check_triangle_count(total);

  std::vector<Triangle> triangles;
  triangles.reserve(total);
  if (polygons > 0) source_face.reserve(total);
  std::uint64_t by_kind[3] = {0, 0, 0};
  double most_out_of_plane = 0;
  std::vector<Vec3> corners;
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const auto& face = soup.faces[f];
    if (face.size() == 3) {
      triangles.push_back({static_cast<std::int32_t>(face[0]), static_cast<std::int32_t>(face[1]),
                           static_cast<std::int32_t>(face[2])});
      if (polygons > 0) source_face.push_back(static_cast<std::int64_t>(f));
      continue;
    }
    corners.clear();
    for (const std::int64_t v : face) corners.push_back(soup.points[static_cast<std::size_t>(v)]);
    PolygonTriangles split;
    try {
      split = triangulate_polygon(corners);
    } catch (const InputError& e) {
      throw InputError("face " + std::to_string(f) + " (a polygon of " + std::to_string(face.size()) +
                       " vertices) " + e.what());
    }
    ++by_kind[static_cast<int>(split.split)];
    if (split.split == PolygonSplit::warped_ears) most_out_of_plane = std::max(most_out_of_plane, split.out_of_plane);
    for (const auto& t : split.triangles) {
      triangles.push_back({static_cast<std::int32_t>(face[static_cast<std::size_t>(t[0])]),
                           static_cast<std::int32_t>(face[static_cast<std::size_t>(t[1])]),
                           static_cast<std::int32_t>(face[static_cast<std::size_t>(t[2])])});
      source_face.push_back(static_cast<std::int64_t>(f));
    }
  }
  if (polygons > 0) {
    std::string how;
    const auto add = [&how](std::uint64_t count, const std::string& what) {
      if (count > 0) how += (how.empty() ? "" : ", ") + std::to_string(count) + " " + what;
    };
    add(by_kind[0], "planar and convex as fans");
    add(by_kind[1], "concave or with corners in line by cutting ears in their planes");
    add(by_kind[2], "not planar by cutting ears (next note)");
    notes.push_back("split " + plural(polygons, "polygon", "polygons") + " into triangles (" +
                    plural(total, "triangle", "triangles") + " in all): " + how);
  }
  if (by_kind[2] > 0) {
    std::ostringstream percent;
    percent << std::setprecision(2) << 100 * most_out_of_plane;
    const bool one = by_kind[2] == 1;
    notes.push_back(plural(by_kind[2], "polygon is", "polygons are") + " not planar (corners up to " + percent.str() +
                    (one ? "% of its size off its best-fit plane): split by cutting ears in that plane"
                         : "% of their sizes off their best-fit planes): split by cutting ears in those planes") +
                    ", best-shaped triangles first; where " + (one ? "it bends" : "they bend") +
                    " between corners is a guess (split such polygons in the file to choose)");
  }
  return triangles;
}

// For a file without vertex numbers (STL: triangles only), a non-finite coordinate is named by
// the first triangle that uses it (the point's number would be one the file does not have).
void check_finite_corners(const PolygonSoup& soup) {
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    for (const std::int64_t v : soup.faces[f]) {
      if (v >= 0 && static_cast<std::size_t>(v) < soup.points.size() && !is_finite(soup.points[v]))
        throw InputError("a corner of triangle " + std::to_string(f) + " has a non-finite coordinate " +
                         detail::point_text(soup.points[v]));
    }
  }
}

// "1,280": counts in notes, as the user reads them.
std::string thousands(std::size_t n) {
  const std::string digits = std::to_string(n);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

// The note for faces that meet along an edge only through equal positions, not through shared
// vertices: such faces are separate pieces to the mesh (OFF, OBJ and PLY exporters often give
// every face its own vertices), while the user sees one surface. Vertices that only share a
// position (a pinch split into its fans) are fine. Empty when there are none.
std::string unjoined_note(const std::vector<Vec3>& points, const std::vector<Triangle>& triangles) {
  // Position ids: the points sorted (-0 and +0 are one; the points are finite).
  std::vector<std::int32_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::int32_t>(i);
  const auto less = [&](std::int32_t i, std::int32_t j) {
    const Vec3 &a = points[i], &b = points[j];
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::int32_t> position(points.size());
  std::int32_t positions = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i > 0 && less(order[i - 1], order[i])) ++positions;
    position[order[i]] = positions;
  }
  ++positions;
  if (static_cast<std::size_t>(positions) == points.size()) return "";
  std::vector<std::pair<std::int32_t, std::int32_t>> by_vertex, by_position;
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = t[k], b = t[(k + 1) % 3];
      by_vertex.emplace_back(std::min(a, b), std::max(a, b));
      by_position.emplace_back(std::min(position[a], position[b]), std::max(position[a], position[b]));
    }
  for (auto* edges : {&by_vertex, &by_position}) {
    std::sort(edges->begin(), edges->end());
    edges->erase(std::unique(edges->begin(), edges->end()), edges->end());
  }
  if (by_position.size() == by_vertex.size()) return "";
  return thousands(points.size()) + " vertices at " + thousands(static_cast<std::size_t>(positions)) +
         " positions: faces that meet only at equal positions are not joined (--repair merges them)";
}

// The triangles re-oriented as the checks found, and the points without the unreferenced ones
// (the others in their order): what every passing mesh gets.
std::vector<std::int32_t> finish(const std::vector<Vec3>& points, std::vector<Triangle> triangles,
                                 const detail::SurfaceCheck& surface, TriangleMeshData& out) {
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (surface.flip[t]) std::swap(triangles[t][1], triangles[t][2]);
  }
  if (surface.flips > 0)
    out.notes.push_back("re-oriented " + plural(surface.flips, "triangle", "triangles") +
                        " for a consistent orientation");

  constexpr std::int32_t unused = -1;
  std::vector<std::int32_t> new_index(points.size(), unused);
  for (const Triangle& t : triangles)
    for (const std::int32_t v : t) new_index[v] = 0;
  std::size_t dropped = 0, first_dropped = 0;
  for (std::size_t v = 0; v < points.size(); ++v) {
    if (new_index[v] == unused) {
      if (dropped++ == 0) first_dropped = v;
      continue;
    }
    new_index[v] = static_cast<std::int32_t>(out.points.size());
    out.points.push_back(points[v]);
  }
  if (dropped > 0)
    out.notes.push_back("dropped " + plural(dropped, "unreferenced vertex", "unreferenced vertices") +
                        " (first: " + std::to_string(first_dropped) + ")");
  for (Triangle& t : triangles)
    for (std::int32_t& v : t) v = new_index[v];
  out.triangles = std::move(triangles);
  return new_index;
}

// The caller's repair, then the checks on what it gives. A failure is a plain InputError, not a
// MeshDefectError: the repair was tried and did not remove the defect. The repaired mesh's
// vertices are named by position (their numbers are not the file's).
TriangleMeshData repaired(const PolygonSoup& soup, std::vector<Triangle> triangles, const SoupOptions& options,
                          std::vector<std::string> notes) {
  std::vector<Vec3> points = soup.points;
  options.repair(points, triangles, notes);
  if (triangles.empty()) throw InputError("could not be repaired: nothing is left of the mesh");
  detail::check_indices(triangles, points.size(), detail::mesh_wording);
  TriangleMeshData out;
  out.notes = std::move(notes);
  const std::vector<std::int64_t> triangle_is_face;
  detail::SurfaceCheck surface;
  try {
    detail::check_points(points, triangles.size(), detail::mesh_wording);
    surface = detail::check_surface(points, triangles, detail::TriangleNames(triangle_is_face, points),
                                    detail::AreaCheck::zero_area_is_degenerate);
  } catch (const InputError& e) {
    throw InputError(std::string("could not be repaired: in the repaired mesh, ") + e.what());
  }
  finish(points, std::move(triangles), surface, out);
  // The tags follow their vertices by position (the repair may merge, move or renumber them).
  const auto less = [](const Vec3& a, const Vec3& b) {
    return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : a.z < b.z);
  };
  std::vector<std::int32_t> by_position;  // (sorted only when there are tags to follow)
  if (!soup.sharp.edges.empty() || !soup.sharp.vertices.empty()) {
    by_position.resize(out.points.size());
    for (std::size_t i = 0; i < by_position.size(); ++i) by_position[i] = static_cast<std::int32_t>(i);
    std::sort(by_position.begin(), by_position.end(),
              [&](std::int32_t i, std::int32_t j) { return less(out.points[i], out.points[j]); });
  }
  const auto new_vertex = [&](std::int64_t v) -> std::int32_t {
    const Vec3& p = soup.points[static_cast<std::size_t>(v)];
    const auto it = std::lower_bound(by_position.begin(), by_position.end(), p,
                                     [&](std::int32_t i, const Vec3& q) { return less(out.points[i], q); });
    return it != by_position.end() && out.points[*it] == p ? *it : -1;
  };
  out.sharp = renumbered_tags(soup.sharp, new_vertex, out.triangles, out.notes);
  if (soup.boundary_corners) add_boundary_corners(out);
  add_detected_features(out, options.sharp_angle);
  return out;
}

}  // namespace

TriangleMeshData prepare_triangle_mesh(const PolygonSoup& soup, const SoupOptions& options) {
  if (!soup.numbered_vertices) check_finite_corners(soup);
  detail::check_points(soup.points, soup.faces.size(), detail::file_wording);
  check_faces(soup);

  std::vector<std::string> notes = soup.notes;
  std::vector<std::int64_t> source_face;
  std::vector<Triangle> triangles = triangles_of(soup, options, source_face, notes);
  check_sharp_tags(soup, triangles);
  if (options.repair) return repaired(soup, std::move(triangles), options, std::move(notes));

  TriangleMeshData out;
  out.notes = std::move(notes);
  const detail::TriangleNames name = soup.numbered_vertices ? detail::TriangleNames(source_face)
                                                            : detail::TriangleNames(source_face, soup.points);
  const detail::SurfaceCheck surface =
      detail::check_surface(soup.points, triangles, name, detail::AreaCheck::zero_area_is_degenerate);
  const std::vector<std::int32_t> new_index = finish(soup.points, std::move(triangles), surface, out);
  out.sharp = renumbered_tags(
      soup.sharp, [&](std::int64_t v) { return new_index[static_cast<std::size_t>(v)]; }, out.triangles, out.notes);
  if (soup.boundary_corners) add_boundary_corners(out);
  add_detected_features(out, options.sharp_angle);

  if (std::string note = unjoined_note(out.points, out.triangles); !note.empty()) out.notes.push_back(note);
  return out;
}

}  // namespace rgbmesh
