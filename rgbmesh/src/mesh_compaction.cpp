// RgbMesh::compact: the free slots' memory given back (issue 44). A mesh keeps the slots of its
// largest size (free lists reuse them, nothing shrinks): the moving peak ends with 944,512
// vertex slots for 61,574 vertices. Compaction moves the live elements down, in their order,
// and sizes every array to them.

#include <algorithm>
#include <exception>
#include <utility>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

namespace {

// new_slot[old] for slots alive by `alive`, -1 for free ones; returns the number alive.
template <class Alive>
std::size_t number_live(std::size_t slots, Alive alive, std::vector<std::int32_t>& new_slot) {
  new_slot.assign(slots, -1);
  std::int32_t next = 0;
  for (std::size_t i = 0; i < slots; ++i)
    if (alive(i)) new_slot[i] = next++;
  return static_cast<std::size_t>(next);
}

// The live entries of a per-slot array, in their new slots (exactly sized).
template <class T>
std::vector<T> moved(const std::vector<T>& by_slot, const std::vector<std::int32_t>& new_slot, std::size_t live) {
  std::vector<T> out;
  if (by_slot.empty()) return out;  // (optional arrays: sharp features, generations)
  out.reserve(live);
  for (std::size_t i = 0; i < new_slot.size(); ++i)
    if (new_slot[i] >= 0) out.push_back(by_slot[i]);
  return out;
}

}  // namespace

double RgbMesh::live_fraction() const {
  return v_edge_.empty() ? 1.0 : static_cast<double>(n_vertices_) / static_cast<double>(v_edge_.size());
}

