// rgbmesh::parallel::local_view (local_view.hpp).

#include "rgbmesh/parallel/local_view.hpp"

#include <stdexcept>

#include "rgbmesh/refinement.hpp"

namespace rgbmesh::parallel {

namespace {

// Removes the unprotected vertices above the floor, finest first.
class AwayFromKept final : public LodCriterion {
 public:
  AwayFromKept(const std::vector<char>& kept_vertex, int floor) : kept_(kept_vertex), floor_(floor) {}
  double vertex_priority(const RgbMesh& m, VertexHandle v) const override {
    const auto slot = static_cast<std::size_t>(v.idx);
    if (slot < kept_.size() && kept_[slot]) return 0;
    return m.level(v) > floor_ ? static_cast<double>(m.level(v)) : 0;
  }

 private:
  const std::vector<char>& kept_;
  int floor_;
};

}  // namespace

RgbMesh local_view(const RgbMesh& mesh, const std::vector<char>& keep, int floor, int ghost_layers) {
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
  RgbMesh view = mesh;
  // A removal can make a coarser vertex removable: again until nothing more goes.
  const AwayFromKept criterion(kept_vertex, floor);
  while (selective_refinement(view, criterion).removals > 0) {
  }
  return view;
}

}  // namespace rgbmesh::parallel
