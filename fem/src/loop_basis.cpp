// Loop's limit functions on a triangle's patch, by local subdivision (see loop_basis.hpp).
//
// A patch is a small mesh: the triangles touching the three corners of its central triangle.
// One Loop step of it yields correct control values at the corners (their one-rings are in
// the patch) and at the midpoints of the edges at the corners (both triangles of such an edge
// are in the patch), which are exactly the vertices of the four children's patches. So a
// child's patch values are a fixed matrix times its parent's, and a point is evaluated by
// descending until its sub-triangle has regular corners, where the limit is the quartic box
// spline. That polynomial is not typed in: it is found once, by subdividing the regular patch
// twice and interpolating the exact limit values (limit masks) at the 15 points of the
// degree-4 grid of the triangle, which determine a quartic.
//
// Sharp features (walls that cut fans into sectors, the crease rules of a step, darts' limits)
// are in loop_creases.cpp, reached through loop_patch.hpp where a patch has them: this file
// keeps the plain and boundary rules, which most patches need alone.

#include "rgbmesh/fem/loop_basis.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>

#include "loop_patch.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/loop_rules.hpp"

namespace rgbmesh::fem {

namespace {

using detail::Child;
using detail::gather_patch;
using detail::subdivide;
using detail::Triangles;

// ---------------------------------------------------------------------------------------------
// Gathering a patch in canonical order.

[[noreturn]] void patch_error(const std::array<std::int32_t, 3>& c, const std::string& why) {
  throw InputError("Loop elements: the patch of the triangle of vertices " + std::to_string(c[0]) + ", " +
                   std::to_string(c[1]) + ", " + std::to_string(c[2]) + " " + why);
}

// The ring of every vertex of a small mesh, from its triangles (counter-clockwise).
class NetRings {
 public:
  NetRings(int n, const Triangles& triangles) : next_(static_cast<std::size_t>(n)) {
    for (const auto& t : triangles) {
      for (int k = 0; k < 3; ++k)
        next_[static_cast<std::size_t>(t[k])].push_back({t[(k + 1) % 3], t[(k + 2) % 3]});
    }
  }
  // True for a closed fan. False for a vertex on the boundary, with the path of its
  // neighbours counter-clockwise from one boundary neighbour to the other (empty, or not a
  // path of all its triangles, where the vertex is no fan: gather_loop_patch refuses it).
  bool ring(std::int32_t v, std::vector<std::int32_t>& out) const {
    out.clear();
    const auto& next = next_[static_cast<std::size_t>(v)];
    if (next.empty()) return false;
    // A fan is open where some triangle's first neighbour follows no triangle's second.
    for (const auto& p : next) {
      if (std::any_of(next.begin(), next.end(), [&p](const std::array<int, 2>& q) { return q[1] == p[0]; }))
        continue;
      std::int32_t x = p[0];
      out.push_back(x);
      for (std::size_t step = 0; step < next.size(); ++step) {
        const auto it =
            std::find_if(next.begin(), next.end(), [x](const std::array<int, 2>& q) { return q[0] == x; });
        if (it == next.end()) break;
        x = (*it)[1];
        out.push_back(x);
      }
      return false;
    }
    std::int32_t x = next.front()[0];
    for (std::size_t step = 0; step <= next.size(); ++step) {
      out.push_back(x);
      const auto it =
          std::find_if(next.begin(), next.end(), [x](const std::array<int, 2>& p) { return p[0] == x; });
      if (it == next.end()) return false;
      x = (*it)[1];
      if (x == out.front()) return out.size() == next.size();
    }
    return false;
  }

