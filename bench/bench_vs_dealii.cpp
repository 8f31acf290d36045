// rgbmesh against deal.II on the same adaptive problem, in one process.
//
// The problem is sphere-peak: -Δu + u = f on the unit sphere, u = exp(κ (x·d - 1)) with κ = 100
// (fem::sphere_peak). Both codes start from a coarse mesh of the exact sphere, mark by Dörfler
// with θ = 0.5 on the squared indicators and refine until the unknowns pass --max-dofs:
//   rgbmesh   P1 and P2 (isoparametric, six nodes on the sphere), residual estimators (or ZZ:
//             --p1-estimator, --p2-estimator), on the RGB mesh of the icosahedron, vertices projected onto
//             the sphere, solver `auto` (CHOLMOD, BoomerAMG from 20,000 unknowns when built with PETSc);
//   rgbmesh   Loop-basis elements (--element loop: the hierarchical Loop space of the RGB mesh),
//             their error measured on the exact sphere (the limit surface projected onto it);
//   deal.II   Q1 and Q2 on its six-quadrilateral sphere with the spherical manifold and a
//             mapping of the element's degree, Kelly's estimator, hanging-node constraints,
//             UMFPACK.
// Both measure the error the same way (the lift of surface finite elements, fem::error_norms):
// ‖u∘P - u_h‖ and ‖∇_Γh(u∘P) - ∇_Γh u_h‖ over the discrete surface, P(x) = x/|x|, where
// ∇_Γh(u∘P)(x) = Π_h ∇_Γu(P(x)) / |x| (the derivative of P is (I - P Pᵀ)/|x|). A cycle's time
// is everything but that error computation: setup, assembly, solve, estimate, marking and the
// mesh update (both codes use both cores where they do: deal.II's Kelly estimator through TBB).
//
// Unknowns: rgbmesh's DoFs; deal.II's DoFs less those its hanging-node constraints fix (they are
// not free), the stricter count for the comparison (the ratio against all of deal.II's DoFs is
// printed too). Prints one table per code and order, then the errors interpolated (log-log) at
// 10^4 and 5·10^4 unknowns with the ratios the project aims at: rgbmesh P1 within 1.1 times deal.II
// Q1's H1 error, rgbmesh P2 below Q2's, Loop at most half of Q2's, and rgbmesh's time per
// cycle per unknown no more than deal.II's at the same order; and the time each needs to reach
// the other's last error.
//
// Usage: bench_vs_dealii [--max-dofs N] [--p1-estimator zz|residual] [--p2-estimator zz|residual]
//                        [--only-rgbmesh]

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_refinement.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/error_estimator.h>
#include <deal.II/numerics/vector_tools.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/fem/estimators.hpp"
#include "rgbmesh/fem/problem.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/timing.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using rgbmesh::seconds_since;

struct Row {
  std::size_t unknowns = 0;  // the free unknowns: deal.II's DoFs less those its hanging nodes constrain
  std::size_t dofs = 0;      // deal.II: every DoF, constrained or not
  double l2 = 0, h1 = 0;
  double seconds = 0;  // the cycle without the error computation
};

struct Series {
  std::string name;
  std::vector<Row> rows;
};

rgbmesh::Vec3 to_vec3(const dealii::Point<3>& p) { return {p[0], p[1], p[2]}; }

// ---- deal.II ------------------------------------------------------------------------------

// The errors of a deal.II solution, measured as fem::error_norms measures rgbmesh's.
Row dealii_errors(const dealii::Mapping<2, 3>& mapping, const dealii::DoFHandler<2, 3>& dofs,
                  const dealii::Vector<double>& u, const rgbmesh::fem::ExactSolution& exact, int degree) {
  using namespace dealii;
  const QGauss<2> rule(degree + 3);
  FEValues<2, 3> fv(mapping, dofs.get_fe(), rule,
                    update_values | update_gradients | update_quadrature_points | update_normal_vectors |
                        update_JxW_values);
  std::vector<double> values(rule.size());
  std::vector<Tensor<1, 3>> gradients(rule.size());
  Row r;
  for (const auto& cell : dofs.active_cell_iterators()) {
    fv.reinit(cell);
    fv.get_function_values(u, values);
    fv.get_function_gradients(u, gradients);
    for (unsigned q = 0; q < rule.size(); ++q) {
      const rgbmesh::Vec3 x = to_vec3(fv.quadrature_point(q));
      const double radius = rgbmesh::norm(x);
      const rgbmesh::Vec3 y = x * (1.0 / radius);
      const rgbmesh::Vec3 n = to_vec3(Point<3>(fv.normal_vector(q)));
      rgbmesh::Vec3 g = exact.surface_gradient(y);
      g = (g - rgbmesh::dot(g, n) * n) * (1.0 / radius);
      const rgbmesh::Vec3 gh = to_vec3(Point<3>(gradients[q]));
      const rgbmesh::Vec3 dg = g - gh;
      const double d = exact.value(y) - values[q];
      r.l2 += fv.JxW(q) * d * d;
      r.h1 += fv.JxW(q) * rgbmesh::dot(dg, dg);
    }
  }
  r.l2 = std::sqrt(r.l2);
  r.h1 = std::sqrt(r.h1);
  r.unknowns = dofs.n_dofs();
  return r;
}

