// RgbMesh navigation: iteration over live elements, corners, rotation around a vertex and its
// star, boundary loops, and the output snapshot.

#include <algorithm>
#include <cassert>
#include <unordered_map>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

// ---------------------------------------------------------------------------------------
// Navigation

HandleRange<VertexHandle> RgbMesh::vertices() const {
  return {*this, vertex_slots(), [](const RgbMesh& m, std::int32_t i) { return m.v_edge_[i].valid(); }};
}
HandleRange<EdgeHandle> RgbMesh::edges() const {
  return {*this, edge_slots(), [](const RgbMesh& m, std::int32_t i) { return m.e_vert_[i][0].valid(); }};
}
HandleRange<TriangleHandle> RgbMesh::triangles() const {
  return {*this, triangle_slots(), [](const RgbMesh& m, std::int32_t i) { return m.t_edge_[i][0].valid(); }};
}

std::array<VertexHandle, 3> RgbMesh::triangle_vertices(TriangleHandle t) const {
  const auto& te = t_edge_[t.idx];
  const auto& a = e_vert_[te[0].idx];
  const auto& b = e_vert_[te[1].idx];
  // Corner 1 is shared by edges 0 and 1; corners 0 and 2 are their other ends.
  const VertexHandle c1 = (a[0] == b[0] || a[0] == b[1]) ? a[0] : a[1];
  const VertexHandle c0 = (c1 == a[0]) ? a[1] : a[0];
  const VertexHandle c2 = (c1 == b[0]) ? b[1] : b[0];
  return {c0, c1, c2};
}

int RgbMesh::local_index(TriangleHandle t, EdgeHandle e) const {
  const auto& te = t_edge_[t.idx];
  return te[0] == e ? 0 : (te[1] == e ? 1 : (te[2] == e ? 2 : -1));
}

VertexHandle RgbMesh::opposite_vertex(TriangleHandle t, EdgeHandle e) const {
  const int i = local_index(t, e);
  assert(i >= 0);
  // The far end of the next edge: the endpoint it does not share with e.
  const auto& n = e_vert_[t_edge_[t.idx][(i + 1) % 3].idx];
  const auto& ev = e_vert_[e.idx];
  return (n[0] == ev[0] || n[0] == ev[1]) ? n[1] : n[0];
}

void RgbMesh::replace_edge_triangle(EdgeHandle e, TriangleHandle from, TriangleHandle to) {
  auto& et = e_tri_[e.idx];
  if (et[0] == from) {
    et[0] = to;
  } else {
    assert(et[1] == from);
    et[1] = to;
  }
}

// Rotation around a vertex. In a triangle with v at corner i, edge i leaves v and edge i+2
// arrives at v; going counter-clockwise around v, the leaving edge comes first, and the next
// triangle counter-clockwise is the one beyond the arriving edge. Whether e leaves or arrives
// at v in t is read off the neighbouring edge of t: no corner computation needed.

// The triangle in which e leaves v, and that triangle's edge arriving at v.
std::pair<TriangleHandle, EdgeHandle> RgbMesh::leaving_triangle(VertexHandle v, EdgeHandle e) const {
  for (TriangleHandle t : e_tri_[e.idx]) {
    if (!t.valid()) continue;
    const auto& te = t_edge_[t.idx];
    const int i = te[0] == e ? 0 : (te[1] == e ? 1 : 2);
    const EdgeHandle prev = te[(i + 2) % 3];
    if (e_vert_[prev.idx][0] == v || e_vert_[prev.idx][1] == v) return {t, prev};
  }
  return {TriangleHandle(), EdgeHandle()};
}

// The triangle in which e arrives at v, and that triangle's edge leaving v.
std::pair<TriangleHandle, EdgeHandle> RgbMesh::arriving_triangle(VertexHandle v, EdgeHandle e) const {
  for (TriangleHandle t : e_tri_[e.idx]) {
    if (!t.valid()) continue;
    const auto& te = t_edge_[t.idx];
    const int i = te[0] == e ? 0 : (te[1] == e ? 1 : 2);
    const EdgeHandle next = te[(i + 1) % 3];
    if (e_vert_[next.idx][0] == v || e_vert_[next.idx][1] == v) return {t, next};
  }
  return {TriangleHandle(), EdgeHandle()};
}