 private:
  std::vector<std::vector<std::array<int, 2>>> next_;
};

}  // namespace

LoopPatch detail::gather_patch(const std::array<std::int32_t, 3>& corners, const RingOracle& ring_of,
                               const WallOracle* walls_of, std::array<Fan, 3>* fans_out) {
  // The patch is built from the corners' fans glued where they share triangles, not by vertex
  // ids: its places (slots) are those of the patch as a disc, and two slots may hold the same
  // vertex where the mesh is small around the triangle (a neighbour of valence 3 next to two
  // corners, a ring wrapping round a thin torus). Loop's rules act on the disc, so the limit
  // on the triangle is the disc's, with each slot holding its vertex's value.
  //
  // A corner on the boundary has an open fan, and so has a corner whose fan two or more walls
  // cut: its ring is kept cyclic, with a gap after entry gap[k] (no triangle between that entry
  // and the next), and the boundary rules apply to it (the crease rules, on a sector).
  LoopPatch patch;
  std::array<Fan, 3> fans;
  std::array<std::vector<std::int32_t>, 3> rings;  // the sectors
  std::array<std::vector<char>, 3> walls;          // per entry of each whole fan
  std::array<int, 3> gap = {-1, -1, -1};
  std::vector<std::int32_t> raw;
  std::vector<char> raw_wall;
  for (int k = 0; k < 3; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    const std::int32_t next = corners[static_cast<std::size_t>((k + 1) % 3)],
                       prev = corners[static_cast<std::size_t>((k + 2) % 3)];
    Fan& fan = fans[ku];
    const bool closed = ring_of(corners[ku], raw);
    const std::size_t m = raw.size();
    if (walls_of != nullptr) {
      raw_wall.assign(m, 0);
      (*walls_of)(k, corners[ku], raw, raw_wall);
    }
    // The fan's entries from `next` on, counter-clockwise (the central triangle is (c, next,
    // prev)): entry i is the oracle's entry (start ± i) mod m.
    std::size_t start = m;
    bool forward = true;
    if (closed) {
      const auto it = std::find(raw.begin(), raw.end(), next);
      if (m < 3 || it == raw.end()) patch_error(corners, "is not a triangle fan");
      start = static_cast<std::size_t>(it - raw.begin());
      forward = raw[(start + 1) % m] == prev;
      if (!forward && raw[(start + m - 1) % m] != prev) patch_error(corners, "is not a triangle fan");
    } else {
      // The path's ends are the boundary neighbours; the central triangle is one of its steps.
      for (std::size_t j = 0; j < m && start == m; ++j) {
        if (raw[j] != next) continue;
        if (j + 1 < m && raw[j + 1] == prev)
          start = j, forward = true;
        else if (j > 0 && raw[j - 1] == prev)
          start = j, forward = false;
      }
      if (m < 2 || start == m) patch_error(corners, "is not a triangle fan");
      // The gap follows the path's last entry going forward, its first going backward.
      fan.boundary_gap = static_cast<int>(forward ? m - 1 - start : start);
    }
    const auto entry = [&](std::size_t i) { return forward ? (start + i) % m : (start + m - i) % m; };
    if (walls_of == nullptr && fans_out == nullptr) {  // no sectors: the whole fan, as it comes
      auto& r = rings[ku];
      r.resize(m);
      for (std::size_t i = 0; i < m; ++i) r[i] = raw[entry(i)];
      if (!closed) gap[ku] = fan.boundary_gap, patch.open[ku] = true;
      patch.valence[ku] = static_cast<int>(m);
      continue;
    }
    gap[ku] = cut_fan(raw, walls_of != nullptr ? &raw_wall : nullptr, closed, start, forward, fan, walls[ku],
                      rings[ku]);
    if (gap[ku] >= 0) patch.open[ku] = true;
    patch.valence[ku] = static_cast<int>(fan.sector.size());
  }
  // Provisional slots: the corners, then every ring entry past the two corners it starts with.
  std::array<std::vector<int>, 3> slot;  // slot[k][j]: ring k's entry j
  std::vector<int> parent = {0, 1, 2};
  std::vector<std::int32_t> vertex = {corners[0], corners[1], corners[2]};
  for (int k = 0; k < 3; ++k) {
    const auto& r = rings[static_cast<std::size_t>(k)];
    auto& sk = slot[static_cast<std::size_t>(k)];
    sk = {(k + 1) % 3, (k + 2) % 3};
    for (std::size_t j = 2; j < r.size(); ++j) {
      sk.push_back(static_cast<int>(parent.size()));
      parent.push_back(static_cast<int>(parent.size()));
      vertex.push_back(r[j]);
    }
  }
  const auto find = [&parent](int x) {
    while (parent[static_cast<std::size_t>(x)] != x)
      x = parent[static_cast<std::size_t>(x)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    return x;
  };
  // The triangle beyond edge c_k c_{k+1} is in both fans: the last entry of ring k is the
  // entry after c_k in ring k + 1. On the boundary there is none, and both fans say so. Where
  // one fan stops at the edge and the other goes on across it, the edge must be a wall for the
  // one and a dart's edge for the other (fewer than two walls there: its whole fan counts).
  for (int k = 0; k < 3; ++k) {
    const auto ku = static_cast<std::size_t>(k), kn = static_cast<std::size_t>((k + 1) % 3);
    const auto& here = slot[ku];
    const auto& there = slot[kn];
    const bool open_here = gap[ku] == static_cast<int>(here.size()) - 1;
    const bool open_there = gap[kn] == 1;
    if (open_here != open_there) {
      const bool dart_edge = walls_of != nullptr && (open_here ? walls[kn][1] != 0 : walls[ku][0] != 0);
      if (!dart_edge) patch_error(corners, "is not a manifold neighbourhood (two fans disagree)");
      continue;
    }
    if (open_here) continue;
    const int a = find(here.back()), b = find(there[2]);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
  // Canonical numbering: corners, then the classes in the order of the rings.
  std::vector<int> number(parent.size(), -1);
  for (int k = 0; k < 3; ++k) number[static_cast<std::size_t>(k)] = k;
  patch.vertices = {corners[0], corners[1], corners[2]};
  bool consistent = true;
  for (int k = 0; k < 3; ++k) {
    for (const int provisional : slot[static_cast<std::size_t>(k)]) {
      const int root = find(provisional);
      consistent = consistent &&
                   vertex[static_cast<std::size_t>(root)] == vertex[static_cast<std::size_t>(provisional)];
      if (number[static_cast<std::size_t>(root)] < 0) {
        number[static_cast<std::size_t>(root)] = static_cast<int>(patch.vertices.size());
        patch.vertices.push_back(vertex[static_cast<std::size_t>(root)]);
      }
    }
  }
  if (!consistent) patch_error(corners, "is not a manifold neighbourhood (two fans disagree)");
  for (int k = 0; k < 3; ++k) {
    const auto& sk = slot[static_cast<std::size_t>(k)];
    for (std::size_t j = 0; j < sk.size(); ++j) {
      if (static_cast<int>(j) == gap[static_cast<std::size_t>(k)]) continue;
      std::array<int, 3> t = {k, number[static_cast<std::size_t>(find(sk[j]))],
                              number[static_cast<std::size_t>(find(sk[(j + 1) % sk.size()]))]};
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      if (std::find(patch.triangles.begin(), patch.triangles.end(), t) == patch.triangles.end())
        patch.triangles.push_back(t);
    }
  }
  // A disc: V - E + F = 1 and no edge in more than two triangles. Meshes so coarse that the
  // fans close up on each other (the tetrahedron: the glued fans make the whole sphere) fail.
  std::map<std::pair<int, int>, int> edge_use;
  for (const auto& t : patch.triangles)
    for (int k = 0; k < 3; ++k)
      ++edge_use[std::minmax(t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)])];
  bool disc = static_cast<int>(patch.vertices.size()) - static_cast<int>(edge_use.size()) +
                  static_cast<int>(patch.triangles.size()) ==
              1;
  for (const auto& [edge, uses] : edge_use) disc = disc && uses <= 2;
  if (!disc) patch_error(corners, "closes up on itself (the mesh is too coarse there; refine it once)");
  // The central triangle first, its corners as given.
  const auto central = std::find(patch.triangles.begin(), patch.triangles.end(), std::array<int, 3>{0, 1, 2});
  std::iter_swap(patch.triangles.begin(), central);
  if (fans_out != nullptr) {
    for (int k = 0; k < 3; ++k) {
      Fan& fan = fans[static_cast<std::size_t>(k)];
      fan.vertex.assign(fan.ring.size(), -1);
      for (std::size_t j = 0; j < fan.sector.size(); ++j)
        fan.vertex[static_cast<std::size_t>(fan.sector[j])] =
            number[static_cast<std::size_t>(find(slot[static_cast<std::size_t>(k)][j]))];
    }
    *fans_out = std::move(fans);
  }
  return patch;
}

namespace {

// ---------------------------------------------------------------------------------------------
// One Loop step of a patch, and the patches of the four children of its central triangle.

// Corner k of child c, as (vertex of the subdivided patch): corners 0-2 of the parent keep
// their numbers; the midpoints of edges 01, 12, 20 are given by `mid`.
std::array<int, 3> child_corners(int child, const std::array<int, 3>& mid) {
  switch (child) {
    case 0:
      return {0, mid[0], mid[2]};
    case 1:
      return {mid[0], 1, mid[1]};
    case 2:
      return {mid[2], mid[1], 2};
    default:
      return {mid[1], mid[2], mid[0]};  // the middle child, turned half around
  }
}

// Child parameters from the parent's, and back: children 0-2 are the parent's corner
// triangles scaled by 1/2; child 3 is the middle one, reflected through (1/4, 1/4).
void to_child(int child, double& u, double& v) {
  switch (child) {
    case 0:
      u = 2 * u, v = 2 * v;
      break;
    case 1:
      u = 2 * u - 1, v = 2 * v;
      break;
    case 2:
      u = 2 * u, v = 2 * v - 1;
      break;
    default:
      u = 1 - 2 * u, v = 1 - 2 * v;
      break;
  }
}
void to_parent(int child, double& u, double& v) {
  switch (child) {
    case 0:
      u = u / 2, v = v / 2;
      break;
    case 1:
      u = 0.5 + u / 2, v = v / 2;
      break;
    case 2:
      u = u / 2, v = 0.5 + v / 2;
      break;
    default:
      u = 0.5 - u / 2, v = 0.5 - v / 2;
      break;
  }
}
// d/du of the parent = this times d/du of the child (and the same for v).
double child_derivative_factor(int child) { return child == 3 ? -2.0 : 2.0; }

int child_containing(double u, double v) {
  if (u >= 0.5) return 1;
  if (v >= 0.5) return 2;
  if (u + v <= 0.5) return 0;
  return 3;
}

}  // namespace

detail::Child detail::subdivide(const LoopPatch& parent, int child) {
  const int n = static_cast<int>(parent.vertices.size());
  // Edges of the patch: ends, opposite vertices.
  std::vector<PatchEdge> edges;
  std::map<std::pair<int, int>, int> edge_index;
  const auto edge_of = [&](int a, int b, int opposite) {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    auto [it, inserted] = edge_index.emplace(key, static_cast<int>(edges.size()));
    if (inserted) edges.push_back({key.first, key.second, {}});
    edges[static_cast<std::size_t>(it->second)].opposite.push_back(opposite);
    return n + it->second;
  };
  Triangles fine;
  fine.reserve(4 * parent.triangles.size());
  std::array<int, 3> mid{};
  for (std::size_t i = 0; i < parent.triangles.size(); ++i) {
    const auto [a, b, c] = parent.triangles[i];
    const int ab = edge_of(a, b, c), bc = edge_of(b, c, a), ca = edge_of(c, a, b);
    if (i == 0) mid = {ab, bc, ca};
    fine.push_back({a, ab, ca});
    fine.push_back({ab, b, bc});
    fine.push_back({ca, bc, c});
    fine.push_back({ab, bc, ca});
  }
  const int fine_n = n + static_cast<int>(edges.size());

  // The child's patch in the subdivided mesh; only its vertices need values.
  const NetRings fine_rings(fine_n, fine);
  const RingOracle fine_ring = [&fine_rings](std::int32_t v, std::vector<std::int32_t>& r) {
    return fine_rings.ring(v, r);
  };
  const std::array<int, 3> corners = child_corners(child, mid);
  Child out;
  // Where the patch has sharp features, their rules (loop_creases.cpp) gather the child and give
  // its rows; elsewhere the plain and boundary rules below do.
  std::optional<detail::CreaseStep> creases;
  if (parent.creases == nullptr) {
    out.patch = gather_patch({corners[0], corners[1], corners[2]}, fine_ring, nullptr, nullptr);
  } else {
    creases.emplace(*parent.creases);
    out.patch = creases->gather_child(corners, fine_ring, n, edges, edge_index);
  }

  const NetRings rings(n, parent.triangles);
  std::vector<std::int32_t> ring;
  out.from_parent = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(out.patch.vertices.size()), n);
  for (std::size_t row = 0; row < out.patch.vertices.size(); ++row) {
    const int w = out.patch.vertices[row];
    auto r = out.from_parent.row(static_cast<Eigen::Index>(row));
    out.origin.push_back(w < n ? std::array<int, 2>{w, -1}
                               : std::array<int, 2>{edges[static_cast<std::size_t>(w - n)].a,
                                                    edges[static_cast<std::size_t>(w - n)].b});
    // The even vertices are the parent's corners, whose fans (or sectors) the patch holds
    // whole, and the odd ones lie on edges at the corners, whose triangles it holds: a fan that
    // does not close and an edge with one triangle are the surface's boundary (or a crease),
    // not the patch's.
    if (w < n) {
      if (creases) {
        if (w > 2) throw std::logic_error("subdivide: an even vertex of a child patch is no parent corner");
        creases->add_even_row(w, r);
      } else if (rings.ring(w, ring)) {  // Loop's vertex rule over the parent ring (Eq. 3)
        const int k = static_cast<int>(ring.size());
        const double a = loop::even_neighbor_weight(k);
        r(w) = 1.0 - k * a;
        for (const std::int32_t x : ring) r(x) += a;
      } else {  // the boundary's vertex rule: its two boundary neighbours only
        if (ring.size() < 2) throw std::logic_error("subdivide: an even vertex of a child patch has no fan");
        r(w) = loop::kCreaseEvenSelf;
        r(ring.front()) += loop::kCreaseEvenNeighbor, r(ring.back()) += loop::kCreaseEvenNeighbor;
      }
      continue;
    }
    const PatchEdge& e = edges[static_cast<std::size_t>(w - n)];
    loop::OddMask mask;  // the edge rule (Eq. 1)
    if (creases) {
      mask = creases->odd_mask(e.a, e.b);
    } else if (e.opposite.size() == 1) {
      mask = loop::odd_mask(kInfiniteSharpness, true);  // a boundary edge: its midpoint (Eq. 2)
    }
    r(e.a) += mask.end, r(e.b) += mask.end;
    if (mask.opposite == 0.0) continue;
    if (e.opposite.size() != 2)
      throw std::logic_error("subdivide: an odd vertex of a child patch lacks a triangle");
    r(e.opposite[0]) += mask.opposite, r(e.opposite[1]) += mask.opposite;
  }
  return out;
}