Series run_dealii(int degree, const rgbmesh::fem::Problem& problem, std::size_t max_dofs) {
  using namespace dealii;
  Series s{"deal.II Q" + std::to_string(degree), {}};
  Triangulation<2, 3> tria;
  GridGenerator::hyper_sphere(tria, Point<3>(), 1.0);
  tria.set_all_manifold_ids(0);
  tria.set_manifold(0, SphericalManifold<2, 3>(Point<3>()));
  const FE_Q<2, 3> fe(static_cast<unsigned>(degree));
  const MappingQ<2, 3> mapping(static_cast<unsigned>(degree));
  DoFHandler<2, 3> dofs(tria);
  const QGauss<2> rule(static_cast<unsigned>(degree + 1));
  for (;;) {
    const auto t0 = Clock::now();
    dofs.distribute_dofs(fe);
    AffineConstraints<double> constraints;
    DoFTools::make_hanging_node_constraints(dofs, constraints);
    constraints.close();
    DynamicSparsityPattern dsp(dofs.n_dofs());
    DoFTools::make_sparsity_pattern(dofs, dsp, constraints, false);
    SparsityPattern pattern;
    pattern.copy_from(dsp);
    SparseMatrix<double> a(pattern);
    Vector<double> b(dofs.n_dofs()), u(dofs.n_dofs());
    FEValues<2, 3> fv(mapping, fe, rule, update_values | update_gradients | update_quadrature_points | update_JxW_values);
    const unsigned n = fe.n_dofs_per_cell();
    FullMatrix<double> local_a(n, n);
    Vector<double> local_b(n);
    std::vector<types::global_dof_index> index(n);
    for (const auto& cell : dofs.active_cell_iterators()) {
      fv.reinit(cell);
      local_a = 0;
      local_b = 0;
      for (unsigned q = 0; q < rule.size(); ++q) {
        const rgbmesh::Vec3 x = to_vec3(fv.quadrature_point(q));
        const double f = problem.source(x * (1.0 / rgbmesh::norm(x)));  // at the lift, as rgbmesh
        for (unsigned i = 0; i < n; ++i) {
          for (unsigned j = 0; j < n; ++j)
            local_a(i, j) += (fv.shape_grad(i, q) * fv.shape_grad(j, q) +
                              problem.c * fv.shape_value(i, q) * fv.shape_value(j, q)) *
                             fv.JxW(q);
          local_b(i) += f * fv.shape_value(i, q) * fv.JxW(q);
        }
      }
      cell->get_dof_indices(index);
      constraints.distribute_local_to_global(local_a, local_b, index, a, b);
    }
    SparseDirectUMFPACK solver;
    solver.initialize(a);
    solver.vmult(u, b);
    constraints.distribute(u);
    Vector<float> eta(tria.n_active_cells());
    KellyErrorEstimator<2, 3>::estimate(mapping, dofs, QGauss<1>(static_cast<unsigned>(degree + 1)), {}, u, eta);
    double seconds = seconds_since(t0);
    Row r = dealii_errors(mapping, dofs, u, *problem.exact, degree);
    const bool last = dofs.n_dofs() > max_dofs;
    if (!last) {
      const auto t1 = Clock::now();
      GridRefinement::refine_and_coarsen_fixed_fraction(tria, eta, 0.5, 0.0, std::numeric_limits<unsigned>::max(),
                                                        VectorTools::L2_norm);
      tria.execute_coarsening_and_refinement();
      seconds += seconds_since(t1);
    }
    r.seconds = seconds;
    r.dofs = r.unknowns;
    r.unknowns -= constraints.n_constraints();
    s.rows.push_back(r);
    if (last) break;
  }
  return s;
}

