// Repairing triangle soups with CGAL's Polygon Mesh Processing (see repair.hpp). The first steps
// work on the soup, as the file has it; the geometric ones (collapses, flips) need a halfedge
// mesh, which only a manifold, consistently oriented surface can become: hence the order
//   soup: isolated points, duplicate positions, zero-area and duplicate triangles, back-to-back
//         pairs, orientation (splitting what is non-manifold, cutting what cannot be oriented)
//   mesh: remaining non-manifold vertices, degenerate triangles, needles, caps.
// Counts for the note come from CGAL's return values and its orientation visitor, or from
// comparing before and after where CGAL returns none.

#include "rgbmesh/repair/repair.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/manifoldness.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <map>
#include <numeric>
#include <set>
#include <utility>

#include "rgbmesh/errors.hpp"

namespace rgbmesh::repair {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Polygon = std::vector<std::size_t>;
using Mesh = CGAL::Surface_mesh<Point>;
using Edge = std::pair<std::size_t, std::size_t>;  // lower id first
using Key = std::array<std::size_t, 3>;            // a triangle's corners, sorted

// Coordinates closer to zero than this times the bounding-box diagonal are rounding noise.
constexpr double zero_snap = 1e-12;

struct Soup {
  std::vector<Point> points;
  std::vector<Polygon> polygons;  // triangles (repair_polygon_soup wants resizable polygons)
};

Edge edge_of(std::size_t a, std::size_t b) { return {std::min(a, b), std::max(a, b)}; }

Key key_of(const Polygon& p) {
  Key k = {p[0], p[1], p[2]};
  std::sort(k.begin(), k.end());
  return k;
}

std::string counted(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) { parent_[find(a)] = find(b); }

 private:
  std::vector<std::size_t> parent_;
};

// Isolated points, positions shared by several points, triangles that lost a corner to the merge
// (two corners at one position: zero area; removing one joins its neighbours directly, which is
// what collapsing it would do, so no hole opens) and exact repeats of a triangle (one copy kept).
void clean_soup(Soup& soup, RepairReport& report) {
  report.isolated_vertices = PMP::remove_isolated_points_in_polygon_soup(soup.points, soup.polygons);
  report.merged_vertices = PMP::merge_duplicate_points_in_polygon_soup(soup.points, soup.polygons);
  const auto coincident = static_cast<std::size_t>(
      std::count_if(soup.polygons.begin(), soup.polygons.end(),
                    [](const Polygon& p) { return p[0] == p[1] || p[1] == p[2] || p[2] == p[0]; }));
  const std::size_t before = soup.polygons.size();
  // Orientation matters here: opposite copies are the back-to-back pairs, decided below.
  PMP::repair_polygon_soup(soup.points, soup.polygons,
                           CGAL::parameters::erase_all_duplicates(false).require_same_orientation(true));
  report.zero_area_triangles += coincident;
  report.repeated_triangles = before - soup.polygons.size() - coincident;
}

