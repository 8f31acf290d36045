// Orientation of triangle soups (see orient_triangles.hpp): the soup's edges found once by a
// counting sort of the sides (buckets.hpp), then the walk and the fans on arrays, so that each
// step is linear in the number of triangles.

#include "rgbmesh/repair/orient_triangles.hpp"

#include <algorithm>

#include "buckets.hpp"

namespace rgbmesh::repair {
namespace {

using Triangle = std::array<std::size_t, 3>;
constexpr std::size_t kNone = ~std::size_t{0};

// The edges: side k of triangle t (from corner k to corner k + 1, as the input gave them) lies on
// edge on_edge[3 t + k]; an edge of one or two triangles lists them (the second kNone for one); an
// edge that is never crossed (non-manifold, or cut by the walk) is closed.
struct Edges {
  std::vector<std::size_t> on_edge;
  std::vector<std::array<std::size_t, 2>> triangles;
  std::vector<char> closed;
  std::size_t non_manifold = 0;

  std::size_t other(std::size_t edge, std::size_t t) const {
    const auto& two = triangles[edge];
    return two[0] == t ? two[1] : two[0];
  }
};

Edges edges_of(const std::vector<Triangle>& triangles, std::size_t point_count) {
  const std::size_t sides = 3 * triangles.size();
  // The sides by lower end, each as (higher end, side).
  auto by_lower = buckets<std::pair<std::size_t, std::size_t>>(point_count, sides, [&](auto&& add) {
    for (std::size_t s = 0; s < sides; ++s) {
      const Triangle& t = triangles[s / 3];
      const std::size_t a = t[s % 3], b = t[(s % 3 + 1) % 3];
      add(std::min(a, b), std::make_pair(std::max(a, b), s));
    }
  });
  Edges edges;
  edges.on_edge.assign(sides, kNone);
  edges.triangles.reserve(sides / 2 + 1);
  edges.closed.reserve(sides / 2 + 1);
  for (std::size_t v = 0; v < point_count; ++v) {
    const auto first = by_lower.items.begin() + static_cast<std::ptrdiff_t>(by_lower.start[v]);
    const auto last = by_lower.items.begin() + static_cast<std::ptrdiff_t>(by_lower.start[v + 1]);
    std::sort(first, last);
    for (auto i = first, j = first; i != last; i = j) {
      for (j = i + 1; j != last && j->first == i->first;) ++j;
      const std::size_t edge = edges.triangles.size();
      for (auto s = i; s != j; ++s) edges.on_edge[s->second] = edge;
      edges.triangles.push_back({i->second / 3, j - i == 2 ? (i + 1)->second / 3 : kNone});
      edges.closed.push_back(j - i > 2);
      edges.non_manifold += j - i > 2;
    }
  }
  return edges;
}

// Whether triangle t has corner a followed by corner b.
bool runs(const Triangle& t, std::size_t a, std::size_t b) {
  for (int k = 0; k < 3; ++k)
    if (t[k] == a) return t[(k + 1) % 3] == b;
  return false;
}

}  // namespace

SoupOrientation orient_triangles(std::vector<Triangle>& triangles, std::size_t point_count) {
  SoupOrientation out;
  Edges edges = edges_of(triangles, point_count);
  out.non_manifold_edges = edges.non_manifold;
  const std::size_t n = triangles.size();

  // A reversed triangle [a, b, c] is [c, b, a]: its sides from positions 0, 1, 2 are the input's
  // sides 1, 0, 2.
  std::vector<char> reversed(n, 0), visited(n, 0);
  const auto edge_at = [&](std::size_t t, int position) {
    static constexpr int kReversedSide[3] = {1, 0, 2};
    return edges.on_edge[3 * t + static_cast<std::size_t>(reversed[t] ? kReversedSide[position] : position)];
  };
  std::vector<std::size_t> stack;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (visited[seed]) continue;
    visited[seed] = 1;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::size_t t = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const std::size_t edge = edge_at(t, k);
        if (edges.closed[edge]) continue;
        const std::size_t u = edges.other(edge, t);
        if (u == kNone) continue;
        const bool same_way = runs(triangles[u], triangles[t][k], triangles[t][(k + 1) % 3]);
        if (visited[u]) {
          if (same_way && !edges.closed[edge]) {  // both fixed and they disagree: cut here
            edges.closed[edge] = 1;
            ++out.cut_edges;
          }
          continue;
        }
        if (same_way) {
          std::reverse(triangles[u].begin(), triangles[u].end());
          reversed[u] = 1;
          ++out.reversed_triangles;
        }
        visited[u] = 1;
        stack.push_back(u);
      }
    }
  }

  // The fans around each vertex: its triangles joined across open edges at the vertex.
  const auto around = buckets<std::size_t>(point_count, 3 * n, [&](auto&& add) {
    for (std::size_t t = 0; t < n; ++t)
      for (const std::size_t v : triangles[t]) add(v, t);
  });
  std::vector<std::size_t> fan_of(n, kNone);
  for (std::size_t v = 0; v < point_count; ++v) {
    const auto first = around.items.begin() + static_cast<std::ptrdiff_t>(around.start[v]);
    const auto last = around.items.begin() + static_cast<std::ptrdiff_t>(around.start[v + 1]);
    std::size_t fans = 0;
    for (auto it = first; it != last; ++it) {
      if (fan_of[*it] != kNone) continue;
      fan_of[*it] = fans;
      stack.assign(1, *it);
      while (!stack.empty()) {
        const std::size_t t = stack.back();
        stack.pop_back();
        const int at =
            static_cast<int>(std::find(triangles[t].begin(), triangles[t].end(), v) - triangles[t].begin());
        for (const int position : {at, (at + 2) % 3}) {  // the sides leaving and entering v
          const std::size_t edge = edge_at(t, position);
          if (edges.closed[edge]) continue;
          const std::size_t u = edges.other(edge, t);
          if (u == kNone || fan_of[u] != kNone) continue;
          fan_of[u] = fans;
          stack.push_back(u);
        }
      }
      ++fans;
    }
    if (fans > 1) {
      ++out.split_vertices;
      out.vertex_copies += fans;
      const std::size_t first_copy = point_count + out.copied_from.size();
      for (std::size_t f = 1; f < fans; ++f) out.copied_from.push_back(v);
      for (auto it = first; it != last; ++it)
        if (const std::size_t f = fan_of[*it]; f > 0)
          std::replace(triangles[*it].begin(), triangles[*it].end(), v, first_copy + f - 1);
    }
    for (auto it = first; it != last; ++it) fan_of[*it] = kNone;
  }
  return out;
}

}  // namespace rgbmesh::repair
