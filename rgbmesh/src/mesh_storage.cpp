// RgbMesh storage: copying, capacity, handles in messages, observers.

#include <algorithm>
#include <sstream>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

// ---------------------------------------------------------------------------------------
// Copying: topology, geometry and property values; observers belong to the original.

RgbMesh::RgbMesh(const RgbMesh& o)
    : v_edge_(o.v_edge_),
      v_level_(o.v_level_),
      v_parents_(o.v_parents_),
      v_control_(o.v_control_),
      v_limit_index_(o.v_limit_index_),
      limits_(o.limits_),
      limits_free_(o.limits_free_),
      v_flags_(o.v_flags_),
      base_eigenvalue_(o.base_eigenvalue_),
      v_free_(o.v_free_),
      e_vert_(o.e_vert_),
      e_tri_(o.e_tri_),
      e_info_(o.e_info_),
      e_free_(o.e_free_),
      t_edge_(o.t_edge_),
      t_info_(o.t_info_),
      t_free_(o.t_free_),
      n_vertices_(o.n_vertices_),
      n_edges_(o.n_edges_),
      n_triangles_(o.n_triangles_),
      n_base_vertices_(o.n_base_vertices_),
      base_euler_(o.base_euler_),
      counters_(o.counters_) {
  for (const auto& p : o.vertex_properties_) vertex_properties_.push_back(p->clone());
}

RgbMesh& RgbMesh::operator=(const RgbMesh& o) {
  if (this != &o) {
    RgbMesh copy(o);
    *this = std::move(copy);
  }
  return *this;
}

// ---------------------------------------------------------------------------------------
// Allocation

void RgbMesh::reserve(std::size_t vertices, std::size_t edges, std::size_t triangles) {
  if (vertices > v_edge_.capacity()) {
    v_edge_.reserve(vertices);
    v_level_.reserve(vertices);
    v_parents_.reserve(vertices);
    v_control_.reserve(vertices);
    v_limit_index_.reserve(vertices);
    v_flags_.reserve(vertices);
  }
  if (edges > e_vert_.capacity()) {
    e_vert_.reserve(edges);
    e_tri_.reserve(edges);
    e_info_.reserve(edges);
  }
  if (triangles > t_edge_.capacity()) {
    t_edge_.reserve(triangles);
    t_info_.reserve(triangles);
  }
}

std::size_t RgbMesh::memory_bytes() const {
  const auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(v_edge_) + bytes(v_level_) + bytes(v_parents_) + bytes(v_control_) + bytes(v_limit_index_) +
         bytes(limits_) + bytes(limits_free_) + bytes(v_flags_) + bytes(v_free_) + bytes(e_vert_) + bytes(e_tri_) +
         bytes(e_info_) + bytes(e_free_) + bytes(t_edge_) + bytes(t_info_) + bytes(t_free_) + bytes(base_eigenvalue_);
}

std::size_t RgbMesh::storage_bytes(std::size_t vertices, std::size_t edges, std::size_t triangles) {
  // Per vertex: its arrays, plus a limit position for about a quarter of them (the side table).
  const std::size_t vertex = sizeof(EdgeHandle) + sizeof(std::uint8_t) + sizeof(std::array<VertexHandle, 2>) +
                             sizeof(Vec3) + sizeof(std::int32_t) + sizeof(std::uint8_t) + sizeof(Vec3) / 4;
  const std::size_t edge = sizeof(std::array<VertexHandle, 2>) + sizeof(std::array<TriangleHandle, 2>) + 1;
  const std::size_t triangle = sizeof(std::array<EdgeHandle, 3>) + 1;
  return vertices * vertex + edges * edge + triangles * triangle;
}

std::string RgbMesh::describe(EdgeHandle e) const {
  std::ostringstream s;
  s << "edge " << e.idx;
  if (alive(e)) {
    s << " (" << e_vert_[e.idx][0].idx << ", " << e_vert_[e.idx][1].idx << "; "
      << (is_red(e) ? "red" : "green") << ", level " << level(e) << ")";
  } else {
    s << " (not alive)";
  }
  return s.str();
}

std::string RgbMesh::describe(VertexHandle v) const {
  std::ostringstream s;
  s << "vertex " << v.idx;
  if (alive(v)) {
    s << " (level " << level(v) << ")";
  } else {
    s << " (not alive)";
  }
  return s.str();
}

void RgbMesh::fail(const char* op, const std::string& what) const {
  throw PreconditionError(std::string(op) + ": " + what);
}

// ---------------------------------------------------------------------------------------
// Observers

int RgbMesh::add_insertion_observer(InsertionCallback cb) {
  insertion_observers_.push_back({next_observer_id_, std::move(cb)});
  return next_observer_id_++;
}

int RgbMesh::add_removal_observer(RemovalCallback cb) {
  removal_observers_.push_back({next_observer_id_, std::move(cb)});
  return next_observer_id_++;
}

void RgbMesh::remove_observer(int id) {
  auto drop = [id](auto& list) {
    list.erase(std::remove_if(list.begin(), list.end(), [id](const auto& o) { return o.id == id; }),
               list.end());
  };
  drop(insertion_observers_);
  drop(removal_observers_);
}

}  // namespace rgbmesh