RgbMesh::Renumbering RgbMesh::compact() {
  if (journal_ != nullptr) fail("compact", "called while compute_limits is running (from an observer)");
  Renumbering map;
  const std::size_t nv = number_live(v_edge_.size(), [&](std::size_t i) { return v_edge_[i].valid(); }, map.vertex);
  const std::size_t ne = number_live(e_vert_.size(), [&](std::size_t i) { return e_vert_[i][0].valid(); }, map.edge);
  const std::size_t nt = number_live(t_edge_.size(), [&](std::size_t i) { return t_edge_[i][0].valid(); }, map.triangle);

  // Generations: a slot's next generation is one more than the larger of its own and that of
  // the element moving in, so that every handle made before is stale (checked handles only).
  const auto next_generations = [](const Generations& g, const std::vector<std::int32_t>& new_slot,
                                   std::size_t live) {
    Generations out;
    if (g.empty()) return out;
    out.assign(live, 0);
    for (std::size_t i = 0; i < new_slot.size(); ++i)
      if (new_slot[i] >= 0) {
        const auto to = static_cast<std::size_t>(new_slot[i]);
        out[to] = std::max(g[to], g[i]) + 1;
      }
    return out;
  };
  Generations vg = next_generations(v_generation_, map.vertex, nv);
  Generations eg = next_generations(e_generation_, map.edge, ne);
  Generations tg = next_generations(t_generation_, map.triangle, nt);
  const auto vertex = [&](VertexHandle v) {
    return v.valid() && map.vertex[static_cast<std::size_t>(v.idx)] >= 0
               ? stamped(VertexHandle(map.vertex[static_cast<std::size_t>(v.idx)]), vg)
               : VertexHandle();
  };
  const auto edge = [&](EdgeHandle e) {
    return e.valid() ? stamped(EdgeHandle(map.edge[static_cast<std::size_t>(e.idx)]), eg) : EdgeHandle();
  };
  const auto triangle = [&](TriangleHandle t) {
    return t.valid() ? stamped(TriangleHandle(map.triangle[static_cast<std::size_t>(t.idx)]), tg)
                     : TriangleHandle();
  };

  // Every new array is made before anything changes (std::bad_alloc leaves the mesh as it was).
  std::vector<EdgeHandle> v_edge = moved(v_edge_, map.vertex, nv);
  for (EdgeHandle& e : v_edge) e = edge(e);
  std::vector<std::array<VertexHandle, 2>> v_parents = moved(v_parents_, map.vertex, nv);
  for (auto& parents : v_parents) parents = {vertex(parents[0]), vertex(parents[1])};
  std::vector<std::uint8_t> v_level = moved(v_level_, map.vertex, nv);
  std::vector<Vec3> v_control = moved(v_control_, map.vertex, nv);
  // Known limit positions (a side table with free entries of its own) packed in vertex order.
  std::vector<std::int32_t> v_limit_index = moved(v_limit_index_, map.vertex, nv);
  std::vector<Vec3> limits;
  limits.reserve(static_cast<std::size_t>(std::count_if(v_limit_index.begin(), v_limit_index.end(),
                                                        [](std::int32_t i) { return i >= 0; })));
  for (std::int32_t& i : v_limit_index)
    if (i >= 0) {
      limits.push_back(limits_[static_cast<std::size_t>(i)]);
      i = static_cast<std::int32_t>(limits.size() - 1);
    }
  std::vector<std::uint8_t> v_flags = moved(v_flags_, map.vertex, nv);
  std::vector<std::int32_t> v_rail = moved(v_rail_, map.vertex, nv);
  std::vector<std::uint32_t> v_rail_position = moved(v_rail_position_, map.vertex, nv);
  std::unordered_map<std::int32_t, VertexHistory> history;
  history.reserve(history_.size());
  for (const auto& [slot, h] : history_)
    if (map.vertex[static_cast<std::size_t>(slot)] >= 0) history.emplace(map.vertex[static_cast<std::size_t>(slot)], h);

  std::vector<std::array<VertexHandle, 2>> e_vert = moved(e_vert_, map.edge, ne);
  for (auto& ends : e_vert) ends = {vertex(ends[0]), vertex(ends[1])};
  std::vector<std::array<TriangleHandle, 2>> e_tri = moved(e_tri_, map.edge, ne);
  for (auto& sides : e_tri) sides = {triangle(sides[0]), triangle(sides[1])};
  std::vector<std::uint8_t> e_info = moved(e_info_, map.edge, ne);

  std::vector<std::array<EdgeHandle, 3>> t_edge = moved(t_edge_, map.triangle, nt);
  for (auto& sides : t_edge) sides = {edge(sides[0]), edge(sides[1]), edge(sides[2])};
  std::vector<std::uint8_t> t_info = moved(t_info_, map.triangle, nt);

  // Nothing below allocates (but shrink_to_fit, which gives up rather than fail).
  v_edge_.swap(v_edge);
  v_parents_.swap(v_parents);
  v_level_.swap(v_level);
  v_control_.swap(v_control);
  v_limit_index_.swap(v_limit_index);
  limits_.swap(limits);
  limits_free_head_ = -1;  // packed: no free entries
  limits_free_count_ = 0;
  v_flags_.swap(v_flags);
  v_rail_.swap(v_rail);
  v_rail_position_.swap(v_rail_position);
  history_.swap(history);
  v_generation_.swap(vg);
  e_vert_.swap(e_vert);
  e_tri_.swap(e_tri);
  e_info_.swap(e_info);
  e_generation_.swap(eg);
  t_edge_.swap(t_edge);
  t_info_.swap(t_info);
  t_generation_.swap(tg);
  // Properties in place: user data is moved, not copied (their views keep pointing at them).
  for (const auto& p : vertex_properties_) p->renumber(map.vertex, nv);
  v_free_ = e_free_ = t_free_ = -1;

  std::exception_ptr first;
  for (const auto& o : renumbering_observers_) {
    try {
      o.cb(map);
    } catch (...) {
      if (!first) first = std::current_exception();
    }
  }
  rethrow_if(first);
  return map;
}

}  // namespace rgbmesh
