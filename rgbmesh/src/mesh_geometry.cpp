// RGB subdivision geometry (section VI): Loop control points of odd vertices from their
// stencils, limit positions, and control points of even vertices by the multi-step rule.
//
// A vertex v inserted at level l stores p^l(v) and, once known, p_inf(v). Its control point
// at level l + k is g^k p^l(v) + (1 - g^k) p_inf(v) (Eq. 7, 9). The limit position needs the
// level-l control points of v's Loop neighbours at level l (Eq. 6, 8): for a boundary vertex
// its two boundary neighbours, which are its parents; for an interior vertex its six
// neighbours (the two parents and four vertices of level l), which exist in the mesh exactly
// when no triangle incident at v is coarser than v. Since p_inf(v) depends only on the base
// mesh, it is computed once, when first needed, and cached; removals never invalidate it.
// (The paper accumulates it from contributions as neighbours arrive, VI-B; computing it from
// the complete ring when first needed gives the same value without per-insertion work.)

#include <algorithm>
#include <array>
#include <exception>
#include <limits>
#include <vector>

#include "rgbmesh/detail/parallel_for.hpp"
#include "rgbmesh/loop_rules.hpp"
#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

void RgbMesh::store_limit(VertexHandle v, const Vec3& p) const {
  std::int32_t& index = v_limit_index_[v.idx];
  if (index < 0) {
    if (limits_free_head_ >= 0) {
      index = limits_free_head_;
      limits_free_head_ = static_cast<std::int32_t>(limits_[static_cast<std::size_t>(index)].x);
      --limits_free_count_;
    } else {
      // The table grows before anything changes.
      if (limits_.size() == limits_.capacity()) limits_.reserve(std::max<std::size_t>(64, 2 * limits_.size()));
      limits_.emplace_back();
      index = static_cast<std::int32_t>(limits_.size() - 1);
    }
  }
  limits_[index] = p;
}

void RgbMesh::reserve_limits(std::size_t more) const {
  const std::size_t reused = std::min(more, limits_free_count_);
  const std::size_t needed = limits_.size() + (more - reused);
  if (needed > limits_.capacity()) limits_.reserve(needed);
}

void RgbMesh::release_limit(VertexHandle v) {
  std::int32_t& index = v_limit_index_[v.idx];
  if (index >= 0) {
    limits_[static_cast<std::size_t>(index)] = Vec3{static_cast<double>(limits_free_head_), 0.0, 0.0};
    limits_free_head_ = index;
    ++limits_free_count_;
  }
  index = -1;
}

void RgbMesh::init_base_geometry() {
  const std::size_t n = v_edge_.size();
  v_limit_index_.assign(n, -1);
  limits_.clear();
  limits_free_head_ = -1;
  limits_free_count_ = 0;
  limits_.reserve(n);  // every base vertex has its limit
  v_flags_.assign(n, 0);
  base_eigenvalue_.assign(n, 0.25);
  VertexStar s;
  for (std::size_t i = 0; i < n; ++i) {
    const VertexHandle v(static_cast<std::int32_t>(i));
    star(v, s);
    const Vec3& p = v_control_[i];
    if (s.boundary) {
      // Crease rule: only the two boundary neighbours count (Eq. 8).
      v_flags_[i] |= kBoundaryFlag;
      store_limit(v, loop::kBoundaryLimitSelf * p +
                         loop::kBoundaryLimitNeighbor *
                             (v_control_[s.neighbors.front().idx] + v_control_[s.neighbors.back().idx]));
      continue;
    }
    const int valence = static_cast<int>(s.neighbors.size());
    Vec3 sum;
    for (VertexHandle w : s.neighbors) sum += v_control_[w.idx];
    const double b = loop::limit_neighbor_weight(valence);
    store_limit(v, (1.0 - valence * b) * p + b * sum);
    base_eigenvalue_[i] = loop::subdominant_eigenvalue(valence);
  }
}

int RgbMesh::shown_level(VertexHandle v) const {
  expect_alive(v, "shown_level");
  int k = kMaxLevel + 1;
  visit_edges(v, [&](EdgeHandle e) {
    if (!is_red(e)) k = std::min(k, level(e));
    return true;
  });
  return k;
}

Vec3 RgbMesh::control_point(VertexHandle v, int k) const {
  expect_alive(v, "control_point");
  const int steps = k - level(v);
  if (steps <= 0) {
    if (steps < 0)
      fail("control_point", describe(v) + " has no control point at level " + std::to_string(k));
    return v_control_[v.idx];
  }
  if (!try_limit(v))
    fail("control_point", describe(v) + " has an incomplete Loop ring at its level (call complete_limit or "
                                        "compute_limits first)");
  return known_control_point(v, k);
}

