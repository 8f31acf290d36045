// The topological primitives under every operator (section IV): bisect (a vertex on an edge,
// each incident triangle halved), flip (an edge swap) and unbisect (the inverse of bisect), and
// the slots they take from and give back to the free lists. Kept in one file so that the
// allocation inlines into the primitives, which run once per split, swap and merge.

#include <algorithm>
#include <cassert>
#include <cstdint>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

// ---------------------------------------------------------------------------------------
// Room for new elements

void RgbMesh::make_room(std::size_t vertices, std::size_t edges, std::size_t triangles) {
  // New elements take free slots first, then spare capacity: the room is the capacity less the
  // live elements. Growth is geometric, as push_back's would be.
  if (v_edge_.capacity() - n_vertices_ < vertices)
    grow_vertex_arrays(std::max(2 * v_edge_.capacity(), v_edge_.size() + vertices));
  if (e_vert_.capacity() - n_edges_ < edges)
    grow_edge_arrays(std::max(2 * e_vert_.capacity(), e_vert_.size() + edges));
  if (t_edge_.capacity() - n_triangles_ < triangles)
    grow_triangle_arrays(std::max(2 * t_edge_.capacity(), t_edge_.size() + triangles));
}

// ---------------------------------------------------------------------------------------
// Allocation, within the room make_room made: the arrays do not grow here.

VertexHandle RgbMesh::new_vertex() {
  VertexHandle v;
  if (v_free_ >= 0) {
    // Reset the properties first: a throwing copy then leaves everything as it was.
    const auto slot = static_cast<std::size_t>(v_free_);
    for (auto& p : vertex_properties_) p->reset(slot);
    v = VertexHandle(v_free_);
    v_free_ = v_parents_[slot][0].idx;
    v_parents_[slot] = {VertexHandle(), VertexHandle()};
  } else {
    const std::size_t n = v_edge_.size();
    // Properties first, as above; undo those that grew if a later one throws.
    std::size_t grown = 0;
    try {
      for (; grown < vertex_properties_.size(); ++grown) vertex_properties_[grown]->resize(n + 1);
    } catch (...) {
      for (std::size_t i = 0; i < grown; ++i) vertex_properties_[i]->resize(n);
      throw;
    }
    assert(n < v_edge_.capacity());
    v = VertexHandle(static_cast<std::int32_t>(n));
    v_edge_.emplace_back();
    v_level_.push_back(0);
    v_parents_.push_back({VertexHandle(), VertexHandle()});
    v_control_.emplace_back();
    v_limit_index_.push_back(-1);
    v_flags_.push_back(0);
    if (creases_) {
      v_rail_.push_back(-1);
      v_rail_position_.push_back(0);
    }
#if RGBMESH_CHECKED_HANDLES
    v_generation_.push_back(1);
#endif
  }
  ++n_vertices_;
  return stamped(v);
}

EdgeHandle RgbMesh::new_edge(VertexHandle a, VertexHandle b, std::uint8_t info) {
  EdgeHandle e;
  if (e_free_ >= 0) {
    e = EdgeHandle(e_free_);
    e_free_ = e_tri_[e.idx][0].idx;
    e_vert_[e.idx] = {a, b};
    e_tri_[e.idx] = {TriangleHandle(), TriangleHandle()};
    e_info_[e.idx] = info;
  } else {
    assert(e_vert_.size() < e_vert_.capacity());
    e = EdgeHandle(static_cast<std::int32_t>(e_vert_.size()));
    e_vert_.push_back({a, b});
    e_tri_.push_back({TriangleHandle(), TriangleHandle()});
    e_info_.push_back(info);
#if RGBMESH_CHECKED_HANDLES
    e_generation_.push_back(1);
#endif
  }
  ++n_edges_;
  return stamped(e);
}

TriangleHandle RgbMesh::new_triangle(const std::array<EdgeHandle, 3>& edges) {
  TriangleHandle t;
  if (t_free_ >= 0) {
    t = TriangleHandle(t_free_);
    t_free_ = t_edge_[t.idx][1].idx;
    t_edge_[t.idx] = edges;
  } else {
    assert(t_edge_.size() < t_edge_.capacity());
    t = TriangleHandle(static_cast<std::int32_t>(t_edge_.size()));
    t_edge_.push_back(edges);
    t_info_.push_back(0);
#if RGBMESH_CHECKED_HANDLES
    t_generation_.push_back(1);
#endif
  }
  ++n_triangles_;
  return stamped(t);
}

namespace {

#if RGBMESH_CHECKED_HANDLES
// A freed slot's next element is a new one: handles to the old one become stale. 0 means
// "unknown" in a handle, so the count skips it when it wraps around.
void next_generation(std::vector<std::uint32_t>& g, std::int32_t slot) {
  std::uint32_t& x = g[static_cast<std::size_t>(slot)];
  x = x == UINT32_MAX ? 1 : x + 1;
}
#endif

}  // namespace

