// P1 finite elements on surfaces, against exact solutions and theory: quadrature exactness,
// constants and coordinate functions on the sphere, convergence rates under uniform
// refinement, effectivity of the estimators, agreement of the solvers, conservation on a
// Loop surface, and clear errors for bad problems.

#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include "rgbmesh/detail/parallel_for.hpp"
#include "rgbmesh/fem/estimators.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/soup.hpp"
#include "test_meshes.hpp"
#include "test_rates.hpp"

namespace rgbmesh::fem {
namespace {

// The unit sphere from the icosahedron refined to `level`, vertices projected onto it.
SurfaceMesh sphere(int level) {
  RgbMesh m = testing::icosahedron().build();
  selective_refinement(m, UniformLevel(level));
  return build_surface_mesh(m, Projection(project_to_unit_sphere));
}

double factorial(int k) { return k <= 1 ? 1.0 : k * factorial(k - 1); }

TEST(Quadrature, ExactForPolynomialsOfDegreeFive) {
  const Vec3 p0{0.3, -0.2, 0.1}, p1{1.7, 0.4, -0.3}, p2{0.5, 1.9, 0.8};
  const double area = triangle_geometry(p0, p1, p2).area;
  for (int a = 0; a <= 5; ++a) {
    for (int b = 0; a + b <= 5; ++b) {
      for (int c = 0; a + b + c <= 5; ++c) {
        double q = 0;
        for (const auto& pt : triangle_quadrature())
          q += pt.weight * area * std::pow(pt.barycentric[0], a) * std::pow(pt.barycentric[1], b) *
               std::pow(pt.barycentric[2], c);
        // ∫_T λ0^a λ1^b λ2^c = 2 |T| a! b! c! / (a + b + c + 2)!
        const double exact = 2 * area * factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 2);
        EXPECT_NEAR(q, exact, 1e-15) << a << b << c;
      }
    }
  }
}

TEST(Fem, ConstantsAreReproducedExactly) {
  const SurfaceMesh mesh = sphere(2);
  const System sys = assemble(mesh, Problem{});
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(mesh.num_dofs()));
  EXPECT_LT((sys.stiffness * ones).cwiseAbs().maxCoeff(), 1e-13);  // the Laplacian of a constant
  // -Δu + u = 1 has the solution u = 1, which P1 contains: the discrete solution is exactly 1.
  Problem p;
  p.c = 1;
  p.source = [](const Vec3&) { return 1.0; };
  const Solution s = solve(mesh, p);
  EXPECT_LT((s.u - ones).cwiseAbs().maxCoeff(), 1e-12);
  // The mass matrix integrates 1 to the area of the polyhedron.
  EXPECT_NEAR(ones.dot(sys.mass * ones), mesh.total_area(), 1e-12);
}

TEST(Fem, CoordinateFunctionsBehaveAsTheoryPredicts) {
  // On a polyhedron the coordinate functions are linear on each triangle: they are in the P1
  // space exactly. Then (1) Σ_i (K x)_i = 0 (the discrete mean-curvature normal integrates to
  // zero), (2) Σ_k x_kᵀ K x_k = 2 |Γ_h| exactly (the tangential projector has trace 2), and
  // (3) on the sphere, where -Δx = 2x, the Rayleigh quotient Σ xᵀKx / Σ xᵀMx tends to the
  // eigenvalue 2 at the rate of P1 eigenvalues, h² (a quarter per level).
  std::vector<double> dofs, err;
  for (int level = 1; level <= 5; ++level) {
    const SurfaceMesh mesh = sphere(level);
    const System sys = assemble(mesh, Problem{});
    double kk = 0, mm = 0;
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::VectorXd x(static_cast<Eigen::Index>(mesh.num_dofs()));
      for (std::size_t i = 0; i < mesh.num_dofs(); ++i) x[static_cast<Eigen::Index>(i)] = mesh.points[i][axis];
      EXPECT_NEAR((sys.stiffness * x).sum(), 0.0, 1e-12);
      kk += x.dot(sys.stiffness * x);
      mm += x.dot(sys.mass * x);
    }
    EXPECT_NEAR(kk, 2 * mesh.total_area(), 1e-12 * kk);
    dofs.push_back(static_cast<double>(mesh.num_dofs()));
    err.push_back(std::abs(kk / mm - 2.0));
  }
  EXPECT_NEAR(testing::log_log_slope(dofs, err), -1.0, 0.15);
}