bool RgbMesh::has_limit(VertexHandle v) const {
  expect_alive(v, "has_limit");
  return try_limit(v);
}

Vec3 RgbMesh::level_point(VertexHandle v, int l) const {
  expect_alive(v, "level_point");
  if (l <= level(v)) return v_control_[v.idx];
  if (try_limit(v)) return known_control_point(v, l);
  return control_point(v);
}

Vec3 RgbMesh::limit_position(VertexHandle v) const {
  expect_alive(v, "limit_position");
  if (!try_limit(v))
    fail("limit_position", describe(v) + " has an incomplete Loop ring at its level (call complete_limit or "
                                         "compute_limits first)");
  return limits_[v_limit_index_[v.idx]];
}

template <class Known>
bool RgbMesh::limit_from_ring(VertexHandle v, Vec3& limit, Known known) const {
  const int l = level(v);
  const auto [pa, pb] = v_parents_[v.idx];
  if (v_flags_[v.idx] & (kBoundaryFlag | kCreaseFlag)) {
    // The boundary neighbours of a boundary vertex at its own level are its parents (Eq. 8);
    // so are the crease neighbours of a vertex on an infinitely sharp edge.
    limit = loop::kBoundaryLimitSelf * v_control_[v.idx] +
            loop::kBoundaryLimitNeighbor * (known_control_point(pa, l) + known_control_point(pb, l));
    return true;
  }
  // Interior: the six Loop neighbours at level l. Each green edge at v is a Loop edge of
  // level l or a piece of one (its far end then descends from v by repeated halving:
  // follow parents back to level l). A red edge coarser than v means a triangle coarser
  // than v, hence a missing neighbour.
  std::array<Vec3, 6> ring;
  int count = 0;
  bool complete = true;
  visit_edges(v, [&](EdgeHandle e) {
    if (is_red(e)) {
      if (level(e) < l) complete = false;
      return complete;
    }
    VertexHandle w = other_vertex(e, v);
    while (level(w) > l) {
      const auto& p = v_parents_[w.idx];
      w = (p[0] == v) ? p[1] : p[0];
    }
    if ((level(w) < l && !known(w)) || count == 6) {
      complete = false;
      return false;
    }
    ring[count++] = known_control_point(w, l);
    return true;
  });
  if (!complete || count != 6) return false;
  // Summed in an order of the points themselves, not of the edges around v (which start
  // wherever v's first edge is): the limit is then the same to the last bit in every copy of
  // the mesh, however its vertices were numbered or inserted (issue 24).
  std::sort(ring.begin(), ring.end(), [](const Vec3& a, const Vec3& b) {
    return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : a.z < b.z);
  });
  Vec3 sum;
  for (const Vec3& p : ring) sum += p;
  limit = 0.5 * v_control_[v.idx] + (1.0 / 12.0) * sum;
  return true;
}

bool RgbMesh::try_limit(VertexHandle v) const {
  if (limit_known(v)) return true;
  const auto [pa, pb] = v_parents_[v.idx];
  // Both rules use the parents at level l, which are coarser: their limits come first, and
  // those of the coarser ring vertices too (recursively).
  if (!try_limit(pa) || !try_limit(pb)) return false;
  if (v_flags_[v.idx] & kTransientFlag) return transient_limit(v);
  Vec3 limit;
  if (!limit_from_ring(v, limit, [this](VertexHandle w) { return try_limit(w); })) return false;
  store_limit(v, limit);
  return true;
}

bool RgbMesh::ring_limit(VertexHandle v, Vec3& limit) const {
  // try_limit without its recursion and without storing, so that threads may share the mesh.
  const auto [pa, pb] = v_parents_[v.idx];
  if (!pa.valid() || !pb.valid() || !limit_known(pa) || !limit_known(pb)) return false;
  if (v_flags_[v.idx] & kTransientFlag) return false;  // its history is stored by try_limit
  return limit_from_ring(v, limit, [this](VertexHandle w) { return limit_known(w); });
}

