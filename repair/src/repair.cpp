// Repairing triangle soups with CGAL's Polygon Mesh Processing (see repair.hpp). The first steps
// work on the soup, as the file has it; the geometric ones (collapses, flips) need a halfedge
// mesh, which only a manifold, consistently oriented surface can become: hence the order
//   soup: isolated points, duplicate positions, zero-area and duplicate triangles, back-to-back
//         pairs, orientation (splitting what is non-manifold, cutting what cannot be oriented)
//   mesh: remaining non-manifold vertices, degenerate triangles, needles, caps.
// Counts for the note come from CGAL's return values and its orientation visitor, or from
// comparing before and after where CGAL returns none.
//
// Most exports need little of this, so the costly steps run only where they have work: the soup's
// surface is checked in linear time (surface_defects), only the components that fail go through
// orient_polygon_soup, and the halfedge mesh is built only when some triangle is degenerate, a
// needle or a cap within the bounds (needs_geometric_repair). Triangles are fixed-size arrays,
// not vectors, so that a million of them cost no million allocations.

#include "rgbmesh/repair/repair.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>  // isolated and duplicate points
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "buckets.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/repair/orient_triangles.hpp"

namespace rgbmesh::repair {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Polygon = std::array<std::size_t, 3>;
using Mesh = CGAL::Surface_mesh<Point>;
using Edge = std::pair<std::size_t, std::size_t>;  // lower id first
using Key = std::array<std::size_t, 3>;            // a triangle's corners, sorted

// Coordinates closer to zero than this times the bounding-box diagonal are rounding noise.
constexpr double zero_snap = 1e-12;

struct Soup {
  std::vector<Point> points;
  std::vector<Polygon> polygons;  // triangles
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

// Points at equal positions merged into the first of them, the others' numbers following in
// order: what CGAL's merge_duplicate_points_in_polygon_soup gives, by a sort instead of a map
// (several times faster on a million points). Returns how many points went.
std::size_t merge_duplicate_points(Soup& soup) {
  const std::size_t n = soup.points.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto less = [&](std::size_t a, std::size_t b) {
    const Point &p = soup.points[a], &q = soup.points[b];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::size_t> first(n);  // the first point at each point's position
  for (std::size_t i = 0; i < n; ++i)
    first[order[i]] =
        i > 0 && soup.points[order[i]] == soup.points[order[i - 1]] ? first[order[i - 1]] : order[i];
  std::vector<std::size_t> number(n);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (first[i] == i) {
      soup.points[kept] = soup.points[i];
      number[i] = kept++;
    }
  if (kept == n) return 0;
  for (Polygon& t : soup.polygons)
    for (std::size_t& v : t) v = number[first[v]];
  soup.points.resize(kept);
  return n - kept;
}

// Isolated points, positions shared by several points, triangles that lost a corner to the merge
// (two corners at one position: zero area; removing one joins its neighbours directly, which is
// what collapsing it would do, so no hole opens) and exact repeats of a triangle (same corners in
// the same cyclic order: one copy kept, the first). (CGAL's repair_polygon_soup does the last two
// for polygons of any size, with a vector per polygon; for triangles a sort of fixed-size keys is
// several times faster.) Returns the opposite copies that are left (same corners, the other
// order; the lower triangle number first): the back-to-back pairs, decided next.
std::vector<std::array<std::size_t, 2>> clean_soup(Soup& soup, RepairReport& report) {
  report.isolated_vertices = PMP::remove_isolated_points_in_polygon_soup(soup.points, soup.polygons);
  report.merged_vertices = merge_duplicate_points(soup);
  const auto coincident = [](const Polygon& p) { return p[0] == p[1] || p[1] == p[2] || p[2] == p[0]; };
  // The corners sorted, then the cyclic rotation that starts at the smallest: copies are side by
  // side, repeats equal in both.
  struct Copy {
    Key corners;
    Polygon rotation;
    std::size_t triangle;
    bool operator<(const Copy& o) const {
      return std::tie(corners, rotation, triangle) < std::tie(o.corners, o.rotation, o.triangle);
    }
  };
  std::vector<Copy> copies;
  copies.reserve(soup.polygons.size());
  std::vector<char> remove(soup.polygons.size(), 0);
  for (std::size_t t = 0; t < soup.polygons.size(); ++t) {
    const Polygon& p = soup.polygons[t];
    if (coincident(p)) {
      remove[t] = 1;
      ++report.zero_area_triangles;
      continue;
    }
    const int first = p[0] < p[1] ? (p[0] < p[2] ? 0 : 2) : (p[1] < p[2] ? 1 : 2);
    copies.push_back({key_of(p), Polygon{p[first], p[(first + 1) % 3], p[(first + 2) % 3]}, t});
  }
  std::sort(copies.begin(), copies.end());
  std::vector<std::array<std::size_t, 2>> pairs;
  for (std::size_t i = 0, j; i < copies.size(); i = j) {
    // A triangle has two cyclic orders: the first copy of each stays.
    std::size_t kept[2] = {copies[i].triangle, 0}, orders = 1;
    for (j = i + 1; j < copies.size() && copies[j].corners == copies[i].corners; ++j) {
      if (copies[j].rotation == copies[j - 1].rotation) {
        remove[copies[j].triangle] = 1;
        ++report.repeated_triangles;
      } else {
        kept[orders++] = copies[j].triangle;
      }
    }
    if (orders == 2) pairs.push_back({std::min(kept[0], kept[1]), std::max(kept[0], kept[1])});
  }
  if (report.zero_area_triangles + report.repeated_triangles == 0) return pairs;
  std::vector<std::size_t> number(soup.polygons.size());
  std::size_t kept = 0;
  for (std::size_t t = 0; t < soup.polygons.size(); ++t)
    if (!remove[t]) {
      number[t] = kept;
      soup.polygons[kept++] = soup.polygons[t];
    }
  soup.polygons.resize(kept);
  for (auto& pair : pairs) pair = {number[pair[0]], number[pair[1]]};
  // Points only the removed triangles used (not counted: they were not isolated in the input).
  PMP::remove_isolated_points_in_polygon_soup(soup.points, soup.polygons);
  return pairs;
}

// Back-to-back pairs: two triangles with the same corners in opposite orders. Between two parts
// that touch (a CAD union, an OpenSCAD export) they are the wall where the parts meet: both go,
// and the parts become one surface. On a two-sided sheet (a plane exported for both sides) they
// are the sheet itself: one copy stays. Connected pairs form regions; a region is a wall when it
// has a rim and other triangles continue from every edge of it; a sheet's rim is free, and a
// closed two-sided surface has no rim. A pair of zero-area triangles always goes: it covers
// nothing from either side (OpenSCAD writes such pairs where a vertex lies on an edge).
void resolve_back_to_back(Soup& soup, const std::vector<std::array<std::size_t, 2>>& pairs,
                          RepairReport& report) {
  if (pairs.empty()) return;

  std::map<Edge, std::vector<std::size_t>> pairs_of_edge;  // the pairs along each of their edges
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const Polygon& t = soup.polygons[pairs[p][0]];
    for (int k = 0; k < 3; ++k) pairs_of_edge[edge_of(t[k], t[(k + 1) % 3])].push_back(p);
  }
  std::vector<char> on_pair(soup.points.size(), 0);  // (to look up only the sides that may count)
  for (const auto& [edge, along] : pairs_of_edge) on_pair[edge.first] = on_pair[edge.second] = 1;
  std::map<Edge, std::size_t> uses;  // triangles along those edges, the pairs' own included
  for (const Polygon& t : soup.polygons)
    for (int k = 0; k < 3; ++k) {
      if (!on_pair[t[k]] || !on_pair[t[(k + 1) % 3]]) continue;
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

// A triangle's corner at a vertex: the corners after and before it, and the triangle.
struct Corner {
  std::size_t next, previous, triangle;
};

// Whether the triangles around one vertex form a single fan, consistently oriented: each corner
// contributes the edge (next corner -> previous corner) of the vertex's link, and the link must be
// one path or one cycle. Linear for the small valences of real meshes, k log k for a huge one.
class FanCheck {
 public:
  bool one_fan(const Corner* link, std::size_t k) {
    if (k <= 1) return true;
    successor_.assign(k, kNone);
    in_degree_.assign(k, 0);
    const auto link_to = [&](std::size_t i, std::size_t j) {
      successor_[i] = j;
      return ++in_degree_[j] == 1;
    };
    if (k <= 16) {
      for (std::size_t i = 0; i < k; ++i)
        for (std::size_t j = 0; j < k; ++j) {
          if (i != j && link[i].next == link[j].next) return false;  // an edge twice, one way
          if (link[i].previous == link[j].next && successor_[i] == kNone && !link_to(i, j)) return false;
        }
    } else {
      sorted_.clear();
      for (std::size_t i = 0; i < k; ++i) sorted_.emplace_back(link[i].next, i);
      std::sort(sorted_.begin(), sorted_.end());
      for (std::size_t i = 1; i < k; ++i)
        if (sorted_[i].first == sorted_[i - 1].first) return false;
      for (std::size_t i = 0; i < k; ++i) {
        const auto it = std::lower_bound(sorted_.begin(), sorted_.end(),
                                         std::make_pair(link[i].previous, std::size_t{0}));
        if (it != sorted_.end() && it->first == link[i].previous && !link_to(i, it->second)) return false;
      }
    }
    std::size_t start = 0, starts = 0;
    for (std::size_t i = 0; i < k; ++i)
      if (in_degree_[i] == 0) start = i, ++starts;
    if (starts > 1) return false;
    std::size_t visited = 1;
    for (std::size_t i = successor_[start]; i != kNone && i != start && visited <= k; i = successor_[i])
      ++visited;
    return visited == k;
  }

 private:
  static constexpr std::size_t kNone = ~std::size_t{0};
  std::vector<std::size_t> successor_, in_degree_;
  std::vector<std::pair<std::size_t, std::size_t>> sorted_;
};

// What keeps a soup from being an oriented surface, in linear time (what CGAL's
// is_polygon_soup_a_polygon_mesh decides, which is several times slower): the triangles along an
// edge of more than two triangles or of two that run it the same way, and those around a vertex
// whose triangles are not one fan. `component` labels the pieces joined across edges of two
// triangles: what orient_polygon_soup would look at together.
struct SurfaceDefects {
  std::vector<char> off;
  std::size_t count = 0;
  std::vector<std::size_t> component;
};

SurfaceDefects surface_defects(const std::vector<Polygon>& polygons, std::size_t point_count) {
  SurfaceDefects out;
  out.off.assign(polygons.size(), 0);
  // The corners by vertex: each gives the vertex's link an edge (next corner -> previous corner)
  // and its triangle the sides (vertex -> next) and (previous -> vertex).
  const auto corners = buckets<Corner>(point_count, 3 * polygons.size(), [&](auto&& add) {
    for (std::size_t t = 0; t < polygons.size(); ++t)
      for (std::size_t k = 0; k < 3; ++k)
        add(polygons[t][k], Corner{polygons[t][(k + 1) % 3], polygons[t][(k + 2) % 3], t});
  });
  UnionFind pieces(polygons.size());
  FanCheck fans;
  struct Side {
    std::size_t other, triangle;
    bool outgoing;
  };
  std::vector<Side> sides;  // the sides from v to higher-numbered vertices, each edge seen once
  for (std::size_t v = 0; v < point_count; ++v) {
    const Corner* begin = corners.items.data() + corners.start[v];
    const std::size_t k = corners.start[v + 1] - corners.start[v];
    sides.clear();
    for (const Corner* c = begin; c != begin + k; ++c) {
      if (c->next > v) sides.push_back({c->next, c->triangle, true});
      if (c->previous > v) sides.push_back({c->previous, c->triangle, false});
    }
    std::sort(sides.begin(), sides.end(), [](const Side& a, const Side& b) { return a.other < b.other; });
    for (std::size_t i = 0, j; i < sides.size(); i = j) {
      for (j = i + 1; j < sides.size() && sides[j].other == sides[i].other;) ++j;
      const bool manifold = j - i == 1 || (j - i == 2 && sides[i].outgoing != sides[i + 1].outgoing);
      if (j - i == 2) pieces.unite(sides[i].triangle, sides[i + 1].triangle);
      if (!manifold)
        for (std::size_t e = i; e < j; ++e) out.off[sides[e].triangle] = 1;
    }
    if (!fans.one_fan(begin, k))
      for (const Corner* c = begin; c != begin + k; ++c) out.off[c->triangle] = 1;
  }
  out.component.resize(polygons.size());
  for (std::size_t t = 0; t < polygons.size(); ++t) {
    out.component[t] = pieces.find(t);
    out.count += out.off[t];
  }
  return out;
}

// Consistent orientation by orient_triangles (CGAL's orient_polygon_soup's rule), which splits
// non-manifold edges and vertices (each fan gets its own copy of the vertex) and cuts a surface
// that cannot be oriented open along the edges where the orientation would flip. Only the pieces
// with a defect are walked: the others are oriented surfaces already, which the walk would leave
// as they are, and they share no vertex with those walked (a shared vertex is not one fan).
void orient(Soup& soup, RepairReport& report) {
  const SurfaceDefects defects = surface_defects(soup.polygons, soup.points.size());
  if (defects.count == 0) return;
  std::vector<char> piece_off(soup.polygons.size(), 0);
  for (std::size_t t = 0; t < soup.polygons.size(); ++t)
    if (defects.off[t]) piece_off[defects.component[t]] = 1;
  std::vector<std::size_t> chosen;  // the triangles of the pieces with a defect, in order
  for (std::size_t t = 0; t < soup.polygons.size(); ++t)
    if (piece_off[defects.component[t]]) chosen.push_back(t);
  std::vector<Polygon> part;
  part.reserve(chosen.size());
  for (const std::size_t t : chosen) part.push_back(soup.polygons[t]);

  const SoupOrientation orientation = orient_triangles(part, soup.points.size());
  for (std::size_t i = 0; i < chosen.size(); ++i) soup.polygons[chosen[i]] = part[i];
  for (const std::size_t from : orientation.copied_from) soup.points.push_back(soup.points[from]);
  report.non_manifold_edges = orientation.non_manifold_edges;
  report.cut_edges = orientation.cut_edges;
  report.split_vertices = orientation.split_vertices;
  report.vertex_copies = orientation.vertex_copies;
  report.reoriented_triangles = orientation.reversed_triangles;
}

void require_surface(const Soup& soup) {
  if (surface_defects(soup.polygons, soup.points.size()).count > 0)
    throw InputError(
        "could not be repaired: the triangles make no surface even with their non-manifold edges "
        "and vertices split");
}

Mesh mesh_of(const Soup& soup) {
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
    Polygon corners{};
    int k = 0;
    for (const Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      if (k < 3) corners[k++] = v;
    keys.insert(key_of(corners));
  }
  return keys;
}

// Whether collapse_and_flip could change anything: some triangle is degenerate (collinear
// corners, CGAL's exact predicate), or a needle whose shortest edge is within the bound, or a cap
// whose apex is within the bound of its longest edge (the tests of CGAL's
// remove_almost_degenerate_faces, here with margins so that no triangle it would take is missed).
// Most exports have none, and then the halfedge mesh is not needed at all.
bool needs_geometric_repair(const Soup& soup, double max_move, const RepairOptions& options) {
  const double pi = std::acos(-1.0);
  const double cap_cosine = std::cos(options.cap_angle_degrees * pi / 180) + 1e-6;
  const double ratio_squared = 0.99 * options.needle_ratio * options.needle_ratio;
  const double reach = 1.01 * max_move, reach_squared = reach * reach;
  for (const Polygon& t : soup.polygons) {
    const Point &a = soup.points[t[0]], &b = soup.points[t[1]], &c = soup.points[t[2]];
    if (CGAL::collinear(a, b, c)) return true;
    if (!(max_move > 0)) continue;
    const std::array<Point, 3> corner = {a, b, c};
    std::array<double, 3> length_squared{};  // of the side opposite each corner
    for (int k = 0; k < 3; ++k)
      length_squared[k] = CGAL::to_double(CGAL::squared_distance(corner[(k + 1) % 3], corner[(k + 2) % 3]));
    const auto [shortest, longest] = std::minmax_element(length_squared.begin(), length_squared.end());
    if (*longest >= ratio_squared * *shortest && *shortest <= reach_squared) return true;
    // The largest angle is opposite the longest side; the apex's height over that side is
    // twice the area over the side's length.
    const int apex = static_cast<int>(longest - length_squared.begin());
    const auto u = corner[(apex + 1) % 3] - corner[apex], v = corner[(apex + 2) % 3] - corner[apex];
    const double uu = u.squared_length(), vv = v.squared_length();
    if (!(uu > 0 && vv > 0)) return true;
    const double cosine = (u * v) / std::sqrt(uu * vv);
    const double height_squared = CGAL::cross_product(u, v).squared_length() / *longest;
    if (cosine <= cap_cosine && height_squared <= reach_squared) return true;
  }
  return false;
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
    soup.polygons.push_back(Polygon{static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                                    static_cast<std::size_t>(t[2])});

  resolve_back_to_back(soup, clean_soup(soup, report), report);
  points.clear();
  triangles.clear();
  if (soup.polygons.empty()) return report;  // the caller says that nothing is left
  orient(soup, report);
  // Whether the result is a surface is checked after the repair with every input's checks
  // (prepare_triangle_mesh), which name what is wrong; the halfedge mesh needs it before.
  if (!needs_geometric_repair(soup, report.max_move, options)) {
    // Back to the caller's form directly: the soup's points are all used (isolated ones went).
    for (const Point& p : soup.points) points.emplace_back(p.x(), p.y(), p.z());
    triangles.reserve(soup.polygons.size());
    for (const Polygon& t : soup.polygons)
      triangles.push_back({static_cast<std::int32_t>(t[0]), static_cast<std::int32_t>(t[1]),
                           static_cast<std::int32_t>(t[2])});
    return report;
  }
  require_surface(soup);
  Mesh mesh = mesh_of(soup);
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
