// Loop-basis elements (fem::build_loop_space, solve_loop) against exact solutions on the unit
// sphere, and against what the space must hold exactly (constants).

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "rgbmesh/errors.hpp"
#include "rgbmesh/fem/loop_elements.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

RgbMesh uniform(const testing::BaseMesh& base, int level) {
  RgbMesh mesh = base.build();
  selective_refinement(mesh, UniformLevel(level));
  return mesh;
}

const fem::Projection kSphere(fem::project_to_unit_sphere);

// -Δu + u = 1 has the solution u = 1 on any closed surface, and the Loop space holds the
// constants (its functions sum to one), so the discrete solution is 1 too, on the limit
// surface itself and on its projection, at extraordinary vertices as elsewhere.
TEST(LoopElements, ReproduceConstants) {
  fem::Problem one;
  one.name = "one";
  one.c = 1;
  one.source = [](const Vec3&) { return 1.0; };
  for (const testing::BaseMesh& base : {testing::icosahedron(), testing::cube(), testing::torus(6, 8)}) {
    RgbMesh mesh = uniform(base, 1);
    for (const bool projected : {false, true}) {
      if (projected && base.name != "icosahedron") continue;
      const fem::LoopSpace space =
          fem::build_loop_space(mesh, projected ? std::optional(kSphere) : std::nullopt);
      const fem::Solution s = fem::solve_loop(space, one);
      EXPECT_LT((s.u.array() - 1.0).abs().maxCoeff(), 1e-11) << base.name;
      EXPECT_LT((fem::loop_vertex_values(space, s.u).array() - 1.0).abs().maxCoeff(), 1e-11) << base.name;
    }
  }
}

struct SphereRun {
  std::size_t dofs;
  fem::ErrorNorms errors;
  int iterations;
};

SphereRun solve_on_sphere(int level, const fem::Problem& problem,
                          const fem::LoopQuadratureOptions& quadrature = {},
                          fem::SolverKind solver = fem::SolverKind::automatic) {
  RgbMesh mesh = uniform(testing::icosahedron(), level);
  const fem::LoopSpace space = fem::build_loop_space(mesh, kSphere, quadrature);
  fem::SolveOptions options;
  options.solver = solver;
  const fem::Solution s = fem::solve_loop(space, problem, options);
  return {space.num_dofs(), fem::loop_error_norms(space, s.u, *problem.exact, s.zero_mean), s.iterations};
}

// u = xyz on the unit sphere (c = 0, zero mean). Loop's functions reproduce cubics where the
// corners are regular (H1 error O(h³), L2 O(h⁴)) but only linear functions at the 12
// extraordinary vertices of valence 5, whose neighbourhoods of area O(h²) bound the rates at
// O(h²) in H1 and O(h³) in L2. Measured: H1 rates 3.18, 2.93, 2.61, 2.44 per halving of h,
// L2 rates 4.33, 4.07, 3.74, 3.58.
TEST(LoopElements, SphereHarmonicConvergesAtTheRatesExtraordinaryVerticesAllow) {
  const fem::Problem problem = fem::sphere_harmonic();
  std::vector<SphereRun> runs;
  for (int level = 1; level <= 5; ++level) runs.push_back(solve_on_sphere(level, problem));
  for (std::size_t i = 1; i < runs.size(); ++i) {
    const double h1_rate = std::log2(runs[i - 1].errors.h1 / runs[i].errors.h1);
    const double l2_rate = std::log2(runs[i - 1].errors.l2 / runs[i].errors.l2);
    std::printf("  level %zu, %zu unknowns: L2 %.3e (rate %.2f), H1 %.3e (rate %.2f)\n", i + 1, runs[i].dofs,
                runs[i].errors.l2, l2_rate, runs[i].errors.h1, h1_rate);
    EXPECT_GT(h1_rate, 2.0 - 0.1) << "level " << i + 1;
    EXPECT_GT(l2_rate, 3.0 - 0.1) << "level " << i + 1;
  }
  // P2 on the same number of unknowns (the mesh one level coarser): the smooth space is far
  // more accurate per unknown (measured: 45 times in H1, 69 times in L2).
  RgbMesh coarser = uniform(testing::icosahedron(), 4);
  const fem::SurfaceMesh p2 = fem::build_surface_mesh(coarser, kSphere, 2);
  ASSERT_EQ(p2.num_dofs(), runs.back().dofs);
  const fem::Solution s2 = fem::solve(p2, problem);
  const fem::ErrorNorms e2 = fem::error_norms(p2, s2.u, *problem.exact, true);
  std::printf("  P2 with as many unknowns: L2 %.3e, H1 %.3e\n", e2.l2, e2.h1);
  EXPECT_LT(runs.back().errors.h1, e2.h1 / 10);
  EXPECT_LT(runs.back().errors.l2, e2.l2 / 10);
}