void RgbMesh::store_ring_limits(int below_level) {
  // A vertex's limit needs only the limits of coarser vertices (its parents and the coarser
  // ones of its ring), so each level's can be computed at once, in parallel, once the coarser
  // levels' are stored. The mesh does not change meanwhile; results are stored in vertex
  // order by this thread. A vertex left out (incomplete ring) is left to compute_limits.
  std::vector<std::vector<VertexHandle>> by_level;
  for (VertexHandle v : vertices()) {
    if (limit_known(v) || v_level_[v.idx] == 0 || v_level_[v.idx] >= below_level) continue;
    const std::size_t l = v_level_[v.idx];
    if (by_level.size() <= l) by_level.resize(l + 1);
    by_level[l].push_back(v);
  }
  std::size_t unknown = 0;
  for (const std::vector<VertexHandle>& level_vertices : by_level) unknown += level_vertices.size();
  reserve_limits(unknown);
  constexpr std::size_t kBlock = std::size_t{1} << 16;
  const std::size_t cores = detail::hardware_threads();
  std::vector<Vec3> value;
  std::vector<char> known;
  for (const std::vector<VertexHandle>& level_vertices : by_level) {
    for (std::size_t begin = 0; begin < level_vertices.size(); begin += kBlock) {
      const std::size_t n = std::min(kBlock, level_vertices.size() - begin);
      value.resize(n);
      known.assign(n, 0);
      // ring_limit reads the mesh only and throws nothing for live vertices.
      detail::parallel_for(n, 4096, cores, [&](std::size_t, std::size_t i) {
        known[i] = ring_limit(level_vertices[begin + i], value[i]) ? 1 : 0;
      });
      for (std::size_t i = 0; i < n; ++i)
        if (known[i]) store_limit(level_vertices[begin + i], value[i]);
    }
  }
}

void RgbMesh::raise_star(VertexHandle v) {
  const int l = level(v);
  VertexStar s;
  std::vector<EdgeHandle> raising;
  for (;;) {
    star(v, s);
    TriangleHandle coarse;
    for (TriangleHandle t : s.triangles) {
      if (level(t) < l) coarse = t;
    }
    if (!coarse.valid()) return;
    raising_edges(coarse, raising);
    if (!raising.empty()) {
      split_edge(raising.front());
      continue;
    }
    // A blue pair on a red edge (left unstable by hand-applied operators): the BB-swap raises it.
    EdgeHandle red_edge;
    for (EdgeHandle f : t_edge_[coarse.idx]) {
      if (is_red(f)) red_edge = f;
    }
    if (!red_edge.valid()) fail("complete_limit", "internal error: no operation raises a triangle at " + describe(v));
    swap_bb(red_edge);
  }
}

void RgbMesh::complete_limit(VertexHandle v) {
  v = checked(v, "complete_limit");
  if (limit_known(v)) return;
  const auto [pa, pb] = v_parents_[v.idx];
  complete_limit(pa);
  complete_limit(pb);
  if (!(v_flags_[v.idx] & (kBoundaryFlag | kCreaseFlag))) raise_star(v);
  if (!try_limit(v)) fail("complete_limit", "internal error: the Loop ring of " + describe(v) + " is incomplete");
}

VertexHandle RgbMesh::stencil_apex(TriangleHandle t, EdgeHandle e) const {
  const VertexHandle o = opposite_vertex(t, e);
  if (color(t) != Color::red) return o;
  // A red triangle is half of its parent triangle; e is the parent's edge and o the midpoint
  // of another parent edge, whose far end is the apex the Loop stencil uses (VI-C, Fig. 12).
  const auto& p = v_parents_[o.idx];
  const auto& ev = e_vert_[e.idx];
  return (p[0] == ev[0] || p[0] == ev[1]) ? p[1] : p[0];
}

std::array<VertexHandle, 4> RgbMesh::loop_stencil(EdgeHandle e) const {
  // Only a refinable edge has both Loop triangles of its level in the mesh.
  if (!alive(e) || !is_refinable(e)) fail("loop_stencil", describe(e) + " is not refinable");
  return stencil(e);
}

std::array<VertexHandle, 4> RgbMesh::stencil(EdgeHandle e) const {
  const auto& ev = e_vert_[e.idx];
  const auto& et = e_tri_[e.idx];
  return {ev[0], ev[1], stencil_apex(et[0], e), et[1].valid() ? stencil_apex(et[1], e) : VertexHandle()};
}

bool RgbMesh::prepare_stencil(const std::array<VertexHandle, 4>& st, int l) {
  bool completed = false;
  for (VertexHandle s : st) {
    if (s.valid() && level(s) < l && !try_limit(s)) {
      complete_limit(s);
      completed = true;
    }
  }
  return completed;
}

Vec3 RgbMesh::odd_control_point(EdgeHandle e) const {
  const int l = level(e);
  auto st = loop_stencil(e);
  const loop::OddMask mask = odd_mask(e);
  if (mask.opposite == 0.0) st[2] = st[3] = VertexHandle();  // not used
  for (VertexHandle s : st) {
    if (s.valid() && level(s) < l && !try_limit(s))
      fail("odd_control_point", "the limit position of stencil vertex " + describe(s) + " is not known");
  }
  return stencil_point(st, l, odd_mask(e));
}

