// Turning a polygon soup into a clean, consistently oriented, manifold triangle mesh.
//
// Everything is O(n log n): the combinatorial checks sort half-edges and triangle keys instead of
// building per-vertex adjacency lists, and vertex-manifoldness is a union-find over corners.

#include "rgbmesh/soup.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace rgbmesh {
namespace {

using Triangle = std::array<std::int32_t, 3>;

// The RGB mesh numbers vertices and triangles with int32, and corners (3 per triangle) index the
// union-find below, so the triangle count is bounded by a third of the int32 range.
constexpr std::int64_t max_vertices = std::numeric_limits<std::int32_t>::max();
constexpr std::int64_t max_triangles = std::numeric_limits<std::int32_t>::max() / 3;

// Relative area threshold: a triangle is degenerate when area <= zero_area * longest_edge^2.
constexpr double zero_area = 1e-14;

// At most this many triangles are listed in one message.
constexpr std::size_t max_listed = 10;

std::string number(double x) {
  char buf[32];
  const auto result = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, result.ptr);
}

std::string point_text(const Vec3& p) {
  return "(" + number(p.x) + ", " + number(p.y) + ", " + number(p.z) + ")";
}

std::string plural(std::size_t n, const char* singular, const char* plural_form) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural_form);
}

// Names triangles in messages. Without triangulation triangle i is face i of the soup; after
// fan-splitting, the source face is given too so that the user can find it in the file.
class TriangleNames {
 public:
  explicit TriangleNames(const std::vector<std::int64_t>& source_face) : source_face_(source_face) {}

  // "4" or "4 (from face 2)".
  std::string one(std::int32_t t) const { return list({t}); }

  // "2, 5, 8" or "2, 5, 8 (from faces 1, 4, 6)", shortened after max_listed entries.
  std::string list(const std::vector<std::int32_t>& triangles) const {
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
    if (!source_face_.empty())
      text += (triangles.size() == 1 ? " (from face " : " (from faces ") + faces + ")";
    return text;
  }

 private:
  const std::vector<std::int64_t>& source_face_;
};

// One side of a triangle: half-edge k of triangle t runs from corner k to corner k+1.
struct HalfEdge {
  std::int32_t lo, hi;  // endpoints, lo < hi
  std::int32_t triangle;
  std::int8_t k;
  bool forward;  // runs lo -> hi

  friend bool operator<(const HalfEdge& a, const HalfEdge& b) {
    if (a.lo != b.lo) return a.lo < b.lo;
    if (a.hi != b.hi) return a.hi < b.hi;
    return a.triangle < b.triangle;
  }
  bool same_edge(const HalfEdge& o) const { return lo == o.lo && hi == o.hi; }
};

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

void check_vertices(const PolygonSoup& soup) {
  if (soup.points.empty() || soup.faces.empty())
    throw InputError("the mesh is empty (" + plural(soup.points.size(), "vertex", "vertices") + ", " +
                     plural(soup.faces.size(), "face", "faces") + ")");
  if (static_cast<std::uint64_t>(soup.points.size()) > static_cast<std::uint64_t>(max_vertices))
    throw InputError("the mesh has " + std::to_string(soup.points.size()) + " vertices; at most " +
                     std::to_string(max_vertices) + " are supported");
  for (std::size_t v = 0; v < soup.points.size(); ++v) {
    if (!is_finite(soup.points[v]))
      throw InputError("vertex " + std::to_string(v) + " has a non-finite coordinate " +
                       point_text(soup.points[v]));
  }
}

void check_faces(const PolygonSoup& soup) {
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    if (soup.faces[f].size() < 3)
      throw InputError("face " + std::to_string(f) + " has " +
                       plural(soup.faces[f].size(), "vertex", "vertices") + "; a face needs at least 3");
  }
  const auto n = static_cast<std::int64_t>(soup.points.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    for (const std::int64_t v : soup.faces[f]) {
      if (v < 0 || v >= n)
        throw InputError("face " + std::to_string(f) + " references vertex " + std::to_string(v) +
                         " but the file has " + plural(soup.points.size(), "vertex", "vertices"));
    }
  }
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
  if (total > static_cast<std::uint64_t>(max_triangles))
    throw InputError("the mesh has " + std::to_string(total) + " triangles; at most " +
                     std::to_string(max_triangles) + " are supported");

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

void check_degenerate(const std::vector<Vec3>& points, const std::vector<Triangle>& triangles,
                      const TriangleNames& name) {
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto [a, b, c] = triangles[t];
    const auto fail = [&](const std::string& why) {
      throw InputError("triangle " + name.one(static_cast<std::int32_t>(t)) + " is degenerate: " + why);
    };
    const auto vertices = [&] {
      return std::to_string(a) + ", " + std::to_string(b) + ", " + std::to_string(c);
    };
    if (a == b || a == c || b == c)
      fail("it repeats vertex " + std::to_string(a == b || a == c ? a : b) + " (" + vertices() + ")");

    double largest = 0;
    for (const std::int32_t v : {a, b, c})
      largest = std::max({largest, std::abs(points[v].x), std::abs(points[v].y), std::abs(points[v].z)});
    if (largest == 0) fail("its vertices " + vertices() + " are all at " + point_text(points[a]));
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
    if (squared[longest] == 0) fail("its vertices " + vertices() + " are all at " + point_text(points[a]));
    const double area = 0.5 * norm(cross(edge[(longest + 1) % 3], edge[(longest + 2) % 3]));
    if (area <= zero_area * squared[longest])
      fail("it has zero area (vertices " + vertices() + " are collinear)");
  }
}

