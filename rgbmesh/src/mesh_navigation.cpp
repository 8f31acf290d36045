// RgbMesh navigation: iteration over live elements, corners, rotation around a vertex and its
// star, boundary loops, and the output snapshot.

#include <algorithm>
#include <unordered_map>

#include "rgbmesh/mesh.hpp"

namespace rgbmesh {

HandleRange<VertexHandle> RgbMesh::vertices() const {
  return {*this, vertex_slots(), [](const RgbMesh& m, std::int32_t i) { return m.v_edge_[i].valid(); }};
}
HandleRange<EdgeHandle> RgbMesh::edges() const {
  return {*this, edge_slots(), [](const RgbMesh& m, std::int32_t i) { return m.e_vert_[i][0].valid(); }};
}
HandleRange<TriangleHandle> RgbMesh::triangles() const {
  return {*this, triangle_slots(), [](const RgbMesh& m, std::int32_t i) { return m.t_edge_[i][0].valid(); }};
}

void RgbMesh::star(VertexHandle v, VertexStar& out) const {
  expect_alive(v, "star");
  // A corrupted structure must not loop forever (validate() relies on this).
  const std::size_t guard = n_edges_ + 1;
  auto collect_from = [&](EdgeHandle first) {
    out.edges.clear();
    out.neighbors.clear();
    out.triangles.clear();
    EdgeHandle e = first;
    for (std::size_t step = 0; step < guard; ++step) {
      out.edges.push_back(e);
      const auto& ends = e_vert_[e.idx];
      out.neighbors.push_back(ends[0] == v ? ends[1] : ends[0]);
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
  expect_alive(v, "is_boundary");
  bool boundary = false;
  visit_edges(v, [&](EdgeHandle e) {
    boundary = boundary || is_boundary(e);
    return !boundary;
  });
  return boundary;
}

int RgbMesh::valence(VertexHandle v) const {
  expect_alive(v, "valence");
  int n = 0;
  visit_edges(v, [&](EdgeHandle) {
    ++n;
    return true;
  });
  return n;
}

EdgeHandle RgbMesh::find_edge(VertexHandle a, VertexHandle b) const {
  expect_alive(a, "find_edge");
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
  // Boundary edges, grouped into loops through their shared vertices.
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

std::vector<std::uint8_t> RgbMesh::shown_levels() const {
  // The lowest level of the edges that are not red, in one pass over the edge arrays: walking
  // around every vertex took most of the time of a snapshot of millions of vertices.
  std::vector<std::uint8_t> shown(v_edge_.size(), static_cast<std::uint8_t>(kMaxLevel + 1));
  for (std::size_t e = 0; e < e_vert_.size(); ++e) {
    if (!e_vert_[e][0].valid() || (e_info_[e] & 0x80) != 0) continue;
    const auto edge_level = static_cast<std::uint8_t>(e_info_[e] & 0x7f);
    for (const VertexHandle v : e_vert_[e]) shown[v.idx] = std::min(shown[v.idx], edge_level);
  }
  return shown;
}

MeshSnapshot RgbMesh::snapshot(Points points, bool geometry_arrays) const {
  MeshSnapshot s;
  std::vector<std::int32_t> index(v_edge_.size(), -1);
  std::vector<std::uint8_t> shown = shown_levels();
  s.points.reserve(n_vertices_);
  s.vertex_level.reserve(n_vertices_);
  s.vertex_handle.reserve(n_vertices_);
  NamedArray control{"control_point", 3, {}}, limit{"limit", 3, {}};
  if (geometry_arrays) {
    control.values.reserve(3 * n_vertices_);
    limit.values.reserve(3 * n_vertices_);
  }
  for (VertexHandle v : vertices()) {
    index[v.idx] = static_cast<std::int32_t>(s.points.size());
    const Vec3 c = control_point(v, shown[v.idx]);
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
  std::vector<std::uint8_t>().swap(shown);
  s.triangles.reserve(n_triangles_);
  s.triangle_level.reserve(n_triangles_);
  s.triangle_color.reserve(n_triangles_);
  s.triangle_handle.reserve(n_triangles_);
  for (TriangleHandle t : triangles()) {
    const auto c = triangle_vertices(t);
    s.triangles.push_back({index[c[0].idx], index[c[1].idx], index[c[2].idx]});
    s.triangle_level.push_back(static_cast<std::uint8_t>(level(t)));
    s.triangle_color.push_back(color(t));
    s.triangle_handle.push_back(t);
  }
  add_sharp_features(s);
  return s;
}

void RgbMesh::add_sharp_features(MeshSnapshot& s) const {
  s.vertex_rule.clear();
  s.sharp = SharpFeatures();
  if (!creases_) return;
  std::vector<std::int32_t> index(v_edge_.size(), -1);
  for (std::size_t i = 0; i < s.vertex_handle.size(); ++i) index[s.vertex_handle[i].idx] = static_cast<std::int32_t>(i);
  s.sharp.method = sharp_features().method;
  s.vertex_rule.reserve(s.vertex_handle.size());
  for (VertexHandle v : s.vertex_handle) s.vertex_rule.push_back(static_cast<std::uint8_t>(vertex_rule(v)));
  for (EdgeHandle e : edges()) {
    const std::int32_t a = index[e_vert_[e.idx][0].idx], b = index[e_vert_[e.idx][1].idx];
    if (a < 0 || b < 0 || is_boundary(e)) continue;
    const float sharp = sharpness(e);
    if (sharp > 0.0f) s.sharp.edges.push_back({a, b, sharp});
  }
  for (std::size_t base = 0; base < n_base_vertices_; ++base) {
    const VertexHandle v(static_cast<std::int32_t>(base));
    const float sharp = vertex_sharpness(v, shown_level(v));
    if (sharp > 0.0f && index[base] >= 0) s.sharp.vertices.push_back({index[base], sharp});
  }
}

}  // namespace rgbmesh