Vec3 RgbMesh::stencil_point(const std::array<VertexHandle, 4>& st, int l) const {
  const Vec3 ends = known_control_point(st[0], l) + known_control_point(st[1], l);
  if (!st[3].valid()) return 0.5 * ends;  // boundary edge (Eq. 2)
  return 0.375 * ends + 0.125 * (known_control_point(st[2], l) + known_control_point(st[3], l));  // Eq. 1
}

Vec3 RgbMesh::stencil_point(const std::array<VertexHandle, 4>& st, int l, const loop::OddMask& mask) const {
  const Vec3 ends = known_control_point(st[0], l) + known_control_point(st[1], l);
  // Boundary edges (Eq. 2) and creases: the midpoint; else Eq. 1, or a semi-sharp blend.
  if (mask.opposite == 0.0) return mask.end * ends;
  return mask.end * ends + mask.opposite * (known_control_point(st[2], l) + known_control_point(st[3], l));
}

std::vector<Vec3> RgbMesh::split_limits(const std::vector<EdgeHandle>& edges) {
  compute_limits();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<Vec3> out(edges.size(), Vec3(nan, nan, nan));
  // The edges by their ends: splits and swaps change edge handles, never vertex handles.
  std::vector<std::array<VertexHandle, 2>> ends(edges.size());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const EdgeHandle e = checked(edges[i], "split_limits");
    if (!is_red(e) && level(e) < kMaxLevel) ends[i] = e_vert_[e.idx];
  }
  // The vertex that splits the edge a-b, if there is one: a neighbour of a with parents a, b.
  const auto midpoint = [this](VertexHandle a, VertexHandle b) {
    VertexHandle found;
    visit_edges(a, [&](EdgeHandle f) {
      const VertexHandle w = other_vertex(f, a);
      const auto& p = v_parents_[w.idx];
      if ((p[0] == a && p[1] == b) || (p[0] == b && p[1] == a)) found = w;
      return !found.valid();
    });
    return found;
  };
  const OperationCounters counters = counters_;
  std::vector<JournalEntry> journal;
  journal_ = &journal;
  std::exception_ptr error;
  try {
    std::vector<VertexHandle> inserted(edges.size());
    for (std::size_t i = 0; i < edges.size(); ++i) {
      const auto [a, b] = ends[i];
      if (!a.valid()) continue;
      VertexHandle m = midpoint(a, b);
      if (!m.valid()) {
        // Not split by an earlier split: the edge is still there, green (only its own split
        // removes a green edge).
        const EdgeHandle e = find_edge(a, b);
        if (e.valid() && !is_red(e)) m = split_edge(e);
      }
      inserted[i] = m;
    }
    for (std::size_t i = 0; i < edges.size(); ++i) {
      if (!inserted[i].valid()) continue;
      complete_limit(inserted[i]);
      out[i] = limit_position(inserted[i]);
    }
  } catch (...) {
    error = std::current_exception();
  }
  journal_ = nullptr;
  const std::exception_ptr observer_error = rollback(journal);
  counters_ = counters;
  rethrow_if(error);
  rethrow_if(observer_error);
  return out;
}

std::size_t RgbMesh::compute_limits() {
  store_ring_limits();
  std::vector<VertexHandle> missing;
  for (VertexHandle v : vertices()) {
    if (!try_limit(v)) missing.push_back(v);
  }
  if (missing.empty()) return 0;
  // Complete the rings, then undo every operation in reverse order. Undoing (rather than
  // removing the helper vertices in any order) restores the very same triangulation: RGB
  // triangulations with the same vertices may differ by RB-swaps.
  // The strong guarantee: whatever is thrown (an observer's exception, std::bad_alloc), the
  // journal undoes what was done before it propagates. Undoing cannot fail: flips and
  // unbisections allocate nothing, and the observers' exceptions wait until the end.
  const OperationCounters counters = counters_;
  std::vector<JournalEntry> journal;
  journal_ = &journal;
  std::exception_ptr error;
  try {
    for (VertexHandle v : missing) complete_limit(v);
  } catch (...) {
    error = std::current_exception();
  }
  journal_ = nullptr;
  const std::size_t helpers = counters_.splits - counters.splits;
  const std::exception_ptr observer_error = rollback(journal);
  counters_ = counters;
  rethrow_if(error);
  rethrow_if(observer_error);
  return helpers;
}

std::exception_ptr RgbMesh::rollback(const std::vector<JournalEntry>& journal) {
  std::exception_ptr first;
  for (auto it = journal.rbegin(); it != journal.rend(); ++it) {
    if (it->kind == JournalEntry::flip) {
      flip(EdgeHandle(it->handle), it->info_before);
    } else {
      const VertexHandle v = stamped(VertexHandle(it->handle));
      const std::exception_ptr e = notify_removing(v);
      if (!first) first = e;
      unbisect(v);
    }
  }
  return first;
}

}  // namespace rgbmesh
