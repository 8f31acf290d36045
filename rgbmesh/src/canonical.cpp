// Vertex names and canonical trapezoid diagonals (canonical.hpp).

#include "rgbmesh/canonical.hpp"

#include <algorithm>

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

}  // namespace rgbmesh