// The default quadrature (12 symmetric points per sub-triangle, 6 levels towards extraordinary
// corners) against a much finer one (7 x 7, 10 levels): the solutions' errors, both measured
// with the finer rule, agree to 1e-4 relative.
TEST(LoopElements, DefaultQuadratureIsConverged) {
  const fem::Problem problem = fem::sphere_peak();
  RgbMesh mesh = uniform(testing::icosahedron(), 4);
  fem::LoopQuadratureOptions fine;
  fine.extraordinary_depth = 10;
  fine.points_per_direction = 7;
  const fem::LoopSpace usual = fem::build_loop_space(mesh, kSphere),
                       reference = fem::build_loop_space(mesh, kSphere, fine);
  ASSERT_EQ(usual.vertex, reference.vertex);  // the same unknowns
  const fem::Solution a = fem::solve_loop(usual, problem), b = fem::solve_loop(reference, problem);
  const fem::ErrorNorms ea = fem::loop_error_norms(reference, a.u, *problem.exact),
                        eb = fem::loop_error_norms(reference, b.u, *problem.exact);
  std::printf("  H1 %.6e (default rule) %.6e (fine rule); L2 %.6e %.6e\n", ea.h1, eb.h1, ea.l2, eb.l2);
  EXPECT_NEAR(ea.h1, eb.h1, 1e-4 * eb.h1);
  EXPECT_NEAR(ea.l2, eb.l2, 1e-4 * eb.l2);
}

// BoomerAMG on the Loop stiffness matrix (wider stencil than P1: 37 unknowns a row where the
// corners are regular) converges in few iterations, to the direct solver's solution.
TEST(LoopElements, AmgSolvesTheLoopSystem) {
  if (!fem::amg_available()) GTEST_SKIP() << "built without PETSc";
  const fem::Problem problem = fem::sphere_peak();
  const SphereRun direct = solve_on_sphere(5, problem, {}, fem::SolverKind::ldlt);
  const SphereRun amg = solve_on_sphere(5, problem, {}, fem::SolverKind::amg);
  std::printf("  AMG: %d iterations on %zu unknowns\n", amg.iterations, amg.dofs);
  EXPECT_LE(amg.iterations, 30);
  EXPECT_NEAR(amg.errors.h1, direct.errors.h1, 1e-6 * direct.errors.h1);
}