// Back-to-back pairs: two triangles with the same corners in opposite orders. Between two parts
// that touch (a CAD union, an OpenSCAD export) they are the wall where the parts meet: both go,
// and the parts become one surface. On a two-sided sheet (a plane exported for both sides) they
// are the sheet itself: one copy stays. Connected pairs form regions; a region is a wall when it
// has a rim and other triangles continue from every edge of it; a sheet's rim is free, and a
// closed two-sided surface has no rim. A pair of zero-area triangles always goes: it covers
// nothing from either side (OpenSCAD writes such pairs where a vertex lies on an edge).
void resolve_back_to_back(Soup& soup, RepairReport& report) {
  std::vector<std::pair<Key, std::size_t>> keys;  // sorted: the copies of a triangle side by side
  keys.reserve(soup.polygons.size());
  for (std::size_t t = 0; t < soup.polygons.size(); ++t) keys.emplace_back(key_of(soup.polygons[t]), t);
  std::sort(keys.begin(), keys.end());
  std::vector<std::array<std::size_t, 2>> pairs;  // after clean_soup: at most one copy per orientation
  for (std::size_t i = 0; i + 1 < keys.size(); ++i)
    if (keys[i].first == keys[i + 1].first) pairs.push_back({keys[i].second, keys[i + 1].second});
  if (pairs.empty()) return;

  std::map<Edge, std::vector<std::size_t>> pairs_of_edge;  // the pairs along each of their edges
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const Polygon& t = soup.polygons[pairs[p][0]];
    for (int k = 0; k < 3; ++k) pairs_of_edge[edge_of(t[k], t[(k + 1) % 3])].push_back(p);
  }
  std::map<Edge, std::size_t> uses;  // triangles along those edges, the pairs' own included
  for (const Polygon& t : soup.polygons)
    for (int k = 0; k < 3; ++k) {
      const auto it = pairs_of_edge.find(edge_of(t[k], t[(k + 1) % 3]));
      if (it != pairs_of_edge.end()) ++uses[it->first];
    }
  UnionFind regions(pairs.size());
  for (const auto& [edge, along] : pairs_of_edge)
    for (std::size_t i = 1; i < along.size(); ++i) regions.unite(along[0], along[i]);
  // A rim edge belongs to one pair of its region (so to 2 of the triangles along it).
  std::vector<char> has_rim(pairs.size(), 0), free_rim(pairs.size(), 0);
  for (const auto& [edge, along] : pairs_of_edge) {
    if (along.size() != 1) continue;
    const std::size_t region = regions.find(along[0]);
    has_rim[region] = 1;
    if (uses[edge] <= 2) free_rim[region] = 1;
  }
  std::vector<char> remove(soup.polygons.size(), 0);
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const Polygon& t = soup.polygons[pairs[p][0]];
    const bool flat = CGAL::collinear(soup.points[t[0]], soup.points[t[1]], soup.points[t[2]]);
    const std::size_t region = regions.find(p);
    const bool wall = has_rim[region] && !free_rim[region];
    remove[pairs[p][1]] = 1;
    if (flat || wall) remove[pairs[p][0]] = 1;
    if (flat)
      report.zero_area_triangles += 2;
    else
      ++(wall ? report.back_to_back_removed : report.back_to_back_kept);
  }
  std::vector<Polygon> kept;
  kept.reserve(soup.polygons.size());
  for (std::size_t t = 0; t < soup.polygons.size(); ++t)
    if (!remove[t]) kept.push_back(std::move(soup.polygons[t]));
  soup.polygons = std::move(kept);
  report.isolated_vertices += PMP::remove_isolated_points_in_polygon_soup(soup.points, soup.polygons);
}

// What orient_polygon_soup reports while it works (it takes its visitor by value: hence the
// pointer to the counts).
struct OrientationCounts {
  std::set<Edge> non_manifold_edges;
  std::size_t split_vertices = 0, copies = 0, reversed = 0;
  std::map<std::size_t, std::size_t> original;  // a copy's point -> the point it copies
};

struct CountingVisitor : public PMP::Default_orientation_visitor {
  explicit CountingVisitor(OrientationCounts* into) : counts(into) {}
  void non_manifold_edge(std::size_t a, std::size_t b, std::size_t) {
    counts->non_manifold_edges.insert(edge_of(a, b));
  }
  void non_manifold_vertex(std::size_t, std::size_t fans) {
    ++counts->split_vertices;
    counts->copies += fans;
  }
  void duplicated_vertex(std::size_t from, std::size_t copy) { counts->original[copy] = from; }
  void polygon_orientation_reversed(std::size_t) { ++counts->reversed; }
  OrientationCounts* counts;
};

