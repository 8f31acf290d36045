// RgbMesh::from_triangles: the base mesh Σ0, after the checks that prepare_triangle_mesh makes
// (triangle_checks.hpp: one copy of them for both entry points).

#include <string>

#include "rgbmesh/mesh.hpp"
#include "triangle_checks.hpp"

namespace rgbmesh {

namespace {

// Where prepare_triangle_mesh would repair, the library rejects (see from_triangles in
// mesh.hpp): the caller's indices must keep their meaning, and there are no notes to tell.
constexpr const char* repair_hint = " (prepare_triangle_mesh repairs this)";

void reject_what_needs_repair(std::size_t n_points, const std::vector<detail::Triangle>& triangles,
                              const detail::SurfaceCheck& surface) {
  if (surface.flips > 0) {
    const detail::InconsistentPair pair = detail::first_inconsistent_pair(surface.half_edges);
    throw InputError("triangles " + std::to_string(pair.first) + " and " + std::to_string(pair.second) +
                     " are oriented inconsistently across edge (" + std::to_string(pair.lo) + ", " +
                     std::to_string(pair.hi) + ")" + repair_hint);
  }
  std::vector<bool> referenced(n_points, false);
  for (const auto& t : triangles)
    for (const std::int32_t v : t) referenced[v] = true;
  for (std::size_t v = 0; v < n_points; ++v) {
    if (!referenced[v])
      throw InputError("vertex " + std::to_string(v) + " is not referenced by any triangle" + repair_hint);
  }
}

}  // namespace

RgbMesh RgbMesh::from_triangles(const std::vector<Vec3>& points,
                                const std::vector<std::array<std::int32_t, 3>>& triangles, PointRole role) {
  detail::check_points(points, triangles.size(), detail::mesh_wording);
  detail::check_indices(triangles, points.size(), detail::mesh_wording);
  detail::check_triangle_count(triangles.size());
  const std::vector<std::int64_t> no_source_faces;  // triangle i is the caller's triangle i
  const detail::SurfaceCheck surface = detail::check_surface(
      points, triangles, detail::TriangleNames(no_source_faces),
      role == PointRole::surface ? detail::AreaCheck::zero_area_is_degenerate : detail::AreaCheck::skip);
  reject_what_needs_repair(points.size(), triangles, surface);

  RgbMesh m;
  const std::size_t nt = triangles.size();
  m.v_edge_.assign(points.size(), EdgeHandle());
  m.v_level_.assign(points.size(), 0);
  m.v_parents_.assign(points.size(), {VertexHandle(), VertexHandle()});
  m.v_control_ = points;
  m.n_vertices_ = points.size();
  m.n_base_vertices_ = m.n_vertices_;
  m.base_triangles_ = triangles;  // kept for saving the state (rgb_state.hpp)
#if RGBMESH_CHECKED_HANDLES
  m.v_generation_.assign(points.size(), 1);
#endif

  // The checks sorted the half-edges so that the two sides of an edge are adjacent: number
  // the groups, then give the edges their handles in the order the triangles first use them
  // (triangle by triangle, corner by corner), running from the corner where they were first
  // met. Boundary edges have one side, interior ones two (the checks allow no more).
  const std::vector<detail::HalfEdge>& half_edges = surface.half_edges;
  std::vector<std::int32_t> group_of_side(3 * nt);
  std::int32_t groups = 0;
  for (std::size_t i = 0; i < half_edges.size(); ++i) {
    if (i > 0 && !half_edges[i].same_edge(half_edges[i - 1])) ++groups;
    group_of_side[3 * static_cast<std::size_t>(half_edges[i].triangle) + half_edges[i].k] = groups;
  }
  ++groups;
  std::vector<std::int32_t> edge_of_group(static_cast<std::size_t>(groups), -1);
  m.e_vert_.reserve(static_cast<std::size_t>(groups));
  m.e_tri_.reserve(static_cast<std::size_t>(groups));
  m.e_info_.reserve(static_cast<std::size_t>(groups));
  m.t_edge_.reserve(nt);
  m.t_info_.assign(nt, 0);  // green, level 0
  for (std::size_t ti = 0; ti < nt; ++ti) {
    const TriangleHandle t(static_cast<std::int32_t>(ti));
    std::array<EdgeHandle, 3> te;
    for (int k = 0; k < 3; ++k) {
      std::int32_t& edge = edge_of_group[group_of_side[3 * ti + k]];
      if (edge < 0) {
        const std::int32_t a = triangles[ti][k], b = triangles[ti][(k + 1) % 3];
        edge = static_cast<std::int32_t>(m.e_vert_.size());
        m.e_vert_.push_back({VertexHandle(a), VertexHandle(b)});
        m.e_tri_.push_back({t, TriangleHandle()});
        m.e_info_.push_back(edge_info(false, 0));
        m.v_edge_[a] = EdgeHandle(edge);
        m.v_edge_[b] = EdgeHandle(edge);
      } else {
        m.e_tri_[edge][1] = t;
      }
      te[k] = EdgeHandle(edge);
    }
    m.t_edge_.push_back(te);
  }
  m.n_edges_ = m.e_vert_.size();
  m.n_triangles_ = m.t_edge_.size();
#if RGBMESH_CHECKED_HANDLES
  // Every stored handle carries its slot's generation, 1 for all here.
  m.e_generation_.assign(m.e_vert_.size(), 1);
  m.t_generation_.assign(nt, 1);
  for (auto& ev : m.e_vert_)
    for (VertexHandle& v : ev) v = m.stamped(v);
  for (auto& et : m.e_tri_)
    for (TriangleHandle& t : et)
      if (t.valid()) t = m.stamped(t);
  for (auto& te : m.t_edge_)
    for (EdgeHandle& e : te) e = m.stamped(e);
  for (EdgeHandle& e : m.v_edge_) e = m.stamped(e);
#endif
  m.base_euler_ = m.euler_characteristic();
  m.init_base_geometry();
  return m;
}

}  // namespace rgbmesh
