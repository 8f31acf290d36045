// Sharp features on the RGB mesh: where a vertex or edge lies along the sharp base edges
// ("rails"), the rules that follows from it, and the control points of vertices whose rules
// change over the levels (creases.hpp has the table and the evolution; loop_rules.hpp the rules).
//
// A vertex inserted on a piece of a sharp base edge lies on that base edge for good; its
// position there (odd, at its level) and the base edge are all that is stored. The sharpness
// of any Loop edge at any level follows from its ends' positions, so splits, merges, swaps,
// rollbacks and restored states need nothing else.

#include <algorithm>
#include <cassert>
#include <new>
#include <string>

#include "creases.hpp"
#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

const SharpFeatures& RgbMesh::sharp_features() const {
  static const SharpFeatures none;
  return creases_ ? creases_->features() : none;
}

std::int64_t RgbMesh::rail_position(VertexHandle x, std::int32_t r, int l) const {
  if (static_cast<std::size_t>(x.idx) < n_base_vertices_) {
    const detail::Rail& rail = creases_->rails()[static_cast<std::size_t>(r)];
    if (x.idx == rail.a) return 0;
    if (x.idx == rail.b) return std::int64_t{1} << l;
    return -1;
  }
  if (v_rail_[x.idx] != r) return -1;
  return static_cast<std::int64_t>(v_rail_position_[x.idx]) << (l - v_level_[x.idx]);
}

RgbMesh::RailPiece RgbMesh::rail_piece_of(VertexHandle a, VertexHandle b, int l) const {
  if (!creases_) return {};
  const bool a_base = static_cast<std::size_t>(a.idx) < n_base_vertices_;
  const bool b_base = static_cast<std::size_t>(b.idx) < n_base_vertices_;
  std::int32_t r;
  if (a_base && b_base) {
    r = creases_->rail_of(a.idx, b.idx);
  } else if (a_base) {
    r = v_rail_[b.idx];
  } else if (b_base) {
    r = v_rail_[a.idx];
  } else {
    r = v_rail_[a.idx] == v_rail_[b.idx] ? v_rail_[a.idx] : -1;
  }
  if (r < 0) return {};
  const std::int64_t pa = rail_position(a, r, l), pb = rail_position(b, r, l);
  // Two points of one base edge joined by a Loop edge of level l are neighbours along it.
  if (pa < 0 || pb < 0 || (pa - pb != 1 && pb - pa != 1)) return {};
  return {r, static_cast<std::uint64_t>(std::min(pa, pb))};
}

loop::OddMask RgbMesh::sharp_odd_mask(const RailPiece& rp, int l) const {
  const std::int32_t r = rp.rail;
  const std::uint64_t piece = rp.piece;
  const float s = creases_->segment(r, l, piece);
  if (s <= 0.0f) return {};
  // The new vertex is a crease when both halves stay sharp.
  const bool crease = creases_->segment(r, l + 1, 2 * piece) > 0.0f && creases_->segment(r, l + 1, 2 * piece + 1) > 0.0f;
  return loop::odd_mask(s, crease);
}

loop::OddMask RgbMesh::odd_mask(EdgeHandle e) const {
  e = checked(e, "odd_mask");
  if (is_red(e)) fail("odd_mask", describe(e) + " is red; only green edges split");
  const auto& ev = e_vert_[e.idx];
  return odd_mask(rail_piece(ev[0], ev[1], level(e)), level(e), is_boundary(e));
}

float RgbMesh::sharpness(EdgeHandle e) const {
  expect_alive(e, "sharpness");
  if (is_boundary(e)) return kInfiniteSharpness;
  if (is_red(e) || !creases_) return 0.0f;
  const auto& ev = e_vert_[e.idx];
  const RailPiece rp = rail_piece(ev[0], ev[1], level(e));
  return rp.rail < 0 ? 0.0f : creases_->segment(rp.rail, level(e), rp.piece);
}

float RgbMesh::vertex_sharpness(VertexHandle v, int k) const {
  expect_alive(v, "vertex_sharpness");
  if (!creases_ || static_cast<std::size_t>(v.idx) >= n_base_vertices_) return 0.0f;
  return creases_->vertex(v.idx, k);
}

VertexRule RgbMesh::vertex_rule(VertexHandle v, int k) const {
  expect_alive(v, "vertex_rule");
  if (k < level(v)) fail("vertex_rule", describe(v) + " has no rule at level " + std::to_string(k));
  int sharp = (v_flags_[v.idx] & kBoundaryFlag) ? 2 : 0;  // its two boundary edges
  if (creases_) {
    if (static_cast<std::size_t>(v.idx) < n_base_vertices_) {
      for (std::int32_t r : creases_->rails_at(v.idx)) {
        const detail::Rail& rail = creases_->rails()[static_cast<std::size_t>(r)];
        const std::uint64_t end = v.idx == rail.a ? 0 : (std::uint64_t{1} << k) - 1;
        sharp += creases_->segment(r, k, end) > 0.0f;
      }
    } else if (v_rail_[v.idx] >= 0) {
      const std::uint64_t at = static_cast<std::uint64_t>(v_rail_position_[v.idx]) << (k - level(v));
      sharp += creases_->segment(v_rail_[v.idx], k, at - 1) > 0.0f;
      sharp += creases_->segment(v_rail_[v.idx], k, at) > 0.0f;
    }
  }
  return loop::vertex_rule(vertex_sharpness(v, k), sharp);
}

