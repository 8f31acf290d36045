#include "rgbmesh/fem/surface_mesh.hpp"

#include <cmath>
#include <stdexcept>
#include <unordered_map>
#include <string>

#include "rgbmesh/soup.hpp"

namespace rgbmesh::fem {

Vec3 project_to_unit_sphere(const Vec3& p) { return p * (1.0 / norm(p)); }

double SurfaceMesh::total_area() const {
  double a = 0;
  for (const auto& t : triangles) a += triangle_geometry(points[t[0]], points[t[1]], points[t[2]]).area;
  return a;
}

SurfaceMesh::LiftTangents SurfaceMesh::lift_tangents(const Vec3& x, const Vec3& n, double size) const {
  // An orthonormal basis of the plane: e1 across the largest-magnitude axis of n.
  const Vec3 a = std::abs(n.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  LiftTangents t;
  t.e1 = cross(n, a);
  t.e1 = t.e1 * (1.0 / norm(t.e1));
  t.e2 = cross(n, t.e1);
  if (!projection) {
    t.de1 = t.e1;
    t.de2 = t.e2;
    return t;
  }
  // A step well inside the triangle's scale, far above rounding: the O(δ²) error is ~1e-10.
  const double d = 1e-5 * size;
  t.de1 = ((*projection)(x + d * t.e1) - (*projection)(x - d * t.e1)) * (0.5 / d);
  t.de2 = ((*projection)(x + d * t.e2) - (*projection)(x - d * t.e2)) * (0.5 / d);
  return t;
}

double SurfaceMesh::lift_area_factor(const Vec3& x, const Vec3& n, double size) const {
  if (!projection) return 1.0;
  const LiftTangents t = lift_tangents(x, n, size);
  return norm(cross(t.de1, t.de2));
}

TriangleGeometry triangle_geometry(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  TriangleGeometry g;
  const Vec3 n = cross(p1 - p0, p2 - p0);
  const double twice_area = norm(n);
  g.area = 0.5 * twice_area;
  if (!(twice_area > 0)) return g;
  g.normal = n * (1.0 / twice_area);
  // The gradient of the barycentric coordinate of a corner is the opposite edge turned a
  // quarter in the triangle's plane (towards the corner), over twice the area.
  const double s = 1.0 / twice_area;
  g.grad[0] = cross(g.normal, p2 - p1) * s;
  g.grad[1] = cross(g.normal, p0 - p2) * s;
  g.grad[2] = cross(g.normal, p1 - p0) * s;
  return g;
}

const std::array<QuadraturePoint, 7>& triangle_quadrature() {
  // Radon's 7-point rule: the centroid and two orbits of three points.
  static const std::array<QuadraturePoint, 7> rule = [] {
    const double r = std::sqrt(15.0);
    const double a1 = (6.0 - r) / 21.0, b1 = (9.0 + 2.0 * r) / 21.0, w1 = (155.0 - r) / 1200.0;
    const double a2 = (6.0 + r) / 21.0, b2 = (9.0 - 2.0 * r) / 21.0, w2 = (155.0 + r) / 1200.0;
    return std::array<QuadraturePoint, 7>{{{{1.0 / 3, 1.0 / 3, 1.0 / 3}, 9.0 / 40.0},
                                           {{b1, a1, a1}, w1},
                                           {{a1, b1, a1}, w1},
                                           {{a1, a1, b1}, w1},
                                           {{b2, a2, a2}, w2},
                                           {{a2, b2, a2}, w2},
                                           {{a2, a2, b2}, w2}}};
  }();
  return rule;
}

namespace {

// split_limits (like compute_limits) leaves the same triangles, but those its undo re-creates
// may sit in other slots: each FE triangle's handle is found again by its corners (an oriented
// edge names one triangle of a manifold mesh: the corner with the smallest slot and the next).
void find_triangles_again(SurfaceMesh& s, const RgbMesh& mesh) {
  const auto key = [](const std::array<VertexHandle, 3>& c) {
    int k = 0;
    if (c[1].idx < c[k].idx) k = 1;
    if (c[2].idx < c[k].idx) k = 2;
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c[k].idx)) << 32) |
           static_cast<std::uint32_t>(c[(k + 1) % 3].idx);
  };
  std::unordered_map<std::uint64_t, TriangleHandle> by_corners;
  by_corners.reserve(2 * s.triangles.size());
  for (const TriangleHandle t : mesh.triangles()) by_corners.emplace(key(mesh.triangle_vertices(t)), t);
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const auto& c = s.triangles[t];
    const auto it = by_corners.find(key({s.vertex[c[0]], s.vertex[c[1]], s.vertex[c[2]]}));
    if (it == by_corners.end()) throw std::logic_error("build_surface_mesh: a triangle is gone after split_limits");
    s.triangle[t] = it->second;
  }
}