namespace {

// ---------------------------------------------------------------------------------------------
// The regular patch: its quartic polynomials.

constexpr int kMonomials = 15;  // u^i v^j, i + j <= 4

std::array<std::array<int, 2>, kMonomials> monomial_powers() {
  std::array<std::array<int, 2>, kMonomials> p{};
  int m = 0;
  for (int d = 0; d <= 4; ++d)
    for (int j = 0; j <= d; ++j) p[static_cast<std::size_t>(m++)] = {d - j, j};
  return p;
}

double power(double x, int k) { return k <= 0 ? 1.0 : std::pow(x, k); }

// The monomials and their derivatives at (u, v): rows value, du, dv, duu, duv, dvv, duuu,
// duuv, duvv, dvvv.
constexpr int kRows = 10;
using DerivativeRows = Eigen::Matrix<double, kRows, kMonomials>;

double falling(int i, int k) {  // i (i - 1) ... (i - k + 1)
  double f = 1;
  for (int m = 0; m < k; ++m) f *= i - m;
  return f;
}

DerivativeRows monomials(double u, double v) {
  static const auto powers = monomial_powers();
  static const std::array<std::array<int, 2>, kRows> orders = {
      {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}, {3, 0}, {2, 1}, {1, 2}, {0, 3}}};
  DerivativeRows m;
  for (int k = 0; k < kMonomials; ++k) {
    const int i = powers[static_cast<std::size_t>(k)][0], j = powers[static_cast<std::size_t>(k)][1];
    for (int r = 0; r < kRows; ++r) {
      const int a = orders[static_cast<std::size_t>(r)][0], b = orders[static_cast<std::size_t>(r)][1];
      m(r, k) = falling(i, a) * falling(j, b) * power(u, i - a) * power(v, j - b);
    }
  }
  return m;
}