// The unit sphere's projection has its derivatives in closed form (first and second); any other
// projection is differentiated by central differences. The same sphere given as a lambda (which
// takes the differences) must give the same solution, estimate and fourth-order solution
// (second derivatives of the geometry) to the differences' accuracy.
TEST(LoopElements, SphereProjectionsDerivativesInClosedFormMatchDifferences) {
  const fem::Projection differenced = [](const Vec3& x) { return fem::project_to_unit_sphere(x); };
  RgbMesh mesh = uniform(testing::icosahedron(), 3);
  const fem::LoopSpace closed = fem::build_loop_space(mesh, kSphere), numeric = fem::build_loop_space(mesh, differenced);
  const fem::Problem problem = fem::sphere_harmonic();
  const fem::Solution a = fem::solve_loop(closed, problem), b = fem::solve_loop(numeric, problem);
  EXPECT_LT((a.u - b.u).norm(), 1e-6 * a.u.norm());
  const double ea = fem::loop_residual_estimate(closed, problem, a.u).total,
               eb = fem::loop_residual_estimate(numeric, problem, b.u).total;
  EXPECT_NEAR(ea, eb, 1e-5 * eb);
  const fem::BiharmonicProblem fourth = fem::sphere_biharmonic();
  const fem::Solution c = fem::solve_loop_biharmonic(closed, fourth), d = fem::solve_loop_biharmonic(numeric, fourth);
  EXPECT_LT((c.u - d.u).norm(), 1e-5 * c.u.norm());
  std::printf("  closed form against differences: u %.1e, estimate %.1e, fourth order %.1e (relative)\n",
              (a.u - b.u).norm() / a.u.norm(), std::abs(ea - eb) / eb, (c.u - d.u).norm() / c.u.norm());
}

// The Laplace-Beltrami operator of the coordinate functions of a surface is its mean curvature
// vector, normal to the surface: on the Loop limit surface, whose coordinates are functions of
// the space (the control points' coordinates as coefficients), loop_laplacian's vector must be
// normal at every quadrature point, extraordinary corners included.
TEST(LoopElements, LaplacianOfTheCoordinatesIsNormal) {
  RgbMesh mesh = uniform(testing::icosahedron(), 2);
  const fem::LoopSpace space = fem::build_loop_space(mesh);
  std::array<Eigen::VectorXd, 3> coordinate;
  for (int k = 0; k < 3; ++k) {
    coordinate[static_cast<std::size_t>(k)].resize(static_cast<Eigen::Index>(space.num_dofs()));
    for (std::size_t i = 0; i < space.num_dofs(); ++i)
      coordinate[static_cast<std::size_t>(k)][static_cast<Eigen::Index>(i)] = space.control[i][k];
  }
  double worst = 0, smallest = 1e300;
  for (std::size_t e = 0; e < space.elements.size(); e += 7) {
    for (std::size_t p = 0; p < space.elements[e].rule->size(); p += 3) {
      const Vec3 curvature(fem::loop_laplacian(space, e, p, coordinate[0]),
                           fem::loop_laplacian(space, e, p, coordinate[1]),
                           fem::loop_laplacian(space, e, p, coordinate[2]));
      const fem::LoopPoint q = fem::loop_point(space, e, p);
      const Vec3 n = cross(q.xu, q.xv) * (1.0 / norm(cross(q.xu, q.xv)));
      worst = std::max(worst, norm(curvature - dot(curvature, n) * n) / norm(curvature));
      smallest = std::min(smallest, -dot(curvature, n));  // 2H > 0 on this convex surface (outward n)
    }
  }
  std::printf("  largest tangential part %.1e of |Δx|; smallest 2H %.3f\n", worst, smallest);
  EXPECT_LT(worst, 1e-10);
  EXPECT_GT(smallest, 0);
}

// The residual estimator follows the H1 error at its rate: the ratio of the two stays within
// a small band as the mesh is refined (the estimator is reliable and efficient up to
// constants), on the sphere through the projection.
TEST(LoopElements, ResidualEstimatorFollowsTheError) {
  const fem::Problem problem = fem::sphere_harmonic();
  std::vector<double> ratio;
  for (int level = 2; level <= 5; ++level) {
    RgbMesh mesh = uniform(testing::icosahedron(), level);
    const fem::LoopSpace space = fem::build_loop_space(mesh, kSphere);
    const fem::Solution s = fem::solve_loop(space, problem);
    const fem::ErrorNorms e = fem::loop_error_norms(space, s.u, *problem.exact, true);
    const fem::Estimate eta = fem::loop_residual_estimate(space, problem, s.u);
    ASSERT_EQ(eta.eta.size(), space.elements.size());
    ratio.push_back(eta.total / e.h1);
    std::printf("  level %d: estimate %.3e, H1 error %.3e, ratio %.2f\n", level, eta.total, e.h1,
                ratio.back());
  }
  for (const double r : ratio) {
    EXPECT_GT(r, 0.5);
    EXPECT_LT(r, 20);
  }
  EXPECT_LT(*std::max_element(ratio.begin(), ratio.end()) / *std::min_element(ratio.begin(), ratio.end()),
            2.0);
}