// P2: one node per edge, numbered after the vertices in the order the triangles meet the
// edges. With a projection, at the projection of the edge's midpoint; on the Loop limit surface,
// at the limit position of the vertex that splitting the edge would insert (RgbMesh::
// split_limits), or, for a red edge (a trapezoid's diagonal, which no subdivision vertex
// splits), at the midpoint of its ends.
void add_edge_nodes(SurfaceMesh& s, RgbMesh& mesh) {
  std::unordered_map<std::uint64_t, std::int32_t> node_of_edge;
  node_of_edge.reserve(2 * s.triangles.size());
  s.edge_nodes.resize(s.triangles.size());
  std::vector<EdgeHandle> edges;
  std::vector<std::array<std::int32_t, 2>> ends;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      std::int32_t a = s.triangles[t][k], b = s.triangles[t][(k + 1) % 3];
      if (a > b) std::swap(a, b);
      const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
      const auto [it, inserted] = node_of_edge.try_emplace(key, static_cast<std::int32_t>(s.points.size() + edges.size()));
      if (inserted) {
        edges.push_back(mesh.triangle_edges(s.triangle[t])[k]);
        ends.push_back({a, b});
      }
      s.edge_nodes[t][k] = it->second;
    }
  }
  std::vector<Vec3> limits;
  if (!s.projection) {
    limits = mesh.split_limits(edges);
    find_triangles_again(s, mesh);
  }
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const Vec3 middle = 0.5 * (s.points[ends[i][0]] + s.points[ends[i][1]]);
    if (s.projection)
      s.points.push_back((*s.projection)(middle));
    else
      s.points.push_back(std::isfinite(limits[i].x) ? limits[i] : middle);
  }
  // A boundary edge is edge k of its triangle where its ends are corners k and k+1.
  for (SurfaceMesh::BoundaryEdge& e : s.boundary_edges)
    for (int k = 0; k < 3; ++k)
      if (s.triangles[e.triangle][k] == e.a) e.middle = s.edge_nodes[e.triangle][k];
}

}  // namespace

