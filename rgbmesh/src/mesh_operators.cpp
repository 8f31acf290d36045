// RgbMesh's local operators (section IV): the attributes and predicates that select them,
// the topological primitives (bisect, flip, unbisect), the named splits, merges and swaps,
// and split_edge, which composes them (section V-B). remove_vertex is in mesh_removal.cpp.

#include <algorithm>
#include <cassert>
#include <exception>
#include <string>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

const char* to_string(SplitKind k) {
  switch (k) {
    case SplitKind::not_refinable:
      return "not refinable";
    case SplitKind::gg:
      return "GG-split";
    case SplitKind::rg:
      return "RG-split";
    case SplitKind::rr1:
      return "RR1-split";
    case SplitKind::rr2:
      return "RR2-split";
    case SplitKind::g_boundary:
      return "G-boundary-split";
    case SplitKind::r_boundary:
      return "R-boundary-split";
  }
  return "?";
}

const char* to_string(MergeKind k) {
  switch (k) {
    case MergeKind::not_mergeable:
      return "not mergeable";
    case MergeKind::r4:
      return "R4-merge";
    case MergeKind::r2gb:
      return "R2GB-merge";
    case MergeKind::gbgb:
      return "GBGB-merge";
    case MergeKind::g2b2:
      return "G2B2-merge";
    case MergeKind::r2_boundary:
      return "R2-boundary-merge";
    case MergeKind::gb_boundary:
      return "GB-boundary-merge";
  }
  return "?";
}

// ---------------------------------------------------------------------------------------
// Attributes and predicates

void RgbMesh::raising_edges(TriangleHandle t, std::vector<EdgeHandle>& out) const {
  expect_alive(t, "raising_edges");
  out.clear();
  const int l = level(t);
  TriangleHandle source = t;
  if (color(t) == Color::blue) {
    // A blue triangle rises when its red sibling splits its coarse edge and the pair is
    // BB-swapped (section V-B).
    for (EdgeHandle f : triangle_edges(t)) {
      if (is_red(f)) source = other_triangle(f, t);
    }
    if (!source.valid() || color(source) != Color::red || level(source) != l) return;
  }
  for (EdgeHandle f : triangle_edges(source)) {
    if (!is_red(f) && level(f) == l) out.push_back(f);
  }
}

bool RgbMesh::is_refinable(EdgeHandle e) const {
  expect_alive(e, "is_refinable");
  if (is_red(e)) return false;
  const int l = level(e);
  for (TriangleHandle t : e_tri_[e.idx]) {
    if (t.valid() && level(t) != l) return false;
  }
  return l < kMaxLevel;
}

bool RgbMesh::is_removable(VertexHandle v) const {
  expect_alive(v, "is_removable");
  const int l = level(v);
  if (l == 0) return false;
  bool removable = true;
  visit_edges(v, [&](EdgeHandle e) {
    removable = level(other_vertex(e, v)) <= l;
    return removable;
  });
  return removable;
}

bool RgbMesh::is_stable() const {
  for (EdgeHandle e : edges()) {
    if (!is_red(e)) continue;
    const auto& et = e_tri_[e.idx];
    if (et[1].valid() && color(et[0]) == Color::blue && color(et[1]) == Color::blue) return false;
  }
  return true;
}

SplitKind RgbMesh::split_kind(EdgeHandle e) const {
  if (!alive(e) || !is_refinable(e)) return SplitKind::not_refinable;
  const auto& et = e_tri_[e.idx];
  if (!et[1].valid()) {
    return color(et[0]) == Color::green ? SplitKind::g_boundary : SplitKind::r_boundary;
  }
  const Color c0 = color(et[0]), c1 = color(et[1]);
  if (c0 == Color::green && c1 == Color::green) return SplitKind::gg;
  if (c0 == Color::green || c1 == Color::green) return SplitKind::rg;
  // Both red: RR1 when the two red edges end at different endpoints of e (the diamond's
  // boundary alternates red-green-red-green), RR2 when they share one (Fig. 5).
  auto red_end = [&](TriangleHandle t) {
    for (EdgeHandle f : t_edge_[t.idx]) {
      if (is_red(f)) {
        const auto& fv = e_vert_[f.idx];
        const auto& ev = e_vert_[e.idx];
        return (fv[0] == ev[0] || fv[1] == ev[0]) ? ev[0] : ev[1];
      }
    }
    return VertexHandle();
  };
  return red_end(et[0]) == red_end(et[1]) ? SplitKind::rr2 : SplitKind::rr1;
}