// The regular patch of the triangular lattice, in canonical order.
LoopPatch regular_lattice_patch() {
  // Lattice points within one step of the corners (0,0), (1,0), (0,1).
  const std::array<std::array<int, 2>, 6> steps = {{{1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}}};
  std::vector<std::array<int, 2>> points = {{0, 0}, {1, 0}, {0, 1}};
  for (int c = 0; c < 3; ++c) {
    for (const auto& s : steps) {
      const std::array<int, 2> p = {points[static_cast<std::size_t>(c)][0] + s[0],
                                    points[static_cast<std::size_t>(c)][1] + s[1]};
      if (std::find(points.begin(), points.end(), p) == points.end()) points.push_back(p);
    }
  }
  const auto index = [&points](int i, int j) {
    const auto it = std::find(points.begin(), points.end(), std::array<int, 2>{i, j});
    return it == points.end() ? -1 : static_cast<int>(it - points.begin());
  };
  Triangles triangles;
  for (int i = -2; i <= 2; ++i) {
    for (int j = -2; j <= 2; ++j) {
      const std::array<std::array<int, 3>, 2> candidates = {
          {{index(i, j), index(i + 1, j), index(i, j + 1)},
           {index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)}}};
      for (const auto& t : candidates) {
        if (t[0] < 0 || t[1] < 0 || t[2] < 0) continue;
        if (t[0] > 2 && t[1] > 2 && t[2] > 2) continue;  // touches no corner
        triangles.push_back(t);
      }
    }
  }
  const NetRings rings(static_cast<int>(points.size()), triangles);
  const LoopPatch gathered = gather_loop_patch(
      {0, 1, 2}, [&rings](std::int32_t v, std::vector<std::int32_t>& r) { return rings.ring(v, r); });
  // Its vertices are lattice indices; the patch of the patch itself numbers them canonically.
  LoopPatch patch = gathered;
  for (std::size_t i = 0; i < patch.vertices.size(); ++i) patch.vertices[i] = static_cast<std::int32_t>(i);
  return patch;
}

// Coefficients (kMonomials x 12) of the 12 basis functions of the regular patch.
const Eigen::Matrix<double, kMonomials, 12>& regular_polynomials() {
  static const Eigen::Matrix<double, kMonomials, 12> coefficients = [] {
    const LoopPatch root = regular_lattice_patch();
    if (root.vertices.size() != 12)
      throw std::logic_error("regular_polynomials: the lattice patch has not 12 vertices");
    Eigen::Matrix<double, kMonomials, kMonomials> a;
    Eigen::Matrix<double, kMonomials, 12> b;
    std::vector<std::array<int, 2>> seen;  // grid points (4u, 4v) found
    for (int c1 = 0; c1 < 4; ++c1) {
      const Child child = subdivide(root, c1);
      for (int c2 = 0; c2 < 4; ++c2) {
        const Child grandchild = subdivide(child.patch, c2);
        const Eigen::MatrixXd from_root = grandchild.from_parent * child.from_parent;
        for (int corner = 0; corner < 3; ++corner) {
          double u = corner == 1 ? 1 : 0, v = corner == 2 ? 1 : 0;
          to_parent(c2, u, v);
          to_parent(c1, u, v);
          const std::array<int, 2> grid = {static_cast<int>(std::lround(4 * u)),
                                           static_cast<int>(std::lround(4 * v))};
          if (std::find(seen.begin(), seen.end(), grid) != seen.end()) continue;
          const int row = static_cast<int>(seen.size());
          seen.push_back(grid);
          a.row(row) = monomials(grid[0] / 4.0, grid[1] / 4.0).row(0);
          b.row(row) = (loop_corner_limit(grandchild.patch, corner).transpose() * from_root);
        }
      }
    }
    if (seen.size() != kMonomials) throw std::logic_error("regular_polynomials: the grid has not 15 points");
    return Eigen::Matrix<double, kMonomials, 12>(a.fullPivLu().solve(b));
  }();
  return coefficients;
}

// Value and derivatives (rows) of the 12 regular basis functions at (u, v).
Eigen::Matrix<double, kRows, 12> regular_basis(double u, double v) {
  return monomials(u, v) * regular_polynomials();
}