// The fourth-order problem Δ²u + u = f on the unit sphere, which the C¹ Loop space solves
// without mixed variables. Measured on u = xyz: rates of ‖Δ(u - u_h)‖ 1.92, 1.74, 1.45, 1.28
// (and 1.20 at 40,962 unknowns), of the L2 error 4.05, 3.64, 3.00, 2.58, of the H1 error 3.19,
// 2.93, 2.59, 2.42. Where the corners are regular the space reproduces cubics (‖Δe‖ O(h²));
// at the 12 extraordinary vertices only linear functions, so second derivatives keep an O(1)
// error on O(h²) of area: ‖Δe‖ tends to O(h), and the L2 and H1 errors to O(h²).
TEST(LoopElements, BiharmonicConvergesWithoutMixedVariables) {
  for (const fem::BiharmonicProblem& problem : {fem::sphere_biharmonic(), fem::sphere_biharmonic_peak()}) {
    std::vector<fem::BiharmonicErrors> errors;
    for (int level = 2; level <= 5; ++level) {
      RgbMesh mesh = uniform(testing::icosahedron(), level);
      const fem::LoopSpace space = fem::build_loop_space(mesh, kSphere);
      const fem::Solution s = fem::solve_loop_biharmonic(space, problem);
      errors.push_back(fem::loop_biharmonic_errors(space, s.u, problem));
    }
    for (std::size_t i = 1; i < errors.size(); ++i) {
      const double l2 = std::log2(errors[i - 1].l2 / errors[i].l2),
                   h1 = std::log2(errors[i - 1].h1 / errors[i].h1),
                   lap = std::log2(errors[i - 1].laplacian / errors[i].laplacian);
      std::printf("  %s level %zu: L2 %.3e (rate %.2f), H1 %.3e (%.2f), Laplacian %.3e (%.2f)\n",
                  problem.name.c_str(), i + 2, errors[i].l2, l2, errors[i].h1, h1, errors[i].laplacian, lap);
      EXPECT_GT(lap, 1.0 - 0.1) << problem.name;
      EXPECT_GT(h1, 2.0 - 0.1) << problem.name;
      EXPECT_GT(l2, 2.0 - 0.1) << problem.name;
    }
  }
  // c must be positive on a closed surface (the constants would be free).
  fem::BiharmonicProblem singular = fem::sphere_biharmonic();
  singular.c = 0;
  RgbMesh mesh = uniform(testing::icosahedron(), 1);
  EXPECT_THROW(fem::solve_loop_biharmonic(fem::build_loop_space(mesh, kSphere), singular), InputError);
}

