// SolutionTransfer: P1 values follow the linear interpolant through splits; P2 values follow
// the stored quadratic (injection at new vertices, quarter points on the halves, the old
// element at the new interior edges, also through RGB's forced splits and swaps), and refining
// then coarsening back returns the stored P2 function exactly.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rgbmesh/adapt/solution_transfer.hpp"
#include "rgbmesh/fem/problem.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"

namespace rgbmesh::adapt {
namespace {

// The icosahedron refined uniformly `levels` Loop levels, as the base (level 0) of a new mesh.
RgbMesh sphere_base(int levels) {
  const TriangleMeshData ico = icosahedron();
  RgbMesh fine = RgbMesh::from_triangles(ico.points, ico.triangles);
  selective_refinement(fine, UniformLevel(2 * levels));
  std::vector<Vec3> points;
  std::vector<std::int32_t> slot_to_point(static_cast<std::size_t>(fine.vertex_slots()), -1);
  for (const VertexHandle v : fine.vertices()) {
    slot_to_point[v.idx] = static_cast<std::int32_t>(points.size());
    const Vec3 p = fine.control_point(v);  // on the sphere after projection
    points.push_back(p * (1.0 / norm(p)));
  }
  std::vector<std::array<std::int32_t, 3>> triangles;
  for (const TriangleHandle t : fine.triangles()) {
    const auto c = fine.triangle_vertices(t);
    triangles.push_back({slot_to_point[c[0].idx], slot_to_point[c[1].idx], slot_to_point[c[2].idx]});
  }
  return RgbMesh::from_triangles(points, triangles);
}

Eigen::VectorXd random_values(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::VectorXd u(static_cast<Eigen::Index>(n));
  for (Eigen::Index i = 0; i < u.size(); ++i) u[i] = value(rng);
  return u;
}

// The DOF of the edge node between two vertices of a P2 mesh (-1 if no triangle has that edge).
std::int32_t edge_dof(const fem::SurfaceMesh& fe, VertexHandle a, VertexHandle b) {
  for (std::size_t t = 0; t < fe.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const VertexHandle p = fe.vertex[fe.triangles[t][k]], q = fe.vertex[fe.triangles[t][(k + 1) % 3]];
      if ((p == a && q == b) || (p == b && q == a)) return fe.edge_nodes[t][k];
    }
  }
  return -1;
}

double value_at(const fem::SurfaceMesh& fe, const Eigen::VectorXd& u, VertexHandle v) {
  return u[fe.dof_of_vertex[v.idx]];
}

TEST(SolutionTransfer, LinearValuesFollowTheInterpolantAndQuadraticOnesTheStoredFunction) {
  const fem::Projection sphere(fem::project_to_unit_sphere);
  RgbMesh mesh = sphere_base(1);
  // P1: the new vertex takes the mean of its edge's ends.
  {
    RgbMesh copy = mesh;
    SolutionTransfer on_copy(copy);
    const fem::SurfaceMesh fe = fem::build_surface_mesh(copy, sphere, 1);
    const Eigen::VectorXd u = random_values(fe.num_dofs(), 1);
    on_copy.store(fe, u);
    const EdgeHandle e = *copy.edges().begin();
    const auto [a, b] = copy.edge_vertices(e);
    const VertexHandle v = copy.split_edge(e);
    const fem::SurfaceMesh after = fem::build_surface_mesh(copy, sphere, 1);
    const Eigen::VectorXd carried = on_copy.on(after);
    EXPECT_DOUBLE_EQ(value_at(after, carried, v), 0.5 * (value_at(fe, u, a) + value_at(fe, u, b)));
  }
  // P2: one split of an edge of the base (level 0: no forced splits, no swaps).
  SolutionTransfer transfer(mesh);
  const fem::SurfaceMesh fe = fem::build_surface_mesh(mesh, sphere, 2);
  const Eigen::VectorXd u = random_values(fe.num_dofs(), 2);
  transfer.store(fe, u);
  const EdgeHandle e = *mesh.edges().begin();
  const auto [a, b] = mesh.edge_vertices(e);
  const double ua = value_at(fe, u, a), ub = value_at(fe, u, b), um = u[edge_dof(fe, a, b)];
  const VertexHandle v = mesh.split_edge(e);
  const fem::SurfaceMesh after = fem::build_surface_mesh(mesh, sphere, 2);
  const Eigen::VectorXd carried = transfer.on(after);
  EXPECT_EQ(value_at(after, carried, v), um);  // injection: the node is where v went
  EXPECT_DOUBLE_EQ(carried[edge_dof(after, a, v)], 0.375 * ua + 0.75 * um - 0.125 * ub);
  EXPECT_DOUBLE_EQ(carried[edge_dof(after, v, b)], 0.375 * ub + 0.75 * um - 0.125 * ua);
  int apexes = 0;
  for (const VertexHandle c : mesh.star(v).neighbors) {
    if (c == a || c == b) continue;
    ++apexes;
    const double expected = -0.125 * (ua + ub) + 0.25 * um +
                            0.5 * (u[edge_dof(fe, b, c)] + u[edge_dof(fe, c, a)]);
    EXPECT_NEAR(carried[edge_dof(after, v, c)], expected, 1e-15);
  }
  EXPECT_EQ(apexes, 2);
  // Every other node keeps its value.
  for (const VertexHandle w : mesh.vertices()) {
    if (w == v) continue;
    EXPECT_EQ(value_at(after, carried, w), value_at(fe, u, w));
  }
}

TEST(SolutionTransfer, RefiningThenCoarseningBackReturnsTheStoredQuadraticExactly) {
  const fem::Projection sphere(fem::project_to_unit_sphere);
  RgbMesh mesh = sphere_base(1);
  SolutionTransfer transfer(mesh);
  const fem::SurfaceMesh fe = fem::build_surface_mesh(mesh, sphere, 2);
  const Eigen::VectorXd u = random_values(fe.num_dofs(), 3);
  transfer.store(fe, u);
  // Selective refinement around a point (forced splits and swaps included), then all the way
  // back to the base.
  const RefinementResult up = selective_refinement(mesh, BallLevel(Vec3(0.0, 0.6, 0.8), 0.5, 5));
  ASSERT_GT(up.splits, 100u);
  ASSERT_TRUE(mesh.validate(true).empty());
  const RefinementResult down = selective_refinement(mesh, CoarsenAll());
  ASSERT_EQ(down.removals, up.splits);
  const fem::SurfaceMesh back = fem::build_surface_mesh(mesh, sphere, 2);
  ASSERT_EQ(back.num_dofs(), fe.num_dofs());
  const Eigen::VectorXd carried = transfer.on(back);
  // The same function: node by node, through the vertices' handles (base handles persist).
  for (const VertexHandle w : mesh.vertices()) EXPECT_EQ(value_at(back, carried, w), value_at(fe, u, w));
  std::size_t edges = 0;
  for (const EdgeHandle e : mesh.edges()) {
    const auto [p, q] = mesh.edge_vertices(e);
    EXPECT_EQ(carried[edge_dof(back, p, q)], u[edge_dof(fe, p, q)]);
    ++edges;
  }
  EXPECT_EQ(edges, mesh.num_edges());
}

// One uniform Loop level (forced splits and RGB's swaps included): every node of the finer P2
// mesh carries the stored quadratic at its place in the old element, worked out here from the
// 1-to-4 split itself: a new vertex (midpoint of old edge ab) the edge's node; the half edge
// a-v the quarter point 3/8 u_a + 3/4 u_ab - 1/8 u_b; the edge between the midpoints of ab and
// bc (an edge of the inner triangle) the point (¼, ½, ¼) of triangle abc:
// -(u_a + u_c)/8 + (u_ab + u_bc)/2 + u_ca/4.
TEST(SolutionTransfer, AUniformLevelCarriesTheQuadraticAtItsParametricPoints) {
  const fem::Projection sphere(fem::project_to_unit_sphere);
  RgbMesh mesh = sphere_base(2);
  SolutionTransfer transfer(mesh);
  const fem::SurfaceMesh coarse = fem::build_surface_mesh(mesh, sphere, 2);
  const Eigen::VectorXd u = random_values(coarse.num_dofs(), 4);
  transfer.store(coarse, u);
  selective_refinement(mesh, UniformLevel(1));
  const fem::SurfaceMesh fine = fem::build_surface_mesh(mesh, sphere, 2);
  const Eigen::VectorXd carried = transfer.on(fine);
  const auto old_value = [&](VertexHandle v) { return value_at(coarse, u, v); };
  const auto old_edge = [&](VertexHandle a, VertexHandle b) { return u[edge_dof(coarse, a, b)]; };
  std::size_t vertices = 0, halves = 0, inner = 0;
  for (const VertexHandle v : mesh.vertices()) {
    if (mesh.level(v) == 0) continue;
    const auto [a, b] = mesh.parents(v);
    EXPECT_EQ(value_at(fine, carried, v), old_edge(a, b));
    ++vertices;
  }
  for (std::size_t t = 0; t < fine.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      VertexHandle p = fine.vertex[fine.triangles[t][k]], q = fine.vertex[fine.triangles[t][(k + 1) % 3]];
      const double value = carried[fine.edge_nodes[t][k]];
      if (mesh.level(p) > mesh.level(q)) std::swap(p, q);
      if (mesh.level(p) == 0) {  // a half: p old, q the midpoint of p and r
        const auto [x, y] = mesh.parents(q);
        const VertexHandle r = x == p ? y : x;
        EXPECT_NEAR(value, 0.375 * old_value(p) + 0.75 * old_edge(p, r) - 0.125 * old_value(r), 1e-14);
        ++halves;
      } else {  // inner: midpoints of ab and bc
        const auto pp = mesh.parents(p), qp = mesh.parents(q);
        const VertexHandle b = (pp[0] == qp[0] || pp[0] == qp[1]) ? pp[0] : pp[1];
        const VertexHandle a = pp[0] == b ? pp[1] : pp[0], c = qp[0] == b ? qp[1] : qp[0];
        EXPECT_NEAR(value,
                    -0.125 * (old_value(a) + old_value(c)) + 0.5 * (old_edge(a, b) + old_edge(b, c)) +
                        0.25 * old_edge(c, a),
                    1e-14);
        ++inner;
      }
    }
  }
  EXPECT_EQ(vertices, coarse.num_dofs() - coarse.vertex.size());
  EXPECT_EQ(halves, 2 * 2 * vertices);  // each half seen from its two triangles
  EXPECT_EQ(inner, 3 * 2 * coarse.triangles.size());
}

}  // namespace
}  // namespace rgbmesh::adapt