// ---------------------------------------------------------------------------------------
// Splits (Fig. 5)

VertexHandle RgbMesh::checked_split(EdgeHandle e, SplitKind kind, const char* op) {
  e = checked(e, op);
  const SplitKind actual = split_kind(e);
  if (actual != kind)
    fail(op, describe(e) + " is " +
                 (actual == SplitKind::not_refinable ? std::string("not refinable")
                                                     : std::string("a case for ") + to_string(actual)));
  const VertexHandle m = split_unreported(e, kind, op);
  // A hand-applied split may leave an unstable pair: that is the caller's to resolve.
  rethrow_if(notify_inserted(m));
  return m;
}

VertexHandle RgbMesh::split_unreported(EdgeHandle e, SplitKind kind, const char* op) {
  // The stencil's coarser vertices need their limit positions; providing them may insert
  // vertices around them, never touching e's triangles, which are finer (section VI-C).
  std::array<VertexHandle, 4> st = stencil(e);
  if (!creases_) {
    if (prepare_stencil(st, level(e)) && split_kind(e) != kind)
      fail(op, "internal error: preparing the stencil changed " + describe(e));
    return bisect(e, stencil_point(st, level(e)));
  }
  const auto& ends = e_vert_[e.idx];
  const RailPiece rp = rail_piece(ends[0], ends[1], level(e));
  const loop::OddMask mask = odd_mask(rp, level(e), !st[3].valid());
  // On a crease only the ends count: the vertices across need no limits.
  if (mask.opposite == 0.0) st[2] = st[3] = VertexHandle();
  if (prepare_stencil(st, level(e)) && split_kind(e) != kind)
    fail(op, "internal error: preparing the stencil changed " + describe(e));
  return bisect(e, stencil_point(st, level(e), mask), &rp);
}

VertexHandle RgbMesh::split_gg(EdgeHandle e) { return checked_split(e, SplitKind::gg, "split_gg"); }
VertexHandle RgbMesh::split_rg(EdgeHandle e) { return checked_split(e, SplitKind::rg, "split_rg"); }
VertexHandle RgbMesh::split_rr1(EdgeHandle e) { return checked_split(e, SplitKind::rr1, "split_rr1"); }
VertexHandle RgbMesh::split_rr2(EdgeHandle e) { return checked_split(e, SplitKind::rr2, "split_rr2"); }
VertexHandle RgbMesh::split_g_boundary(EdgeHandle e) {
  return checked_split(e, SplitKind::g_boundary, "split_g_boundary");
}
VertexHandle RgbMesh::split_r_boundary(EdgeHandle e) {
  return checked_split(e, SplitKind::r_boundary, "split_r_boundary");
}

VertexHandle RgbMesh::split_refinable(EdgeHandle e) {
  e = checked(e, "split_refinable");
  const SplitKind kind = split_kind(e);
  if (kind == SplitKind::not_refinable) fail("split_refinable", describe(e) + " is not refinable");
  return checked_split(e, kind, "split_refinable");
}

// ---------------------------------------------------------------------------------------
// Merges (inverse of Fig. 5)