// The two triangles along each edge that has exactly two: those orientation may cut apart.
std::vector<std::pair<Edge, std::array<std::size_t, 2>>> two_sided_edges(
    const std::vector<Polygon>& polygons) {
  std::vector<std::pair<Edge, std::size_t>> sides;
  sides.reserve(3 * polygons.size());
  for (std::size_t t = 0; t < polygons.size(); ++t)
    for (int k = 0; k < 3; ++k) sides.emplace_back(edge_of(polygons[t][k], polygons[t][(k + 1) % 3]), t);
  std::sort(sides.begin(), sides.end());
  std::vector<std::pair<Edge, std::array<std::size_t, 2>>> out;
  for (std::size_t i = 0, j; i < sides.size(); i = j) {
    for (j = i + 1; j < sides.size() && sides[j].first == sides[i].first;) ++j;
    if (j - i == 2) out.push_back({sides[i].first, {sides[i].second, sides[i + 1].second}});
  }
  return out;
}

// Consistent orientation by orient_polygon_soup, which splits non-manifold edges and vertices
// (each fan gets its own copy of the vertex) and cuts a surface that cannot be oriented open along
// the edges where the orientation would flip. Those cuts are the edges that two triangles shared
// before and share no more (a non-manifold vertex's fans never share an edge).
void orient(Soup& soup, RepairReport& report) {
  const auto shared = two_sided_edges(soup.polygons);
  OrientationCounts counts;
  PMP::orient_polygon_soup(soup.points, soup.polygons, CGAL::parameters::visitor(CountingVisitor(&counts)));
  report.non_manifold_edges = counts.non_manifold_edges.size();
  report.split_vertices = counts.split_vertices;
  report.vertex_copies = counts.copies;
  report.reoriented_triangles = counts.reversed;
  if (counts.original.empty()) return;
  const auto original = [&](std::size_t v) {
    const auto it = counts.original.find(v);
    return it == counts.original.end() ? v : it->second;
  };
  // The points that triangle t has now at the ends of edge e (as it was before).
  const auto now = [&](std::size_t t, const Edge& e) {
    const Polygon& p = soup.polygons[t];
    for (int k = 0; k < 3; ++k) {
      const std::size_t a = p[k], b = p[(k + 1) % 3];
      if (edge_of(original(a), original(b)) == e) return edge_of(a, b);
    }
    return Edge{0, 0};
  };
  for (const auto& [edge, triangles] : shared)
    if (now(triangles[0], edge) != now(triangles[1], edge)) ++report.cut_edges;
}

Mesh mesh_of(const Soup& soup) {
  if (!PMP::is_polygon_soup_a_polygon_mesh(soup.polygons))
    throw InputError(
        "could not be repaired: the triangles make no surface even with their non-manifold edges "
        "and vertices split");
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(soup.points, soup.polygons, mesh);
  return mesh;
}

std::size_t degenerate_count(const Mesh& mesh) {
  std::vector<Mesh::Face_index> found;
  PMP::degenerate_faces(mesh, std::back_inserter(found));
  return found.size();
}

