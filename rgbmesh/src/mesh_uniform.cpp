// One uniform level at once (RgbMesh::split_all_edges): the 1-to-4 split of every triangle of
// a uniform mesh, which is what split_edge on every edge gives (section V on a mesh that is
// all green: each split's forced splits and swaps cancel out level by level), written as
// passes over the arrays. Every pass writes only the slots that belong to its own edge,
// triangle or vertex, so each runs on every core, and the result does not depend on the number
// of threads.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <new>
#include <string>

#include "rgbmesh/detail/parallel_for.hpp"
#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

bool RgbMesh::is_uniform() const {
  if (v_free_ >= 0 || e_free_ >= 0 || t_free_ >= 0 || e_info_.empty()) return false;
  // Green edges of one level: the level byte without the red bit, all equal.
  const std::uint8_t first = e_info_.front();
  if (first & 0x80) return false;
  return std::all_of(e_info_.begin(), e_info_.end(), [first](std::uint8_t b) { return b == first; });
}

std::size_t RgbMesh::split_all_edges() {
  if (!is_uniform())
    fail("split_all_edges", "the mesh is not uniform (a red edge, two edge levels or free slots)");
  const int l = e_info_.front() & 0x7f;
  if (l + 1 > kMaxLevel) fail("split_all_edges", "level " + std::to_string(l + 1) + " is above kMaxLevel");

  // Odd control points need the level-l points of the stencils' coarser vertices: their limit
  // positions (Eq. 7, 9). Every ring is complete in a uniform mesh, so they are all computable.
  store_ring_limits(l);
  for (std::int32_t i = 0; i < vertex_slots(); ++i) {
    const VertexHandle v(i);
    if (v_level_[i] < l && !try_limit(v))
      fail("split_all_edges", "internal error: no limit position for " + describe(v));
  }

  const std::size_t nv = v_edge_.size(), ne = e_vert_.size(), nt = t_edge_.size();
  const std::size_t new_nv = nv + ne, new_ne = 2 * ne + 3 * nt, new_nt = 4 * nt;
  if (new_nv > static_cast<std::size_t>(INT32_MAX) || new_ne > static_cast<std::size_t>(INT32_MAX) ||
      new_nt > static_cast<std::size_t>(INT32_MAX))
    throw std::bad_alloc();
  // Room first (a throwing reserve changes nothing), then the properties (undone if one
  // throws); after that nothing can fail.
  reserve(new_nv, new_ne, new_nt);
  std::size_t grown = 0;
  try {
    for (; grown < vertex_properties_.size(); ++grown) vertex_properties_[grown]->resize(new_nv);
  } catch (...) {
    for (std::size_t i = 0; i < grown; ++i) vertex_properties_[i]->resize(nv);
    throw;
  }
  v_edge_.resize(new_nv);
  v_level_.resize(new_nv, static_cast<std::uint8_t>(l + 1));
  v_parents_.resize(new_nv);
  v_control_.resize(new_nv);
  v_limit_index_.resize(new_nv, -1);
  v_flags_.resize(new_nv, 0);
  if (creases_) {
    v_rail_.resize(new_nv, -1);
    v_rail_position_.resize(new_nv, 0);
  }
  e_vert_.resize(new_ne);
  e_tri_.resize(new_ne);
  e_info_.assign(new_ne, edge_info(false, l + 1));
  t_edge_.resize(new_nt);
  t_info_.assign(new_nt, static_cast<std::uint8_t>((static_cast<int>(Color::green) << 6) | (l + 1)));
#if RGBMESH_CHECKED_HANDLES
  v_generation_.resize(new_nv, 1);
  e_generation_.resize(new_ne, 1);
  t_generation_.resize(new_nt, 1);
#endif
  // Handles as the mesh hands them out (with their slots' generations in checked builds).
  const auto vertex = [this](std::size_t i) { return stamped(VertexHandle(static_cast<std::int32_t>(i))); };
  const auto edge = [this](std::size_t i) { return stamped(EdgeHandle(static_cast<std::int32_t>(i))); };
  const auto triangle = [this](std::size_t i) {
    return stamped(TriangleHandle(static_cast<std::int32_t>(i)));
  };
  const std::size_t cores = detail::hardware_threads();
  constexpr std::size_t kBlock = 8192;

  // 1. The new vertices, from the old mesh (read only): vertex nv + e splits edge e.
  detail::parallel_for(ne, kBlock, cores, [&](std::size_t, std::size_t e) {
    const std::size_t m = nv + e;
    const EdgeHandle h(static_cast<std::int32_t>(e));
    const auto [a, b] = e_vert_[e];
    const bool boundary = !e_tri_[e][1].valid();
    v_parents_[m] = e_vert_[e];
    v_flags_[m] = boundary ? kBoundaryFlag : 0;
    if (!creases_) {
      v_control_[m] = stencil_point(stencil(h), l);
    } else {
      const RailPiece rp = rail_piece(a, b, l);
      v_control_[m] = stencil_point(stencil(h), l, odd_mask(rp, l, boundary));
      if (rp.rail >= 0) place_on_rail(vertex(m), rp, l);  // (the new slots start off every rail)
    }
    v_edge_[m] = edge(e);
  });
  // 2. The halves: e keeps the one at its first end, ne + e is the other.
  detail::parallel_for(ne, kBlock, cores, [&](std::size_t, std::size_t e) {
    const VertexHandle m = vertex(nv + e);
    e_vert_[ne + e] = {m, e_vert_[e][1]};
    e_vert_[e][1] = m;
  });
  // 3. An old vertex whose edge lost it to the other half points to that half.
  detail::parallel_for(nv, kBlock, cores, [&](std::size_t, std::size_t v) {
    const std::size_t e = static_cast<std::size_t>(v_edge_[v].idx);
    if (e_vert_[e][0].idx != static_cast<std::int32_t>(v)) v_edge_[v] = edge(ne + e);
  });
  // 4. Each triangle (c0, c1, c2), edge k from c_k to c_k+1 split at m_k, becomes its middle
  // (m0, m1, m2) in its own slot and the corners (c_k, m_k, m_k-1) in slots nt + 3t + k,
  // through the inner edges (m_k, m_k-1) in slots 2 ne + 3t + k.
  detail::parallel_for(nt, kBlock, cores, [&](std::size_t, std::size_t t) {
    const auto te = t_edge_[t];
    std::array<std::array<VertexHandle, 2>, 3> ends;  // edge k's ends before the split
    for (int k = 0; k < 3; ++k) ends[k] = {e_vert_[te[k].idx][0], e_vert_[ne + te[k].idx][1]};
    const auto shared = [](const std::array<VertexHandle, 2>& a, const std::array<VertexHandle, 2>& b) {
      return (a[0] == b[0] || a[0] == b[1]) ? a[0] : a[1];
    };
    std::array<VertexHandle, 3> c;
    c[1] = shared(ends[0], ends[1]);
    c[0] = ends[0][0] == c[1] ? ends[0][1] : ends[0][0];
    c[2] = ends[1][0] == c[1] ? ends[1][1] : ends[1][0];
    // The half of edge k at corner v.
    const auto half = [&](int k, VertexHandle v) {
      const std::size_t e = static_cast<std::size_t>(te[k].idx);
      return ends[k][0] == v ? edge(e) : edge(ne + e);
    };
    const auto midpoint = [&](int k) { return vertex(nv + static_cast<std::size_t>(te[k].idx)); };
    std::array<EdgeHandle, 3> inner;
    for (int k = 0; k < 3; ++k) {
      const std::size_t e = 2 * ne + 3 * t + static_cast<std::size_t>(k),
                        corner = nt + 3 * t + static_cast<std::size_t>(k);
      inner[k] = edge(e);
      e_vert_[e] = {midpoint(k), midpoint((k + 2) % 3)};
      e_tri_[e] = {triangle(corner), triangle(t)};
      t_edge_[corner] = {half(k, c[k]), inner[k], half((k + 2) % 3, c[k])};
    }
    t_edge_[t] = {inner[1], inner[2], inner[0]};
  });
  // 5. The halves' triangles: the corners, on the sides where their edge had its triangles.
  detail::parallel_for(ne, kBlock, cores, [&](std::size_t, std::size_t e) {
    const std::array<EdgeHandle, 2> halves = {edge(e), edge(ne + e)};
    const auto before = e_tri_[e];
    for (int side = 0; side < 2; ++side) {
      const TriangleHandle t = before[side];
      for (int h = 0; h < 2; ++h) e_tri_[halves[h].idx][side] = TriangleHandle();
      if (!t.valid()) continue;
      for (int k = 0; k < 3; ++k) {
        const std::size_t corner = nt + 3 * static_cast<std::size_t>(t.idx) + static_cast<std::size_t>(k);
        const auto& ce = t_edge_[corner];
        for (int h = 0; h < 2; ++h)
          if (ce[0] == halves[h] || ce[2] == halves[h]) e_tri_[halves[h].idx][side] = triangle(corner);
      }
    }
  });

  n_vertices_ += ne;
  n_edges_ = new_ne;
  n_triangles_ = new_nt;
  counters_.splits += ne;
  std::exception_ptr first;
  for (std::size_t m = nv; m < new_nv; ++m) {
    const std::exception_ptr e = notify_inserted(vertex(m));
    if (!first) first = e;
  }
  rethrow_if(first);
  return ne;
}

}  // namespace rgbmesh