struct Convergence {
  std::vector<double> dofs, l2, h1, eta_residual, eta_zz;
};

Convergence uniform_convergence(const Problem& problem, int from, int to) {
  Convergence c;
  for (int level = from; level <= to; ++level) {
    const SurfaceMesh mesh = sphere(level);
    const Solution s = solve(mesh, problem);
    const ErrorNorms e = error_norms(mesh, s.u, *problem.exact, s.zero_mean);
    c.dofs.push_back(static_cast<double>(mesh.num_dofs()));
    c.l2.push_back(e.l2);
    c.h1.push_back(e.h1);
    c.eta_residual.push_back(residual_estimator(mesh, problem, s.u).total);
    c.eta_zz.push_back(zz_estimator(mesh, s.u).total);
  }
  return c;
}

void expect_rates_and_effectivity(const Convergence& c, const std::string& what) {
  const std::size_t n = c.dofs.size();
  // Asymptotic rates from the last three meshes: L2 ~ h² ~ N^-1, H1 ~ h ~ N^-1/2.
  const std::vector<double> d(c.dofs.end() - 3, c.dofs.end());
  EXPECT_NEAR(testing::log_log_slope(d, {c.l2.end() - 3, c.l2.end()}), -1.0, 0.15) << what;
  EXPECT_NEAR(testing::log_log_slope(d, {c.h1.end() - 3, c.h1.end()}), -0.5, 0.15) << what;
  // Effectivity indices η / ‖∇(u - u_h)‖ stay in a fixed band (a factor 1.5 from first to
  // last) over the refinements.
  for (const auto* eta : {&c.eta_residual, &c.eta_zz}) {
    double lo = 1e300, hi = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double eff = (*eta)[i] / c.h1[i];
      lo = std::min(lo, eff);
      hi = std::max(hi, eff);
    }
    EXPECT_GT(lo, 0.1) << what;
    EXPECT_LT(hi / lo, 1.5) << what << (eta == &c.eta_zz ? " (ZZ)" : " (residual)");
  }
}

TEST(Fem, SphereHarmonicConvergesAtTheTheoreticalRates) {
  const Convergence c = uniform_convergence(sphere_harmonic(), 2, 6);
  expect_rates_and_effectivity(c, "sphere-harmonic");
}

TEST(Fem, SpherePeakConvergesAtTheTheoreticalRates) {
  const Convergence c = uniform_convergence(sphere_peak(), 3, 7);
  expect_rates_and_effectivity(c, "sphere-peak");
}

TEST(Fem, EverySolverGivesTheSameSolution) {
  const SurfaceMesh mesh = sphere(4);
  for (const Problem& p : {sphere_harmonic(), sphere_peak()}) {
    SolveOptions o;
    o.solver = SolverKind::ldlt;
    const Solution ref = solve(mesh, p, o);
    std::vector<SolverKind> others = {SolverKind::cg_ichol};
    if (cholmod_available()) others.push_back(SolverKind::cholmod);
    for (SolverKind k : others) {
      o.solver = k;
      const Solution s = solve(mesh, p, o);
      EXPECT_EQ(s.solver, k);
      EXPECT_LT((s.u - ref.u).cwiseAbs().maxCoeff(), 1e-7 * ref.u.cwiseAbs().maxCoeff()) << p.name << " " << to_string(k);
    }
  }
}

