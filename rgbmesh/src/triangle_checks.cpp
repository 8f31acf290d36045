// The checks shared by prepare_triangle_mesh and RgbMesh::from_triangles (see the header).

#include "triangle_checks.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numeric>
#include <system_error>
#include <utility>

namespace rgbmesh::detail {
namespace {

// Relative area threshold: a triangle is degenerate when area <= zero_area * longest_edge^2.
constexpr double zero_area = 1e-14;

// At most this many triangles are listed in one message.
constexpr std::size_t max_listed = 10;

template <class Real>
std::string number(Real x) {
  char buf[32];
  const auto result = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, result.ptr);
}

// What a repair does about each defect (MeshDefectError::hint).
constexpr const char* degenerate_hint = "collapses degenerate triangles";
constexpr const char* duplicate_hint = "removes duplicate triangles";
constexpr const char* edge_hint = "splits non-manifold edges";
constexpr const char* vertex_hint = "splits non-manifold vertices";
constexpr const char* orientation_hint = "cuts the surface open where it cannot be oriented";

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::int32_t find(std::int32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];  // path halving keeps the trees flat
      x = parent_[x];
    }
    return x;
  }
  void unite(std::int32_t a, std::int32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::int32_t> parent_;
};

void check_degenerate(const std::vector<Vec3>& points, const std::vector<Triangle>& triangles,
                      const TriangleNames& name, AreaCheck area_check) {
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    // Named variables, not a structured binding: lambdas may capture bindings only from C++20
    // on (GCC accepts it in C++17, clang 14 does not).
    const std::int32_t a = triangles[t][0], b = triangles[t][1], c = triangles[t][2];
    const auto fail = [&](const std::string& why) {
      throw MeshDefectError("triangle " + name.one(static_cast<std::int32_t>(t)) + " is degenerate: " + why,
                            degenerate_hint);
    };
    const auto vertices = [&] {
      if (name.by_position()) return name.position(a) + ", " + name.position(b) + ", " + name.position(c);
      return std::to_string(a) + ", " + std::to_string(b) + ", " + std::to_string(c);
    };
    const auto all_at = [&] {
      if (name.by_position()) return "its corners are all at " + name.position(a);
      return "its vertices " + vertices() + " are all at " + point_text(points[a]);
    };
    if (a == b || a == c || b == c) {
      const std::int32_t repeated = a == b || a == c ? a : b;
      if (name.by_position()) fail("it repeats " + name.vertex(repeated));
      fail("it repeats vertex " + std::to_string(repeated) + " (" + vertices() + ")");
    }
    if (area_check == AreaCheck::skip) continue;

    double largest = 0;
    for (const std::int32_t v : {a, b, c})
      largest = std::max({largest, std::abs(points[v].x), std::abs(points[v].y), std::abs(points[v].z)});
    if (largest == 0) fail(all_at());
    // Scaling by a power of two is exact and brings the coordinates into [-2, 2], so that the
    // squared lengths below can neither overflow nor vanish for tiny meshes.
    const int exponent = std::ilogb(largest);
    const auto scaled = [exponent](const Vec3& q) {
      return Vec3(std::scalbn(q.x, -exponent), std::scalbn(q.y, -exponent), std::scalbn(q.z, -exponent));
    };
    const std::array<Vec3, 3> p = {scaled(points[a]), scaled(points[b]), scaled(points[c])};
    // Edge i is opposite corner i. The area is taken at the corner opposite the longest edge:
    // its two edges are the shortest ones, which keeps the cross product accurate.
    const std::array<Vec3, 3> edge = {p[2] - p[1], p[0] - p[2], p[1] - p[0]};
    const std::array<double, 3> squared = {dot(edge[0], edge[0]), dot(edge[1], edge[1]),
                                           dot(edge[2], edge[2])};
    const int longest = static_cast<int>(std::max_element(squared.begin(), squared.end()) - squared.begin());
    if (squared[longest] == 0) fail(all_at());
    const double area = 0.5 * norm(cross(edge[(longest + 1) % 3], edge[(longest + 2) % 3]));
    if (area <= zero_area * squared[longest])
      fail(name.by_position() ? "it has zero area (its corners " + vertices() + " are collinear)"
                              : "it has zero area (vertices " + vertices() + " are collinear)");
  }
}

