// Loop's limit functions on meshes with sharp features (see loop_basis.hpp): the rules of
// creases, darts, corners and semi-sharp edges and vertices, which loop_basis.cpp consults
// through loop_patch.hpp wherever a patch has any. Kept apart from the plain subdivision and
// evaluation because most patches have no features, and the rules are a subject of their own.
//
// Sharp features change two things. A patch's fans are cut where infinitely sharp edges
// ("walls") bound a sector of them, so the patch holds only the side of each crease its
// triangle is on. And its corners' rules are those of loop_rules.hpp, which need the
// sharpness of every edge at a corner one level down (LoopCreases: per corner its sharp edges,
// and of each the half at its far end, which Chaikin's averages take from the far end's edges):
// a step computes the child's from the parent's, so a patch carries what all its descendants
// need.

#include <Eigen/LU>
#include <algorithm>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include "loop_patch.hpp"
#include "rgbmesh/fem/loop_basis.hpp"
#include "rgbmesh/loop_rules.hpp"

namespace rgbmesh::fem {

namespace {

using detail::CornerStep;
using detail::Fan;
using detail::gather_patch;
using detail::MatrixRow;
using detail::WallOracle;

// ---------------------------------------------------------------------------------------------
// The rules at a patch's corners on a mesh with sharp features (loop_rules.hpp), one step at a
// time, as the RGB mesh's vertices evolve (rgbmesh/src/creases.cpp).

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

std::uint32_t bits(float x) {
  std::uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Gathering: fans cut at walls, and the features the corners' rules need.

int detail::cut_fan(const std::vector<std::int32_t>& raw, const std::vector<char>* raw_wall, bool closed,
                    std::size_t start, bool forward, Fan& fan, std::vector<char>& wall,
                    std::vector<std::int32_t>& sector_ring) {
  const std::size_t m = raw.size();
  const auto entry = [&](std::size_t i) { return forward ? (start + i) % m : (start + m - i) % m; };
  int gap = -1;
  std::vector<int>& order = fan.raw;
  order.resize(m);
  fan.ring.resize(m);
  for (std::size_t i = 0; i < m; ++i) {
    order[i] = static_cast<int>(entry(i));
    fan.ring[i] = raw[entry(i)];
  }
  wall.resize(m);
  int count = 0;
  for (std::size_t i = 0; i < m; ++i) {
    wall[i] = fan.boundary(i) || (raw_wall != nullptr && (*raw_wall)[static_cast<std::size_t>(order[i])]);
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
    gap = static_cast<int>(last);
  }
  if (fan.sector.size() == m) {
    sector_ring = fan.ring;
  } else {
    sector_ring.reserve(fan.sector.size());
    for (const int i : fan.sector) sector_ring.push_back(fan.ring[static_cast<std::size_t>(i)]);
  }
  return gap;
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

// ---------------------------------------------------------------------------------------------
// One step of subdivision with the crease rules.

detail::CreaseStep::CreaseStep(const LoopCreases& creases) : creases_(creases) {
  for (int k = 0; k < 3; ++k) steps_[static_cast<std::size_t>(k)] = corner_step(creases_, k);
}

LoopPatch detail::CreaseStep::gather_child(const std::array<int, 3>& corners, const RingOracle& fine_ring,
                                           int n, const std::vector<PatchEdge>& edges,
                                           const std::map<std::pair<int, int>, int>& midpoint) const {
  // The walls at the child's corners: the halves of a parent corner's walls, and the two
  // halves of a wall that a midpoint splits.
  const WallOracle walls = [&](int, std::int32_t v, const std::vector<std::int32_t>& ring,
                               std::vector<char>& wall) {
    if (v < n) {
      if (v > 2) throw std::logic_error("subdivide: a child's corner is no parent corner");
      for (std::size_t i = 0; i < ring.size(); ++i) {
        if (ring[i] < n) continue;
        const PatchEdge& e = edges[static_cast<std::size_t>(ring[i] - n)];
        const int s = spoke_to(creases_, v, e.a == v ? e.b : e.a);
        wall[i] =
            s >= 0 &&
            loop::is_infinitely_sharp(
                creases_.corner[static_cast<std::size_t>(v)].spokes[static_cast<std::size_t>(s)].sharpness);
      }
      return;
    }
    const PatchEdge& e = edges[static_cast<std::size_t>(v - n)];
    if (!loop::is_infinitely_sharp(edge_sharpness(creases_, steps_, e.a, e.b).s)) return;
    for (std::size_t i = 0; i < ring.size(); ++i) wall[i] = ring[i] == e.a || ring[i] == e.b;
  };
  std::array<Fan, 3> fans;
  LoopPatch patch = gather_patch({corners[0], corners[1], corners[2]}, fine_ring, &walls, &fans);
  std::vector<std::array<int, 2>> ends;
  for (const PatchEdge& e : edges) ends.push_back({e.a, e.b});
  patch.creases = child_creases(creases_, steps_, n, ends, midpoint, corners, fans);
  return patch;
}

// The vertex rule of corner k for one step: blended with the next level's rule where a crease
// or corner turns into another rule (transition_weight), as OpenSubdiv and the mesh do.
void detail::CreaseStep::add_even_row(int k, MatrixRow row) const {
  const CornerStep& step = steps_[static_cast<std::size_t>(k)];
  const LoopCreases::Corner& corner = creases_.corner[static_cast<std::size_t>(k)];
  const bool blends =
      (step.rule == VertexRule::crease || step.rule == VertexRule::corner) && step.next != step.rule;
  if (!blends) {
    add_even_mask(corner, k, step.rule, step.s, 1.0, row);
    return;
  }
  const double w = loop::transition_weight(creases_.method, step.vs, step.vt, static_cast<int>(step.s.size()),
                                           step.s.data(), step.t.data());
  add_even_mask(corner, k, step.rule, step.s, w, row);
  add_even_mask(corner, k, step.next, step.t, 1.0 - w, row);
}

loop::OddMask detail::CreaseStep::odd_mask(int a, int b) const {
  const EdgeSharpness es = edge_sharpness(creases_, steps_, a, b);
  return loop::odd_mask(es.s, es.half_a > 0.0f && es.half_b > 0.0f);
}

// ---------------------------------------------------------------------------------------------
// Limits and keys.

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

Eigen::VectorXd detail::crease_corner_limit(const LoopPatch& patch, int corner) {
  const Eigen::Index size = static_cast<Eigen::Index>(patch.vertices.size());
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
  throw std::logic_error("loop_corner_limit: a corner rule that is none of Loop's");
}

std::vector<std::uint32_t> detail::crease_key(const LoopCreases& c) {
  std::vector<std::uint32_t> k;
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
  return k;
}

}  // namespace rgbmesh::fem