MergeKind RgbMesh::merge_kind(VertexHandle v) const {
  if (!alive(v) || level(v) == 0) return MergeKind::not_mergeable;
  const auto [a, b] = v_parents_[v.idx];
  const int l = level(v) - 1;
  VertexStar& s = scratch_star_;  // reused: no allocation per removal
  star(v, s);
  const std::size_t n = s.edges.size();
  if (n != (s.boundary ? 3u : 4u)) return MergeKind::not_mergeable;
  // Locate the halves of the split edge in the star.
  std::size_t ia = n, ib = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (s.neighbors[i] == a) ia = i;
    if (s.neighbors[i] == b) ib = i;
  }
  if (ia == n || ib == n) return MergeKind::not_mergeable;
  for (std::size_t i : {ia, ib}) {
    if (is_red(s.edges[i]) || level(s.edges[i]) != l + 1) return MergeKind::not_mergeable;
  }
  if (s.boundary && !((ia == 0 && ib == 2) || (ia == 2 && ib == 0))) return MergeKind::not_mergeable;
  if (!s.boundary && (ia + 2) % 4 != ib) return MergeKind::not_mergeable;
  // Each side is the pair of triangles around the middle edge between the halves:
  // G-form (two red triangles on a red edge of level l: the side was a green triangle) or
  // R-form (green + blue on a green edge of level l+1: the side was a red triangle).
  enum SideForm { bad, g_form, r_form };
  struct SideInfo {
    SideForm form;
    VertexHandle green_end;
  };
  auto side = [&](std::size_t mid) -> SideInfo {
    const EdgeHandle me = s.edges[mid];
    const TriangleHandle t0 = s.triangles[(mid + n - 1) % n];  // before the middle edge
    const TriangleHandle t1 = s.triangles[mid % s.triangles.size()];
    const Color c0 = color(t0), c1 = color(t1);
    if (is_red(me) && level(me) == l && c0 == Color::red && c1 == Color::red && level(t0) == l &&
        level(t1) == l)
      return {g_form, VertexHandle()};
    if (!is_red(me) && level(me) == l + 1 && level(s.neighbors[mid]) == l + 1) {
      if (c0 == Color::green && c1 == Color::blue && level(t0) == l + 1 && level(t1) == l)
        return {r_form, s.neighbors[(mid + n - 1) % n]};
      if (c0 == Color::blue && c1 == Color::green && level(t0) == l && level(t1) == l + 1)
        return {r_form, s.neighbors[(mid + 1) % n]};
    }
    return {bad, VertexHandle()};
  };
  if (s.boundary) {
    const SideInfo si = side(1);
    if (si.form == g_form) return MergeKind::r2_boundary;
    if (si.form == r_form) return MergeKind::gb_boundary;
    return MergeKind::not_mergeable;
  }
  const SideInfo s0 = side((ia + 1) % 4), s1 = side((ia + 3) % 4);
  if (s0.form == bad || s1.form == bad) return MergeKind::not_mergeable;
  if (s0.form == g_form && s1.form == g_form) return MergeKind::r4;
  if (s0.form != s1.form) return MergeKind::r2gb;
  // Both sides were red: RR1 when the green triangles sit at different parent endpoints.
  return s0.green_end == s1.green_end ? MergeKind::g2b2 : MergeKind::gbgb;
}

EdgeHandle RgbMesh::checked_merge(VertexHandle v, MergeKind kind, const char* op) {
  v = checked(v, op);
  const MergeKind actual = merge_kind(v);
  if (actual != kind)
    fail(op, describe(v) + " is " +
                 (actual == MergeKind::not_mergeable ? std::string("not mergeable")
                                                     : std::string("a case for ") + to_string(actual)));
  // Observers first (the vertex still exists); the merge cannot fail and is carried out even
  // if one of them throws, so that every observer's view matches the mesh.
  const std::exception_ptr observer_error = notify_removing(v);
  const EdgeHandle restored = unbisect(v);
  rethrow_if(observer_error);
  return restored;
}

EdgeHandle RgbMesh::merge_r4(VertexHandle v) { return checked_merge(v, MergeKind::r4, "merge_r4"); }
EdgeHandle RgbMesh::merge_r2gb(VertexHandle v) { return checked_merge(v, MergeKind::r2gb, "merge_r2gb"); }
EdgeHandle RgbMesh::merge_gbgb(VertexHandle v) { return checked_merge(v, MergeKind::gbgb, "merge_gbgb"); }
EdgeHandle RgbMesh::merge_g2b2(VertexHandle v) { return checked_merge(v, MergeKind::g2b2, "merge_g2b2"); }
EdgeHandle RgbMesh::merge_r2_boundary(VertexHandle v) {
  return checked_merge(v, MergeKind::r2_boundary, "merge_r2_boundary");
}
EdgeHandle RgbMesh::merge_gb_boundary(VertexHandle v) {
  return checked_merge(v, MergeKind::gb_boundary, "merge_gb_boundary");
}