// The refined picture: a closed surface again (every edge in two triangles, Euler
// characteristic 2 on the sphere), 4^levels pieces per element, its values at the vertices'
// limit positions those of loop_vertex_values, and close to the exact solution everywhere.
TEST(LoopElements, RefinedViewIsTheSmoothSolution) {
  const fem::Problem problem = fem::sphere_peak();
  RgbMesh mesh = uniform(testing::icosahedron(), 4);
  const fem::LoopSpace space = fem::build_loop_space(mesh, kSphere);
  const fem::Solution s = fem::solve_loop(space, problem);
  const MeshSnapshot view = fem::loop_refined_view(space, s.u, 2);
  ASSERT_EQ(view.triangles.size(), 16 * space.elements.size());
  std::map<std::pair<std::int32_t, std::int32_t>, int> edges;
  for (const auto& t : view.triangles)
    for (int k = 0; k < 3; ++k)
      ++edges[std::minmax(t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)])];
  for (const auto& [edge, count] : edges) ASSERT_EQ(count, 2);
  EXPECT_EQ(static_cast<long>(view.points.size()) - static_cast<long>(edges.size()) +
                static_cast<long>(view.triangles.size()),
            2);
  // No piece folds: each faces outwards (a point shared along an edge in the wrong place would
  // keep the edges paired but fold the pieces beside it).
  for (const auto& t : view.triangles) {
    const Vec3 &a = view.points[static_cast<std::size_t>(t[0])], &b = view.points[static_cast<std::size_t>(t[1])],
               &c = view.points[static_cast<std::size_t>(t[2])];
    ASSERT_GT(dot(cross(b - a, c - a), a + b + c), 0);
  }
  const std::vector<double>& values = view.point_data[0].values;
  const Eigen::VectorXd at_vertices = fem::loop_vertex_values(space, s.u);
  double worst = 0, at_vertex = 0;
  for (std::size_t i = 0; i < view.points.size(); ++i) {
    EXPECT_NEAR(norm(view.points[i]), 1.0, 1e-14);
    worst = std::max(worst, std::abs(values[i] - problem.exact->value(view.points[i])));
  }
  for (std::size_t d = 0; d < space.num_dofs(); ++d) {
    // A vertex's point in the view: the one at its limit position.
    const Vec3 p = fem::project_to_unit_sphere(mesh.limit_position(space.vertex[d]));
    for (std::size_t i = 0; i < view.points.size(); ++i)
      if (norm(view.points[i] - p) < 1e-12)
        at_vertex = std::max(at_vertex, std::abs(values[i] - at_vertices(static_cast<Eigen::Index>(d))));
  }
  std::printf("  %zu points; largest error against the exact solution %.2e\n", view.points.size(), worst);
  EXPECT_LT(at_vertex, 1e-13);
  EXPECT_LT(worst, 5e-3);  // the peak has height 1; measured 3.3e-3
  // Handed to a P1 mesh of the same triangles in either numbering, each vertex keeps its value
  // (close to the exact one at its point) and each triangle its indicator.
  const fem::Estimate estimate = fem::loop_residual_estimate(space, problem, s.u);
  for (const fem::DofOrder order : {fem::DofOrder::canonical, fem::DofOrder::mesh}) {
    const fem::SurfaceMesh p1 = fem::build_surface_mesh(mesh, kSphere, 1, order);
    const Eigen::VectorXd on_p1 = fem::loop_values_on(space, s.u, p1);
    const std::vector<double> eta = fem::loop_element_values_on(space, estimate.eta, p1);
    for (std::size_t i = 0; i < p1.num_dofs(); ++i)
      ASSERT_NEAR(on_p1(static_cast<Eigen::Index>(i)), problem.exact->value(p1.points[i]), 5e-3);
    for (std::size_t d = 0; d < space.num_dofs(); ++d)
      ASSERT_EQ(on_p1(p1.dof_of_vertex[static_cast<std::size_t>(space.vertex[d].idx)]),
                at_vertices(static_cast<Eigen::Index>(d)));
    for (std::size_t e = 0; e < space.elements.size(); ++e)
      for (std::size_t t = 0; t < p1.triangle.size(); ++t)
        if (p1.triangle[t] == space.elements[e].triangle) {
          ASSERT_EQ(eta[t], estimate.eta[e]);
        }
  }
}