// The half-edges in (lo, hi, triangle) order, so that the sides of one edge are adjacent. A
// counting sort on lo (O(n), the bulk of the work for a million triangles) followed by a sort
// of each vertex's few half-edges; within a bucket they arrive in triangle order already.
std::vector<HalfEdge> sorted_half_edges(std::size_t n_points, const std::vector<Triangle>& triangles) {
  std::vector<std::size_t> start(n_points + 1, 0);
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) ++start[static_cast<std::size_t>(std::min(t[k], t[(k + 1) % 3])) + 1];
  for (std::size_t v = 0; v < n_points; ++v) start[v + 1] += start[v];
  std::vector<HalfEdge> half_edges(3 * triangles.size());
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::int8_t k = 0; k < 3; ++k) {
      const std::int32_t from = triangles[t][k], to = triangles[t][(k + 1) % 3];
      const std::int32_t lo = std::min(from, to);
      half_edges[next[static_cast<std::size_t>(lo)]++] = {lo, std::max(from, to),
                                                          static_cast<std::int32_t>(t), k, from < to};
    }
  }
  for (std::size_t v = 0; v < n_points; ++v) {
    if (start[v + 1] - start[v] > 1)
      std::sort(half_edges.begin() + static_cast<std::ptrdiff_t>(start[v]),
                half_edges.begin() + static_cast<std::ptrdiff_t>(start[v + 1]));
  }
  return half_edges;
}

// Two triangles with the same vertex set share all three edges, with the same third vertex
// across each: duplicates are found among the triangles of each edge. Of all duplicate pairs,
// the one whose later triangle comes first is reported (with the earliest partner: for three
// copies, the first two).
void check_duplicates(const std::vector<HalfEdge>& half_edges, const std::vector<Triangle>& triangles,
                      const TriangleNames& name) {
  const auto third = [&](const HalfEdge& h) { return triangles[h.triangle][(h.k + 2) % 3]; };
  std::int32_t first = -1, second = -1;
  const auto consider = [&](std::int32_t a, std::int32_t b) {  // a < b
    if (second < 0 || b < second || (b == second && a < first)) {
      first = a;
      second = b;
    }
  };
  std::vector<std::pair<std::int32_t, std::int32_t>> thirds;  // (third vertex, triangle)
  for (std::size_t begin = 0, end; begin < half_edges.size(); begin = end) {
    for (end = begin + 1; end < half_edges.size() && half_edges[end].same_edge(half_edges[begin]);) ++end;
    if (end - begin == 2) {
      if (third(half_edges[begin]) == third(half_edges[begin + 1]))
        consider(half_edges[begin].triangle, half_edges[begin + 1].triangle);
    } else if (end - begin > 2) {
      // A non-manifold edge (reported later unless a duplicate is found): group its triangles
      // by third vertex; within a group they stay in triangle order.
      thirds.clear();
      for (std::size_t i = begin; i < end; ++i)
        thirds.emplace_back(third(half_edges[i]), half_edges[i].triangle);
      std::sort(thirds.begin(), thirds.end());
      for (std::size_t i = 0; i + 1 < thirds.size(); ++i) {
        if (thirds[i].first == thirds[i + 1].first) consider(thirds[i].second, thirds[i + 1].second);
      }
    }
  }
  if (second < 0) return;
  Triangle key = triangles[first];
  std::string corners;
  if (name.by_position()) {
    corners =
        "corners " + name.position(key[0]) + ", " + name.position(key[1]) + ", " + name.position(key[2]);
  } else {
    std::sort(key.begin(), key.end());
    corners =
        "vertices " + std::to_string(key[0]) + ", " + std::to_string(key[1]) + ", " + std::to_string(key[2]);
  }
  throw MeshDefectError(
      "triangles " + name.one(first) + " and " + name.one(second) + " are duplicates (" + corners + ")",
      duplicate_hint);
}

// Throws on edges with more than two triangles (naming the edge whose third triangle comes
// first).
void check_edges_manifold(const std::vector<HalfEdge>& half_edges, const TriangleNames& name) {
  std::size_t worst_begin = 0, worst_end = 0;
  for (std::size_t begin = 0, end; begin < half_edges.size(); begin = end) {
    for (end = begin + 1; end < half_edges.size() && half_edges[end].same_edge(half_edges[begin]);) ++end;
    if (end - begin > 2 &&
        (worst_end == 0 || half_edges[begin + 2].triangle < half_edges[worst_begin + 2].triangle)) {
      worst_begin = begin;
      worst_end = end;
    }
  }
  if (worst_end == 0) return;
  std::vector<std::int32_t> sharing;
  for (std::size_t i = worst_begin; i < worst_end; ++i) sharing.push_back(half_edges[i].triangle);
  throw MeshDefectError(name.edge(half_edges[worst_begin].lo, half_edges[worst_begin].hi) + " is shared by " +
                            std::to_string(sharing.size()) + " triangles: " + name.list(sharing),
                        edge_hint);
}