// ---- rgbmesh ------------------------------------------------------------------------------

Series run_rgbmesh(int order, const std::string& estimator, const rgbmesh::fem::Problem& problem,
                   std::size_t max_dofs) {
  using namespace rgbmesh;
  Series s{"rgbmesh P" + std::to_string(order) + (estimator == "zz" ? " (ZZ)" : " (residual)"), {}};
  const TriangleMeshData ico = icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  adapt::AdaptOptions o;
  o.projection = fem::Projection(fem::project_to_unit_sphere);
  o.order = order;
  o.estimator = fem::make_estimator(estimator);
  o.marking = std::make_shared<adapt::DorflerMarking>(0.5);
  o.max_cycles = 100;
  o.max_dofs = max_dofs;
  adapt::run_cycles(mesh, problem, o, [&](const adapt::CycleState& c) {
    // The cycle's time includes the errors; take them out as for deal.II (measured again).
    const auto t0 = Clock::now();
    const fem::ErrorNorms e = fem::error_norms(c.fe, c.u, *problem.exact);
    const double norms = seconds_since(t0);
    s.rows.push_back({c.report.dofs, c.report.dofs, e.l2, e.h1, std::max(0.0, c.report.seconds - norms)});
  });
  return s;
}

// Loop-basis elements (AdaptOptions::Element::loop: the hierarchical Loop space of each RGB
// mesh), marked as P1 and P2 are. Their error is the one run_cycles measures on the exact
// sphere (the limit surface projected onto it: fem::loop_error_norms), taken out of the cycle
// time as the others' are.
Series run_rgbmesh_loop(const rgbmesh::fem::Problem& problem, std::size_t max_dofs) {
  using namespace rgbmesh;
  Series s{"rgbmesh Loop (residual)", {}};
  const TriangleMeshData ico = icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  adapt::AdaptOptions o;
  o.projection = fem::Projection(fem::project_to_unit_sphere);
  o.element = adapt::AdaptOptions::Element::loop;
  o.marking = std::make_shared<adapt::DorflerMarking>(0.5);
  o.max_cycles = 100;
  o.max_dofs = max_dofs;
  adapt::run_cycles(mesh, problem, o, [&](const adapt::CycleState& c) {
    s.rows.push_back({c.report.dofs, c.report.dofs, *c.report.error_l2, *c.report.error_h1,
                      std::max(0.0, c.report.seconds - c.report.error_seconds)});
  });
  return s;
}

// ---- report -------------------------------------------------------------------------------

void print(const Series& s) {
  std::printf("\n%s\n%10s %10s %12s %12s %10s %12s\n", s.name.c_str(), "unknowns", "all_dofs", "L2", "H1", "cycle_s",
              "us/unknown");
  for (const Row& r : s.rows)
    std::printf("%10zu %10zu %12.4e %12.4e %10.4f %12.3f\n", r.unknowns, r.dofs, r.l2, r.h1, r.seconds,
                1e6 * r.seconds / static_cast<double>(r.unknowns));
}

// A quantity of the series at n unknowns, interpolated linearly in log-log between the cycles
// around n (NaN outside the run).
template <class Get>
double at_unknowns(const Series& s, double n, Get get, bool all_dofs = false) {
  const auto x = [all_dofs](const Row& r) { return static_cast<double>(all_dofs ? r.dofs : r.unknowns); };
  for (std::size_t i = 0; i + 1 < s.rows.size(); ++i) {
    const double n0 = x(s.rows[i]), n1 = x(s.rows[i + 1]);
    if (n0 <= n && n <= n1) {
      const double t = n1 > n0 ? std::log(n / n0) / std::log(n1 / n0) : 0.0;
      return std::exp((1 - t) * std::log(get(s.rows[i])) + t * std::log(get(s.rows[i + 1])));
    }
  }
  return std::nan("");
}

// Time per cycle per unknown over the cycles from n/4 to 4n unknowns (cycle times are noisy).
double microseconds_per_unknown(const Series& s, double n) {
  double seconds = 0, unknowns = 0;
  for (const Row& r : s.rows) {
    const auto u = static_cast<double>(r.unknowns);
    if (u >= n / 4 && u <= 4 * n) {
      seconds += r.seconds;
      unknowns += u;
    }
  }
  return unknowns > 0 ? 1e6 * seconds / unknowns : std::nan("");
}