std::set<Key> triangle_keys(const Mesh& mesh) {
  std::set<Key> keys;
  for (const Mesh::Face_index f : mesh.faces()) {
    Polygon corners;
    for (const Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      corners.push_back(v);
    keys.insert(key_of(corners));
  }
  return keys;
}

// Zero-area triangles (collinear corners), then needles and caps within the bounds. Collapses
// keep one end of the edge where it is (CGAL moves no vertex), so a point moves by at most the
// edge's length; a flip changes the surface by at most the cap's height.
void collapse_and_flip(Mesh& mesh, double max_move, const RepairOptions& options, RepairReport& report) {
  if (const std::size_t degenerate = degenerate_count(mesh); degenerate > 0) {
    PMP::remove_degenerate_faces(mesh);
    report.zero_area_triangles += degenerate - std::min(degenerate, degenerate_count(mesh));
  }
  // A zero bound would mean "no limit" to CGAL: then nothing is collapsed or flipped.
  if (!(max_move > 0)) return;
  // Needles only (a cap threshold of -1 is an angle of exactly 180 degrees: none is left).
  std::size_t before = mesh.number_of_faces();
  PMP::experimental::remove_almost_degenerate_faces(mesh, -1.0, options.needle_ratio, max_move);
  report.needle_triangles = before - mesh.number_of_faces();
  // Caps only (no ratio of edge lengths is that large). Flips keep the vertices, so the triangles
  // that are new afterwards are the flipped pairs.
  constexpr double no_needles = 1e30;
  const double pi = std::acos(-1.0);
  const std::set<Key> keys = triangle_keys(mesh);
  before = mesh.number_of_faces();
  PMP::experimental::remove_almost_degenerate_faces(
      mesh, std::cos(options.cap_angle_degrees * pi / 180), no_needles, max_move,
      CGAL::parameters::flip_triangle_height_threshold(max_move));
  report.removed_caps = before - mesh.number_of_faces();
  std::size_t fresh = 0;
  for (const Key& k : triangle_keys(mesh)) fresh += keys.count(k) == 0;
  report.flipped_caps = fresh / 2;
}

double diagonal(const std::vector<Vec3>& points) {
  if (points.empty()) return 0;
  Vec3 lo = points.front(), hi = lo;
  for (const Vec3& p : points) {
    lo = Vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
    hi = Vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
  }
  return norm(hi - lo);
}

// Coordinates that are zero but for rounding (a CAD tool's cos 90 degrees is 6e-17) set to zero.
// Points on an axis-aligned line then lie on it exactly, and CGAL's exact predicates see the
// triangles between them as degenerate, which they are: a few such points along one edge make a
// chain of slivers that neither flips nor collapses remove, but the collapse of degenerate faces
// does.
std::size_t snap_to_zero(std::vector<Vec3>& points, double below) {
  std::size_t snapped = 0;
  for (Vec3& p : points)
    for (double* c : {&p.x, &p.y, &p.z})
      if (*c != 0 && std::abs(*c) < below) {
        *c = 0;
        ++snapped;
      }
  return snapped;
}

}  // namespace

bool RepairReport::changed() const {
  return snapped_coordinates + isolated_vertices + merged_vertices + zero_area_triangles +
             repeated_triangles + back_to_back_removed + back_to_back_kept + non_manifold_edges + cut_edges +
             split_vertices + reoriented_triangles + needle_triangles + flipped_caps + removed_caps >
         0;
}

std::string RepairReport::note() const {
  if (!changed()) return "repaired: nothing needed repair";
  std::vector<std::string> parts;
  const auto add = [&](std::size_t n, const std::string& text) {
    if (n > 0) parts.push_back(text);
  };
  add(snapped_coordinates, "set " + counted(snapped_coordinates, "coordinate", "coordinates") + " within " +
                               "1e-12 of the diagonal to 0");
  add(isolated_vertices, "dropped " + counted(isolated_vertices, "isolated vertex", "isolated vertices"));
  add(merged_vertices, "merged " + counted(merged_vertices, "duplicate vertex", "duplicate vertices"));
  add(zero_area_triangles,
      "collapsed " + counted(zero_area_triangles, "zero-area triangle", "zero-area triangles"));
  add(repeated_triangles,
      "removed " + counted(repeated_triangles, "repeated triangle", "repeated triangles"));
  add(back_to_back_removed, "removed " +
                                counted(back_to_back_removed, "back-to-back pair", "back-to-back pairs") +
                                " of triangles (walls between touching parts)");
  add(back_to_back_kept, "kept one triangle of " +
                             counted(back_to_back_kept, "back-to-back pair", "back-to-back pairs") +
                             " (a two-sided sheet)");
  add(non_manifold_edges, "split " + counted(non_manifold_edges, "non-manifold edge", "non-manifold edges"));
  add(cut_edges, "cut the surface open along " + counted(cut_edges, "edge", "edges") + " to orient it");
  add(split_vertices, "split " + counted(split_vertices, "non-manifold vertex", "non-manifold vertices") +
                          " into " + std::to_string(vertex_copies));
  add(reoriented_triangles, "re-oriented " + counted(reoriented_triangles, "triangle", "triangles"));
  add(needle_triangles, "collapsed " + counted(needle_triangles, "needle triangle", "needle triangles"));
  add(flipped_caps, "flipped " + counted(flipped_caps, "cap triangle", "cap triangles"));
  add(removed_caps, "removed " + counted(removed_caps, "cap triangle", "cap triangles") + " on the boundary");
  std::string text = "repaired: ";
  for (std::size_t i = 0; i < parts.size(); ++i) text += (i > 0 ? ", " : "") + parts[i];
  if (snapped_coordinates + needle_triangles + flipped_caps + removed_caps > 0) {
    char bound[64];
    std::snprintf(bound, sizeof bound, " (no point moved by more than %.3g)", max_move);
    text += bound;
  }
  return text;
}

