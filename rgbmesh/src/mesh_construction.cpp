// RgbMesh::from_triangles: the base mesh Σ0.

#include <unordered_map>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/soup.hpp"

namespace rgbmesh {

namespace {

std::uint64_t pair_key(std::int32_t a, std::int32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Construction

RgbMesh RgbMesh::from_triangles(const std::vector<Vec3>& points,
                                const std::vector<std::array<std::int32_t, 3>>& triangles) {
  RgbMesh m;
  const auto nv = static_cast<std::int32_t>(points.size());
  if (nv == 0 || triangles.empty()) throw InputError("the mesh is empty");
  m.v_edge_.assign(nv, EdgeHandle());
  m.v_level_.assign(nv, 0);
  m.v_parents_.assign(nv, {VertexHandle(), VertexHandle()});
  m.v_control_ = points;
  m.n_vertices_ = static_cast<std::size_t>(nv);
  m.n_base_vertices_ = m.n_vertices_;

  std::unordered_map<std::uint64_t, EdgeHandle> edge_of;
  edge_of.reserve(triangles.size() * 2);
  m.t_edge_.reserve(triangles.size());
  m.t_info_.reserve(triangles.size());
  for (std::size_t ti = 0; ti < triangles.size(); ++ti) {
    const auto& tri = triangles[ti];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= nv)
        throw InputError("triangle " + std::to_string(ti) + " references vertex " + std::to_string(tri[k]) +
                         " out of range");
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0])
      throw InputError("triangle " + std::to_string(ti) + " is degenerate");
    const TriangleHandle t(static_cast<std::int32_t>(ti));
    std::array<EdgeHandle, 3> te;
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = tri[k], b = tri[(k + 1) % 3];
      auto [it, inserted] = edge_of.try_emplace(pair_key(a, b), EdgeHandle());
      if (inserted) {
        const EdgeHandle e(static_cast<std::int32_t>(m.e_vert_.size()));
        m.e_vert_.push_back({VertexHandle(a), VertexHandle(b)});
        m.e_tri_.push_back({t, TriangleHandle()});
        m.e_info_.push_back(edge_info(false, 0));
        it->second = e;
        m.v_edge_[a] = e;
        m.v_edge_[b] = e;
      } else {
        const EdgeHandle e = it->second;
        auto& et = m.e_tri_[e.idx];
        // The second triangle of an edge must traverse it in the opposite direction.
        if (et[1].valid())
          throw InputError("edge (" + std::to_string(a) + ", " + std::to_string(b) +
                           ") is shared by more than two triangles");
        if (m.e_vert_[e.idx][0].idx != b)
          throw InputError("triangle " + std::to_string(ti) +
                           " is oriented inconsistently with its neighbour across edge (" +
                           std::to_string(a) + ", " + std::to_string(b) + ")");
        et[1] = t;
      }
      te[k] = it->second;
    }
    m.t_edge_.push_back(te);
    m.t_info_.push_back(0);  // green, level 0
  }
  m.n_edges_ = m.e_vert_.size();
  m.n_triangles_ = m.t_edge_.size();
  for (std::int32_t v = 0; v < nv; ++v) {
    if (!m.v_edge_[v].valid())
      throw InputError("vertex " + std::to_string(v) + " is not referenced by any triangle");
  }
  // Manifold vertices: the fan reached from the stored edge must cover every incident edge.
  std::vector<int> degree(nv, 0);
  for (const auto& ev : m.e_vert_) {
    ++degree[ev[0].idx];
    ++degree[ev[1].idx];
  }
  VertexStar s;
  for (std::int32_t v = 0; v < nv; ++v) {
    m.star(VertexHandle(v), s);
    if (static_cast<int>(s.edges.size()) != degree[v])
      throw InputError("vertex " + std::to_string(v) + " is non-manifold");
  }
  m.base_euler_ = m.euler_characteristic();
  m.init_base_geometry();
  return m;
}

}  // namespace rgbmesh
