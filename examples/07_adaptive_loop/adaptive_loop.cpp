// Example 07: the adaptive loop written by hand.
//
// Example 02 calls adapt::run_cycles, which hides the loop. This program writes the same loop
// out from the library's primitives, so that it can be copied and changed: a different
// estimator, marking by hand, coarsening by another rule, output at every step. Each cycle
//   1. builds the finite-element mesh of the current RGB mesh (vertices projected onto the
//      unit sphere, where the exact solution is known),
//   2. solves -Δu + u = f, starting from the previous solution carried to the new mesh,
//   3. estimates the error per triangle (the residual estimator),
//   4. marks triangles (Dörfler: the fewest carrying half of Σ η²) and vertices whose star's
//      indicators are all small,
//   5. refines the marked triangles and removes the marked vertices through the RGB queues
//      (paper section V), one vertex at a time, the mesh conforming throughout, while the
//      transfer object follows every insertion and removal.
// With --check, the same problem goes through adapt::run_cycles too, and the program fails
// unless both give the same unknowns, estimates and errors in every cycle.

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <exception>
#include <new>
#include <vector>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/adapt/marking.hpp"
#include "rgbmesh/adapt/solution_transfer.hpp"
#include "rgbmesh/canonical.hpp"
#include "rgbmesh/fem/estimators.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"

using namespace rgbmesh;

struct Row {
  std::size_t dofs = 0;
  double estimate = 0, error_l2 = 0, error_h1 = 0;
};

RgbMesh start_mesh() {
  const TriangleMeshData ico = icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  selective_refinement(mesh, UniformLevel(1));
  return mesh;
}

// Both loops stop after `cycles` solves, or once an adaptation leaves more than max_dofs
// unknowns (that mesh is not solved): Dörfler marking grows the mesh about 1.5 times a cycle.
std::vector<Row> hand_written_loop(int cycles, double coarsen_below, std::size_t max_dofs) {
  RgbMesh mesh = start_mesh();
  const fem::Problem problem = fem::sphere_peak();
  const fem::Projection sphere(fem::project_to_unit_sphere);
  const fem::ResidualEstimator estimator;
  const adapt::DorflerMarking marking(0.5);
  adapt::SolutionTransfer transfer(mesh);  // observes the mesh from here on
  std::vector<Row> rows;
  for (int cycle = 0; cycle < cycles; ++cycle) {
    // 1-2. The finite-element mesh and the solve, from the carried values.
    const fem::SurfaceMesh fe = fem::build_surface_mesh(mesh, sphere);
    const Eigen::VectorXd guess = transfer.on(fe);
    fem::SolveOptions solve_options;
    if (guess.size() > 0) solve_options.initial_guess = &guess;
    const fem::Solution solution = fem::solve(fe, problem, solve_options);

    // 3. The estimate, and the errors against the exact solution.
    const fem::Estimate estimate = estimator.estimate(fe, problem, solution.u, {});
    const fem::ErrorNorms errors = fem::error_norms(fe, solution.u, *problem.exact);
    rows.push_back({fe.num_dofs(), estimate.total, errors.l2, errors.h1});
    std::printf("  %5d %9zu  %10.3e  %10.3e  %10.3e\n", cycle, fe.num_dofs(), errors.l2, errors.h1,
                estimate.total);
    if (cycle + 1 == cycles) break;  // the last mesh is kept as solved

    // 4. Marks: triangles to refine (per FE triangle), then vertices to remove, whose largest
    // indicator over their star is below a fraction of the smallest marked indicator.
    const adapt::Indicators indicators(estimate.eta);
    const std::vector<char> marked = marking.mark(indicators);
    std::vector<double> triangle_values(static_cast<std::size_t>(mesh.triangle_slots()), 0.0);
    for (std::size_t t = 0; t < marked.size(); ++t)
      if (marked[t]) triangle_values[static_cast<std::size_t>(fe.triangle[t].idx)] = 1.0;
    std::vector<double> vertex_values;
    double threshold = 0;
    if (coarsen_below > 0) {
      vertex_values.assign(static_cast<std::size_t>(mesh.vertex_slots()), 0.0);
      for (std::size_t t = 0; t < fe.triangles.size(); ++t)
        for (const std::int32_t v : fe.triangles[t]) {
          double& value = vertex_values[static_cast<std::size_t>(fe.vertex[static_cast<std::size_t>(v)].idx)];
          value = std::max(value, estimate.eta[t]);
        }
      threshold = coarsen_below * marking.refinement_threshold(indicators, marked);
    }

    // 5. Refine and coarsen through the queues; the transfer follows, from this solution.
    transfer.store(fe, solution.u);
    selective_refinement(
        mesh, FieldCriterion(std::move(triangle_values), 0.5, std::move(vertex_values), threshold));
    // The diagonals of trapezoids chosen by the vertices' names (canonical.hpp), as
    // run_cycles does: the mesh then depends on its vertices only, not on the order of the
    // splits.
    canonical_diagonals(mesh);
    if (mesh.num_vertices() > max_dofs) {  // P1: one unknown per vertex
      std::printf("  stopped: the next mesh has %zu unknowns, more than --max-dofs\n", mesh.num_vertices());
      break;
    }
  }
  return rows;
}

