// The topological primitives under every operator (section IV): bisect (a vertex on an edge,
// each incident triangle halved), flip (an edge swap) and unbisect (the inverse of bisect), and
// the slots they take from and give back to the free lists.

#include <algorithm>
#include <cassert>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

// ---------------------------------------------------------------------------------------
// Allocation

VertexHandle RgbMesh::new_vertex() {
  VertexHandle v;
  if (!v_free_.empty()) {
    v = VertexHandle(v_free_.back());
    v_free_.pop_back();
  } else {
    v = VertexHandle(static_cast<std::int32_t>(v_edge_.size()));
    v_edge_.emplace_back();
    v_level_.push_back(0);
    v_parents_.push_back({VertexHandle(), VertexHandle()});
    v_control_.emplace_back();
    v_limit_index_.push_back(-1);
    v_flags_.push_back(0);
    for (auto& p : vertex_properties_) p->resize(v_edge_.size());
  }
  ++n_vertices_;
  return v;
}

EdgeHandle RgbMesh::new_edge(VertexHandle a, VertexHandle b, std::uint8_t info) {
  EdgeHandle e;
  if (!e_free_.empty()) {
    e = EdgeHandle(e_free_.back());
    e_free_.pop_back();
    e_vert_[e.idx] = {a, b};
    e_tri_[e.idx] = {TriangleHandle(), TriangleHandle()};
    e_info_[e.idx] = info;
  } else {
    e = EdgeHandle(static_cast<std::int32_t>(e_vert_.size()));
    e_vert_.push_back({a, b});
    e_tri_.push_back({TriangleHandle(), TriangleHandle()});
    e_info_.push_back(info);
  }
  ++n_edges_;
  return e;
}

TriangleHandle RgbMesh::new_triangle(const std::array<EdgeHandle, 3>& edges) {
  TriangleHandle t;
  if (!t_free_.empty()) {
    t = TriangleHandle(t_free_.back());
    t_free_.pop_back();
    t_edge_[t.idx] = edges;
  } else {
    t = TriangleHandle(static_cast<std::int32_t>(t_edge_.size()));
    t_edge_.push_back(edges);
    t_info_.push_back(0);
  }
  ++n_triangles_;
  return t;
}

void RgbMesh::free_vertex(VertexHandle v) {
  v_edge_[v.idx] = EdgeHandle();
  v_parents_[v.idx] = {VertexHandle(), VertexHandle()};
  v_flags_[v.idx] = 0;
  release_limit(v);
  v_free_.push_back(v.idx);
  --n_vertices_;
}

void RgbMesh::free_edge(EdgeHandle e) {
  e_vert_[e.idx] = {VertexHandle(), VertexHandle()};
  e_tri_[e.idx] = {TriangleHandle(), TriangleHandle()};
  e_free_.push_back(e.idx);
  --n_edges_;
}

void RgbMesh::free_triangle(TriangleHandle t) {
  t_edge_[t.idx] = {EdgeHandle(), EdgeHandle(), EdgeHandle()};
  t_free_.push_back(t.idx);
  --n_triangles_;
}

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
VertexHandle RgbMesh::bisect(EdgeHandle e, const Vec3& control) {
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
  if (journal_) journal_->push_back({JournalEntry::bisect, m.idx, 0});
  return m;
}

// Replaces the diagonal e of the quadrilateral formed by its two triangles with the other
// diagonal. t0 = (a, b, c) and t1 = (b, a, d) become (d, b, c) and (c, a, d).
void RgbMesh::flip(EdgeHandle e, std::uint8_t new_info) {
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

EdgeHandle RgbMesh::unbisect(VertexHandle m, EdgeHandle ea, EdgeHandle eb) {
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
