// rgbmesh::parallel::local_view (local_view.hpp).

#include "rgbmesh/parallel/local_view.hpp"

#include <queue>
#include <stdexcept>
#include <utility>

#include "rgbmesh/canonical.hpp"

namespace rgbmesh::parallel {

namespace {

// Removes the vertices above the floor that are not kept, finest first (the level's highest
// first, then by slot), as far as they go. A removal can make only its neighbours removable
// (section V-A), so they are the ones tried again. The diagonals are chosen by names after
// every removal, as selective refinement's coarsening chooses them, since whether a neighbour
// is removable next depends on them. Written out instead of a selective_refinement run with a
// criterion: that run also tests every edge and triangle and computes every limit position,
// which a view's coarsening, several times a cycle, does not need.
std::size_t remove_unkept(RgbMesh& mesh, const std::vector<char>& kept_vertex, int floor) {
  const auto eligible = [&](VertexHandle v) {
    return !kept_vertex[static_cast<std::size_t>(v.idx)] && mesh.level(v) > floor && mesh.is_removable(v);
  };
  std::priority_queue<std::pair<int, std::int32_t>> queue;  // (level, slot)
  for (const VertexHandle v : mesh.vertices())
    if (eligible(v)) queue.emplace(mesh.level(v), v.idx);
  if (queue.empty()) return 0;
  const std::vector<VertexName> names = vertex_names(mesh);
  canonical_diagonals(mesh, names);
  std::size_t removed = 0;
  VertexStar star;
  while (!queue.empty()) {
    const VertexHandle v(queue.top().second);
    queue.pop();
    if (!mesh.alive(v) || !eligible(v)) continue;
    mesh.star(v, star);
    mesh.remove_vertex(v);
    canonical_diagonals_near(mesh, names, star.neighbors);
    ++removed;
    for (const VertexHandle n : star.neighbors)
      if (mesh.alive(n) && eligible(n)) queue.emplace(mesh.level(n), n.idx);
  }
  return removed;
}

}  // namespace

RgbMesh local_view(const RgbMesh& mesh, const std::vector<char>& keep, int floor, int ghost_layers) {
  RgbMesh view = mesh;
  coarsen_away(view, keep, floor, ghost_layers);
  return view;
}

std::size_t coarsen_away(RgbMesh& mesh, const std::vector<char>& keep, int floor, int ghost_layers) {
  if (keep.size() != static_cast<std::size_t>(mesh.triangle_slots()))
    throw std::invalid_argument("local_view: one flag per triangle slot is needed");
  if (ghost_layers < 0) throw std::invalid_argument("local_view: the ghost layers must be 0 or more");
  // The kept triangles' corners, then each ghost layer's.
  std::vector<char> kept_vertex(static_cast<std::size_t>(mesh.vertex_slots()), 0);
  for (const TriangleHandle t : mesh.triangles())
    if (keep[static_cast<std::size_t>(t.idx)])
      for (const VertexHandle v : mesh.triangle_vertices(t)) kept_vertex[static_cast<std::size_t>(v.idx)] = 1;
  for (int layer = 0; layer < ghost_layers; ++layer) {
    std::vector<char> next = kept_vertex;
    for (const TriangleHandle t : mesh.triangles()) {
      const auto c = mesh.triangle_vertices(t);
      bool touches = false;
      for (const VertexHandle v : c) touches = touches || kept_vertex[static_cast<std::size_t>(v.idx)];
      if (touches)
        for (const VertexHandle v : c) next[static_cast<std::size_t>(v.idx)] = 1;
    }
    kept_vertex = std::move(next);
  }
  return remove_unkept(mesh, kept_vertex, floor);
}

}  // namespace rgbmesh::parallel

namespace rgbmesh::parallel {

std::unordered_set<std::int32_t> vertex_slots_alive(const RgbMesh& mesh) {
  std::unordered_set<std::int32_t> s;
  for (const VertexHandle v : mesh.vertices()) s.insert(v.idx);
  return s;
}

VertexKeys vertex_keys(const RgbMesh& view, const std::unordered_set<std::int32_t>& start) {
  VertexKeys k;
  std::vector<VertexHandle> inserted;
  for (const VertexHandle v : view.vertices()) {
    if (start.count(v.idx)) {
      k.of_slot[v.idx] = static_cast<VertexKey>(v.idx);
      k.vertex[static_cast<VertexKey>(v.idx)] = v;
    } else {
      inserted.push_back(v);
    }
  }
  // Parents first: they are of lower level.
  std::sort(inserted.begin(), inserted.end(), [&view](VertexHandle a, VertexHandle b) { return view.level(a) < view.level(b); });
  for (const VertexHandle v : inserted) {
    const auto& p = view.parents(v);
    const VertexKey a = k.of_slot.at(p[0].idx), b = k.of_slot.at(p[1].idx), key = child_key(a, b);
    k.of_slot[v.idx] = key;
    k.vertex[key] = v;
    k.parents[key] = {a, b};
  }
  return k;
}

std::unordered_set<VertexKey> key_region(const std::unordered_set<VertexKey>& start, const VertexKeys& keys) {
  std::unordered_set<VertexKey> r = start;
  for (bool grew = true; grew;) {
    grew = false;
    for (const auto& [key, p] : keys.parents)
      if (!r.count(key) && r.count(p[0]) && r.count(p[1])) grew = r.insert(key).second || grew;
  }
  return r;
}

std::size_t make_splits(RgbMesh& view, const std::unordered_set<std::int32_t>& start,
                        const std::unordered_set<VertexKey>& fine,
                        const std::map<VertexKey, std::array<VertexKey, 2>>& splits) {
  std::size_t made = 0;
  // A split may make another possible (its parent inserted, its edge made green): again until
  // none is.
  for (bool again = true; again;) {
    again = false;
    const VertexKeys k = vertex_keys(view, start);
    const std::unordered_set<VertexKey> region = key_region(fine, k);
    for (const auto& [key, p] : splits) {
      if (k.vertex.count(key) || !region.count(p[0]) || !region.count(p[1])) continue;
      const EdgeHandle e = view.find_edge(k.vertex.at(p[0]), k.vertex.at(p[1]));
      if (!e.valid() || view.is_red(e)) continue;
      view.split_edge(e);
      ++made;
      again = true;
      break;  // the keys and handles change with every split
    }
  }
  return made;
}

}  // namespace rgbmesh::parallel
