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
// Sharp features change two things. A patch's fans are cut where infinitely sharp edges
// ("walls") bound a sector of them, so the patch holds only the side of each crease its
// triangle is on. And its corners' rules are those of loop_rules.hpp, which need the
// sharpness of every edge at a corner one level down (LoopCreases: per corner its sharp edges,
// and of each the half at its far end, which Chaikin's averages take from the far end's edges):
// a step computes the child's from the parent's, so a patch carries what all its descendants
// need.

#include "rgbmesh/fem/loop_basis.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>

#include "rgbmesh/errors.hpp"
#include "rgbmesh/loop_rules.hpp"

namespace rgbmesh::fem {

namespace {

using Triangles = std::vector<std::array<int, 3>>;

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

// Per entry of a vertex's ring (as the ring oracle gave it): whether the edge to it is a wall,
// infinitely sharp, so that where a fan has two or more (its boundary edges counting) it is cut
// into sectors there. Called with the corner's index (0-2), its vertex and ring.
using WallOracle = std::function<void(int corner, std::int32_t vertex, const std::vector<std::int32_t>& ring,
                                      std::vector<char>& wall)>;

// What gathering found of a corner's fan: its ring oriented counter-clockwise from the next
// corner (the whole fan), each entry's place in the oracle's ring, the entries of the sector
// that holds the central triangle (from the next corner on), the patch vertex of each of those
// (-1 for the entries outside), and the entry after which an open fan has no triangle.
struct Fan {
  std::vector<std::int32_t> ring;
  std::vector<int> raw, sector, vertex;
  int boundary_gap = -1;
  bool boundary(std::size_t i) const {
    const int m = static_cast<int>(ring.size());
    return boundary_gap >= 0 &&
           (static_cast<int>(i) == boundary_gap || static_cast<int>(i) == (boundary_gap + 1) % m);
  }
};

// The patch of a triangle (see gather_loop_patch), its corners' fans cut at walls where
// `walls_of` is given, with what was found of them in `fans` (if given).
LoopPatch gather_patch(const std::array<std::int32_t, 3>& corners, const RingOracle& ring_of,
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
    std::vector<int>& order = fan.raw;
    order.resize(m);
    fan.ring.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
      order[i] = static_cast<int>(entry(i));
      fan.ring[i] = raw[entry(i)];
    }
    std::vector<char>& wall = walls[ku];
    wall.resize(m);
    int count = 0;
    for (std::size_t i = 0; i < m; ++i) {
      wall[i] = fan.boundary(i) || (walls_of != nullptr && raw_wall[static_cast<std::size_t>(order[i])]);
      count += wall[i];
    }
    // The sector of the central triangle (entries 0 and 1): from the last wall before entry 1
    // to the first one from it on. A closed fan with fewer than two walls stays whole (one wall
    // ends a crease inside smooth surface: a dart, whose rules use the whole fan).
    fan.sector.reserve(m);
    if (closed && count < 2) {
      for (std::size_t i = 0; i < m; ++i) fan.sector.push_back(static_cast<int>(i));
    } else {
      std::size_t last = 1;
      while (!wall[last]) ++last;
      std::size_t first = 0;
      if (!wall[0]) {
        first = m - 1;
        while (!wall[first]) --first;
      }
      for (std::size_t i = 0; i <= last; ++i) fan.sector.push_back(static_cast<int>(i));
      if (first > 0)
        for (std::size_t i = first; i < m; ++i) fan.sector.push_back(static_cast<int>(i));
      gap[ku] = static_cast<int>(last);
      patch.open[ku] = true;
    }
    if (fan.sector.size() == m) {
      rings[ku] = fan.ring;
    } else {
      rings[ku].reserve(fan.sector.size());
      for (const int i : fan.sector) rings[ku].push_back(fan.ring[static_cast<std::size_t>(i)]);
    }
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

// ---------------------------------------------------------------------------------------------
// The rules at a patch's corners on a mesh with sharp features (loop_rules.hpp), one step at a
// time, as the RGB mesh's vertices evolve (rgbmesh/src/creases.cpp).

// One step of a corner's rules: its sharp edges' sharpness now (s) and of their halves at the
// corner one level down (t), its own sharpness now and then, and its rule on both levels.
struct CornerStep {
  std::vector<float> s, t;
  float vs = 0, vt = 0;
  VertexRule rule = VertexRule::smooth, next = VertexRule::smooth;
};

int count_sharp(const std::vector<float>& s) {
  return static_cast<int>(std::count_if(s.begin(), s.end(), [](float x) { return x > 0.0f; }));
}

CornerStep corner_step(const LoopCreases& creases, int k) {
  const LoopCreases::Corner& corner = creases.corner[static_cast<std::size_t>(k)];
  CornerStep step;
  for (const LoopCreases::Spoke& spoke : corner.spokes) step.s.push_back(spoke.sharpness);
  const int n = static_cast<int>(step.s.size());
  for (const float s : step.s) step.t.push_back(loop::child_sharpness(creases.method, s, step.s.data(), n));
  step.vs = corner.sharpness;
  step.vt = loop::decrement_sharpness(step.vs);
  step.rule = loop::vertex_rule(step.vs, count_sharp(step.s));
  step.next = loop::vertex_rule(step.vt, count_sharp(step.t));
  return step;
}

// The spoke of corner k towards patch vertex x, or -1.
int spoke_to(const LoopCreases& creases, int k, int x) {
  const auto& spokes = creases.corner[static_cast<std::size_t>(k)].spokes;
  for (std::size_t i = 0; i < spokes.size(); ++i)
    if (spokes[i].to == x) return static_cast<int>(i);
  return -1;
}

// The sharpness of the patch edge ab (one end a corner) and of its halves one level down.
struct EdgeSharpness {
  float s = 0, half_a = 0, half_b = 0;
  bool boundary = false;
};
EdgeSharpness edge_sharpness(const LoopCreases& creases, const std::array<CornerStep, 3>& steps, int a,
                             int b) {
  EdgeSharpness out;
  bool found = false;
  for (const auto [from, to] : {std::array<int, 2>{a, b}, std::array<int, 2>{b, a}}) {
    if (from > 2) continue;
    const int i = spoke_to(creases, from, to);
    if (i < 0) continue;
    const LoopCreases::Spoke& spoke =
        creases.corner[static_cast<std::size_t>(from)].spokes[static_cast<std::size_t>(i)];
    const float near = steps[static_cast<std::size_t>(from)].t[static_cast<std::size_t>(i)];
    out.s = spoke.sharpness;
    out.boundary = spoke.boundary;
    // The far end's half: the far corner's own step where the far end is a corner too.
    if (from == a) {
      out.half_a = near;
      if (!found) out.half_b = spoke.far_child;
    } else {
      out.half_b = near;
      if (!found) out.half_a = spoke.far_child;
    }
    found = true;
  }
  return out;
}

// A row of a column-major matrix (strided).
using MatrixRow = Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>>;

// Adds `scale` times corner k's vertex mask under `rule` (its sharp edges' sharpness `sharp`)
// to a row over the patch's vertices.
void add_even_mask(const LoopCreases::Corner& corner, int k, VertexRule rule, const std::vector<float>& sharp,
                   double scale, MatrixRow row) {
  switch (rule) {
    case VertexRule::smooth:
    case VertexRule::dart: {
      if (corner.sector) throw std::logic_error("subdivide: a smooth rule on a sector of a fan");
      const int n = static_cast<int>(corner.ring.size());
      const double a = loop::even_neighbor_weight(n);
      row(k) += scale * (1.0 - n * a);
      for (const std::int32_t x : corner.ring) row(x) += scale * a;
      return;
    }
    case VertexRule::crease:
      row(k) += scale * loop::kCreaseEvenSelf;
      for (std::size_t i = 0; i < sharp.size(); ++i) {
        if (!(sharp[i] > 0.0f)) continue;
        const std::int32_t to = corner.spokes[i].to;
        if (to < 0) throw std::logic_error("subdivide: a crease's edge lies outside its sector");
        row(to) += scale * loop::kCreaseEvenNeighbor;
      }
      return;
    case VertexRule::corner:
      row(k) += scale;
      return;
  }
}

// The vertex rule of corner k for one step: blended with the next level's rule where a crease
// or corner turns into another rule (transition_weight), as OpenSubdiv and the mesh do.
void add_even_row(const LoopCreases& creases, const CornerStep& step, int k, MatrixRow row) {
  const LoopCreases::Corner& corner = creases.corner[static_cast<std::size_t>(k)];
  const bool blends =
      (step.rule == VertexRule::crease || step.rule == VertexRule::corner) && step.next != step.rule;
  if (!blends) {
    add_even_mask(corner, k, step.rule, step.s, 1.0, row);
    return;
  }
  const double w = loop::transition_weight(creases.method, step.vs, step.vt, static_cast<int>(step.s.size()),
                                           step.s.data(), step.t.data());
  add_even_mask(corner, k, step.rule, step.s, w, row);
  add_even_mask(corner, k, step.next, step.t, 1.0 - w, row);
}

// The sharp features of a child patch, from its parent's (corners' steps `steps`): a parent
// corner keeps its edges' halves, a midpoint of a sharp central edge has that edge's two halves.
// `fine` names each vertex of the subdivided parent (n + e for the midpoint of edge e, whose
// ends are `ends[e]`); `fans` are the child's corners' fans in it. Null where nothing is sharp.
std::shared_ptr<const LoopCreases> child_creases(const LoopCreases& parent,
                                                 const std::array<CornerStep, 3>& steps, int n,
                                                 const std::vector<std::array<int, 2>>& ends,
                                                 const std::map<std::pair<int, int>, int>& midpoint,
                                                 const std::array<int, 3>& corners,
                                                 const std::array<Fan, 3>& fans) {
  auto out = std::make_shared<LoopCreases>();
  out->method = parent.method;
  bool any = false;
  const CreaseMethod method = parent.method;
  for (int kk = 0; kk < 3; ++kk) {
    const Fan& fan = fans[static_cast<std::size_t>(kk)];
    LoopCreases::Corner& corner = out->corner[static_cast<std::size_t>(kk)];
    // The child patch's vertex that fine vertex v is in this corner's sector, or -1.
    const auto in_sector = [&fan](int v) {
      for (const int i : fan.sector)
        if (fan.ring[static_cast<std::size_t>(i)] == v) return fan.vertex[static_cast<std::size_t>(i)];
      return -1;
    };
    for (const int i : fan.sector) corner.ring.push_back(fan.vertex[static_cast<std::size_t>(i)]);
    const int v = corners[static_cast<std::size_t>(kk)];
    if (v < n) {  // a parent corner: the halves of its sharp edges at it
      if (v > 2) throw std::logic_error("subdivide: a child's corner is no parent corner");
      const CornerStep& step = steps[static_cast<std::size_t>(v)];
      const LoopCreases::Corner& from = parent.corner[static_cast<std::size_t>(v)];
      corner.sharpness = step.vt;
      corner.sector = from.sector;
      for (std::size_t i = 0; i < from.spokes.size(); ++i) {
        const float t = step.t[i];
        if (!(t > 0.0f)) continue;
        LoopCreases::Spoke spoke;
        spoke.sharpness = t;
        spoke.boundary = from.spokes[i].boundary;
        if (from.spokes[i].to >= 0) {
          spoke.to = in_sector(n + midpoint.at(std::minmax(v, static_cast<int>(from.spokes[i].to))));
          // At the midpoint the half meets the far half (far_child): Chaikin's pair.
          const float pair[2] = {t, from.spokes[i].far_child};
          spoke.far_child = loop::child_sharpness(method, t, pair, 2);
        }
        corner.spokes.push_back(spoke);
      }
    } else {  // the midpoint of a central edge ab: sharp along the edge's halves
      const int a = ends[static_cast<std::size_t>(v - n)][0], b = ends[static_cast<std::size_t>(v - n)][1];
      for (const auto [end, other] : {std::array<int, 2>{a, b}, std::array<int, 2>{b, a}}) {
        const int i = spoke_to(parent, end, other);
        if (i < 0) continue;
        const CornerStep& step = steps[static_cast<std::size_t>(end)];
        const float t = step.t[static_cast<std::size_t>(i)];
        if (!(t > 0.0f)) continue;
        LoopCreases::Spoke spoke;
        spoke.sharpness = t;
        spoke.boundary =
            parent.corner[static_cast<std::size_t>(end)].spokes[static_cast<std::size_t>(i)].boundary;
        spoke.to = in_sector(end);
        // Its far end is the corner `end`, where the next level's halves average over all its edges.
        spoke.far_child = loop::child_sharpness(method, t, step.t.data(), static_cast<int>(step.t.size()));
        corner.spokes.push_back(spoke);
      }
      corner.sector = corner.spokes.size() == 2 && loop::is_infinitely_sharp(corner.spokes[0].sharpness);
    }
    any = any || corner.sharpness > 0.0f ||
          std::any_of(corner.spokes.begin(), corner.spokes.end(),
                      [](const LoopCreases::Spoke& s) { return !s.boundary; });
  }
  if (!any) return nullptr;
  return out;
}

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

struct Child {
  LoopPatch patch;
  Eigen::MatrixXd from_parent;             ///< patch values = from_parent * parent patch values
  std::vector<std::array<int, 2>> origin;  ///< per child vertex: {parent vertex, -1} or the edge's ends
};

// The patch of child `child` of a patch's central triangle.
Child subdivide(const LoopPatch& parent, int child) {
  const int n = static_cast<int>(parent.vertices.size());
  // Edges of the patch: ends, opposite vertices.
  struct Edge {
    int a, b;
    std::vector<int> opposite;
  };
  std::vector<Edge> edges;
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
  const LoopCreases* creases = parent.creases.get();
  std::array<CornerStep, 3> steps;
  if (creases == nullptr) {
    out.patch = gather_patch({corners[0], corners[1], corners[2]}, fine_ring, nullptr, nullptr);
  } else {
    for (int k = 0; k < 3; ++k) steps[static_cast<std::size_t>(k)] = corner_step(*creases, k);
    // The walls at the child's corners: the halves of a parent corner's walls, and the two
    // halves of a wall that a midpoint splits.
    const WallOracle walls = [&](int, std::int32_t v, const std::vector<std::int32_t>& ring,
                                 std::vector<char>& wall) {
      if (v < n) {
        if (v > 2) throw std::logic_error("subdivide: a child's corner is no parent corner");
        for (std::size_t i = 0; i < ring.size(); ++i) {
          if (ring[i] < n) continue;
          const Edge& e = edges[static_cast<std::size_t>(ring[i] - n)];
          const int s = spoke_to(*creases, v, e.a == v ? e.b : e.a);
          wall[i] =
              s >= 0 &&
              loop::is_infinitely_sharp(
                  creases->corner[static_cast<std::size_t>(v)].spokes[static_cast<std::size_t>(s)].sharpness);
        }
        return;
      }
      const Edge& e = edges[static_cast<std::size_t>(v - n)];
      if (!loop::is_infinitely_sharp(edge_sharpness(*creases, steps, e.a, e.b).s)) return;
      for (std::size_t i = 0; i < ring.size(); ++i) wall[i] = ring[i] == e.a || ring[i] == e.b;
    };
    std::array<Fan, 3> fans;
    out.patch = gather_patch({corners[0], corners[1], corners[2]}, fine_ring, &walls, &fans);
    std::vector<std::array<int, 2>> ends;
    for (const Edge& e : edges) ends.push_back({e.a, e.b});
    out.patch.creases = child_creases(*creases, steps, n, ends, edge_index, corners, fans);
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
      if (creases != nullptr) {
        if (w > 2) throw std::logic_error("subdivide: an even vertex of a child patch is no parent corner");
        add_even_row(*creases, steps[static_cast<std::size_t>(w)], w, r);
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
    const Edge& e = edges[static_cast<std::size_t>(w - n)];
    loop::OddMask mask;  // the edge rule (Eq. 1)
    if (creases != nullptr) {
      const EdgeSharpness es = edge_sharpness(*creases, steps, e.a, e.b);
      mask = loop::odd_mask(es.s, es.half_a > 0.0f && es.half_b > 0.0f);
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
  std::vector<double> gauss_x, gauss_w;
  std::vector<LoopBasisAt> basis;
  std::vector<double> u, v, weight;

  // The points of the collapsed Gauss rule on a sub-triangle `levels` steps down, given the map
  // of its parameters to the root's (`to_root`).
  template <class Place>
  void add_points(int levels, const Place& place) {
    const double area = std::ldexp(1.0, -2 * levels);
    for (std::size_t a = 0; a < gauss_x.size(); ++a) {
      for (std::size_t b = 0; b < gauss_x.size(); ++b) {
        const double s = gauss_x[a], t = gauss_x[b] * (1 - gauss_x[a]);
        double ru = s, rv = t;
        basis.push_back(place(s, t, ru, rv));
        u.push_back(ru);
        v.push_back(rv);
        weight.push_back(area * gauss_w[a] * gauss_w[b] * (1 - gauss_x[a]));
      }
    }
  }

  // path: the children taken from the root, to map points back.
  void build(const LoopPatch& patch, const Eigen::MatrixXd& to_local, double factor, std::vector<int>& path) {
    const int levels = static_cast<int>(path.size());
    const auto root_params = [&path](double& s, double& t) {
      for (auto it = path.rbegin(); it != path.rend(); ++it) to_parent(*it, s, t);
    };
    if (patch.regular()) {
      const Eigen::MatrixXd lattice = to_lattice(patch, to_local);
      add_points(levels, [&](double s, double t, double& ru, double& rv) {
        LoopBasisAt at;
        set_from(at, regular_basis(s, t), lattice, factor);
        root_params(ru, rv);
        return at;
      });
      return;
    }
    if (levels >= options.extraordinary_depth) {
      add_points(levels, [&](double s, double t, double& ru, double& rv) {
        LoopBasisAt at;
        set_from(at, evaluate_loop_basis(patch, s, t), to_local, factor);
        root_params(ru, rv);
        return at;
      });
      return;
    }
    for (int c = 0; c < 4; ++c) {
      const Child child = subdivide(patch, c);
      path.push_back(c);
      build(child.patch, child.from_parent * to_local, factor * child_derivative_factor(c), path);
      path.pop_back();
    }
  }
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

std::uint32_t bits(float x) {
  std::uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

PatchKey patch_key(const LoopPatch& patch) {
  PatchKey key{patch.triangles, {}};
  if (!patch.creases) return key;
  const LoopCreases& c = *patch.creases;
  std::vector<std::uint32_t>& k = key.creases;
  k.push_back(1 + static_cast<std::uint32_t>(c.method));
  for (const LoopCreases::Corner& corner : c.corner) {
    k.push_back(bits(corner.sharpness));
    k.push_back(corner.sector ? 1u : 0u);
    k.push_back(static_cast<std::uint32_t>(corner.ring.size()));
    for (const std::int32_t x : corner.ring) k.push_back(static_cast<std::uint32_t>(x));
    k.push_back(static_cast<std::uint32_t>(corner.spokes.size()));
    for (const LoopCreases::Spoke& s : corner.spokes) {
      k.push_back(static_cast<std::uint32_t>(s.to));
      k.push_back(bits(s.sharpness));
      k.push_back(bits(s.far_child));
      k.push_back(s.boundary ? 1u : 0u);
    }
  }
  return key;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

bool LoopCreases::plain(int k) const {
  const Corner& c = corner[static_cast<std::size_t>(k)];
  if (c.sharpness > 0.0f) return false;
  if (c.spokes.empty()) return true;
  return c.spokes.size() == 2 && loop::is_infinitely_sharp(c.spokes[0].sharpness) &&
         loop::is_infinitely_sharp(c.spokes[1].sharpness);
}

bool LoopCreases::transient(int k) const {
  const Corner& c = corner[static_cast<std::size_t>(k)];
  return loop::is_semi_sharp(c.sharpness) ||
         std::any_of(c.spokes.begin(), c.spokes.end(),
                     [](const Spoke& s) { return loop::is_semi_sharp(s.sharpness); });
}

LoopPatch gather_loop_patch(const std::array<std::int32_t, 3>& corners, const RingOracle& ring_of) {
  return gather_patch(corners, ring_of, nullptr, nullptr);
}

LoopPatch gather_loop_patch(const std::array<std::int32_t, 3>& corners, const RingOracle& ring_of,
                            const LoopFeatures& features) {
  if (!features.at) return gather_patch(corners, ring_of, nullptr, nullptr);
  std::array<LoopVertexFeatures, 3> at;
  const auto ask = [&features](std::int32_t v, const std::vector<std::int32_t>& ring, LoopVertexFeatures& f) {
    features.at(v, ring, f);
    if (f.edges.size() != ring.size() || (!f.order.empty() && f.order.size() != ring.size()))
      throw std::invalid_argument("gather_loop_patch: the features of vertex " + std::to_string(v) +
                                  " do not match its ring");
  };
  const WallOracle walls = [&](int k, std::int32_t v, const std::vector<std::int32_t>& ring,
                               std::vector<char>& wall) {
    LoopVertexFeatures& f = at[static_cast<std::size_t>(k)];
    ask(v, ring, f);
    for (std::size_t i = 0; i < ring.size(); ++i) wall[i] = loop::is_infinitely_sharp(f.edges[i]);
  };
  std::array<Fan, 3> fans;
  LoopPatch patch = gather_patch(corners, ring_of, &walls, &fans);
  // Where a sharp edge's half at its far end one level down depends on the far end's other
  // edges (Chaikin's averages), its ring and features are asked for.
  std::vector<std::int32_t> far_ring;
  LoopVertexFeatures far;
  std::vector<float> around;
  const auto half_at = [&](std::int32_t x, std::int32_t from, float s) {
    if (loop::is_infinitely_sharp(s) || features.method == CreaseMethod::uniform)
      return loop::decrement_sharpness(s);
    ring_of(x, far_ring);
    ask(x, far_ring, far);
    around.clear();
    std::vector<std::size_t> order(far_ring.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    if (!far.order.empty())
      std::stable_sort(order.begin(), order.end(),
                       [&far](std::size_t i, std::size_t j) { return far.order[i] < far.order[j]; });
    bool found = false;
    for (const std::size_t i : order) {
      around.push_back(far.edges[i]);
      found = found || far_ring[i] == from;
    }
    if (!found) throw std::invalid_argument("gather_loop_patch: the rings of two neighbours disagree");
    return loop::child_sharpness(features.method, s, around.data(), static_cast<int>(around.size()));
  };
  auto creases = std::make_shared<LoopCreases>();
  creases->method = features.method;
  bool any = false;
  for (int k = 0; k < 3; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    const Fan& fan = fans[ku];
    const LoopVertexFeatures& f = at[ku];
    LoopCreases::Corner& corner = creases->corner[ku];
    corner.sharpness = std::min(f.sharpness, kInfiniteSharpness);
    corner.sector = patch.open[ku];
    for (const int i : fan.sector) corner.ring.push_back(fan.vertex[static_cast<std::size_t>(i)]);
    // Its sharp edges in the order the mesh sums them (the order of their sharp base edges).
    std::vector<std::size_t> sharp;
    for (std::size_t i = 0; i < fan.ring.size(); ++i)
      if (fan.boundary(i) || f.edges[static_cast<std::size_t>(fan.raw[i])] > 0.0f) sharp.push_back(i);
    if (!f.order.empty())
      std::stable_sort(sharp.begin(), sharp.end(), [&](std::size_t i, std::size_t j) {
        return f.order[static_cast<std::size_t>(fan.raw[i])] < f.order[static_cast<std::size_t>(fan.raw[j])];
      });
    for (const std::size_t i : sharp) {
      LoopCreases::Spoke spoke;
      spoke.boundary = fan.boundary(i);
      spoke.sharpness = spoke.boundary
                            ? kInfiniteSharpness
                            : std::min(f.edges[static_cast<std::size_t>(fan.raw[i])], kInfiniteSharpness);
      spoke.to = fan.vertex[i];
      if (spoke.to >= 0) spoke.far_child = half_at(fan.ring[i], corners[ku], spoke.sharpness);
      corner.spokes.push_back(spoke);
      any = any || !spoke.boundary;
    }
    any = any || corner.sharpness > 0.0f;
  }
  if (any) patch.creases = std::move(creases);
  return patch;
}

namespace {

// The limit at a dart, where the rules have settled: the fixed point of its ring's
// subdivision (the smooth vertex rule, the midpoint on the sharp edge), found as the left
// eigenvector of eigenvalue 1 of the ring's subdivision matrix.
Eigen::VectorXd dart_limit(const LoopCreases& creases, int k, Eigen::Index size) {
  const LoopCreases::Corner& corner = creases.corner[static_cast<std::size_t>(k)];
  const std::size_t n = corner.ring.size();
  std::vector<float> s(n, 0.0f);
  for (const LoopCreases::Spoke& spoke : corner.spokes)
    for (std::size_t i = 0; i < n; ++i)
      if (corner.ring[i] == spoke.to) s[i] = spoke.sharpness;
  const Eigen::Index m = static_cast<Eigen::Index>(n) + 1;  // the centre, then the ring
  Eigen::MatrixXd step = Eigen::MatrixXd::Zero(m, m);
  const double a = loop::even_neighbor_weight(static_cast<int>(n));
  step(0, 0) = 1.0 - static_cast<double>(n) * a;
  for (Eigen::Index i = 1; i < m; ++i) step(0, i) = a;
  for (std::size_t i = 0; i < n; ++i) {
    const loop::OddMask mask = loop::odd_mask(s[i], true);  // settled: a sharp edge's halves stay sharp
    const Eigen::Index r = static_cast<Eigen::Index>(i) + 1;
    step(r, 0) += mask.end, step(r, r) += mask.end;
    step(r, static_cast<Eigen::Index>((i + n - 1) % n) + 1) += mask.opposite;
    step(r, static_cast<Eigen::Index>((i + 1) % n) + 1) += mask.opposite;
  }
  // lᵀ S = lᵀ: the rows of Sᵀ - I sum to zero, so one of them makes room for Σ l = 1.
  Eigen::MatrixXd system = step.transpose() - Eigen::MatrixXd::Identity(m, m);
  system.row(0).setOnes();
  const Eigen::VectorXd l = system.fullPivLu().solve(Eigen::VectorXd::Unit(m, 0));
  Eigen::VectorXd w = Eigen::VectorXd::Zero(size);
  w(k) += l(0);
  for (std::size_t i = 0; i < n; ++i) w(corner.ring[i]) += l(static_cast<Eigen::Index>(i) + 1);
  return w;
}

}  // namespace

Eigen::VectorXd loop_corner_limit(const LoopPatch& patch, int corner) {
  const Eigen::Index size = static_cast<Eigen::Index>(patch.vertices.size());
  if (patch.creases) {
    const LoopCreases& creases = *patch.creases;
    // Rules that change over the next levels: subdivided towards the corner (child `corner`
    // keeps it as its corner `corner`) until they settle.
    if (creases.transient(corner)) {
      const Child child = subdivide(patch, corner);
      return child.from_parent.transpose() * loop_corner_limit(child.patch, corner);
    }
    const LoopCreases::Corner& c = creases.corner[static_cast<std::size_t>(corner)];
    Eigen::VectorXd w = Eigen::VectorXd::Zero(size);
    switch (loop::vertex_rule(c.sharpness, static_cast<int>(c.spokes.size()))) {
      case VertexRule::corner:
        w(corner) = 1;
        return w;
      case VertexRule::crease:  // the crease is a cubic B-spline of its vertices
        w(corner) = loop::kBoundaryLimitSelf;
        for (const LoopCreases::Spoke& spoke : c.spokes) {
          if (spoke.to < 0)
            throw std::logic_error("loop_corner_limit: a crease's edge lies outside its sector");
          w(spoke.to) += loop::kBoundaryLimitNeighbor;
        }
        return w;
      case VertexRule::dart:
        return dart_limit(creases, corner, size);
      case VertexRule::smooth: {
        const int k = static_cast<int>(c.ring.size());
        const double b = loop::limit_neighbor_weight(k);
        w(corner) = 1.0 - k * b;
        for (const std::int32_t x : c.ring) w(x) += b;
        return w;
      }
    }
  }
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

std::shared_ptr<const LoopQuadrature> loop_quadrature(const LoopPatch& patch,
                                                      const LoopQuadratureOptions& options) {
  if (options.points_per_direction < 1 || options.points_per_direction > 20 ||
      options.extraordinary_depth < 0 || options.extraordinary_depth > 20)
    throw std::invalid_argument("loop_quadrature: points per direction in [1, 20], depth in [0, 20]");
  using Key = std::pair<std::array<int, 2>, PatchKey>;
  // The rules of a closed mesh refined once are few (one extraordinary corner each, a handful
  // of valences); an irregular base mesh has one per distinct neighbourhood of its triangles
  // (the cow: about a hundred, 0.5 MB each). The cache is emptied when it passes 256 MB, so
  // that a long session with many meshes stays bounded; spaces keep the rules they use.
  static std::mutex mutex;
  static std::map<Key, std::shared_ptr<const LoopQuadrature>> cache;
  static std::size_t cached_bytes = 0;
  const Key key{{options.points_per_direction, options.extraordinary_depth}, patch_key(patch)};
  {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto it = cache.find(key);
    if (it != cache.end()) return it->second;
  }
  RuleBuilder builder{options, {}, {}, {}, {}, {}, {}};
  gauss_legendre(options.points_per_direction, builder.gauss_x, builder.gauss_w);
  LoopPatch local = patch;
  for (std::size_t i = 0; i < local.vertices.size(); ++i) local.vertices[i] = static_cast<std::int32_t>(i);
  const Eigen::Index n = static_cast<Eigen::Index>(local.vertices.size());
  std::vector<int> path;
  builder.build(local, Eigen::MatrixXd::Identity(n, n), 1.0, path);

  auto rule = std::make_shared<LoopQuadrature>();
  rule->patch = local;
  const Eigen::Index q = static_cast<Eigen::Index>(builder.basis.size());
  rule->u = std::move(builder.u);
  rule->v = std::move(builder.v);
  rule->weight = std::move(builder.weight);
  for (Eigen::MatrixXd* m : {&rule->value, &rule->du, &rule->dv, &rule->duu, &rule->duv, &rule->dvv})
    m->resize(n, q);
  for (Eigen::Index p = 0; p < q; ++p) {
    const LoopBasisAt& at = builder.basis[static_cast<std::size_t>(p)];
    rule->value.col(p) = at.value;
    rule->du.col(p) = at.du;
    rule->dv.col(p) = at.dv;
    rule->duu.col(p) = at.duu;
    rule->duv.col(p) = at.duv;
    rule->dvv.col(p) = at.dvv;
  }
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
  LoopPatch local = parent;
  for (std::size_t i = 0; i < local.vertices.size(); ++i) local.vertices[i] = static_cast<std::int32_t>(i);
  Child c = subdivide(local, child);
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

LoopFeatures tagged_features(const SharpFeatures& features) {
  // Edges by their ends (a < b): sharpness and rank, the order of the tags (the mesh's rails).
  auto edges =
      std::make_shared<std::map<std::pair<std::int32_t, std::int32_t>, std::pair<float, std::int32_t>>>();
  for (std::size_t i = 0; i < features.edges.size(); ++i) {
    const SharpEdge& e = features.edges[i];
    (*edges)[std::minmax(e.a, e.b)] = {e.sharpness, static_cast<std::int32_t>(i)};
  }
  auto vertices = std::make_shared<std::map<std::int32_t, float>>();
  for (const SharpVertex& v : features.vertices) (*vertices)[v.v] = v.sharpness;
  LoopFeatures out;
  out.method = features.method;
  out.at = [edges, vertices](std::int32_t v, const std::vector<std::int32_t>& ring, LoopVertexFeatures& f) {
    const auto own = vertices->find(v);
    f.sharpness = own == vertices->end() ? 0.0f : own->second;
    f.edges.assign(ring.size(), 0.0f);
    f.order.assign(ring.size(), std::numeric_limits<std::int32_t>::max());
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const auto it = edges->find(std::minmax(v, ring[i]));
      if (it == edges->end()) continue;
      f.edges[i] = it->second.first;
      f.order[i] = it->second.second;
    }
  };
  return out;
}

}  // namespace rgbmesh::fem