TEST(Fem, DirichletProblemOnAnOpenSurfaceIsExactForLinearFunctions) {
  // On a flat disk, u = 1 + 2x - y is harmonic: with that Dirichlet data and f = 0, P1
  // reproduces it exactly, on any mesh; the estimators then vanish.
  RgbMesh m = testing::fan_disk(7).build();
  selective_refinement(m, UniformLevel(3));
  // A flat disk: project onto the plane z = 0.
  const SurfaceMesh mesh = build_surface_mesh(m, Projection([](const Vec3& p) { return Vec3(p.x, p.y, 0); }));
  Problem p;
  p.dirichlet = [](const Vec3& x) { return 1 + 2 * x.x - x.y; };
  p.exact = ExactSolution{p.dirichlet, [](const Vec3&) { return Vec3(2, -1, 0); }};  // in the plane z = 0
  const Solution s = solve(mesh, p);
  const ErrorNorms e = error_norms(mesh, s.u, *p.exact);
  EXPECT_LT(e.l2, 1e-12);
  EXPECT_LT(e.h1, 1e-9);  // the lift's derivative by central differences: rounding of ~1e-10
  EXPECT_LT(residual_estimator(mesh, p, s.u).total, 1e-10);
  // With a Neumann part carrying the exact flux (on y < 0), the same solution.
  p.is_neumann = [](const Vec3& x) { return x.y < 0; };
  p.neumann_flux = [](const Vec3& x) {
    const double r = std::hypot(x.x, x.y);  // the outward normal of the polygon is close to x/r
    return (2 * x.x - x.y) / r;
  };
  const Solution s2 = solve(mesh, p);
  EXPECT_LT(error_norms(mesh, s2.u, *p.exact).h1, 0.05);  // the polygon's normals are not x/r
}