// The control values of the regular lattice patch (12, canonical order) as a matrix times
// those of a regular patch with corners on the boundary: the patch completed beyond each
// boundary edge ab at a corner, of triangle abt, by the ghost vertex g = a + b - t, and by
// the triangle of two ghosts that closes the corner's fan. Loop's boundary rules are the
// interior rules applied to the completion, whose ghosts subdivide into the ghosts of the
// next level (the boundary vertex rule 3/4, 1/8, 1/8 is the interior one with these ghosts,
// and the boundary edge rule 1/2, 1/2 the edge rule), so the limit is the box spline of the
// completion. The same holds beyond an infinitely sharp edge, whose rules are the boundary's.
// Built once per connectivity: in a regular patch with sharp features each corner's sector is
// its whole fan in the patch (a triangle beyond a corner's wall would belong to a corner whose
// rule is not plain), so the triangles decide the completion.
Eigen::MatrixXd boundary_completion(const LoopPatch& patch);

const Eigen::MatrixXd& cached_boundary_completion(const LoopPatch& patch) {
  static std::mutex mutex;
  static std::map<Triangles, std::shared_ptr<const Eigen::MatrixXd>> cache;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto it = cache.find(patch.triangles);
    if (it != cache.end()) return *it->second;
  }
  auto made = std::make_shared<const Eigen::MatrixXd>(boundary_completion(patch));
  const std::lock_guard<std::mutex> lock(mutex);
  // Entries are never dropped (callers hold references). A regular patch at the boundary is a
  // piece of the half lattice: which corners are on the boundary and where the central
  // triangle sits in their fans, a few dozen connectivities in all.
  return *cache.emplace(patch.triangles, std::move(made)).first->second;
}

// The map from a regular patch's values to the box spline's 12 control values.
Eigen::MatrixXd to_lattice(const LoopPatch& patch, const Eigen::MatrixXd& to_local) {
  if (patch.closed()) return to_local;
  return cached_boundary_completion(patch) * to_local;
}

Eigen::MatrixXd boundary_completion(const LoopPatch& patch) {
  const int n = static_cast<int>(patch.vertices.size());
  const NetRings rings(n, patch.triangles);
  Triangles completed = patch.triangles;
  std::map<std::pair<int, int>, int> ghost_of_edge;
  std::vector<std::array<int, 3>> ghost_sum;  // a + b - t
  const auto ghost = [&](int a, int b, int t) {
    const auto [it, inserted] =
        ghost_of_edge.emplace(std::minmax(a, b), n + static_cast<int>(ghost_sum.size()));
    if (inserted) ghost_sum.push_back({a, b, t});
    return it->second;
  };
  const auto add = [&completed](std::array<int, 3> t) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    if (std::find(completed.begin(), completed.end(), t) == completed.end()) completed.push_back(t);
  };
  std::vector<std::int32_t> path;
  for (int k = 0; k < 3; ++k) {
    if (!patch.open[static_cast<std::size_t>(k)]) continue;
    if (rings.ring(k, path) || path.size() != 4)
      throw std::logic_error("boundary_completion: a boundary corner is not regular");
    // Triangles (k, p_j, p_j+1) counter-clockwise; the boundary edges are k p0 and k p3.
    const int g_last = ghost(k, path[3], path[2]), g_first = ghost(k, path[0], path[1]);
    add({k, path[3], g_last});
    add({k, g_last, g_first});
    add({k, g_first, path[0]});
  }
  const int total = n + static_cast<int>(ghost_sum.size());
  const LoopPatch lattice = gather_loop_patch({0, 1, 2}, triangle_rings(total, completed));
  if (!lattice.regular() || !lattice.closed() || lattice.vertices.size() != 12)
    throw InputError(
        "Loop elements: a patch at the boundary closes up on itself (the mesh is too coarse there; "
        "refine it once)");
  Eigen::MatrixXd map = Eigen::MatrixXd::Zero(12, n);
  for (Eigen::Index i = 0; i < 12; ++i) {
    const int w = lattice.vertices[static_cast<std::size_t>(i)];
    if (w < n) {
      map(i, w) = 1;
    } else {
      const auto& g = ghost_sum[static_cast<std::size_t>(w - n)];
      map(i, g[0]) += 1, map(i, g[1]) += 1, map(i, g[2]) -= 1;
    }
  }
  return map;
}

// The basis of a patch `factor` times finer (each derivative scaled by factor per order) seen
// from the root patch whose control values map to this one's by `to_local`.
void set_from(LoopBasisAt& out, const Eigen::Matrix<double, kRows, 12>& local,
              const Eigen::MatrixXd& to_local, double factor) {
  const auto row = [&](int r, double scale) -> Eigen::VectorXd {
    return scale * (to_local.transpose() * local.row(r).transpose());
  };
  const double f2 = factor * factor, f3 = f2 * factor;
  out.value = row(0, 1), out.du = row(1, factor), out.dv = row(2, factor);
  out.duu = row(3, f2), out.duv = row(4, f2), out.dvv = row(5, f2);
  out.duuu = row(6, f3), out.duuv = row(7, f3), out.duvv = row(8, f3), out.dvvv = row(9, f3);
}

void set_from(LoopBasisAt& out, const LoopBasisAt& local, const Eigen::MatrixXd& to_local, double factor) {
  const auto map = [&](const Eigen::VectorXd& x, double scale) -> Eigen::VectorXd {
    return scale * (to_local.transpose() * x);
  };
  const double f2 = factor * factor, f3 = f2 * factor;
  out.value = map(local.value, 1), out.du = map(local.du, factor), out.dv = map(local.dv, factor);
  out.duu = map(local.duu, f2), out.duv = map(local.duv, f2), out.dvv = map(local.dvv, f2);
  out.duuu = map(local.duuu, f3), out.duuv = map(local.duuv, f3), out.duvv = map(local.duvv, f3);
  out.dvvv = map(local.dvvv, f3);
}

// ---------------------------------------------------------------------------------------------
// Quadrature.

struct RuleBuilder {
  const LoopQuadratureOptions& options;
  std::vector<std::array<double, 3>> reference;  // (s, t, weight) on the parameter triangle
  std::vector<LoopBasisAt> basis, second_basis;  // second_basis: the second track's, if any
  std::vector<double> u, v, weight;

