#include "rgbmesh/fem/surface_mesh.hpp"

#include <cmath>
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

SurfaceMesh build_surface_mesh(RgbMesh& mesh, std::optional<Projection> projection) {
  mesh.compute_limits();
  SurfaceMesh s;
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
  return s;
}

}  // namespace rgbmesh::fem