// The time of all cycles up to the first whose H1 error is at most h1 (NaN if none is).
double seconds_to_reach(const Series& s, double h1) {
  double seconds = 0;
  for (const Row& r : s.rows) {
    seconds += r.seconds;
    if (r.h1 <= h1) return seconds;
  }
  return std::nan("");
}

void compare(const Series& ours, const Series& theirs, const char* target) {
  std::printf("\n%s against %s\n%10s %12s %12s %8s %12s %12s %8s %8s %10s\n", ours.name.c_str(),
              theirs.name.c_str(), "unknowns", "H1 ours", "H1 theirs", "ratio", "us/u ours", "us/u theirs", "ratio",
              "L2 ratio", "H1 by all");
  for (const double n : {1e4, 5e4}) {
    const auto h1 = [](const Row& r) { return r.h1; };
    const auto l2 = [](const Row& r) { return r.l2; };
    const double a = at_unknowns(ours, n, h1), b = at_unknowns(theirs, n, h1);
    const double ta = microseconds_per_unknown(ours, n), tb = microseconds_per_unknown(theirs, n);
    std::printf("%10.0f %12.4e %12.4e %8.3f %12.3f %12.3f %8.3f %8.3f %10.3f\n", n, a, b, a / b, ta, tb, ta / tb,
                at_unknowns(ours, n, l2) / at_unknowns(theirs, n, l2), a / at_unknowns(theirs, n, h1, true));
  }
  std::printf("(unknowns: deal.II's DoFs less the hanging-node constrained ones; 'H1 by all': the H1 ratio\n"
              " against deal.II's error at as many DoFs, constrained ones included)\n");
  const double reached = theirs.rows.back().h1;
  const double ours_seconds = seconds_to_reach(ours, reached);
  if (std::isnan(ours_seconds))
    std::printf(
        "to %s's last H1 error (%.3e): not reached here within --max-dofs (last error %.3e), %.3f s "
        "there\n",
        theirs.name.c_str(), reached, ours.rows.back().h1, seconds_to_reach(theirs, reached));
  else
    std::printf("to %s's last H1 error (%.3e): %.3f s of cycles here, %.3f s there\n", theirs.name.c_str(),
                reached, ours_seconds, seconds_to_reach(theirs, reached));
  std::printf("target: H1 ratio %s, time ratio <= 1\n", target);
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t max_dofs = 100000;
  std::string p1_estimator = "residual", p2_estimator = "residual";
  bool only_rgbmesh = false;
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--max-dofs") && has_value) {
      max_dofs = std::strtoull(argv[++i], nullptr, 10);
    } else if ((!std::strcmp(argv[i], "--p1-estimator") || !std::strcmp(argv[i], "--p2-estimator")) && has_value) {
      const std::string e = argv[i + 1];
      if (e != "zz" && e != "residual") {
        std::fprintf(stderr, "bench_vs_dealii: %s takes zz or residual, not '%s'\n", argv[i], e.c_str());
        return 2;
      }
      (argv[i][3] == '1' ? p1_estimator : p2_estimator) = e;
      ++i;
    } else if (!std::strcmp(argv[i], "--only-rgbmesh")) {
      only_rgbmesh = true;
    } else {
      std::fprintf(stderr, "usage: bench_vs_dealii [--max-dofs N] [--p1-estimator zz|residual] "
                           "[--p2-estimator zz|residual] [--only-rgbmesh]\n");
      return 2;
    }
  }
  const rgbmesh::fem::Problem problem = rgbmesh::fem::sphere_peak();
  const Series p1 = run_rgbmesh(1, p1_estimator, problem, max_dofs);
  const Series p2 = run_rgbmesh(2, p2_estimator, problem, max_dofs);
  const Series loop = run_rgbmesh_loop(problem, max_dofs);
  print(p1);
  print(p2);
  print(loop);
  if (only_rgbmesh) return 0;
  const Series q1 = run_dealii(1, problem, max_dofs);
  const Series q2 = run_dealii(2, problem, max_dofs);
  print(q1);
  print(q2);
  compare(p1, q1, "<= 1.1");
  compare(p2, q2, "< 1");
  compare(loop, q2, "<= 0.5");
  return 0;
}
