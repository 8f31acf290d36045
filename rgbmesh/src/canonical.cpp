// Vertex names and canonical trapezoid diagonals (canonical.hpp).

#include "rgbmesh/canonical.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace rgbmesh {

VertexName child_name(VertexName a, VertexName b) {
  if (a > b) std::swap(a, b);  // the parents' order is not part of the name
  // splitmix64's finaliser over a combination of both: well spread, cheap.
  VertexName h = a * 0x9E3779B97F4A7C15ull + (b ^ 0xD1B54A32D192ED03ull);
  h ^= h >> 31;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 29;
  h *= 0x94D049BB133111EBull;
  h ^= h >> 32;
  return h | (VertexName{1} << 63);
}

std::vector<VertexName> vertex_names(const RgbMesh& mesh) {
  std::vector<VertexName> name(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  std::vector<char> known(name.size(), 0);
  std::vector<VertexHandle> pending;
  // Parents before children, without recursion: a vertex waits on the stack until both
  // parents are named (a chain is at most the mesh's depth in levels).
  for (const VertexHandle v : mesh.vertices()) {
    pending.push_back(v);
    while (!pending.empty()) {
      const VertexHandle u = pending.back();
      const auto s = static_cast<std::size_t>(u.idx);
      if (known[s]) {
        pending.pop_back();
        continue;
      }
      if (mesh.level(u) == 0) {
        name[s] = static_cast<VertexName>(u.idx);
        known[s] = 1;
        pending.pop_back();
        continue;
      }
      const auto& p = mesh.parents(u);
      const auto a = static_cast<std::size_t>(p[0].idx), b = static_cast<std::size_t>(p[1].idx);
      if (!known[a]) {
        pending.push_back(p[0]);
      } else if (!known[b]) {
        pending.push_back(p[1]);
      } else {
        name[s] = child_name(name[a], name[b]);
        known[s] = 1;
        pending.pop_back();
      }
    }
  }
  return name;
}

namespace {

// Whether e is a trapezoid's diagonal (a red edge between a red and a blue triangle of its
// level) that does not end at the corner with the smallest name.
bool off_canonical_diagonal(const RgbMesh& mesh, const std::vector<VertexName>& names, EdgeHandle e) {
  if (!mesh.alive(e) || !mesh.is_red(e)) return false;
  const auto& t = mesh.edge_triangles(e);
  if (!t[1].valid()) return false;
  const int l = mesh.level(e);
  if (mesh.level(t[0]) != l || mesh.level(t[1]) != l) return false;
  const Color c0 = mesh.color(t[0]), c1 = mesh.color(t[1]);
  if (!((c0 == Color::red && c1 == Color::blue) || (c0 == Color::blue && c1 == Color::red))) return false;
  const auto name = [&names](VertexHandle v) { return names[static_cast<std::size_t>(v.idx)]; };
  // The trapezoid's corners: the diagonal's ends and the two opposite corners.
  const auto& d = mesh.edge_vertices(e);
  const VertexName on_diagonal = std::min(name(d[0]), name(d[1]));
  const VertexName off_diagonal = std::min(name(mesh.opposite_vertex(t[0], e)), name(mesh.opposite_vertex(t[1], e)));
  return off_diagonal < on_diagonal;
}

}  // namespace

std::size_t canonical_diagonals(RgbMesh& mesh, const std::vector<VertexName>& names) {
  std::size_t swaps = 0;
  const std::int32_t slots = mesh.edge_slots();
  for (std::int32_t i = 0; i < slots; ++i) {
    // Each pair of triangles is the trapezoid of one parent, disjoint from every other pair:
    // one pass is enough.
    const EdgeHandle e(i);
    if (!off_canonical_diagonal(mesh, names, e)) continue;
    mesh.swap_rb(e);
    ++swaps;
  }
  return swaps;
}

std::size_t canonical_diagonals_near(RgbMesh& mesh, const std::vector<VertexName>& names,
                                     const std::vector<VertexHandle>& vertices) {
  // A trapezoid that an operation made or changed has a triangle at one of the vertices it
  // inserted or whose star it changed; its diagonal is an edge of that triangle.
  // Called after every operation of a stage: the scratch space is kept between calls.
  thread_local std::vector<EdgeHandle> candidates;
  thread_local VertexStar star;
  candidates.clear();
  for (const VertexHandle v : vertices) {
    if (!mesh.alive(v)) continue;
    mesh.star(v, star);
    for (const TriangleHandle t : star.triangles)
      for (const EdgeHandle f : mesh.triangle_edges(t))
        if (mesh.is_red(f)) candidates.push_back(f);
  }
  std::sort(candidates.begin(), candidates.end(), [](EdgeHandle a, EdgeHandle b) { return a.idx < b.idx; });
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  std::size_t swaps = 0;
  for (const EdgeHandle e : candidates) {
    if (!off_canonical_diagonal(mesh, names, e)) continue;
    mesh.swap_rb(e);
    ++swaps;
  }
  return swaps;
}

std::vector<VertexHandle> canonical_vertex_order(const RgbMesh& mesh) {
  // Every vertex's level, then a counting sort by level; within a level the key is the pair of
  // the parents' ranks, which the coarser levels have fixed already. Two vertices of one level
  // never share both parents (they would be the midpoint of one edge), so keys are unique.
  const std::size_t slots = static_cast<std::size_t>(mesh.vertex_slots());
  std::vector<std::size_t> count;
  for (const VertexHandle v : mesh.vertices()) {
    const auto l = static_cast<std::size_t>(mesh.level(v));
    if (count.size() <= l + 1) count.resize(l + 2, 0);
    ++count[l + 1];
  }
  for (std::size_t l = 1; l < count.size(); ++l) count[l] += count[l - 1];
  std::vector<VertexHandle> order(mesh.num_vertices());
  {
    std::vector<std::size_t> next(count.begin(), count.end());
    for (const VertexHandle v : mesh.vertices()) order[next[static_cast<std::size_t>(mesh.level(v))]++] = v;
  }
  // Level 0 is in slot order already: a base vertex's slot is its base index.
  std::vector<std::uint32_t> rank(slots, 0);
  std::vector<std::pair<std::uint64_t, VertexHandle>> keyed;
  for (std::size_t l = 0; l + 1 < count.size(); ++l) {
    const std::size_t begin = count[l], end = count[l + 1];
    if (l > 0) {
      keyed.clear();
      for (std::size_t i = begin; i < end; ++i) {
        const auto& p = mesh.parents(order[i]);
        std::uint64_t a = rank[static_cast<std::size_t>(p[0].idx)], b = rank[static_cast<std::size_t>(p[1].idx)];
        if (a > b) std::swap(a, b);
        keyed.emplace_back(a << 32 | b, order[i]);
      }
      std::sort(keyed.begin(), keyed.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
      for (std::size_t i = begin; i < end; ++i) order[i] = keyed[i - begin].second;
    }
    for (std::size_t i = begin; i < end; ++i) rank[static_cast<std::size_t>(order[i].idx)] = static_cast<std::uint32_t>(i);
  }
  return order;
}

std::vector<TriangleHandle> canonical_triangle_order(const RgbMesh& mesh, const std::vector<VertexHandle>& vertex_order) {
  std::vector<std::uint32_t> rank(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  for (std::size_t i = 0; i < vertex_order.size(); ++i) rank[static_cast<std::size_t>(vertex_order[i].idx)] = static_cast<std::uint32_t>(i);
  // Each triangle's key: its first corner's rank and the other two's, in the triangle's order.
  struct Keyed {
    std::uint32_t first;
    std::uint64_t rest;
    TriangleHandle t;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(mesh.num_triangles());
  std::vector<std::size_t> start(vertex_order.size() + 1, 0);
  for (const TriangleHandle t : mesh.triangles()) {
    const auto c = mesh.triangle_vertices(t);
    const std::uint32_t r[3] = {rank[static_cast<std::size_t>(c[0].idx)], rank[static_cast<std::size_t>(c[1].idx)],
                                rank[static_cast<std::size_t>(c[2].idx)]};
    const int k = r[0] < r[1] ? (r[0] < r[2] ? 0 : 2) : (r[1] < r[2] ? 1 : 2);
    keyed.push_back({r[k], std::uint64_t{r[(k + 1) % 3]} << 32 | r[(k + 2) % 3], t});
    ++start[r[k] + 1];
  }
  // A counting sort by the first corner, then each bucket (the triangles at one vertex, a
  // handful) by the other two.
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<Keyed> sorted(keyed.size());
  {
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (const Keyed& x : keyed) sorted[next[x.first]++] = x;
  }
  std::vector<TriangleHandle> order;
  order.reserve(sorted.size());
  for (std::size_t v = 0; v + 1 < start.size(); ++v) {
    const auto b = sorted.begin() + static_cast<std::ptrdiff_t>(start[v]), e = sorted.begin() + static_cast<std::ptrdiff_t>(start[v + 1]);
    std::sort(b, e, [](const Keyed& x, const Keyed& y) { return x.rest < y.rest; });
    for (auto it = b; it != e; ++it) order.push_back(it->t);
  }
  return order;
}

}  // namespace rgbmesh