void check_duplicates(const std::vector<Triangle>& triangles, const TriangleNames& name) {
  std::vector<std::pair<Triangle, std::int32_t>> keyed(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    Triangle key = triangles[t];
    std::sort(key.begin(), key.end());
    keyed[t] = {key, static_cast<std::int32_t>(t)};
  }
  std::sort(keyed.begin(), keyed.end());
  // Within a run of equal keys the triangles are in file order; report the run whose second
  // triangle comes first in the file.
  std::size_t worst = 0;  // index of the first entry of the reported run; 0 with none found
  bool found = false;
  for (std::size_t begin = 0, end; begin < keyed.size(); begin = end) {
    for (end = begin + 1; end < keyed.size() && keyed[end].first == keyed[begin].first;) ++end;
    if (end - begin > 1 && (!found || keyed[begin + 1].second < keyed[worst + 1].second)) {
      worst = begin;
      found = true;
    }
  }
  if (!found) return;
  const Triangle& key = keyed[worst].first;
  throw InputError("triangles " + name.one(keyed[worst].second) + " and " +
                   name.one(keyed[worst + 1].second) + " are duplicates (vertices " + std::to_string(key[0]) +
                   ", " + std::to_string(key[1]) + ", " + std::to_string(key[2]) + ")");
}

// Half-edges sorted so that the sides of one edge are adjacent; throws on edges with more than two
// triangles (naming the edge whose third triangle comes first in the file).
std::vector<HalfEdge> sorted_half_edges(const std::vector<Triangle>& triangles, const TriangleNames& name) {
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(3 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::int8_t k = 0; k < 3; ++k) {
      const std::int32_t from = triangles[t][k], to = triangles[t][(k + 1) % 3];
      half_edges.push_back(
          {std::min(from, to), std::max(from, to), static_cast<std::int32_t>(t), k, from < to});
    }
  }
  std::sort(half_edges.begin(), half_edges.end());

  std::size_t worst_begin = 0, worst_end = 0;
  for (std::size_t begin = 0, end; begin < half_edges.size(); begin = end) {
    for (end = begin + 1; end < half_edges.size() && half_edges[end].same_edge(half_edges[begin]);) ++end;
    if (end - begin > 2 &&
        (worst_end == 0 || half_edges[begin + 2].triangle < half_edges[worst_begin + 2].triangle)) {
      worst_begin = begin;
      worst_end = end;
    }
  }
  if (worst_end != 0) {
    std::vector<std::int32_t> sharing;
    for (std::size_t i = worst_begin; i < worst_end; ++i) sharing.push_back(half_edges[i].triangle);
    throw InputError("edge (" + std::to_string(half_edges[worst_begin].lo) + ", " +
                     std::to_string(half_edges[worst_begin].hi) + ") is shared by " +
                     std::to_string(sharing.size()) + " triangles: " + name.list(sharing));
  }
  return half_edges;
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

// A vertex is manifold when its triangles form one fan: the corners at the vertex, joined across
// the interior edges through it, must form a single group.
void check_vertex_fans(std::size_t n_points, const std::vector<Triangle>& triangles,
                       const std::vector<HalfEdge>& half_edges) {
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
      throw InputError("vertex " + std::to_string(v) + " is non-manifold: its triangles form " +
                       std::to_string(fans[v]) + " separate fans");
  }
}

// Flips triangles so that neighbours run their shared edge in opposite directions; each
// edge-connected component keeps the orientation of its lowest-numbered triangle (the first
// seed of the breadth-first search). Returns the number of flipped triangles.
std::size_t orient(std::vector<Triangle>& triangles, const Adjacency& adj, const TriangleNames& name) {
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
          throw InputError("the surface is not orientable (Möbius-like): triangle " + name.one(n) +
                           " cannot be oriented consistently with triangle " + name.one(t) +
                           " across edge (" + std::to_string(std::min(a, b)) + ", " +
                           std::to_string(std::max(a, b)) + ")");
        }
      }
    }
  }
  std::size_t flipped = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (flip[t] == 1) {
      std::swap(triangles[t][1], triangles[t][2]);
      ++flipped;
    }
  }
  return flipped;
}

}  // namespace

TriangleMeshData prepare_triangle_mesh(const PolygonSoup& soup, const SoupOptions& options) {
  check_vertices(soup);
  check_faces(soup);

  TriangleMeshData out;
  std::vector<std::int64_t> source_face;
  std::vector<Triangle> triangles = triangles_of(soup, options, source_face, out.notes);
  const TriangleNames name(source_face);

  check_degenerate(soup.points, triangles, name);
  check_duplicates(triangles, name);
  const std::vector<HalfEdge> half_edges = sorted_half_edges(triangles, name);
  check_vertex_fans(soup.points.size(), triangles, half_edges);

  const std::size_t flipped = orient(triangles, adjacency_of(triangles.size(), half_edges), name);
  if (flipped > 0)
    out.notes.push_back("re-oriented " + plural(flipped, "triangle", "triangles") +
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
