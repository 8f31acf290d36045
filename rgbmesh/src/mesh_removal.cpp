// RgbMesh::remove_vertex (section IV-D, Fig. 11): the swaps that bring each side of a removable
// vertex's star into a mergeable form, then the merge; and the names of those configurations.

#include <algorithm>
#include <cassert>
#include <cstring>
#include <exception>
#include <new>
#include <string>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

namespace {

char color_letter(Color c) {
  switch (c) {
    case Color::green:
      return 'G';
    case Color::red:
      return 'R';
    case Color::blue:
      return 'B';
  }
  return '?';
}

}  // namespace

void RgbMesh::remove_vertex(VertexHandle v) {
  v = checked(v, "remove_vertex");
  // Named copies, not a structured binding: lambdas may capture those only from C++20.
  const VertexHandle a = v_parents_[v.idx][0];
  const VertexHandle b = v_parents_[v.idx][1];
  // One walk around v checks removability (section IV-D) and finds the halves of its edge.
  const int l = level(v);
  bool removable = l > 0;
  EdgeHandle halves[2];
  visit_edges(v, [&](EdgeHandle e) {
    const VertexHandle w = other_vertex(e, v);
    if (level(w) > l) removable = false;
    if (w == a) halves[0] = e;
    if (w == b) halves[1] = e;
    return removable;
  });
  if (!removable)
    fail("remove_vertex", describe(v) + " is not removable (level 0, or a neighbour has a higher level)");
  // Observers hear of the removal while the mesh is still as the caller left it. What follows
  // cannot fail (swaps and the merge allocate nothing), so the removal is carried out even if
  // an observer throws, and its exception propagates from a valid, stable mesh.
  const std::exception_ptr observer_error = notify_removing(v);
  // Bring each side of the split edge to a mergeable form by the swaps of Fig. 11. A side is
  // the fan of triangles between the halves (v, a) and (v, b), read counter-clockwise from
  // one of them; as colors it is one of RR, GB, BG (mergeable), GBR, RBG (one RB-swap), GGG
  // (one GG-swap) or GBBG (BB-swap, then GG-swap). Both fans are walked without allocating.
  // (The halves are never swapped, so their handles stay valid throughout.)
  for (int side = 0; side < 2; ++side) {
    for (int step = 0; step < 3; ++step) {
      TriangleHandle fan[5];
      EdgeHandle inner[4];  // inner[i] separates fan[i] and fan[i+1]
      int n = 0;
      EdgeHandle e = halves[side];
      while (n < 5) {
        const auto [t, arriving] = leaving_triangle(v, e);
        if (!t.valid()) break;  // the boundary: this side is read from the other parent
        fan[n++] = t;
        const VertexHandle next = other_vertex(arriving, v);
        if (next == a || next == b) break;
        inner[n - 1] = arriving;
        e = arriving;
      }
      if (n == 0) break;
      char colors[6] = {};
      for (int i = 0; i < n; ++i) colors[i] = color_letter(color(fan[i]));
      const auto is = [&colors](const char* pattern) { return std::strcmp(colors, pattern) == 0; };
      if (is("RR") || is("GB") || is("BG")) break;
      if (is("GBR")) {
        swap_rb(inner[1]);
      } else if (is("RBG")) {
        swap_rb(inner[0]);
      } else if (is("GGG")) {
        swap_gg(inner[1]);
      } else if (is("GBBG")) {
        swap_bb(inner[1]);
      } else {
        fail("remove_vertex", describe(v) + " has an unexpected star side '" + std::string(colors) + "'");
      }
    }
  }
  // Both sides are now in mergeable form (checked in debug builds; validate() checks the result).
  // The check reads the star into a scratch vector, which may allocate: an allocation failure
  // skips the check instead of stopping the removal between its swaps and its merge.
#ifndef NDEBUG
  try {
    assert(merge_kind(v) != MergeKind::not_mergeable);
  } catch (const std::bad_alloc&) {
  }
#endif
  unbisect(v, halves[0], halves[1]);
  rethrow_if(observer_error);
}

std::string RgbMesh::removal_configuration(VertexHandle v) const {
  if (!alive(v) || !is_removable(v)) return {};
  const auto [a, b] = v_parents_[v.idx];
  VertexStar s;
  star(v, s);
  const std::size_t n = s.edges.size();
  // Read each side counter-clockwise from the parent endpoint where it starts.
  std::string sides[2];
  int count = 0;
  for (std::size_t i = 0; i < n && count < 2; ++i) {
    if (s.neighbors[i] != a && s.neighbors[i] != b) continue;
    std::string colors;
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t j = (i + k) % n;
      if (j >= s.triangles.size()) break;
      colors += color_letter(color(s.triangles[j]));
      const VertexHandle next = s.neighbors[(j + 1) % n];
      if (next == a || next == b) break;
    }
    if (!colors.empty()) sides[count++] = colors;
  }
  if (count == 1) return sides[0];
  // A rotation by 180 degrees around v exchanges the sides.
  const std::string x = sides[0] + "|" + sides[1], y = sides[1] + "|" + sides[0];
  return std::min(x, y);
}

}  // namespace rgbmesh
