#pragma once
// What the VTK XML files hold, as the streaming writer's arrays (xml_stream.hpp): a mesh
// snapshot, a point cloud, or an RgbMesh read directly, without a snapshot.
//
// Arrays of a mesh file, in this order (rgb_state_io.hpp documents the rgb_ ones):
//   field data  rgb_state_version, rgb_base_points, rgb_base_triangles   (with a state)
//   point data  level (UInt8), every NamedArray (Float64; from RgbMesh: control_point, limit),
//               rgb_base_vertex, rgb_parents                              (with a state)
//   cell data   level, color (UInt8), every NamedArray (Float64)
// Both ways of writing a mesh give the same file byte for byte (tested).

#include <cstdint>
#include <memory>
#include <vector>

#include "rgbmesh/mesh.hpp"
#include "xml_stream.hpp"

namespace rgbmesh::detail {

// Arrays that read the snapshot's memory: it must outlive the write.
XmlDataSet snapshot_data_set(const MeshSnapshot& mesh, bool unstructured);

// Points as vertex cells (a point cloud .vtp), with Float64 point data.
XmlDataSet point_cloud_data_set(const std::vector<Vec3>& points, const std::vector<NamedArray>& point_data);

// The file RgbMesh::snapshot + save_state would give, computed block by block from the mesh as
// the file is written: besides the mesh, it holds a byte per vertex slot (shown levels) and,
// where the mesh has free slots, the numbering of its vertices and triangles (12 bytes per
// vertex). Every vertex needs its limit position (RgbMesh::compute_limits). The mesh must not
// change while the data set exists.
class MeshDataSet {
 public:
  MeshDataSet(const RgbMesh& mesh, bool unstructured, bool limit_points);
  const XmlDataSet& data() const { return data_; }

 private:
  VertexHandle vertex(std::size_t point) const {
    return VertexHandle(vertex_slot_.empty() ? static_cast<std::int32_t>(point) : vertex_slot_[point]);
  }
  // The slot of cell `cell`, and of the cell after the one in `slot`. Where the live triangles
  // are not the first slots, every kCellStride-th cell's slot is kept (4 bytes per 1,024 cells
  // instead of 4 per cell) and the slots between are walked: cells are written in ranges.
  static constexpr std::size_t kCellStride = 1024;
  std::int32_t triangle_slot(std::size_t cell) const {
    if (cell_checkpoint_.empty()) return static_cast<std::int32_t>(cell);
    std::int32_t slot = cell_checkpoint_[cell / kCellStride];
    for (std::size_t k = cell % kCellStride; k > 0; --k) slot = next_triangle_slot(slot);
    return slot;
  }
  std::int32_t next_triangle_slot(std::int32_t slot) const {
    if (cell_checkpoint_.empty()) return slot + 1;
    do ++slot;
    while (slot < mesh_.triangle_slots() && !mesh_.alive(TriangleHandle(slot)));
    return slot;
  }
  // Calls f(triangle) for cells [first, first + count).
  template <class F>
  void for_cells(std::size_t first, std::size_t count, F f) const {
    std::int32_t slot = triangle_slot(first);
    for (std::size_t i = 0; i < count; ++i, slot = next_triangle_slot(slot)) f(TriangleHandle(slot));
  }
  std::int32_t point(VertexHandle v) const { return point_of_slot_.empty() ? v.idx : point_of_slot_[v.idx]; }
  Vec3 shown_point(std::size_t point) const;

  const RgbMesh& mesh_;
  std::vector<std::uint8_t> shown_;         // per vertex slot
  std::vector<std::int32_t> vertex_slot_;   // point -> slot; empty where they are the same
  std::vector<std::int32_t> point_of_slot_; // slot -> point; empty where they are the same
  std::vector<std::int32_t> cell_checkpoint_; // slot of every kCellStride-th cell; empty where cells are slots
  XmlDataSet data_;
};

}  // namespace rgbmesh::detail