EdgeHandle RgbMesh::merge(VertexHandle v) {
  v = checked(v, "merge");
  const MergeKind kind = merge_kind(v);
  if (kind == MergeKind::not_mergeable) fail("merge", describe(v) + " is not mergeable");
  return checked_merge(v, kind, "merge");
}

// ---------------------------------------------------------------------------------------
// Swaps (Fig. 6)

EdgeHandle RgbMesh::swap_bb(EdgeHandle e) {
  e = checked(e, "swap_bb");
  const auto& et = e_tri_[e.idx];
  const int l = level(e);
  const bool ok = is_red(e) && et[1].valid() && color(et[0]) == Color::blue && color(et[1]) == Color::blue &&
                  level(et[0]) == l && level(et[1]) == l;
  if (!ok) fail("swap_bb", describe(e) + " is not a red edge between two blue triangles of its level");
  // The new diagonal joins two midpoints of level l+1: green, level l+1.
  flip(e, edge_info(false, l + 1));
  ++counters_.swaps_bb;
  return e;
}

EdgeHandle RgbMesh::swap_gg(EdgeHandle e) {
  e = checked(e, "swap_gg");
  const auto& et = e_tri_[e.idx];
  const int l = level(e);
  bool ok = !is_red(e) && l > 0 && et[1].valid() && color(et[0]) == Color::green &&
            color(et[1]) == Color::green && level(et[0]) == l && level(et[1]) == l;
  if (ok) {
    // One of the two triangles must be the central child of their common parent: all three
    // vertices at level l (section IV-B). That makes them siblings.
    auto all_at_level = [&](TriangleHandle t) {
      for (VertexHandle v : triangle_vertices(t))
        if (level(v) != l) return false;
      return true;
    };
    ok = all_at_level(et[0]) != all_at_level(et[1]);
  }
  if (!ok)
    fail("swap_gg", describe(e) + " is not shared by a central and a corner green child of one parent");
  // The new diagonal bisects the parent: red, level l-1.
  flip(e, edge_info(true, l - 1));
  ++counters_.swaps_gg;
  return e;
}

EdgeHandle RgbMesh::swap_rb(EdgeHandle e) {
  e = checked(e, "swap_rb");
  const auto& et = e_tri_[e.idx];
  const int l = level(e);
  bool ok = is_red(e) && et[1].valid() && level(et[0]) == l && level(et[1]) == l;
  if (ok) {
    const Color c0 = color(et[0]), c1 = color(et[1]);
    ok = (c0 == Color::red && c1 == Color::blue) || (c0 == Color::blue && c1 == Color::red);
  }
  if (!ok) fail("swap_rb", describe(e) + " is not a red edge between a red and a blue triangle");
  // The other diagonal of the trapezoid bisects the same parent: red at the same level.
  flip(e, edge_info(true, l));
  ++counters_.swaps_rb;
  return e;
}

// ---------------------------------------------------------------------------------------
// Selective refinement primitives (section V)

// BB-swaps every unstable pair that the insertion of m created: the blue triangles of a
// split are incident at the new vertex.
void RgbMesh::stabilize_around(VertexHandle m) {
  for (;;) {
    // Of several unstable pairs, the one whose red edge comes first by its ends' positions:
    // not the first met around m, which depends on where m's edge list starts (issue 24).
    EdgeHandle unstable;
    visit_edges(m, [&](EdgeHandle e) {
      for (TriangleHandle t : e_tri_[e.idx]) {
        if (!t.valid() || color(t) != Color::blue) continue;
        for (EdgeHandle f : t_edge_[t.idx]) {
          if (!is_red(f)) continue;
          const TriangleHandle u = other_triangle(f, t);
          if (u.valid() && color(u) == Color::blue && (!unstable.valid() || edge_precedes(f, unstable))) unstable = f;
          break;
        }
      }
      return true;
    });
    if (!unstable.valid()) return;
    swap_bb(unstable);  // the star changed: look again
  }
}