void RgbMesh::star(VertexHandle v, VertexStar& out) const {
  // A corrupted structure must not loop forever (validate() relies on this).
  const std::size_t guard = n_edges_ + 1;
  auto collect_from = [&](EdgeHandle first) {
    out.edges.clear();
    out.neighbors.clear();
    out.triangles.clear();
    EdgeHandle e = first;
    for (std::size_t step = 0; step < guard; ++step) {
      out.edges.push_back(e);
      out.neighbors.push_back(other_vertex(e, v));
      const auto [t, next] = leaving_triangle(v, e);
      if (!t.valid()) return false;  // hit the boundary
      out.triangles.push_back(t);
      e = next;
      if (e == first) return true;  // closed the cycle
    }
    return true;
  };
  out.boundary = false;
  const EdgeHandle start = v_edge_[v.idx];
  if (collect_from(start)) return;
  // A boundary vertex: walk clockwise to the boundary edge where the fan starts.
  out.boundary = true;
  EdgeHandle first = start;
  for (std::size_t step = 0; step < guard; ++step) {
    const auto [t, prev] = arriving_triangle(v, first);
    if (!t.valid()) break;
    first = prev;
  }
  collect_from(first);
}

bool RgbMesh::is_boundary(VertexHandle v) const {
  bool boundary = false;
  visit_edges(v, [&](EdgeHandle e) {
    boundary = boundary || is_boundary(e);
    return !boundary;
  });
  return boundary;
}

int RgbMesh::valence(VertexHandle v) const {
  int n = 0;
  visit_edges(v, [&](EdgeHandle) {
    ++n;
    return true;
  });
  return n;
}

EdgeHandle RgbMesh::find_edge(VertexHandle a, VertexHandle b) const {
  EdgeHandle found;
  visit_edges(a, [&](EdgeHandle e) {
    if (other_vertex(e, a) == b) found = e;
    return !found.valid();
  });
  return found;
}

int RgbMesh::max_level() const {
  int l = 0;
  for (VertexHandle v : vertices()) l = std::max(l, level(v));
  return l;
}

int RgbMesh::boundary_loops() const {
  // Boundary edges, chained head to tail through their vertices.
  std::unordered_map<std::int32_t, std::int32_t> next_of;  // start vertex -> boundary edge
  std::vector<EdgeHandle> boundary;
  for (EdgeHandle e : edges()) {
    if (!is_boundary(e)) continue;
    boundary.push_back(e);
  }
  std::unordered_map<std::int32_t, std::vector<std::int32_t>> at_vertex;
  for (EdgeHandle e : boundary) {
    at_vertex[e_vert_[e.idx][0].idx].push_back(e.idx);
    at_vertex[e_vert_[e.idx][1].idx].push_back(e.idx);
  }
  std::unordered_map<std::int32_t, bool> seen;
  int loops = 0;
  for (EdgeHandle e0 : boundary) {
    if (seen[e0.idx]) continue;
    ++loops;
    std::vector<std::int32_t> stack{e0.idx};
    while (!stack.empty()) {
      const std::int32_t e = stack.back();
      stack.pop_back();
      if (seen[e]) continue;
      seen[e] = true;
      for (VertexHandle v : e_vert_[e]) {
        for (std::int32_t f : at_vertex[v.idx]) {
          if (!seen[f]) stack.push_back(f);
        }
      }
    }
  }
  return loops;
}

// ---------------------------------------------------------------------------------------
// Output

MeshSnapshot RgbMesh::snapshot(Points points, bool geometry_arrays) const {
  MeshSnapshot s;
  std::vector<std::int32_t> index(v_edge_.size(), -1);
  s.points.reserve(n_vertices_);
  NamedArray control{"control_point", 3, {}}, limit{"limit", 3, {}};
  for (VertexHandle v : vertices()) {
    index[v.idx] = static_cast<std::int32_t>(s.points.size());
    const Vec3 c = control_point(v);
    const Vec3 l = (points == Points::limit || geometry_arrays) ? limit_position(v) : Vec3();
    s.points.push_back(points == Points::limit ? l : c);
    s.vertex_level.push_back(v_level_[v.idx]);
    s.vertex_handle.push_back(v);
    if (geometry_arrays) {
      control.values.insert(control.values.end(), {c.x, c.y, c.z});
      limit.values.insert(limit.values.end(), {l.x, l.y, l.z});
    }
  }
  if (geometry_arrays) {
    s.point_data.push_back(std::move(control));
    s.point_data.push_back(std::move(limit));
  }
  s.triangles.reserve(n_triangles_);
  for (TriangleHandle t : triangles()) {
    const auto c = triangle_vertices(t);
    s.triangles.push_back({index[c[0].idx], index[c[1].idx], index[c[2].idx]});
    s.triangle_level.push_back(static_cast<std::uint8_t>(level(t)));
    s.triangle_color.push_back(color(t));
    s.triangle_handle.push_back(t);
  }
  return s;
}

}  // namespace rgbmesh