RepairReport repair_triangles(std::vector<Vec3>& points, std::vector<std::array<std::int32_t, 3>>& triangles,
                              const RepairOptions& options) {
  RepairReport report;
  const double extent = diagonal(points);
  report.max_move = options.max_move * extent;
  report.snapped_coordinates = snap_to_zero(points, zero_snap * extent);
  Soup soup;
  soup.points.reserve(points.size());
  for (const Vec3& p : points) soup.points.emplace_back(p.x, p.y, p.z);
  soup.polygons.reserve(triangles.size());
  for (const auto& t : triangles)
    soup.polygons.push_back(
        {static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]), static_cast<std::size_t>(t[2])});

  clean_soup(soup, report);
  resolve_back_to_back(soup, report);
  points.clear();
  triangles.clear();
  if (soup.polygons.empty()) return report;  // the caller says that nothing is left
  orient(soup, report);
  Mesh mesh = mesh_of(soup);
  if (const std::size_t created = PMP::duplicate_non_manifold_vertices(mesh); created > 0) {
    ++report.split_vertices;  // (orient_polygon_soup leaves none: counted roughly, never seen)
    report.vertex_copies += created + 1;
  }
  collapse_and_flip(mesh, report.max_move, options, report);

  // Back to the caller's form: the vertices the triangles use, in the mesh's order (the soup's).
  std::vector<std::int32_t> index(mesh.number_of_vertices() + mesh.number_of_removed_vertices(), -1);
  for (const Mesh::Face_index f : mesh.faces())
    for (const Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) index[v] = 0;
  for (const Mesh::Vertex_index v : mesh.vertices()) {
    if (index[v] < 0) continue;
    index[v] = static_cast<std::int32_t>(points.size());
    const Point& p = mesh.point(v);
    points.emplace_back(p.x(), p.y(), p.z());
  }
  for (const Mesh::Face_index f : mesh.faces()) {
    std::array<std::int32_t, 3> t{};
    int k = 0;
    for (const Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      if (k < 3) t[k++] = index[v];
    triangles.push_back(t);
  }
  return report;
}

SoupRepair soup_repair(const RepairOptions& options) {
  return [options](std::vector<Vec3>& points, std::vector<std::array<std::int32_t, 3>>& triangles,
                   std::vector<std::string>& notes) {
    notes.push_back(repair_triangles(points, triangles, options).note());
  };
}

SoupOptions soup_options(bool triangulate, bool repair) {
  SoupOptions options;
  options.triangulate = triangulate;
  if (repair) options.repair = soup_repair();
  return options;
}

PolygonSoup repaired_soup(const PolygonSoup& soup, bool triangulate, std::vector<std::string>& notes) {
  TriangleMeshData mesh;
  try {
    mesh = prepare_triangle_mesh(soup, soup_options(triangulate, true));
  } catch (const InputError& e) {
    notes.push_back(std::string("the faces were not repaired: ") + e.what());
    return soup;
  }
  notes.insert(notes.end(), mesh.notes.begin(), mesh.notes.end());
  PolygonSoup out;
  out.numbered_vertices = false;  // the repaired mesh's numbers are not the file's
  out.points = std::move(mesh.points);
  for (const auto& t : mesh.triangles) out.faces.push_back({t[0], t[1], t[2]});
  return out;
}

}  // namespace rgbmesh::repair