  // One patch followed down the levels: where it is and how its vertices' values come from
  // the root's.
  struct Track {
    LoopPatch patch;
    Eigen::MatrixXd to_local;
  };

  // The reference rule's points on a sub-triangle `levels` steps down, given the map of its
  // parameters to the root's (`place`), with each track's basis (`at`).
  template <class Place, class At>
  void add_points(int levels, const Place& place, const At& at) {
    const double area = std::ldexp(1.0, -2 * levels);
    for (const auto& [s, t, w] : reference) {
      double ru = s, rv = t;
      place(ru, rv);
      basis.push_back(at(0, s, t));
      if (second) second_basis.push_back(at(1, s, t));
      u.push_back(ru);
      v.push_back(rv);
      weight.push_back(area * w);
    }
  }

  // path: the children taken from the root, to map points back. With two tracks (a patch and
  // the patch it is extended by, LoopQuadrature::extension) both are subdivided together until
  // both are regular, so that one set of points serves both.
  void build(const std::array<Track, 2>& tracks, double factor, std::vector<int>& path) {
    const int levels = static_cast<int>(path.size());
    const auto root_params = [&path](double& s, double& t) {
      for (auto it = path.rbegin(); it != path.rend(); ++it) to_parent(*it, s, t);
    };
    const int count = second ? 2 : 1;
    bool regular = true;
    for (int k = 0; k < count; ++k) regular = regular && tracks[static_cast<std::size_t>(k)].patch.regular();
    if (regular) {
      std::array<Eigen::MatrixXd, 2> lattice;
      for (int k = 0; k < count; ++k) {
        const Track& track = tracks[static_cast<std::size_t>(k)];
        lattice[static_cast<std::size_t>(k)] = to_lattice(track.patch, track.to_local);
      }
      add_points(levels, root_params, [&](int k, double s, double t) {
        LoopBasisAt at;
        set_from(at, regular_basis(s, t), lattice[static_cast<std::size_t>(k)], factor);
        return at;
      });
      return;
    }
    if (levels >= options.extraordinary_depth) {
      add_points(levels, root_params, [&](int k, double s, double t) {
        const Track& track = tracks[static_cast<std::size_t>(k)];
        LoopBasisAt at;
        set_from(at, evaluate_loop_basis(track.patch, s, t), track.to_local, factor);
        return at;
      });
      return;
    }
    for (int c = 0; c < 4; ++c) {
      std::array<Track, 2> children;
      for (int k = 0; k < count; ++k) {
        const Track& track = tracks[static_cast<std::size_t>(k)];
        Child child = subdivide(track.patch, c);
        children[static_cast<std::size_t>(k)] = {std::move(child.patch), child.from_parent * track.to_local};
      }
      path.push_back(c);
      build(children, factor * child_derivative_factor(c), path);
      path.pop_back();
    }
  }

  bool second = false;
};

// What a patch's rules and rules' caches are keyed by: its triangles and, where it has any,
// its sharp features (the corners' rings and sharp edges, bit for bit).
struct PatchKey {
  Triangles triangles;
  std::vector<std::uint32_t> creases;
  bool operator<(const PatchKey& o) const {
    return triangles != o.triangles ? triangles < o.triangles : creases < o.creases;
  }
};

PatchKey patch_key(const LoopPatch& patch) {
  PatchKey key{patch.triangles, {}};
  if (patch.creases) key.creases = detail::crease_key(*patch.creases);
  return key;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

LoopPatch gather_loop_patch(const std::array<std::int32_t, 3>& corners, const RingOracle& ring_of) {
  return gather_patch(corners, ring_of, nullptr, nullptr);
}

Eigen::VectorXd loop_corner_limit(const LoopPatch& patch, int corner) {
  if (patch.creases) return detail::crease_corner_limit(patch, corner);
  const Eigen::Index size = static_cast<Eigen::Index>(patch.vertices.size());
  const NetRings rings(static_cast<int>(patch.vertices.size()), patch.triangles);
  std::vector<std::int32_t> ring;
  if (!rings.ring(corner, ring)) {  // the boundary's limit mask: its two boundary neighbours
    if (ring.size() < 2) throw std::logic_error("loop_corner_limit: the corner's fan is not in the patch");
    Eigen::VectorXd w = Eigen::VectorXd::Zero(size);
    w(corner) = loop::kBoundaryLimitSelf;
    w(ring.front()) += loop::kBoundaryLimitNeighbor, w(ring.back()) += loop::kBoundaryLimitNeighbor;
    return w;
  }
  const int k = static_cast<int>(ring.size());
  const double b = loop::limit_neighbor_weight(k);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(size);
  w(corner) = 1.0 - k * b;
  for (const std::int32_t x : ring) w(x) += b;
  return w;
}

LoopBasisAt evaluate_loop_basis(const LoopPatch& patch, double u, double v) {
  const Eigen::Index n = static_cast<Eigen::Index>(patch.vertices.size());
  LoopBasisAt out;
  // At an extraordinary corner itself: the limit mask; the derivatives do not exist there.
  for (int k = 0; k < 3; ++k) {
    const bool here =
        (k == 0 && u == 0 && v == 0) || (k == 1 && u == 1 && v == 0) || (k == 2 && u == 0 && v == 1);
    if (here && !patch.regular_corner(k)) {
      out.value = loop_corner_limit(patch, k);
      const double nan = std::numeric_limits<double>::quiet_NaN();
      out.du = out.dv = out.duu = out.duv = out.dvv = Eigen::VectorXd::Constant(n, nan);
      out.duuu = out.duuv = out.duvv = out.dvvv = out.du;
      return out;
    }
  }
  const double u0 = u, v0 = v;
  LoopPatch current = patch;
  Eigen::MatrixXd to_local = Eigen::MatrixXd::Identity(n, n);
  double factor = 1;
  // Each step halves the point's distance from an extraordinary corner: 60 steps reach below
  // the resolution of doubles, where the point is that corner.
  for (int depth = 0; !current.regular(); ++depth) {
    if (depth == 60) return evaluate_loop_basis(patch, std::round(u0), std::round(v0));
    const int c = child_containing(u, v);
    Child child = subdivide(current, c);
    to_child(c, u, v);
    to_local = child.from_parent * to_local;
    factor *= child_derivative_factor(c);
    current = std::move(child.patch);
  }
  set_from(out, regular_basis(u, v), to_lattice(current, to_local), factor);
  return out;
}

void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(static_cast<std::size_t>(n), 0.0);
  w.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    // Newton's method on P_n from the Chebyshev-like first guess.
    double t = std::cos(loop::kPi * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1, p1 = t;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * t * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = n * (t * p1 - p0) / (t * t - 1);
      const double step = p1 / dp;
      t -= step;
      if (std::abs(step) < 1e-16) break;
    }
    x[static_cast<std::size_t>(i)] = 0.5 * (1 - t);
    w[static_cast<std::size_t>(i)] = 1.0 / ((1 - t * t) * dp * dp);  // on [-1, 1] this is twice it
  }
}

