#include "rgbmesh/fem/surface_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>
#include <string>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/soup.hpp"

namespace rgbmesh::fem {

Vec3 project_to_unit_sphere(const Vec3& p) { return p * (1.0 / norm(p)); }

const std::vector<Named<Projection>>& geometry_table() {
  static const std::vector<Named<Projection>> table = {{"loop", Projection()},
                                                       {"sphere", project_to_unit_sphere}};
  return table;
}

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

double curved_jacobian_ratio(const std::array<Vec3, 6>& x) {
  // With ξ = (λ1, λ2), the map's tangents are linear in ξ: X_ξ = a0 + a1 ξ1 + a2 ξ2 and
  // X_η = b0 + b1 ξ1 + b2 ξ2 (from the P2 basis: corners λk (2λk - 1), edge nodes 4 λk λk+1).
  const Vec3 a0 = -3 * x[0] - x[1] + 4 * x[3], a1 = 4 * x[0] + 4 * x[1] - 8 * x[3], a2 = 4 * x[0] - 4 * x[3] + 4 * x[4] - 4 * x[5];
  const Vec3 b0 = -3 * x[0] - x[2] + 4 * x[5], b1 = a2, b2 = 4 * x[0] + 4 * x[2] - 8 * x[5];
  // The flat triangle's normal N = (X1 - X0) × (X2 - X0): det D(P∘X) / det DX_A = (X_ξ × X_η)·N / |N|²,
  // r(ξ) = c0 + c1 ξ1 + c2 ξ2 + c11 ξ1² + c12 ξ1 ξ2 + c22 ξ2².
  const Vec3 n = cross(x[1] - x[0], x[2] - x[0]);
  const double nn = dot(n, n);
  if (!(nn > 0)) return 0.0;
  const auto along = [&](const Vec3& p, const Vec3& q) { return dot(cross(p, q), n) / nn; };
  const double c0 = along(a0, b0), c1 = along(a0, b1) + along(a1, b0), c2 = along(a0, b2) + along(a2, b0);
  const double c11 = along(a1, b1), c12 = along(a1, b2) + along(a2, b1), c22 = along(a2, b2);
  const auto r = [&](double s, double t) { return c0 + c1 * s + c2 * t + c11 * s * s + c12 * s * t + c22 * t * t; };
  double lowest = std::min({r(0, 0), r(1, 0), r(0, 1)});
  // Each edge, p + s d for s in [0, 1]: r is a quadratic A s² + B s + C there; its vertex.
  const auto edge = [&](double px, double py, double dx, double dy) {
    const double a = c11 * dx * dx + c12 * dx * dy + c22 * dy * dy;
    const double b = c1 * dx + c2 * dy + 2 * c11 * px * dx + c12 * (px * dy + py * dx) + 2 * c22 * py * dy;
    if (a != 0) {
      const double s = -b / (2 * a);
      if (s > 0 && s < 1) lowest = std::min(lowest, r(px + s * dx, py + s * dy));
    }
  };
  edge(0, 0, 1, 0);
  edge(0, 0, 0, 1);
  edge(1, 0, -1, 1);
  // The interior critical point, where ∇r = 0, if it lies inside.
  const double det = 4 * c11 * c22 - c12 * c12;
  if (det != 0) {
    const double s = (-2 * c22 * c1 + c12 * c2) / det, t = (-2 * c11 * c2 + c12 * c1) / det;
    if (s > 0 && t > 0 && s + t < 1) lowest = std::min(lowest, r(s, t));
  }
  return lowest;
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

// Which corner of its mesh triangle FE triangle t starts at (build_surface_mesh may rotate them).
int corner_offset(const SurfaceMesh& s, const RgbMesh& mesh, std::size_t t) {
  const auto c = mesh.triangle_vertices(s.triangle[t]);
  const VertexHandle first = s.vertex[static_cast<std::size_t>(s.triangles[t][0])];
  return c[0] == first ? 0 : c[1] == first ? 1 : 2;
}

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

std::array<Vec3, 6> element_nodes(const SurfaceMesh& s, std::size_t t) {
  const auto& c = s.triangles[t];
  const auto& e = s.edge_nodes[t];
  return {s.points[c[0]], s.points[c[1]], s.points[c[2]], s.points[e[0]], s.points[e[1]], s.points[e[2]]};
}

// P2 elements that fold over (curved_jacobian_ratio below kMinCurvedJacobian) get straight
// edges: their edge nodes move to the chords' midpoints, which makes them affine, hence valid.
// Why: an element's six nodes lie on the surface, but where the surface turns or slides
// sideways by more than the element's width between them (coarse or long, thin triangles
// across curved parts of CAD meshes; Loop's limit positions of an irregular base), the
// quadratic through them folds. On a folded element the stiffness integrates a doubled, partly
// inverted area and the residual estimator's Laplace-Beltrami term, which divides by the area
// element, takes any value up to 10^9 times its neighbours' (an adaptive run then marks that
// one element every cycle and stalls). An element that cannot be curved validly is better
// left flat, as a P1 geometry, and refined if its error says so: its children are curved again
// (every cycle builds the elements anew), and where the surface is smooth the sideways slide
// of a node falls as h² against a width h, so they pass (not next to an extraordinary vertex,
// where Loop's parametrization is the same at every level). The distance from a moved node to the
// surface point it stood for is kept (straightened_gap) for the estimator's geometric term.
// A moved node changes the element on the edge's other side, which is checked again: rounds
// until none folds (each round judges every element before moving any node, so the result does
// not depend on the order of the triangles; each round straightens at least one more edge, and
// affine elements always pass, so it ends). Where Loop's parametrization slides sideways over
// a region (around vertices of high valence, CAD fans), straightening one edge can fold the
// next element, so the rounds run as chains (measured up to 21 rounds on CGAL's joint.off, 17
// on rotor.off). A distributed run builds each process's view the same way; a chain that
// crossed a view's exact ghost layers could place an interface node differently on two
// processes (the distributed tests run on the sphere, where nothing folds).
void straighten_folded_elements(SurfaceMesh& s) {
  const std::size_t nv = s.vertex.size(), nt = s.triangles.size();
  std::vector<std::array<std::int32_t, 2>> sides(s.num_dofs() - nv, {-1, -1});  // edge node -> its triangles
  for (std::size_t t = 0; t < nt; ++t)
    for (const std::int32_t e : s.edge_nodes[t]) {
      auto& side = sides[static_cast<std::size_t>(e) - nv];
      side[side[0] < 0 ? 0 : 1] = static_cast<std::int32_t>(t);
    }
  std::vector<std::size_t> check(nt);
  for (std::size_t t = 0; t < nt; ++t) check[t] = t;
  std::vector<char> straight(s.num_dofs() - nv, 0);
  while (!check.empty()) {
    std::vector<std::size_t> folded;
    for (const std::size_t t : check)
      if (curved_jacobian_ratio(element_nodes(s, t)) < kMinCurvedJacobian) folded.push_back(t);
    std::vector<std::size_t> next;
    for (const std::size_t t : folded) {
      for (int k = 0; k < 3; ++k) {
        const std::int32_t node = s.edge_nodes[t][k];
        const std::size_t e = static_cast<std::size_t>(node) - nv;
        if (straight[e]) continue;
        straight[e] = 1;
        const Vec3 middle = 0.5 * (s.points[s.triangles[t][k]] + s.points[s.triangles[t][(k + 1) % 3]]);
        if (s.straightened_gap.empty()) s.straightened_gap.assign(s.num_dofs(), 0.0);
        s.straightened_gap[static_cast<std::size_t>(node)] = distance(s.points[node], middle);
        s.points[node] = middle;
        for (const std::int32_t other : sides[e])
          if (other >= 0 && static_cast<std::size_t>(other) != t) next.push_back(static_cast<std::size_t>(other));
      }
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    check = std::move(next);
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
    const int offset = corner_offset(s, mesh, t);
    for (int k = 0; k < 3; ++k) {
      std::int32_t a = s.triangles[t][k], b = s.triangles[t][(k + 1) % 3];
      if (a > b) std::swap(a, b);
      const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
      const auto [it, inserted] = node_of_edge.try_emplace(key, static_cast<std::int32_t>(s.points.size() + edges.size()));
      if (inserted) {
        edges.push_back(mesh.triangle_edges(s.triangle[t])[(offset + k) % 3]);
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
  straighten_folded_elements(s);
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

SurfaceMesh build_surface_mesh(RgbMesh& mesh, std::optional<Projection> projection, int order, DofOrder dof_order) {
  if (order != 1 && order != 2) throw InputError("finite elements of order " + std::to_string(order) + ": only 1 and 2");
  mesh.compute_limits();
  SurfaceMesh s;
  s.order = order;
  s.projection = std::move(projection);
  s.dof_of_vertex.assign(static_cast<std::size_t>(mesh.vertex_slots()), -1);
  // By default, unknowns and triangles are numbered in an order that depends on the mesh alone,
  // not on its handles: the same mesh, however built or restored, gives the same system, bit
  // for bit.
  const bool canonical = dof_order == DofOrder::canonical;
  std::vector<VertexHandle> vertex_order;
  std::vector<TriangleHandle> triangle_order;
  if (canonical) {
    vertex_order = canonical_vertex_order(mesh);
    triangle_order = canonical_triangle_order(mesh, vertex_order);
  } else {
    vertex_order.assign(mesh.vertices().begin(), mesh.vertices().end());
    triangle_order.assign(mesh.triangles().begin(), mesh.triangles().end());
  }
  s.points.reserve(vertex_order.size());
  s.vertex.reserve(vertex_order.size());
  for (const VertexHandle v : vertex_order) {
    s.dof_of_vertex[v.idx] = static_cast<std::int32_t>(s.points.size());
    const Vec3 p = mesh.limit_position(v);
    s.points.push_back(s.projection ? (*s.projection)(p) : p);
    s.vertex.push_back(v);
  }
  s.triangles.reserve(triangle_order.size());
  s.triangle.reserve(triangle_order.size());
  for (const TriangleHandle t : triangle_order) {
    // Canonical: corners from the one numbered first (the orientation kept), so that the
    // element's corners, like its place, do not depend on which corner the mesh stores first.
    const auto c = mesh.triangle_vertices(t);
    const std::int32_t d0 = s.dof_of_vertex[c[0].idx], d1 = s.dof_of_vertex[c[1].idx], d2 = s.dof_of_vertex[c[2].idx];
    const int r = !canonical ? 0 : d0 < d1 ? (d0 < d2 ? 0 : 2) : (d1 < d2 ? 1 : 2);
    const auto ti = static_cast<std::int32_t>(s.triangles.size());
    s.triangles.push_back({s.dof_of_vertex[c[r].idx], s.dof_of_vertex[c[(r + 1) % 3].idx], s.dof_of_vertex[c[(r + 2) % 3].idx]});
    s.triangle.push_back(t);
    const auto& tri = s.triangles.back();
    const TriangleGeometry g = triangle_geometry(s.points[tri[0]], s.points[tri[1]], s.points[tri[2]]);
    double longest = 0;
    for (int k = 0; k < 3; ++k) longest = std::max(longest, distance(s.points[tri[k]], s.points[tri[(k + 1) % 3]]));
    if (!(g.area > 1e-14 * longest * longest))
      throw InputError("triangle " + std::to_string(ti) + " (mesh triangle " + std::to_string(t.idx) +
                       ") is degenerate on the surface: area " + std::to_string(g.area));
    std::uint8_t creases = 0;
    for (int k = 0; k < 3; ++k) {
      const EdgeHandle e = mesh.triangle_edges(t)[(r + k) % 3];
      if (mesh.is_boundary(e)) {
        s.boundary_edges.push_back({tri[k], tri[(k + 1) % 3], ti});
      } else if (mesh.has_sharp_features() && loop::is_infinitely_sharp(mesh.sharpness(e))) {
        creases |= static_cast<std::uint8_t>(1 << k);
      }
    }
    if (mesh.has_sharp_features()) s.crease_sides.push_back(creases);
  }
  if (order == 2) add_edge_nodes(s, mesh);
  return s;
}

}  // namespace rgbmesh::fem
