// RgbMesh::from_triangles: the base mesh Σ0, after the checks that prepare_triangle_mesh makes
// (triangle_checks.hpp: one copy of them for both entry points).

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "creases.hpp"
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

RgbMesh RgbMesh::from_triangles(const std::vector<Vec3>& points,
                                const std::vector<std::array<std::int32_t, 3>>& triangles, const SharpFeatures& sharp,
                                PointRole role) {
  RgbMesh m = from_triangles(points, triangles, role);
  // The normal form: each edge and vertex once (the last entry counts, as in OpenSubdiv's
  // shape files), no boundary edge, no zero, at most 10.
  const auto n = static_cast<std::int64_t>(points.size());
  const auto sharpness_error = [](const std::string& what, float s) {
    if (!std::isfinite(s) || s < 0.0f)
      throw InputError(what + " has sharpness " + std::to_string(s) + " (0 or more; 10 is infinitely sharp)");
  };
  std::map<std::pair<std::int32_t, std::int32_t>, float> edges;
  for (std::size_t i = 0; i < sharp.edges.size(); ++i) {
    const SharpEdge& e = sharp.edges[i];
    const std::string what =
        "sharp edge " + std::to_string(i) + " (" + std::to_string(e.a) + ", " + std::to_string(e.b) + ")";
    if (e.a < 0 || e.a >= n || e.b < 0 || e.b >= n)
      throw InputError(what + " names a vertex outside 0.." + std::to_string(n - 1));
    const EdgeHandle h = e.a == e.b ? EdgeHandle() : m.find_edge(VertexHandle(e.a), VertexHandle(e.b));
    if (!h.valid()) throw InputError(what + " is not an edge of the mesh");
    sharpness_error(what, e.sharpness);
    if (m.is_boundary(h)) continue;  // infinitely sharp already
    edges[{std::min(e.a, e.b), std::max(e.a, e.b)}] = std::min(e.sharpness, kInfiniteSharpness);
  }
  std::map<std::int32_t, float> vertices;
  for (std::size_t i = 0; i < sharp.vertices.size(); ++i) {
    const SharpVertex& v = sharp.vertices[i];
    const std::string what = "sharp vertex " + std::to_string(i) + " (" + std::to_string(v.v) + ")";
    if (v.v < 0 || v.v >= n) throw InputError(what + " is outside 0.." + std::to_string(n - 1));
    sharpness_error(what, v.sharpness);
    vertices[v.v] = std::min(v.sharpness, kInfiniteSharpness);
  }
  SharpFeatures normal;
  normal.method = sharp.method;
  for (const auto& [ends, s] : edges)
    if (s > 0.0f) normal.edges.push_back({ends.first, ends.second, s});
  for (const auto& [v, s] : vertices)
    if (s > 0.0f) normal.vertices.push_back({v, s});
  if (normal.empty()) return m;
  m.creases_ = std::make_shared<const detail::CreaseTable>(normal, points.size());
  m.v_rail_.reserve(m.v_edge_.capacity());  // grows with the other vertex arrays (make_room)
  m.v_rail_position_.reserve(m.v_edge_.capacity());
  m.v_rail_.assign(m.v_edge_.size(), -1);
  m.v_rail_position_.assign(m.v_edge_.size(), 0);
  m.init_sharp_base_geometry();
  return m;
}

}  // namespace rgbmesh