namespace {

// The rule on the parameter triangle {s, t >= 0, s + t <= 1} (area 1/2) that every regular
// sub-triangle gets: with points_per_direction = n >= 1 the collapsed Gauss rule (n x n points,
// exact to degree 2n - 2); with 0 the symmetric rule of 12 points exact to degree 6, the
// 4 x 4 rule's degree with three quarters of its points. Its orbits (barycentric coordinates
// (a, a, 1 - 2a) with their 3 permutations twice, (a, b, 1 - a - b) with its 6) solve the
// seven moment equations of the S3-invariant polynomials of degree <= 6 (1, e2, e3, e2^2,
// e2 e3, e3^2, e2^3 with e1 = 1), solved by Newton's method in 40-digit arithmetic
// (scripts/triangle_rule.py derives them again); the rule's test checks every monomial of
// degree <= 6.
std::vector<std::array<double, 3>> reference_rule(int points_per_direction) {
  std::vector<std::array<double, 3>> rule;
  if (points_per_direction >= 1) {
    std::vector<double> x, w;
    gauss_legendre(points_per_direction, x, w);
    for (std::size_t a = 0; a < x.size(); ++a)
      for (std::size_t b = 0; b < x.size(); ++b)
        rule.push_back({x[a], x[b] * (1 - x[a]), w[a] * w[b] * (1 - x[a])});
    return rule;
  }
  struct Orbit {
    double a, b, weight;  // b < 0: the orbit (a, a, 1 - 2a)
  };
  const Orbit orbits[] = {{0.06308901449150223, -1, 0.02542245318510341},
                          {0.24928674517091043, -1, 0.058393137863189684},
                          {0.6365024991213987, 0.3103524510337844, 0.041425537809186785}};
  for (const Orbit& o : orbits) {
    if (o.b < 0) {
      const double c = 1 - 2 * o.a;
      for (const auto& [s, t] : {std::array<double, 2>{o.a, o.a}, {o.a, c}, {c, o.a}})
        rule.push_back({s, t, o.weight});
      continue;
    }
    const double l[3] = {o.a, o.b, 1 - o.a - o.b};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (i != j) rule.push_back({l[i], l[j], o.weight});
  }
  return rule;
}

}  // namespace

namespace {

LoopPatch numbered_locally(const LoopPatch& patch) {
  LoopPatch local = patch;
  for (std::size_t i = 0; i < local.vertices.size(); ++i) local.vertices[i] = static_cast<std::int32_t>(i);
  return local;
}

// A rule's tables from the builder's bases at its points: the first track's functions, then
// rows `extra` of the second's.
void fill_tables(LoopQuadrature& rule, const std::vector<LoopBasisAt>& basis,
                 const std::vector<LoopBasisAt>& second, const std::vector<int>& extra) {
  const Eigen::Index own = static_cast<Eigen::Index>(rule.patch.vertices.size());
  const Eigen::Index n = own + static_cast<Eigen::Index>(extra.size());
  const Eigen::Index q = static_cast<Eigen::Index>(basis.size());
  for (Eigen::MatrixXd* m : {&rule.value, &rule.du, &rule.dv, &rule.duu, &rule.duv, &rule.dvv})
    m->resize(n, q);
  const auto put = [&](Eigen::Index p, const LoopBasisAt& at, Eigen::Index from, Eigen::Index row) {
    rule.value(row, p) = at.value(from);
    rule.du(row, p) = at.du(from);
    rule.dv(row, p) = at.dv(from);
    rule.duu(row, p) = at.duu(from);
    rule.duv(row, p) = at.duv(from);
    rule.dvv(row, p) = at.dvv(from);
  };
  for (Eigen::Index p = 0; p < q; ++p) {
    const LoopBasisAt& at = basis[static_cast<std::size_t>(p)];
    for (Eigen::Index i = 0; i < own; ++i) put(p, at, i, i);
    for (std::size_t k = 0; k < extra.size(); ++k)
      put(p, second[static_cast<std::size_t>(p)], extra[k], own + static_cast<Eigen::Index>(k));
  }
}

std::shared_ptr<const LoopQuadrature> cached_quadrature(const LoopPatch& patch, const LoopPatch* extension,
                                                        const std::vector<int>& rows,
                                                        const LoopQuadratureOptions& options) {
  if (options.points_per_direction < 0 || options.points_per_direction > 20 ||
      options.extraordinary_depth < 0 || options.extraordinary_depth > 20)
    throw std::invalid_argument("loop_quadrature: points per direction in [0, 20], depth in [0, 20]");
  using Key = std::tuple<std::array<int, 2>, PatchKey, std::optional<PatchKey>, std::vector<int>>;
  // The rules of a closed mesh refined once are few (one extraordinary corner each, a handful
  // of valences); an irregular base mesh has one per distinct neighbourhood of its triangles
  // (the cow: about a hundred, 0.5 MB each). The cache is emptied when it passes 256 MB, so
  // that a long session with many meshes stays bounded; spaces keep the rules they use.
  static std::mutex mutex;
  static std::map<Key, std::shared_ptr<const LoopQuadrature>> cache;
  static std::size_t cached_bytes = 0;
  const Key key{{options.points_per_direction, options.extraordinary_depth},
                patch_key(patch),
                extension != nullptr ? std::optional<PatchKey>(patch_key(*extension)) : std::nullopt,
                rows};
  {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto it = cache.find(key);
    if (it != cache.end()) return it->second;
  }
  RuleBuilder builder{options, reference_rule(options.points_per_direction), {}, {}, {}, {}, {}, false};
  std::array<RuleBuilder::Track, 2> tracks;
  tracks[0].patch = numbered_locally(patch);
  tracks[0].to_local = Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(patch.vertices.size()),
                                                 static_cast<Eigen::Index>(patch.vertices.size()));
  if (extension != nullptr) {
    builder.second = true;
    tracks[1].patch = numbered_locally(*extension);
    tracks[1].to_local = Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(extension->vertices.size()),
                                                   static_cast<Eigen::Index>(extension->vertices.size()));
  }
  std::vector<int> path;
  builder.build(tracks, 1.0, path);

  auto rule = std::make_shared<LoopQuadrature>();
  rule->patch = std::move(tracks[0].patch);
  rule->u = std::move(builder.u);
  rule->v = std::move(builder.v);
  rule->weight = std::move(builder.weight);
  fill_tables(*rule, builder.basis, builder.second_basis, rows);
  if (extension != nullptr)
    rule->extension = std::make_shared<const LoopQuadrature::Extension>(
        LoopQuadrature::Extension{std::move(tracks[1].patch), rows});
  const std::size_t bytes = sizeof(double) * static_cast<std::size_t>(rule->value.size()) * 6;
  const std::lock_guard<std::mutex> lock(mutex);
  if (cached_bytes + bytes > (std::size_t{256} << 20)) {
    cache.clear();
    cached_bytes = 0;
  }
  const auto [it, inserted] = cache.emplace(key, std::move(rule));
  if (inserted) cached_bytes += bytes;
  return it->second;
}

}  // namespace