// The error norms measure the error on the surface: the exact solution enters only through
// its values and surface gradient on the exact surface, lifted to the flat triangles. Checked
// against an independent computation: on the unit sphere the lift P(x) = x/|x| has the exact
// derivative (I - ννᵀ)/|x|, so ∇_Γh(u∘P)(x) = Π_h ∇_Γu(P(x)) / |x| (Π_h the projection onto
// the triangle's plane), integrated on 64 pieces of each triangle. Exact solutions whose
// functions vary along the normal off the sphere must give the same norms; the former way
// (the gradient of a 3-D extension, projected onto the flat triangle) does not.
TEST(Fem, ErrorNormsLiftTheSurfaceGradientAndIgnoreTheExtension) {
  RgbMesh m = testing::icosahedron().build();
  selective_refinement(m, UniformLevel(3));
  selective_refinement(m, BallLevel(m.control_point(VertexHandle(0)), 0.4 * norm(m.control_point(VertexHandle(0))), 5));
  const SurfaceMesh mesh = build_surface_mesh(m, Projection(project_to_unit_sphere));
  const Vec3 d(0.9, -1.3, 0.4);
  // u(y) = exp(y·d) on the sphere; ∇_Γu(y) = u (d - (y·d) y).
  const auto u = [d](const Vec3& y) { return std::exp(dot(y, d)); };
  const auto surface_gradient = [u, d](const Vec3& y) { return u(y) * (d - dot(y, d) * y); };
  // The same solution, with functions that are wrong off the sphere (|x|^3 and |x|^7 factors).
  const ExactSolution on_sphere{u, surface_gradient};
  const ExactSolution extended{[u](const Vec3& x) { return u(x) * std::pow(norm(x), 3); },
                               [surface_gradient](const Vec3& x) { return surface_gradient(x) * std::pow(norm(x), 7); }};
  // u_h: the interpolant, plus a wave so that the error is not the interpolation error alone.
  Eigen::VectorXd uh(static_cast<Eigen::Index>(mesh.num_dofs()));
  for (std::size_t i = 0; i < mesh.num_dofs(); ++i)
    uh[static_cast<Eigen::Index>(i)] = u(mesh.points[i]) + 0.01 * std::sin(7 * mesh.points[i].x);

  // The reference.
  const auto& rule = triangle_quadrature();
  constexpr int kPieces = 8;  // per side: 64 pieces
  double l2 = 0, h1 = 0, h1_ambient = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 &p0 = mesh.points[t[0]], &p1 = mesh.points[t[1]], &p2 = mesh.points[t[2]];
    const TriangleGeometry g = triangle_geometry(p0, p1, p2);
    const Vec3 grad_h = uh[t[0]] * g.grad[0] + uh[t[1]] * g.grad[1] + uh[t[2]] * g.grad[2];
    const auto flat = [&](const Vec3& v) { return v - dot(v, g.normal) * g.normal; };
    for (int i = 0; i < kPieces; ++i)
      for (int j = 0; i + j < kPieces; ++j)
        for (int upper = 0; upper < (i + j + 1 < kPieces ? 2 : 1); ++upper) {
          // The piece's corners in barycentric (b1, b2) coordinates, in units of 1/kPieces.
          const std::array<std::array<double, 2>, 3> c =
              upper ? std::array<std::array<double, 2>, 3>{{{double(i + 1), double(j)}, {double(i + 1), double(j + 1)}, {double(i), double(j + 1)}}}
                    : std::array<std::array<double, 2>, 3>{{{double(i), double(j)}, {double(i + 1), double(j)}, {double(i), double(j + 1)}}};
          for (const auto& q : rule) {
            const double b1 = (q.barycentric[0] * c[0][0] + q.barycentric[1] * c[1][0] + q.barycentric[2] * c[2][0]) / kPieces;
            const double b2 = (q.barycentric[0] * c[0][1] + q.barycentric[1] * c[1][1] + q.barycentric[2] * c[2][1]) / kPieces;
            const double b0 = 1 - b1 - b2;
            const Vec3 x = b0 * p0 + b1 * p1 + b2 * p2;
            const Vec3 y = x * (1.0 / norm(x));
            const double w = q.weight * g.area / (kPieces * kPieces);
            const double e = u(y) - (b0 * uh[t[0]] + b1 * uh[t[1]] + b2 * uh[t[2]]);
            const Vec3 de = flat(surface_gradient(y)) * (1.0 / norm(x)) - grad_h;
            // The former way: the 3-D gradient of the extension u(x/|x|) |x|^3, at the lift.
            const Vec3 ambient = surface_gradient(y) + 3.0 * u(y) * y;
            const Vec3 da = flat(ambient) - grad_h;
            l2 += w * e * e;
            h1 += w * dot(de, de);
            h1_ambient += w * dot(da, da);
          }
        }
  }
  l2 = std::sqrt(l2);
  h1 = std::sqrt(h1);
  h1_ambient = std::sqrt(h1_ambient);

  for (const ExactSolution* exact : {&on_sphere, &extended}) {
    const ErrorNorms e = error_norms(mesh, uh, *exact);
    // What is left is the degree-5 rule's error on whole triangles (measured: 2e-5 and 5e-7).
    EXPECT_NEAR(e.l2, l2, 1e-4 * l2);
    EXPECT_NEAR(e.h1, h1, 1e-5 * h1);
  }
  EXPECT_GT(h1_ambient, 1.1 * h1) << "the extension's normal derivative would have leaked into the error: "
                                  << h1_ambient << " against " << h1;
}

// CG with algebraic multigrid (hypre's BoomerAMG through PETSc): the direct solver's solution,
// with iteration counts that do not grow with the mesh (within 30% from 2,562 to 163,842
// unknowns: the issue's ±30% around their mean), with c = 1 and with c = 0 (zero mean, one
// value fixed).
TEST(Fem, AlgebraicMultigridSolvesLikeTheDirectSolverWithSteadyIterationCounts) {
  if (!amg_available()) GTEST_SKIP() << "built without PETSc (Debian: libpetsc-real-dev): no amg solver";
  for (const Problem& p : {sphere_peak(), sphere_harmonic()}) {
    std::vector<int> iterations;
    for (int level = 4; level <= 7; ++level) {  // 2,562 to 163,842 unknowns
      RgbMesh m = testing::icosahedron().build();
      selective_refinement(m, UniformLevel(level));
      const SurfaceMesh mesh = build_surface_mesh(m, Projection(project_to_unit_sphere));
      SolveOptions amg;
      amg.solver = SolverKind::amg;
      const Solution s = solve(mesh, p, amg);
      ASSERT_EQ(s.solver, SolverKind::amg);
      iterations.push_back(s.iterations);
      if (level <= 6) {
        SolveOptions direct;
        direct.solver = SolverKind::ldlt;
        const Solution d = solve(mesh, p, direct);
        EXPECT_LT((s.u - d.u).norm(), 1e-7 * d.u.norm()) << p.name << " level " << level;
      }
    }
    const auto [fewest, most] = std::minmax_element(iterations.begin(), iterations.end());
    const double mean = std::accumulate(iterations.begin(), iterations.end(), 0.0) / static_cast<double>(iterations.size());
    EXPECT_GE(*fewest, 2) << p.name;
    EXPECT_GE(*fewest, 0.7 * mean) << p.name << ": " << ::testing::PrintToString(iterations);
    EXPECT_LE(*most, 1.3 * mean) << p.name << ": " << ::testing::PrintToString(iterations);
  }
}