// A vertex is manifold when its triangles form one fan: the corners at the vertex, joined across
// the interior edges through it, must form a single group.
void check_vertex_fans(std::size_t n_points, const std::vector<Triangle>& triangles,
                       const std::vector<HalfEdge>& half_edges, const TriangleNames& name) {
  UnionFind corners(3 * triangles.size());
  const auto corner = [](std::int32_t t, int k) { return 3 * t + k; };
  for (std::size_t i = 0; i + 1 < half_edges.size(); ++i) {
    const HalfEdge &h1 = half_edges[i], &h2 = half_edges[i + 1];
    if (!h1.same_edge(h2)) continue;
    // h1 runs from its corner k to k+1; h2 visits the same two vertices, in the same or the
    // opposite order.
    const int h1_from = h1.k, h1_to = (h1.k + 1) % 3, h2_from = h2.k, h2_to = (h2.k + 1) % 3;
    const bool same = h1.forward == h2.forward;
    corners.unite(corner(h1.triangle, h1_from), corner(h2.triangle, same ? h2_from : h2_to));
    corners.unite(corner(h1.triangle, h1_to), corner(h2.triangle, same ? h2_to : h2_from));
  }
  std::vector<std::int32_t> fans(n_points, 0);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::int32_t c = corner(static_cast<std::int32_t>(t), k);
      if (corners.find(c) == c) ++fans[triangles[t][k]];
    }
  }
  for (std::size_t v = 0; v < n_points; ++v) {
    if (fans[v] > 1)
      throw MeshDefectError(name.vertex(static_cast<std::int32_t>(v)) +
                                " is non-manifold: its triangles form " + std::to_string(fans[v]) +
                                " separate fans",
                            vertex_hint);
  }
}

// Across each interior edge: the neighbouring triangle, and whether it runs the edge in the same
// direction (which means the two are oriented inconsistently). Indexed by corner 3t+k.
struct Adjacency {
  std::vector<std::int32_t> neighbour;
  std::vector<bool> same_direction;
};

Adjacency adjacency_of(std::size_t n_triangles, const std::vector<HalfEdge>& half_edges) {
  Adjacency adj{std::vector<std::int32_t>(3 * n_triangles, -1), std::vector<bool>(3 * n_triangles, false)};
  for (std::size_t i = 0; i + 1 < half_edges.size(); ++i) {
    const HalfEdge &h1 = half_edges[i], &h2 = half_edges[i + 1];
    if (!h1.same_edge(h2)) continue;
    const bool same = h1.forward == h2.forward;
    adj.neighbour[3 * h1.triangle + h1.k] = h2.triangle;
    adj.neighbour[3 * h2.triangle + h2.k] = h1.triangle;
    adj.same_direction[3 * h1.triangle + h1.k] = same;
    adj.same_direction[3 * h2.triangle + h2.k] = same;
  }
  return adj;
}

// Which triangles to flip so that neighbours run their shared edge in opposite directions; each
// edge-connected component keeps the orientation of its lowest-numbered triangle (the first
// seed of the breadth-first search). Throws when no choice works (non-orientable surface).
std::vector<bool> orientation_flips(const std::vector<Triangle>& triangles, const Adjacency& adj,
                                    const TriangleNames& name) {
  constexpr std::int8_t unvisited = -1;
  std::vector<std::int8_t> flip(triangles.size(), unvisited);
  std::vector<std::int32_t> queue;
  queue.reserve(triangles.size());
  for (std::size_t seed = 0; seed < triangles.size(); ++seed) {
    if (flip[seed] != unvisited) continue;
    flip[seed] = 0;
    queue.assign(1, static_cast<std::int32_t>(seed));
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::int32_t t = queue[head];
      for (int k = 0; k < 3; ++k) {
        const std::int32_t n = adj.neighbour[3 * t + k];
        if (n < 0) continue;
        const std::int8_t wanted =
            static_cast<std::int8_t>(flip[t] ^ (adj.same_direction[3 * t + k] ? 1 : 0));
        if (flip[n] == unvisited) {
          flip[n] = wanted;
          queue.push_back(n);
        } else if (flip[n] != wanted) {
          const std::int32_t a = triangles[t][k], b = triangles[t][(k + 1) % 3];
          throw MeshDefectError("the surface is not orientable (Möbius-like): triangle " + name.one(n) +
                                    " cannot be oriented consistently with triangle " + name.one(t) +
                                    " across " + name.edge(std::min(a, b), std::max(a, b)),
                                orientation_hint);
        }
      }
    }
  }
  return std::vector<bool>(flip.begin(), flip.end());
}

}  // namespace