std::shared_ptr<const LoopQuadrature> loop_quadrature(const LoopPatch& patch,
                                                      const LoopQuadratureOptions& options) {
  return cached_quadrature(patch, nullptr, {}, options);
}

std::shared_ptr<const LoopQuadrature> loop_quadrature(const LoopPatch& patch, const LoopPatch& extension,
                                                      const std::vector<int>& rows,
                                                      const LoopQuadratureOptions& options) {
  if (patch.vertices.size() < 3 || extension.vertices.size() < 3 ||
      !std::equal(patch.vertices.begin(), patch.vertices.begin() + 3, extension.vertices.begin()))
    throw std::invalid_argument("loop_quadrature: the two patches are not of one triangle");
  for (const int r : rows)
    if (r < 0 || static_cast<std::size_t>(r) >= extension.vertices.size())
      throw std::invalid_argument("loop_quadrature: an extension row outside its patch");
  return cached_quadrature(patch, &extension, rows, options);
}

namespace {

Eigen::VectorXd extended(const LoopQuadrature& rule, const Eigen::VectorXd& own,
                         const Eigen::VectorXd& other) {
  const std::vector<int>& rows = rule.extension->rows;
  Eigen::VectorXd out(own.size() + static_cast<Eigen::Index>(rows.size()));
  out.head(own.size()) = own;
  for (std::size_t k = 0; k < rows.size(); ++k)
    out(own.size() + static_cast<Eigen::Index>(k)) = other(rows[k]);
  return out;
}

}  // namespace

LoopBasisAt loop_rule_basis(const LoopQuadrature& rule, double u, double v) {
  LoopBasisAt at = evaluate_loop_basis(rule.patch, u, v);
  if (!rule.extension) return at;
  const LoopBasisAt other = evaluate_loop_basis(rule.extension->patch, u, v);
  for (auto [mine, theirs] : {std::pair{&at.value, &other.value}, {&at.du, &other.du}, {&at.dv, &other.dv},
                              {&at.duu, &other.duu}, {&at.duv, &other.duv}, {&at.dvv, &other.dvv},
                              {&at.duuu, &other.duuu}, {&at.duuv, &other.duuv}, {&at.duvv, &other.duvv},
                              {&at.dvvv, &other.dvvv}})
    if (mine->size() > 0) *mine = extended(rule, *mine, *theirs);
  return at;
}

Eigen::VectorXd loop_rule_corner_limit(const LoopQuadrature& rule, int corner) {
  const Eigen::VectorXd own = loop_corner_limit(rule.patch, corner);
  return rule.extension ? extended(rule, own, loop_corner_limit(rule.extension->patch, corner)) : own;
}

std::shared_ptr<const LoopChildPatch> loop_child_patch(const LoopPatch& parent, int child) {
  if (child < 0 || child > 3) throw std::invalid_argument("loop_child_patch: child in [0, 3]");
  // Keyed by connectivity, as the rules are: an adaptive space asks for the same few patches
  // (the regular one above all) for every cell it subdivides.
  using Key = std::pair<int, PatchKey>;
  static std::mutex mutex;
  static std::map<Key, std::shared_ptr<const LoopChildPatch>> cache;
  static std::size_t cached_bytes = 0;
  Key key{child, patch_key(parent)};
  {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto it = cache.find(key);
    if (it != cache.end()) return it->second;
  }
  Child c = subdivide(numbered_locally(parent), child);
  auto out = std::make_shared<LoopChildPatch>();
  out->patch = std::move(c.patch);
  out->from_parent = std::move(c.from_parent);
  out->origin = std::move(c.origin);
  const std::lock_guard<std::mutex> lock(mutex);
  // Bounded over a long session of many meshes, and above what one irregular base mesh asks
  // for (every base connectivity's four children: 7,200 for elephant-with-holes, 10 MB).
  const std::size_t bytes = sizeof(double) * static_cast<std::size_t>(out->from_parent.size()) +
                            16 * (out->patch.vertices.size() + out->patch.triangles.size()) + 256;
  if (cached_bytes + bytes > (std::size_t{64} << 20)) {
    cache.clear();
    cached_bytes = 0;
  }
  const auto [it, inserted] = cache.emplace(std::move(key), std::move(out));
  if (inserted) cached_bytes += bytes;
  return it->second;
}

int loop_descend(double& u, double& v) {
  const int c = child_containing(u, v);
  to_child(c, u, v);
  return c;
}

RingOracle triangle_rings(std::int32_t vertices, const std::vector<std::array<int, 3>>& triangles) {
  auto rings = std::make_shared<const NetRings>(vertices, triangles);
  return [rings](std::int32_t v, std::vector<std::int32_t>& out) { return rings->ring(v, out); };
}

}  // namespace rgbmesh::fem