// The previous solution as the initial guess (what adaptive cycles pass): solving again from
// the solution itself needs no iteration; `auto` takes the multigrid solver from 20,000
// unknowns on.
TEST(Fem, AlgebraicMultigridStartsFromTheGuessAndIsTheAutomaticChoiceForLargeSystems) {
  if (!amg_available()) GTEST_SKIP() << "built without PETSc (Debian: libpetsc-real-dev): no amg solver";
  RgbMesh m = testing::icosahedron().build();
  selective_refinement(m, UniformLevel(6));  // 40,962 unknowns
  const SurfaceMesh mesh = build_surface_mesh(m, Projection(project_to_unit_sphere));
  const Solution first = solve(mesh, sphere_peak());
  EXPECT_EQ(first.solver, SolverKind::amg);
  EXPECT_GT(first.iterations, 0);
  SolveOptions again;
  again.solver = SolverKind::amg;
  again.initial_guess = &first.u;
  const Solution second = solve(mesh, sphere_peak(), again);
  EXPECT_LE(second.iterations, 1);
  EXPECT_LT((second.u - first.u).norm(), 1e-8 * first.u.norm());
}

TEST(Fem, SolveIsTheGlobalMatricesSystemOnAnyNumberOfThreads) {
  // solve() assembles straight into compressed columns, a block of triangles at a time on every
  // core. Reference: the global stiffness and mass matrices from assemble() (a triplet list,
  // one thread), the Dirichlet values moved to the right-hand side, solved by LDLT. And one
  // thread must give the same solution as all of them, to the last bit.
  RgbMesh m = testing::grid_with_holes(6, 2).build();
  selective_refinement(m, UniformLevel(1));
  selective_refinement(m, BallLevel(m.control_point(VertexHandle(0)), 0.4, 3));  // graded: hanging levels
  for (const int order : {1, 2}) {
    SCOPED_TRACE("order " + std::to_string(order));
    const SurfaceMesh mesh = build_surface_mesh(m, std::nullopt, order);
    Problem p;
    p.name = "reference";
    p.c = 0.7;
    p.source = [](const Vec3& x) { return 1.0 + x.x * x.y; };
    p.dirichlet = [](const Vec3& x) { return x.x - 2.0 * x.y + 0.5 * x.z; };
    SolveOptions direct;
    direct.solver = SolverKind::ldlt;
    const Solution s = solve(mesh, p, direct);
    const unsigned cap = rgbmesh::detail::thread_cap.exchange(1);
    const Solution one_thread = solve(mesh, p, direct);
    rgbmesh::detail::thread_cap.store(cap);
    EXPECT_EQ(0, std::memcmp(s.u.data(), one_thread.u.data(), sizeof(double) * static_cast<std::size_t>(s.u.size())));

    const System sys = assemble(mesh, p);
    const SparseMatrix a = sys.stiffness + p.c * sys.mass;
    const auto n = static_cast<Eigen::Index>(mesh.num_dofs());
    std::vector<char> fixed(static_cast<std::size_t>(n), 0);
    for (const auto& e : mesh.boundary_edges) {
      fixed[static_cast<std::size_t>(e.a)] = fixed[static_cast<std::size_t>(e.b)] = 1;
      if (e.middle >= 0) fixed[static_cast<std::size_t>(e.middle)] = 1;
    }
    std::vector<Eigen::Index> free_row(static_cast<std::size_t>(n), -1);
    Eigen::Index nf = 0;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      if (fixed[static_cast<std::size_t>(i)]) {
        g[i] = p.dirichlet(mesh.points[static_cast<std::size_t>(i)]);
      } else {
        free_row[static_cast<std::size_t>(i)] = nf++;
      }
    }
    ASSERT_GT(nf, 100);
    ASSERT_LT(nf, n);
    const Eigen::VectorXd load = sys.load - a * g;
    std::vector<Eigen::Triplet<double>> free_entries;
    Eigen::VectorXd rhs(nf);
    for (Eigen::Index j = 0; j < a.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(a, j); it; ++it)
        if (free_row[static_cast<std::size_t>(it.row())] >= 0 && free_row[static_cast<std::size_t>(j)] >= 0)
          free_entries.emplace_back(free_row[static_cast<std::size_t>(it.row())], free_row[static_cast<std::size_t>(j)], it.value());
    for (Eigen::Index i = 0; i < n; ++i)
      if (free_row[static_cast<std::size_t>(i)] >= 0) rhs[free_row[static_cast<std::size_t>(i)]] = load[i];
    SparseMatrix a_free(nf, nf);
    a_free.setFromTriplets(free_entries.begin(), free_entries.end());
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(a_free);
    ASSERT_EQ(ldlt.info(), Eigen::Success);
    const Eigen::VectorXd x = ldlt.solve(rhs);
    Eigen::VectorXd reference = g;
    for (Eigen::Index i = 0; i < n; ++i)
      if (free_row[static_cast<std::size_t>(i)] >= 0) reference[i] = x[free_row[static_cast<std::size_t>(i)]];
    EXPECT_LT((s.u - reference).norm(), 1e-11 * reference.norm());
  }
}