void RgbMesh::free_vertex(VertexHandle v) {
  v_edge_[v.idx] = EdgeHandle();
  v_parents_[v.idx] = {VertexHandle(v_free_), VertexHandle()};
  if (v_flags_[v.idx] & kHistoryFlag) history_.erase(v.idx);
  v_flags_[v.idx] = 0;
  if (creases_) {  // a reused slot starts off every rail
    v_rail_[v.idx] = -1;
    v_rail_position_[v.idx] = 0;
  }
  release_limit(v);
  v_free_ = v.idx;
#if RGBMESH_CHECKED_HANDLES
  next_generation(v_generation_, v.idx);
#endif
  --n_vertices_;
}

void RgbMesh::free_edge(EdgeHandle e) {
  e_vert_[e.idx] = {VertexHandle(), VertexHandle()};
  e_tri_[e.idx] = {TriangleHandle(e_free_), TriangleHandle()};
  e_free_ = e.idx;
#if RGBMESH_CHECKED_HANDLES
  next_generation(e_generation_, e.idx);
#endif
  --n_edges_;
}

void RgbMesh::free_triangle(TriangleHandle t) {
  t_edge_[t.idx] = {EdgeHandle(), EdgeHandle(t_free_), EdgeHandle()};
  t_free_ = t.idx;
#if RGBMESH_CHECKED_HANDLES
  next_generation(t_generation_, t.idx);
#endif
  --n_triangles_;
}

// ---------------------------------------------------------------------------------------
// Attributes

void RgbMesh::update_triangle_info(TriangleHandle t) {
  const auto& te = t_edge_[t.idx];
  const int l0 = level(te[0]), l1 = level(te[1]), l2 = level(te[2]);
  const int lo = std::min({l0, l1, l2});
  // Green: all edges at one level; red: one edge a level finer; blue: two (section IV-A).
  const int finer = (l0 > lo) + (l1 > lo) + (l2 > lo);
  t_info_[t.idx] = static_cast<std::uint8_t>((finer << 6) | lo);
}

// ---------------------------------------------------------------------------------------
// Topological primitives

// Inserts a vertex m at the midpoint of e = (v0, v1) and bisects each incident triangle
// (a, b, c) into (a, m, c) and (m, b, c) through a new edge (m, c). The halves of e are green
// one level finer; the bisecting edge is red at e's level in a green triangle and green one
// level finer in a red triangle (section IV-A).
//
// All or nothing: room for the new elements is made before the first change, so that only
// that step (or a vertex property's copy in new_vertex, which changes nothing either) can throw.
VertexHandle RgbMesh::bisect(EdgeHandle e, const Vec3& control, const RailPiece* rail) {
  make_room(1, 3, 2);
  reserve_journal_entry();
  e = stamped(e);  // e is stored below: with the generation of its slot
  const auto [v0, v1] = e_vert_[e.idx];
  const int l = level(e);
  const bool boundary = is_boundary(e);
  struct Side {
    int slot;
    TriangleHandle t;
    VertexHandle a, c;
    EdgeHandle eb, ec;  // (b, c) and (c, a)
    bool red;
  };
  Side sides[2];
  int n = 0;
  for (int k = 0; k < 2; ++k) {
    const TriangleHandle t = e_tri_[e.idx][k];
    if (!t.valid()) continue;
    const int i = local_index(t, e);
    const auto c = triangle_vertices(t);
    sides[n++] = Side{k,
                      t,
                      c[i],
                      c[(i + 2) % 3],
                      t_edge_[t.idx][(i + 1) % 3],
                      t_edge_[t.idx][(i + 2) % 3],
                      color(t) == Color::red};
  }

  const VertexHandle m = new_vertex();
  v_level_[m.idx] = static_cast<std::uint8_t>(l + 1);
  v_parents_[m.idx] = {v0, v1};
  v_control_[m.idx] = control;
  v_flags_[m.idx] = boundary ? kBoundaryFlag : 0;
  if (creases_) {
    const RailPiece rp = rail ? *rail : rail_piece(v0, v1, l);
    if (rp.rail >= 0) place_on_rail(m, rp, l);
  }

  const std::uint8_t half_info = edge_info(false, l + 1);
  const EdgeHandle e1 = new_edge(m, v1, half_info);  // e keeps (v0, m)
  e_vert_[e.idx] = {v0, m};
  e_info_[e.idx] = half_info;
  if (v_edge_[v1.idx] == e) v_edge_[v1.idx] = e1;
  v_edge_[m.idx] = e;

  for (int s = 0; s < n; ++s) {
    const Side& sd = sides[s];
    const EdgeHandle ha = (sd.a == v0) ? e : e1;  // the half at a
    const EdgeHandle hb = (ha == e) ? e1 : e;     // the half at b
    const EdgeHandle mc = new_edge(m, sd.c, sd.red ? edge_info(false, l + 1) : edge_info(true, l));
    const TriangleHandle tb = new_triangle({hb, sd.eb, mc});  // (m, b, c)
    t_edge_[sd.t.idx] = {ha, mc, sd.ec};                      // (a, m, c)
    e_tri_[mc.idx] = {sd.t, tb};
    replace_edge_triangle(sd.eb, sd.t, tb);
    e_tri_[ha.idx][sd.slot] = sd.t;
    e_tri_[hb.idx][sd.slot] = tb;
    update_triangle_info(sd.t);
    update_triangle_info(tb);
  }
  ++counters_.splits;
  if (journal_) journal_->push_back({JournalEntry::bisect, m.idx, 0});  // within capacity
  return m;
}