bool RgbMesh::edge_precedes(EdgeHandle a, EdgeHandle b) const {
  // By the control points of the ends (each at its vertex's own level: the same in every copy
  // of the mesh, whatever the slots), smaller end first, lexicographically.
  const auto less = [](const Vec3& p, const Vec3& q) {
    return p.x != q.x ? p.x < q.x : (p.y != q.y ? p.y < q.y : p.z < q.z);
  };
  const auto ends = [&](EdgeHandle e) {
    const Vec3& p = v_control_[e_vert_[e.idx][0].idx];
    const Vec3& q = v_control_[e_vert_[e.idx][1].idx];
    return less(q, p) ? std::pair<const Vec3*, const Vec3*>(&q, &p) : std::pair<const Vec3*, const Vec3*>(&p, &q);
  };
  const auto [a0, a1] = ends(a);
  const auto [b0, b1] = ends(b);
  if (less(*a0, *b0)) return true;
  if (less(*b0, *a0)) return false;
  return less(*a1, *b1);
}

// Each step (a forced split, the stabilising swaps after it) completes before its insertion is
// reported, so that an observer's exception leaves a valid, stable mesh (see mesh.hpp).
VertexHandle RgbMesh::split_edge(EdgeHandle e) {
  e = checked(e, "split_edge");
  if (is_red(e)) fail("split_edge", describe(e) + " is red; only green edges split");
  const int l = level(e);
  if (l >= kMaxLevel) fail("split_edge", describe(e) + " is at the maximum level");
  // Make e refinable: each incident triangle of level l-1 is decomposed by splitting a
  // coarser green edge (section V-B). Splitting other edges never deletes e (green edges are
  // only removed by their own split or by a merge), so the handle stays valid.
  // When both sides are coarser, the side whose edge comes first by position goes first
  // (edge_precedes), not the first in e's triangle list, which depends on the mesh's history:
  // the order of the forced splits decides which diagonal their trapezoids get (issue 24).
  for (;;) {
    EdgeHandle coarser, unstable;
    for (TriangleHandle t : e_tri_[e.idx]) {
      if (!t.valid() || level(t) == l) continue;
      TriangleHandle red = t;
      if (color(t) == Color::blue) {
        // Its red edge leads to the red triangle of the same parent; if that one is blue
        // too (an unstable pair left by hand-applied operators), the BB-swap is the refinement.
        EdgeHandle red_edge;
        for (EdgeHandle f : t_edge_[t.idx]) {
          if (is_red(f)) red_edge = f;
        }
        red = other_triangle(red_edge, t);
        if (color(red) == Color::blue) {
          if (!unstable.valid() || edge_precedes(red_edge, unstable)) unstable = red_edge;
          continue;
        }
      }
      for (EdgeHandle f : t_edge_[red.idx]) {
        if (!is_red(f) && level(f) == l - 1 && (!coarser.valid() || edge_precedes(f, coarser))) coarser = f;
      }
    }
    if (unstable.valid()) {
      swap_bb(unstable);
      continue;
    }
    if (!coarser.valid()) break;
    split_edge(coarser);
  }
  const SplitKind kind = split_kind(e);
  if (kind == SplitKind::not_refinable)
    fail("split_edge", "internal error: " + describe(e) + " is still not refinable");
  const VertexHandle m = split_unreported(e, kind, "split_edge");
  // Only a red triangle's bisection makes a blue one: GG and green boundary splits cannot
  // leave an unstable pair.
  if (kind != SplitKind::gg && kind != SplitKind::g_boundary) stabilize_around(m);
  rethrow_if(notify_inserted(m));
  return m;
}

}  // namespace rgbmesh