TEST(Fem, LoopSurfaceConservesTheSource) {
  // On a closed surface, ∫(-Δu_h) = 0, so c ∫u_h = ∫f exactly for the discrete solution.
  RgbMesh m = testing::torus(6, 5).build();
  selective_refinement(m, UniformLevel(2));
  const SurfaceMesh mesh = build_surface_mesh(m);  // the vertices on the Loop limit surface
  const Problem p = gaussian_source(mesh.points[0], 0.5);
  const Solution s = solve(mesh, p);
  const System sys = assemble(mesh, p);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(mesh.num_dofs()));
  EXPECT_NEAR(p.c * ones.dot(sys.mass * s.u), sys.load.sum(), 1e-12 * sys.load.sum());
  EXPECT_GT(s.u.maxCoeff(), 0.0);
}

TEST(Fem, ZeroMeanCheckIntegratesOverTheSurfaceNotTheFlatTriangles) {
  // A selectively refined sphere: the flat triangles' area deficit varies over the surface, so
  // the discrete load of the zero-mean source 12xyz sums to 1.7e-3 of its absolute sum; on the
  // sphere itself the source has zero mean, and the solve must accept it.
  RgbMesh m = testing::icosahedron().build();
  selective_refinement(m, UniformLevel(1));
  const Vec3 corner = m.control_point(VertexHandle(0));
  selective_refinement(m, BallLevel(corner + 0.2 * norm(corner) * Vec3(0.3, -0.5, 0.2), 0.3 * norm(corner), 3));
  const SurfaceMesh mesh = build_surface_mesh(m, Projection(project_to_unit_sphere));
  const Problem harmonic = sphere_harmonic();
  const Eigen::VectorXd load = load_vector(mesh, harmonic);
  ASSERT_GT(std::abs(load.sum()), 1e-3 * load.cwiseAbs().sum()) << "the mesh must make the flat load incompatible";
  const Solution s = solve(mesh, harmonic);
  EXPECT_TRUE(s.zero_mean);
  // A coarse mesh (level 1 away from the ball): the error is about that of the uniform level-1
  // mesh, 0.55 (on the flat triangles, against the lifted solution), against an exact solution
  // of H1 seminorm sqrt(12 · 4π/105) = 1.2.
  EXPECT_LT(error_norms(mesh, s.u, *harmonic.exact, true).h1, 0.6);
  // A source with a small but clear mean (0.04 against |12xyz|, of mean 0.955: a relative mean of 4%) is still refused.
  Problem shifted = harmonic;
  shifted.source = [](const Vec3& x) { return 12.0 * x.x * x.y * x.z + 0.04; };
  EXPECT_THROW(solve(mesh, shifted), InputError);
}

