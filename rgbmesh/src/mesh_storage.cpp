// RgbMesh storage: copying, capacity, the free lists as validate() reads them, handles in
// messages and checks, observers. (Taking and freeing slots is in mesh_primitives.cpp.)

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

void detail::bad_handle(const char* accessor, const std::string& what) {
  // An accessor has no way to report an error but this: it is a programming error, like an
  // out-of-range index, and continuing would read another element's data.
  std::fprintf(stderr, "rgbmesh: %s: %s\n", accessor, what.c_str());
  std::fflush(stderr);
  std::abort();
}

// ---------------------------------------------------------------------------------------
// Copying: topology, geometry and property values; observers belong to the original.

RgbMesh::RgbMesh(const RgbMesh& o)
    : v_edge_(o.v_edge_),
      v_level_(o.v_level_),
      v_parents_(o.v_parents_),
      v_control_(o.v_control_),
      v_limit_index_(o.v_limit_index_),
      limits_(o.limits_),
      limits_free_head_(o.limits_free_head_),
      limits_free_count_(o.limits_free_count_),
      v_flags_(o.v_flags_),
      base_eigenvalue_(o.base_eigenvalue_),
      creases_(o.creases_),
      v_rail_(o.v_rail_),
      v_rail_position_(o.v_rail_position_),
      history_(o.history_),
      v_free_(o.v_free_),
      v_generation_(o.v_generation_),
      e_vert_(o.e_vert_),
      e_tri_(o.e_tri_),
      e_info_(o.e_info_),
      e_free_(o.e_free_),
      e_generation_(o.e_generation_),
      t_edge_(o.t_edge_),
      t_info_(o.t_info_),
      t_free_(o.t_free_),
      t_generation_(o.t_generation_),
      n_vertices_(o.n_vertices_),
      n_edges_(o.n_edges_),
      n_triangles_(o.n_triangles_),
      n_base_vertices_(o.n_base_vertices_),
      base_triangles_(o.base_triangles_),
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
// Capacity

void RgbMesh::grow_vertex_arrays(std::size_t capacity) {
  // A throwing reserve leaves every array as it was (only capacities may have grown).
  v_edge_.reserve(capacity);
  v_level_.reserve(capacity);
  v_parents_.reserve(capacity);
  v_control_.reserve(capacity);
  v_limit_index_.reserve(capacity);
  v_flags_.reserve(capacity);
  if (creases_) {
    v_rail_.reserve(capacity);
    v_rail_position_.reserve(capacity);
  }
#if RGBMESH_CHECKED_HANDLES
  v_generation_.reserve(capacity);
#endif
}

void RgbMesh::grow_edge_arrays(std::size_t capacity) {
  e_vert_.reserve(capacity);
  e_tri_.reserve(capacity);
  e_info_.reserve(capacity);
#if RGBMESH_CHECKED_HANDLES
  e_generation_.reserve(capacity);
#endif
}

void RgbMesh::grow_triangle_arrays(std::size_t capacity) {
  t_edge_.reserve(capacity);
  t_info_.reserve(capacity);
#if RGBMESH_CHECKED_HANDLES
  t_generation_.reserve(capacity);
#endif
}

void RgbMesh::reserve(std::size_t vertices, std::size_t edges, std::size_t triangles) {
  if (vertices > v_edge_.capacity()) grow_vertex_arrays(vertices);
  if (edges > e_vert_.capacity()) grow_edge_arrays(edges);
  if (triangles > t_edge_.capacity()) grow_triangle_arrays(triangles);
}

std::size_t RgbMesh::memory_bytes() const {
  const auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(v_edge_) + bytes(v_level_) + bytes(v_parents_) + bytes(v_control_) + bytes(v_limit_index_) +
         bytes(limits_) + bytes(v_flags_) + bytes(e_vert_) + bytes(e_tri_) +
         bytes(e_info_) + bytes(t_edge_) + bytes(t_info_) + bytes(base_eigenvalue_) + bytes(v_generation_) +
         bytes(e_generation_) + bytes(t_generation_) + bytes(base_triangles_) + bytes(v_rail_) +
         bytes(v_rail_position_) + history_bytes();
}

std::size_t RgbMesh::storage_bytes(std::size_t vertices, std::size_t edges, std::size_t triangles) {
  // Per vertex: its arrays, plus a limit position for about a
  // quarter of them (the side table).
  constexpr std::size_t generation = RGBMESH_CHECKED_HANDLES ? sizeof(std::uint32_t) : 0;
  const std::size_t vertex = sizeof(EdgeHandle) + sizeof(std::uint8_t) + sizeof(std::array<VertexHandle, 2>) +
                             sizeof(Vec3) + sizeof(std::int32_t) + sizeof(std::uint8_t) +
                             sizeof(Vec3) / 4 + generation;
  const std::size_t edge =
      sizeof(std::array<VertexHandle, 2>) + sizeof(std::array<TriangleHandle, 2>) + 1 + generation;
  const std::size_t triangle = sizeof(std::array<EdgeHandle, 3>) + 1 + generation;
  return vertices * vertex + edges * edge + triangles * triangle;
}

