#include "rgbmesh/statistics.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace rgbmesh {

namespace {

// Connected components of the triangles (through shared edges), by union-find.
int count_components(const RgbMesh& m) {
  std::vector<std::int32_t> parent(static_cast<std::size_t>(m.triangle_slots()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::int32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (EdgeHandle e : m.edges()) {
    const auto& t = m.edge_triangles(e);
    if (t[1].valid()) parent[find(t[0].idx)] = find(t[1].idx);
  }
  int n = 0;
  for (TriangleHandle t : m.triangles()) n += find(t.idx) == t.idx;
  return n;
}

}  // namespace

MeshStatistics compute_statistics(const RgbMesh& m) {
  MeshStatistics s;
  s.vertices = m.num_vertices();
  s.edges = m.num_edges();
  s.triangles = m.num_triangles();
  s.components = count_components(m);
  s.boundary_loops = m.boundary_loops();
  s.euler_characteristic = m.euler_characteristic();
  s.genus = static_cast<int>((2L * s.components - s.boundary_loops - s.euler_characteristic) / 2);
  std::vector<int> valence(static_cast<std::size_t>(m.vertex_slots()), 0);
  s.shortest_edge = std::numeric_limits<double>::infinity();
  for (EdgeHandle e : m.edges()) {
    const auto& v = m.edge_vertices(e);
    ++valence[v[0].idx];
    ++valence[v[1].idx];
    s.red_edges += m.is_red(e);
    const double l = distance(m.control_point(v[0]), m.control_point(v[1]));
    s.shortest_edge = std::min(s.shortest_edge, l);
    s.longest_edge = std::max(s.longest_edge, l);
  }
  if (s.edges == 0) s.shortest_edge = 0;
  bool first = true;
  for (VertexHandle v : m.vertices()) {
    const Vec3 p = m.control_point(v);
    s.bbox_min = first ? p : Vec3(std::min(s.bbox_min.x, p.x), std::min(s.bbox_min.y, p.y), std::min(s.bbox_min.z, p.z));
    s.bbox_max = first ? p : Vec3(std::max(s.bbox_max.x, p.x), std::max(s.bbox_max.y, p.y), std::max(s.bbox_max.z, p.z));
    first = false;
    ++s.valence_histogram[valence[v.idx]];
    ++s.vertices_per_level[m.level(v)];
    s.max_level = std::max(s.max_level, m.level(v));
  }
  s.bbox_diagonal = norm(s.bbox_max - s.bbox_min);
  for (TriangleHandle t : m.triangles()) {
    ++s.triangles_per_level[m.level(t)][static_cast<int>(m.color(t))];
  }
  if (m.has_sharp_features()) {
    for (EdgeHandle e : m.edges()) {
      if (m.is_boundary(e)) continue;
      const float sharpness = m.sharpness(e);
      s.sharp_edges += sharpness > 0.0f;
      s.semi_sharp_edges += loop::is_semi_sharp(sharpness);
    }
    for (VertexHandle v : m.vertices()) {
      const VertexRule rule = m.vertex_rule(v);
      s.darts += rule == VertexRule::dart;
      s.crease_vertices += rule == VertexRule::crease && !m.is_boundary_vertex(v);
      s.corners += rule == VertexRule::corner;
    }
  }
  return s;
}

LimitDeviation limit_deviation(const RgbMesh& mesh) {
  LimitDeviation worst;
  for (std::size_t i = 0; i < mesh.num_base_vertices(); ++i) {
    const VertexHandle v(static_cast<std::int32_t>(i));
    const double d = distance(mesh.limit_position(v), mesh.insertion_point(v));  // base limits are always known
    if (!worst.vertex.valid() || d > worst.distance) worst = {d, v};
  }
  return worst;
}

}  // namespace rgbmesh