TEST(Fem, AMeshWithOnlyDirichletVerticesHasTheInterpolantAsSolution) {
  // A single triangle: no unknown is free; the solution is the boundary data, and the residual
  // estimator still sees the source (so that adaptive refinement can start from here).
  RgbMesh m = testing::single_triangle().build();
  const SurfaceMesh mesh = build_surface_mesh(m);
  Problem p;
  p.c = 1;
  p.source = [](const Vec3&) { return 1.0; };
  p.dirichlet = [](const Vec3& x) { return 2 * x.x - x.y; };
  const Solution s = solve(mesh, p);
  for (std::size_t i = 0; i < mesh.num_dofs(); ++i)
    EXPECT_DOUBLE_EQ(s.u[static_cast<Eigen::Index>(i)], 2 * mesh.points[i].x - mesh.points[i].y);
  EXPECT_GT(residual_estimator(mesh, p, s.u).total, 0);
}

// A vectorised source and vectorised Dirichlet data (PointValues, what the Python package
// passes for a numpy function) are called once per computation with every point the pointwise
// functions would be called at, and give the same numbers bit for bit: P1 and P2, on an open
// Loop surface (Dirichlet boundary) and on the projected sphere with c = 0 (the zero-mean
// check samples the flat triangles, the P2 load the curved elements).
TEST(Fem, VectorisedDataGiveThePointwiseResults) {
  const auto f = [](const Vec3& x) { return std::sin(3 * x.x) + x.y * x.z; };
  const auto g = [](const Vec3& x) { return 1 + x.x - 2 * x.y; };
  RgbMesh disk = testing::fan_disk(6).build();
  selective_refinement(disk, UniformLevel(2));
  RgbMesh ball = testing::icosahedron().build();
  selective_refinement(ball, UniformLevel(2));
  for (int order : {1, 2}) {
    for (const bool sphere_case : {false, true}) {
      RgbMesh& m = sphere_case ? ball : disk;
      const SurfaceMesh mesh = sphere_case ? build_surface_mesh(m, Projection(project_to_unit_sphere), order)
                                           : build_surface_mesh(m, std::nullopt, order);
      Problem pointwise;
      pointwise.name = "pointwise";
      pointwise.c = sphere_case ? 0.0 : 1.0;
      // On the sphere with c = 0: a zero-mean source (odd in x).
      pointwise.source = sphere_case ? ScalarField([](const Vec3& x) { return x.x * (1 + x.y * x.y); }) : ScalarField(f);
      if (!sphere_case) pointwise.dirichlet = g;
      Problem vectorised = pointwise;
      vectorised.name = "vectorised";
      vectorised.source = nullptr;
      vectorised.dirichlet = nullptr;
      int source_calls = 0, dirichlet_calls = 0;
      std::size_t source_points = 0;
      vectorised.source_values = [&](const Vec3* x, std::size_t n, double* v) {
        ++source_calls;
        source_points += n;
        for (std::size_t i = 0; i < n; ++i) v[i] = pointwise.source(x[i]);
      };
      if (!sphere_case)
        vectorised.dirichlet_values = [&](const Vec3* x, std::size_t n, double* v) {
          ++dirichlet_calls;
          for (std::size_t i = 0; i < n; ++i) v[i] = g(x[i]);
        };
      const Solution a = solve(mesh, pointwise), b = solve(mesh, vectorised);
      const std::string what = "order " + std::to_string(order) + (sphere_case ? " sphere" : " disk");
      ASSERT_EQ(a.u.size(), b.u.size()) << what;
      EXPECT_TRUE(a.u == b.u) << what << ": max difference " << (a.u - b.u).cwiseAbs().maxCoeff();
      // The load, plus the zero-mean check on the sphere: 7 points per triangle each time.
      EXPECT_EQ(source_calls, sphere_case ? 2 : 1) << what;
      EXPECT_EQ(source_points, 7 * mesh.triangles.size() * static_cast<std::size_t>(source_calls)) << what;
      EXPECT_EQ(dirichlet_calls, sphere_case ? 0 : 1) << what;
      const Estimate ea = residual_estimator(mesh, pointwise, a.u), eb = residual_estimator(mesh, vectorised, b.u);
      EXPECT_EQ(ea.eta, eb.eta) << what;
      EXPECT_GT(ea.total, 0) << what;
    }
  }
  // Both forms at once, and values that are not finite, are refused.
  const SurfaceMesh mesh = build_surface_mesh(disk);
  Problem both;
  both.c = 1;
  both.source = f;
  both.source_values = [](const Vec3*, std::size_t n, double* v) { std::fill(v, v + n, 1.0); };
  EXPECT_THROW(solve(mesh, both), InputError);
  Problem nan_source;
  nan_source.c = 1;
  nan_source.source_values = [](const Vec3* x, std::size_t n, double* v) {
    for (std::size_t i = 0; i < n; ++i) v[i] = x[i].x > 0.5 ? std::nan("") : 1.0;
  };
  EXPECT_THROW(solve(mesh, nan_source), InputError);
  Problem nan_boundary;
  nan_boundary.c = 1;
  nan_boundary.dirichlet_values = [](const Vec3*, std::size_t n, double* v) { std::fill(v, v + n, std::nan("")); };
  try {
    solve(mesh, nan_boundary);
    FAIL() << "non-finite Dirichlet data were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Dirichlet data are not finite"), std::string::npos) << e.what();
  }
}