// loop_parametrization_ratio where the limit map is known: on a flat regular lattice a
// box-spline patch reproduces linear functions, so an interior element's map is affine,
// x = p0 + u (p1 - p0) + v (p2 - p0) over its corners, and the ratio is that of the singular
// values of [p1 - p0, p2 - p0]. On the sphere's uniform levels no element comes near singular.
// loop_singular_estimate finds an estimate that sits on such elements, and only then.
TEST(LoopElements, ParametrizationRatioIsTheTangentMapsConditioning) {
  const TriangleMeshData m = square_lattice(8, 1, 0);
  RgbMesh mesh = RgbMesh::from_triangles(m.points, m.triangles);
  const fem::LoopSpace flat = fem::build_loop_space(mesh, std::nullopt, {}, fem::LoopBoundary::loop_rules);
  std::size_t interior = 0;
  for (std::size_t e = 0; e < flat.elements.size(); ++e) {
    const auto& dofs = flat.elements[e].dofs;
    if (dofs.size() != 12) continue;  // a regular patch: all corners of valence 6, away from the boundary
    bool inside = true;
    for (const std::int32_t d : dofs) {
      const Vec3& p = flat.control[static_cast<std::size_t>(d)];
      inside = inside && p.x > 1e-9 && p.x < 1 - 1e-9 && p.y > 1e-9 && p.y < 1 - 1e-9;
    }
    if (!inside) continue;
    ++interior;
    const Vec3 p0 = flat.control[static_cast<std::size_t>(dofs[0])];
    const Vec3 a = flat.control[static_cast<std::size_t>(dofs[1])] - p0,
               b = flat.control[static_cast<std::size_t>(dofs[2])] - p0;
    Eigen::Matrix2d metric;
    metric << dot(a, a), dot(a, b), dot(a, b), dot(b, b);
    const Eigen::Vector2d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(metric).eigenvalues();
    EXPECT_NEAR(fem::loop_parametrization_ratio(flat, e), std::sqrt(lambda(0) / lambda(1)), 1e-9) << e;
  }
  EXPECT_GE(interior, 30u);  // 32: those whose two-rings stay inside

  RgbMesh sphere = uniform(testing::icosahedron(), 2);
  const fem::LoopSpace round = fem::build_loop_space(sphere, kSphere);
  double least = 1;
  for (std::size_t e = 0; e < round.elements.size(); ++e)
    least = std::min(least, fem::loop_parametrization_ratio(round, e));
  std::printf("  sphere, level 2: smallest ratio %.3f\n", least);
  EXPECT_GT(least, 0.3);  // measured 0.56

  // An estimate on one element: reported when that element's ratio is below the threshold.
  std::vector<double> eta(round.elements.size(), 1e-3);
  eta[7] = 1;
  const double ratio = fem::loop_parametrization_ratio(round, 7);
  const fem::LoopSingularEstimate on = fem::loop_singular_estimate(round, eta, 2 * ratio);
  EXPECT_GT(on.share, 0.99);
  EXPECT_EQ(on.elements, 1u);
  EXPECT_DOUBLE_EQ(on.ratio, ratio);
  EXPECT_LT(norm(on.where - fem::loop_point(round, 7, 0).x), 1e-12);
  const fem::LoopSingularEstimate off = fem::loop_singular_estimate(round, eta, 0.5 * ratio);
  EXPECT_EQ(off.share, 0);
  EXPECT_EQ(off.elements, 0u);
  // Spread evenly, an estimate is not on the few singular elements: none below the default.
  EXPECT_EQ(fem::loop_singular_estimate(round, std::vector<double>(round.elements.size(), 1.0)).elements, 0u);
}

TEST(LoopElements, RefusesMeshesItCannotHandleYet) {
  // A mesh with triangles of two levels.
  RgbMesh mixed = testing::icosahedron().build();
  const EdgeHandle e = *mixed.edges().begin();
  mixed.split_edge(e);
  try {
    fem::build_loop_space(mixed);
    FAIL() << "a mesh that is not uniform was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("uniformly refined"), std::string::npos) << error.what();
  }
  RgbMesh open = uniform(testing::fan_disk(6), 1);
  try {
    fem::build_loop_space(open);
    FAIL() << "an open mesh was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("closed surface"), std::string::npos) << error.what();
  }
  // The tetrahedron: every ring holds every vertex, the patch folds onto itself.
  RgbMesh tetra = testing::tetrahedron().build();
  EXPECT_THROW(fem::build_loop_space(tetra), InputError);
}

}  // namespace
}  // namespace rgbmesh