ElementPoint element_point(const SurfaceMesh& mesh, std::size_t triangle, const std::array<double, 3>& l) {
  const auto& c = mesh.triangles[triangle];
  ElementPoint p;
  if (mesh.order == 1) {
    const Vec3 &p0 = mesh.points[c[0]], &p1 = mesh.points[c[1]], &p2 = mesh.points[c[2]];
    const TriangleGeometry g = triangle_geometry(p0, p1, p2);
    p.x = l[0] * p0 + l[1] * p1 + l[2] * p2;
    p.normal = g.normal;
    p.density = g.area;
    p.nodes = 3;
    for (int i = 0; i < 3; ++i) {
      p.dof[i] = c[i];
      p.value[i] = l[i];
      p.gradient[i] = g.grad[i];
    }
    return p;
  }
  // P2: corners λ_k (2 λ_k - 1), edge nodes 4 λ_k λ_k+1, as functions of (ξ, η) = (λ1, λ2)
  // with λ0 = 1 - ξ - η; the element x(ξ, η) = Σ N_i X_i and its tangents x_ξ, x_η.
  const auto& e = mesh.edge_nodes[triangle];
  p.nodes = 6;
  p.dof = {c[0], c[1], c[2], e[0], e[1], e[2]};
  p.value = {l[0] * (2 * l[0] - 1), l[1] * (2 * l[1] - 1), l[2] * (2 * l[2] - 1),
             4 * l[0] * l[1],       4 * l[1] * l[2],       4 * l[2] * l[0]};
  // d/dξ and d/dη of each basis function (dλ0 = -dξ - dη).
  const std::array<double, 6> d_xi = {-(4 * l[0] - 1), 4 * l[1] - 1, 0.0, 4 * (l[0] - l[1]), 4 * l[2], -4 * l[2]};
  const std::array<double, 6> d_eta = {-(4 * l[0] - 1), 0.0, 4 * l[2] - 1, -4 * l[1], 4 * l[1], 4 * (l[0] - l[2])};
  Vec3 x_xi, x_eta;
  for (int i = 0; i < 6; ++i) {
    const Vec3& node = mesh.points[p.dof[i]];
    p.x += p.value[i] * node;
    x_xi += d_xi[i] * node;
    x_eta += d_eta[i] * node;
  }
  // The metric G = JᵀJ of J = [x_ξ x_η]; the surface gradient of N_i is J G⁻¹ ∇_ξ N_i, and the
  // area of the reference triangle (1/2) carries sqrt(det G) to the density.
  const double g11 = dot(x_xi, x_xi), g12 = dot(x_xi, x_eta), g22 = dot(x_eta, x_eta);
  const double det = g11 * g22 - g12 * g12;
  if (!(det > 0)) throw std::runtime_error("a curved triangle is degenerate at a quadrature point");
  const Vec3 n = cross(x_xi, x_eta);
  p.normal = n * (1.0 / norm(n));
  p.density = 0.5 * std::sqrt(det);
  for (int i = 0; i < 6; ++i) {
    const double a = (g22 * d_xi[i] - g12 * d_eta[i]) / det, b = (g11 * d_eta[i] - g12 * d_xi[i]) / det;
    p.gradient[i] = a * x_xi + b * x_eta;
  }
  return p;
}

SurfaceMesh build_surface_mesh(RgbMesh& mesh, std::optional<Projection> projection, int order) {
  if (order != 1 && order != 2) throw InputError("finite elements of order " + std::to_string(order) + ": only 1 and 2");
  mesh.compute_limits();
  SurfaceMesh s;
  s.order = order;
  s.projection = std::move(projection);
  s.dof_of_vertex.assign(static_cast<std::size_t>(mesh.vertex_slots()), -1);
  for (VertexHandle v : mesh.vertices()) {
    s.dof_of_vertex[v.idx] = static_cast<std::int32_t>(s.points.size());
    const Vec3 p = mesh.limit_position(v);
    s.points.push_back(s.projection ? (*s.projection)(p) : p);
    s.vertex.push_back(v);
  }
  for (TriangleHandle t : mesh.triangles()) {
    const auto c = mesh.triangle_vertices(t);
    const auto ti = static_cast<std::int32_t>(s.triangles.size());
    s.triangles.push_back({s.dof_of_vertex[c[0].idx], s.dof_of_vertex[c[1].idx], s.dof_of_vertex[c[2].idx]});
    s.triangle.push_back(t);
    const auto& tri = s.triangles.back();
    const TriangleGeometry g = triangle_geometry(s.points[tri[0]], s.points[tri[1]], s.points[tri[2]]);
    double longest = 0;
    for (int k = 0; k < 3; ++k) longest = std::max(longest, distance(s.points[tri[k]], s.points[tri[(k + 1) % 3]]));
    if (!(g.area > 1e-14 * longest * longest))
      throw InputError("triangle " + std::to_string(ti) + " (mesh triangle " + std::to_string(t.idx) +
                       ") is degenerate on the surface: area " + std::to_string(g.area));
    for (int k = 0; k < 3; ++k) {
      const EdgeHandle e = mesh.triangle_edges(t)[k];
      if (mesh.is_boundary(e)) s.boundary_edges.push_back({tri[k], tri[(k + 1) % 3], ti});
    }
  }
  if (order == 2) add_edge_nodes(s, mesh);
  return s;
}

}  // namespace rgbmesh::fem