std::string plural(std::size_t n, const char* singular, const char* plural_form) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural_form);
}

std::string point_text(const Vec3& p) {
  // A single-precision coordinate (STL stores nothing else) is written as the file has it,
  // 18.7325 rather than 18.732500076293945; any other as the shortest double.
  const auto coordinate = [](double x) {
    // (Converting a double beyond float's range is undefined: checked first.)
    if (std::isfinite(x) && std::abs(x) <= std::numeric_limits<float>::max() &&
        static_cast<double>(static_cast<float>(x)) == x)
      return number(static_cast<float>(x));
    return number(x);
  };
  return "(" + coordinate(p.x) + ", " + coordinate(p.y) + ", " + coordinate(p.z) + ")";
}

std::string TriangleNames::one(std::int32_t t) const { return list({t}); }

std::string TriangleNames::position(std::int32_t v) const { return point_text((*points_)[v]); }

std::string TriangleNames::vertex(std::int32_t v) const {
  if (by_position()) return "the vertex at " + position(v);
  return "vertex " + std::to_string(v);
}

std::string TriangleNames::edge(std::int32_t a, std::int32_t b) const {
  if (by_position()) return "the edge from " + position(a) + " to " + position(b);
  return "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

std::string TriangleNames::list(const std::vector<std::int32_t>& triangles) const {
  std::string text, faces;
  for (std::size_t i = 0; i < triangles.size() && i < max_listed; ++i) {
    const char* separator = i == 0 ? "" : ", ";
    text += separator + std::to_string(triangles[i]);
    if (!source_face_.empty()) faces += separator + std::to_string(source_face_[triangles[i]]);
  }
  if (triangles.size() > max_listed) {
    text += ", ...";
    faces += ", ...";
  }
  if (!source_face_.empty()) text += (triangles.size() == 1 ? " (from face " : " (from faces ") + faces + ")";
  return text;
}

void check_points(const std::vector<Vec3>& points, std::size_t n_faces, const Wording& wording) {
  if (points.empty() || n_faces == 0)
    throw InputError("the mesh is empty (" + plural(points.size(), "vertex", "vertices") + ", " +
                     plural(n_faces, wording.face, wording.faces) + ")");
  if (static_cast<std::uint64_t>(points.size()) > static_cast<std::uint64_t>(max_vertices))
    throw InputError("the mesh has " + std::to_string(points.size()) + " vertices; at most " +
                     std::to_string(max_vertices) + " are supported");
  for (std::size_t v = 0; v < points.size(); ++v) {
    if (!is_finite(points[v]))
      throw InputError("vertex " + std::to_string(v) + " has a non-finite coordinate " +
                       point_text(points[v]));
  }
}

void check_triangle_count(std::uint64_t n_triangles) {
  if (n_triangles > static_cast<std::uint64_t>(max_triangles))
    throw InputError("the mesh has " + std::to_string(n_triangles) + " triangles; at most " +
                     std::to_string(max_triangles) + " are supported");
}

SurfaceCheck check_surface(const std::vector<Vec3>& points, const std::vector<Triangle>& triangles,
                           const TriangleNames& name, AreaCheck area) {
  check_degenerate(points, triangles, name, area);
  SurfaceCheck out;
  out.half_edges = sorted_half_edges(points.size(), triangles);
  check_duplicates(out.half_edges, triangles, name);
  check_edges_manifold(out.half_edges, name);
  check_vertex_fans(points.size(), triangles, out.half_edges, name);
  out.flip = orientation_flips(triangles, adjacency_of(triangles.size(), out.half_edges), name);
  out.flips = static_cast<std::size_t>(std::count(out.flip.begin(), out.flip.end(), true));
  return out;
}

InconsistentPair first_inconsistent_pair(const std::vector<HalfEdge>& half_edges) {
  InconsistentPair best;
  for (std::size_t i = 0; i + 1 < half_edges.size(); ++i) {
    const HalfEdge &h1 = half_edges[i], &h2 = half_edges[i + 1];
    if (!h1.same_edge(h2) || h1.forward != h2.forward) continue;
    // Within an edge the half-edges are sorted by triangle: h1's comes first.
    if (!best.found || h2.triangle < best.second || (h2.triangle == best.second && h1.triangle < best.first))
      best = {true, h1.triangle, h2.triangle, h1.lo, h1.hi};
  }
  return best;
}

}  // namespace rgbmesh::detail