namespace {

// Follows a free list from its head; stops after `slots` steps so that a corrupted list (a
// cycle) cannot hang validate(), which then reports the repeated slot.
template <class Next>
std::vector<std::int32_t> follow(std::int32_t head, std::int32_t slots, Next next) {
  std::vector<std::int32_t> out;
  for (std::int32_t i = head; i >= 0 && i < slots && out.size() <= static_cast<std::size_t>(slots);
       i = next(i))
    out.push_back(i);
  return out;
}

}  // namespace

std::vector<std::int32_t> RgbMesh::free_vertex_slots() const {
  return follow(v_free_, vertex_slots(), [this](std::int32_t i) { return v_parents_[i][0].idx; });
}
std::vector<std::int32_t> RgbMesh::free_edge_slots() const {
  return follow(e_free_, edge_slots(), [this](std::int32_t i) { return e_tri_[i][0].idx; });
}
std::vector<std::int32_t> RgbMesh::free_triangle_slots() const {
  return follow(t_free_, triangle_slots(), [this](std::int32_t i) { return t_edge_[i][1].idx; });
}

// ---------------------------------------------------------------------------------------
// Handles in messages and checks

std::string RgbMesh::describe(VertexHandle v) const {
  std::ostringstream s;
  s << "vertex " << v.idx;
  if (alive(v)) {
    s << " (level " << level(v) << ")";
  } else if (!in_range(v.idx, v_edge_.size())) {
    s << (v.valid() ? " (out of range: " : " (invalid: ") << v_edge_.size() << " vertex slots)";
  } else if (v_edge_[v.idx].valid()) {
    s << " (stale: removed, and its slot now holds another vertex)";
  } else {
    s << " (not alive: removed)";
  }
  return s.str();
}

std::string RgbMesh::describe(EdgeHandle e) const {
  std::ostringstream s;
  s << "edge " << e.idx;
  if (alive(e)) {
    s << " (" << e_vert_[e.idx][0].idx << ", " << e_vert_[e.idx][1].idx << "; "
      << (is_red(e) ? "red" : "green") << ", level " << level(e) << ")";
  } else if (!in_range(e.idx, e_vert_.size())) {
    s << (e.valid() ? " (out of range: " : " (invalid: ") << e_vert_.size() << " edge slots)";
  } else if (e_vert_[e.idx][0].valid()) {
    s << " (stale: freed, and its slot now holds another edge)";
  } else {
    s << " (not alive: freed)";
  }
  return s.str();
}

std::string RgbMesh::describe(TriangleHandle t) const {
  std::ostringstream s;
  s << "triangle " << t.idx;
  if (alive(t)) {
    s << " (level " << level(t) << ")";
  } else if (!in_range(t.idx, t_edge_.size())) {
    s << (t.valid() ? " (out of range: " : " (invalid: ") << t_edge_.size() << " triangle slots)";
  } else if (t_edge_[t.idx][0].valid()) {
    s << " (stale: freed, and its slot now holds another triangle)";
  } else {
    s << " (not alive: freed)";
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
  drop(renumbering_observers_);
}

int RgbMesh::add_renumbering_observer(RenumberingCallback cb) {
  renumbering_observers_.push_back({next_observer_id_, std::move(cb)});
  return next_observer_id_++;
}

namespace {

// Every observer hears of every change, whatever the others do; the first exception is kept
// for the caller, who rethrows it once the mesh is consistent (see "Exceptions" in mesh.hpp).
template <class Observers, class... Args>
std::exception_ptr call_all(const Observers& observers, const Args&... args) {
  std::exception_ptr first;
  for (const auto& o : observers) {
    try {
      o.cb(args...);
    } catch (...) {
      if (!first) first = std::current_exception();
    }
  }
  return first;
}

}  // namespace

std::exception_ptr RgbMesh::notify_inserted(VertexHandle v) const {
  if (insertion_observers_.empty()) return {};
  const auto& p = v_parents_[v.idx];
  return call_all(insertion_observers_, v, p[0], p[1]);
}

std::exception_ptr RgbMesh::notify_removing(VertexHandle v) const {
  if (removal_observers_.empty()) return {};
  return call_all(removal_observers_, stamped(v));
}

}  // namespace rgbmesh