void RgbMesh::reserve_journal_entry() {
  if (journal_ && journal_->size() == journal_->capacity())
    journal_->reserve(std::max<std::size_t>(64, 2 * journal_->capacity()));
}

// Replaces the diagonal e of the quadrilateral formed by its two triangles with the other
// diagonal. t0 = (a, b, c) and t1 = (b, a, d) become (d, b, c) and (c, a, d).
void RgbMesh::flip(EdgeHandle e, std::uint8_t new_info) {
  reserve_journal_entry();  // the only step that can throw, before any change
  e = stamped(e);           // stored below
  if (journal_) journal_->push_back({JournalEntry::flip, e.idx, e_info_[e.idx]});
  const TriangleHandle t0 = e_tri_[e.idx][0], t1 = e_tri_[e.idx][1];
  const int i = local_index(t0, e), j = local_index(t1, e);
  const auto c0 = triangle_vertices(t0), c1 = triangle_vertices(t1);
  const VertexHandle a = c0[i], b = c0[(i + 1) % 3], c = c0[(i + 2) % 3];
  const VertexHandle d = c1[(j + 2) % 3];
  const EdgeHandle bc = t_edge_[t0.idx][(i + 1) % 3], ca = t_edge_[t0.idx][(i + 2) % 3];
  const EdgeHandle ad = t_edge_[t1.idx][(j + 1) % 3], db = t_edge_[t1.idx][(j + 2) % 3];
  t_edge_[t0.idx] = {db, bc, e};
  t_edge_[t1.idx] = {ca, ad, e};
  e_vert_[e.idx] = {c, d};
  e_info_[e.idx] = new_info;
  replace_edge_triangle(ca, t0, t1);
  replace_edge_triangle(db, t1, t0);
  if (v_edge_[a.idx] == e) v_edge_[a.idx] = ca;
  if (v_edge_[b.idx] == e) v_edge_[b.idx] = bc;
  update_triangle_info(t0);
  update_triangle_info(t1);
}

// Inverse of bisect: m (valence 4, or 3 on the boundary) with parents a, b is removed; its
// halves (a, m), (m, b) become the edge (a, b) again, green at level(m) - 1, and on each side
// the two triangles (a, m, c), (m, b, c) become (a, b, c).
EdgeHandle RgbMesh::unbisect(VertexHandle m) {
  const auto [a, b] = v_parents_[m.idx];
  return unbisect(m, find_edge(m, a), find_edge(m, b));
}

// Allocates nothing (the free lists live in the freed slots), so it cannot fail halfway.
EdgeHandle RgbMesh::unbisect(VertexHandle m, EdgeHandle ea, EdgeHandle eb) {
  ea = stamped(ea);  // stored below
  const auto [a, b] = v_parents_[m.idx];
  for (int k = 0; k < 2; ++k) {
    const TriangleHandle ta = e_tri_[ea.idx][k];
    if (!ta.valid()) continue;
    // ta holds ea, (m, c) and (c, a); its neighbour across (m, c) holds eb and (b, c).
    const int ia = local_index(ta, ea);
    const auto& te = t_edge_[ta.idx];
    const EdgeHandle e_next = te[(ia + 1) % 3], e_prev = te[(ia + 2) % 3];
    const auto& nv = e_vert_[e_next.idx];
    const bool next_is_mc = (nv[0] == m || nv[1] == m);
    const EdgeHandle mc = next_is_mc ? e_next : e_prev;
    const int imc = next_is_mc ? (ia + 1) % 3 : (ia + 2) % 3;
    const TriangleHandle tb = other_triangle(mc, ta);
    const int ib = local_index(tb, eb);
    const auto& tbe = t_edge_[tb.idx];
    const EdgeHandle f1 = tbe[(ib + 1) % 3], f2 = tbe[(ib + 2) % 3];
    const EdgeHandle bc = (f1 == mc) ? f2 : f1;
    const VertexHandle c = other_vertex(mc, m);
    t_edge_[ta.idx][imc] = bc;
    replace_edge_triangle(bc, tb, ta);
    if (v_edge_[c.idx] == mc) v_edge_[c.idx] = (next_is_mc ? e_prev : e_next);
    free_triangle(tb);
    free_edge(mc);
  }
  if (v_edge_[b.idx] == eb) v_edge_[b.idx] = ea;
  e_vert_[ea.idx] = {a, b};
  e_info_[ea.idx] = edge_info(false, level(m) - 1);
  free_edge(eb);
  for (TriangleHandle t : e_tri_[ea.idx]) {
    if (t.valid()) update_triangle_info(t);
  }
  free_vertex(m);
  ++counters_.removals;
  return ea;
}

}  // namespace rgbmesh