void RgbMesh::place_on_rail(VertexHandle m, const RailPiece& rp, int l) {
  const std::int32_t r = rp.rail;
  const std::uint64_t piece = rp.piece;
  v_rail_[m.idx] = r;
  v_rail_position_[m.idx] = static_cast<std::uint32_t>(2 * piece + 1);
  const float h0 = creases_->segment(r, l + 1, 2 * piece), h1 = creases_->segment(r, l + 1, 2 * piece + 1);
  if (loop::is_infinitely_sharp(h0) && loop::is_infinitely_sharp(h1)) {
    v_flags_[m.idx] |= kCreaseFlag;
  } else if (loop::is_semi_sharp(h0) || loop::is_semi_sharp(h1)) {
    v_flags_[m.idx] |= kTransientFlag;
  }
}

Vec3 RgbMesh::history_point(VertexHandle v, int l) const {
  const VertexHistory& h = history_.find(v.idx)->second;
  const auto i = static_cast<std::size_t>(l - level(v));
  if (i < h.points.size()) return h.points[i];
  const std::size_t m = h.points.size() - 1;
  const double g = loop::eigenvalue_power(h.g, static_cast<int>(i - m));
  return g * h.points[m] + (1.0 - g) * limits_[v_limit_index_[v.idx]];
}

std::size_t RgbMesh::history_bytes() const {
  // A hash node (key, value, link, hash) per entry, the bucket array, and the points.
  std::size_t bytes = history_.bucket_count() * sizeof(void*);
  for (const auto& [slot, h] : history_)
    bytes += sizeof(slot) + sizeof(h) + 2 * sizeof(void*) + h.points.capacity() * sizeof(Vec3);
  return bytes;
}

template <class Known>
bool RgbMesh::ordered_ring(VertexHandle v, detail::Ring& ring, Known known) const {
  // As limit_from_ring gathers the ring, but in counter-clockwise order, which the rules of a
  // vertex with sharp edges need (its odd neighbours' stencils use their neighbours).
  const int l = level(v);
  std::array<VertexHandle, 6> around;
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
    around[count++] = w;
    return true;
  });
  if (!complete || count != 6) return false;
  ring.centre = v_control_[v.idx];
  ring.level = l;
  ring.base_vertex = -1;
  ring.open = false;
  ring.spokes.assign(6, {});
  const std::int32_t r = v_rail_[v.idx];
  const std::int64_t at = v_rail_position_[v.idx];
  const auto [pa, pb] = v_parents_[v.idx];
  int first = -1;
  for (int i = 0; i < 6; ++i) {
    detail::Spoke& sp = ring.spokes[static_cast<std::size_t>(i)];
    sp.point = known_control_point(around[i], l);
    if (around[i] != pa && around[i] != pb) continue;
    const std::int64_t p = rail_position(around[i], r, l);
    sp.rail = r;
    sp.piece = static_cast<std::uint64_t>(std::min(p, at));
    sp.vertex_first = at < p;
    // Start at the parent whose point comes first (the result must not depend on where the
    // mesh's edge list around v starts: issue 24).
    const auto less = [](const Vec3& x, const Vec3& y) {
      return x.x != y.x ? x.x < y.x : (x.y != y.y ? x.y < y.y : x.z < y.z);
    };
    if (first < 0 || less(sp.point, ring.spokes[static_cast<std::size_t>(first)].point)) first = i;
  }
  assert(first >= 0);
  std::rotate(ring.spokes.begin(), ring.spokes.begin() + first, ring.spokes.end());
  return true;
}

bool RgbMesh::transient_limit(VertexHandle v) const {
  detail::Ring ring;
  if (!ordered_ring(v, ring, [this](VertexHandle w) { return try_limit(w); })) return false;
  const detail::Evolution ev = detail::evolve(creases_.get(), ring, kMaxLevel);
  // The history first (it may throw, changing nothing), then the limit; the flag once both are in.
  history_[v.idx] = VertexHistory{ev.points, ev.g};
  try {
    store_limit(v, ev.limit);
  } catch (...) {
    history_.erase(v.idx);
    throw;
  }
  v_flags_[v.idx] |= kHistoryFlag;
  return true;
}

void RgbMesh::init_sharp_base_geometry() {
  VertexStar s;
  for (std::size_t i = 0; i < n_base_vertices_; ++i) {
    const auto vi = static_cast<std::int32_t>(i);
    if (creases_->rails_at(vi).empty() && creases_->vertex(vi, 0) <= 0.0f) continue;
    const VertexHandle v(vi);
    star(v, s);
    detail::Ring ring;
    ring.centre = v_control_[i];
    ring.base_vertex = vi;
    ring.open = s.boundary;
    for (std::size_t k = 0; k < s.neighbors.size(); ++k) {
      detail::Spoke sp;
      sp.point = v_control_[s.neighbors[k].idx];
      sp.boundary = is_boundary(s.edges[k]);
      sp.rail = creases_->rail_of(vi, s.neighbors[k].idx);
      if (sp.rail >= 0) sp.vertex_first = creases_->rails()[static_cast<std::size_t>(sp.rail)].a == vi;
      ring.spokes.push_back(sp);
    }
    const detail::Evolution ev = detail::evolve(creases_.get(), ring, kMaxLevel);
    store_limit(v, ev.limit);
    base_eigenvalue_[i] = ev.g;
    if (ev.points.size() > 1) {
      history_[vi] = VertexHistory{ev.points, ev.g};
      v_flags_[i] |= kHistoryFlag;
    }
  }
}

}  // namespace rgbmesh