std::vector<Row> library_loop(int cycles, double coarsen_below, std::size_t max_dofs) {
  RgbMesh mesh = start_mesh();
  adapt::AdaptOptions options;
  options.projection = fem::Projection(fem::project_to_unit_sphere);
  options.marking = std::make_shared<adapt::DorflerMarking>(0.5);
  options.coarsen_below = coarsen_below;
  options.max_cycles = cycles;
  options.max_dofs = max_dofs;
  std::vector<Row> rows;
  for (const adapt::CycleReport& r : adapt::run_cycles(mesh, fem::sphere_peak(), options).cycles)
    rows.push_back({r.dofs, r.estimate, *r.error_l2, *r.error_h1});
  return rows;
}

int run(int argc, char** argv) {
  CLI::App app{"Example 07: the adaptive loop written by hand from rgbmesh's primitives."};
  int cycles = 20;
  double coarsen = 0.1;
  bool check = false;
  std::size_t max_dofs = 200000;
  app.add_option("--cycles", cycles, "Cycles to run")->capture_default_str()->check(CLI::Range(1, 40));
  app.add_option("--coarsen", coarsen,
                 "Remove vertices whose star's indicators are below this times the "
                 "smallest marked one, in [0, 1)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.999));
  app.add_option("--max-dofs", max_dofs, "Stop once an adaptation leaves more unknowns than this")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{5000000}));
  app.add_flag("--check", check, "Run adapt::run_cycles on the same problem and compare, cycle by cycle");
  CLI11_PARSE(app, argc, argv);

  std::printf("hand-written loop\n  cycle      dofs    error_L2    error_H1    estimate\n");
  const std::vector<Row> mine = hand_written_loop(cycles, coarsen, max_dofs);
  if (!check) return 0;
  const std::vector<Row> library = library_loop(cycles, coarsen, max_dofs);
  bool same = mine.size() == library.size();
  for (std::size_t i = 0; same && i < mine.size(); ++i)
    same = mine[i].dofs == library[i].dofs && mine[i].estimate == library[i].estimate &&
           mine[i].error_l2 == library[i].error_l2 && mine[i].error_h1 == library[i].error_h1;
  std::printf("adapt::run_cycles on the same problem: %s\n",
              same ? "the same unknowns, estimates and errors in every cycle" : "DIFFERENT");
  return same ? 0 : 1;
}

int main(int argc, char** argv) {
  // The library reports failures by exceptions; the tool's exit codes: 3 for exhausted
  // resources or an internal failure.
  try {
    return run(argc, argv);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "example_07_adaptive_loop: out of memory (lower --cycles or --max-dofs)\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "example_07_adaptive_loop: %s\n", e.what());
  }
  return 3;
}