TEST(Fem, BadProblemsGiveClearErrors) {
  const SurfaceMesh mesh = sphere(2);
  Problem p;
  p.source = [](const Vec3&) { return 1.0; };  // c = 0 on a closed surface: no solution
  try {
    solve(mesh, p);
    FAIL() << "a source of non-zero mean was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("zero mean"), std::string::npos) << e.what();
  }
  p.c = -1;
  EXPECT_THROW(solve(mesh, p), InputError);
  p.c = 1;
  p.source = [](const Vec3& x) { return x.x > 0 ? std::nan("") : 1.0; };
  EXPECT_THROW(solve(mesh, p), InputError);

  // Two parts, one with a Dirichlet boundary and one closed, c = 0: singular.
  testing::BaseMesh two = testing::fan_disk(5);
  const testing::BaseMesh tet = testing::tetrahedron();
  const auto offset = static_cast<std::int32_t>(two.points.size());
  for (const auto& q : tet.points) two.points.push_back(q + Vec3(5, 0, 0));
  for (const auto& t : tet.triangles) two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  RgbMesh m = two.build();
  selective_refinement(m, UniformLevel(1));
  const SurfaceMesh both = build_surface_mesh(m);
  Problem q;
  q.source = [](const Vec3&) { return 1.0; };
  for (SolverKind k : {SolverKind::ldlt, SolverKind::cg_ichol}) {
    SolveOptions o;
    o.solver = k;
    try {
      solve(both, q, o);
      FAIL() << "a singular system was solved by " << to_string(k);
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
    }
  }

  // A projection that flattens the sphere onto a line makes every triangle degenerate.
  RgbMesh ico = testing::icosahedron().build();
  try {
    build_surface_mesh(ico, Projection([](const Vec3& x) { return Vec3(x.x, 0, 0); }));
    FAIL() << "degenerate triangles were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("degenerate"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rgbmesh::fem
