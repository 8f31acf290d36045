// Finite-element assembly and solve time per degree of freedom, 10^4 to 10^6 DOFs, for each
// solver: -Δu + u = f (the sphere-peak problem) on the unit sphere, from an octahedron
// refined uniformly (levels 6 to 9: 16,386 to 1,048,578 DOFs); and the cost of the whole
// adaptive cycle, with the share of mesh adaptation, up to 10^5 DOFs.
//
//   build/bin/bench_fem        (scripts/run-bench.sh runs it too)

#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/fem/loop_elements.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/timing.hpp"

namespace {

using namespace rgbmesh;
using namespace rgbmesh::fem;

const SurfaceMesh& octahedral_sphere(int level) {
  static std::map<int, std::unique_ptr<SurfaceMesh>> cache;
  auto& slot = cache[level];
  if (!slot) {
    const std::vector<Vec3> p = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const std::vector<std::array<std::int32_t, 3>> t = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                                        {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    RgbMesh m = RgbMesh::from_triangles(p, t);
    selective_refinement(m, UniformLevel(level));
    slot = std::make_unique<SurfaceMesh>(build_surface_mesh(m, Projection(project_to_unit_sphere)));
  }
  return *slot;
}

void BM_AssembleAndSolve(benchmark::State& state) {
  const int level = static_cast<int>(state.range(0));
  const auto solver = static_cast<SolverKind>(state.range(1));
  if (solver == SolverKind::cholmod && !cholmod_available()) {
    state.SkipWithError("built without CHOLMOD");
    return;
  }
  if (solver == SolverKind::amg && !amg_available()) {
    state.SkipWithError("built without PETSc: no amg");
    return;
  }
  const SurfaceMesh& mesh = octahedral_sphere(level);
  const Problem problem = sphere_peak();
  SolveOptions options;
  options.solver = solver;
  double assembly = 0, solve_time = 0;
  int iterations = 0;
  for (auto _ : state) {
    const Solution s = solve(mesh, problem, options);
    assembly += s.assembly_seconds;
    solve_time += s.solve_seconds;
    iterations = s.iterations;
    benchmark::DoNotOptimize(s.u.data());
  }
  const double n = static_cast<double>(state.iterations()), dofs = static_cast<double>(mesh.num_dofs());
  state.SetLabel(to_string(solver));
  state.counters["dofs"] = dofs;
  state.counters["assembly_s"] = assembly / n;
  state.counters["solve_s"] = solve_time / n;
  state.counters["us_per_dof"] = 1e6 * (assembly + solve_time) / n / dofs;
  if (solver == SolverKind::cg_ichol || solver == SolverKind::amg) state.counters["cg_iterations"] = iterations;
}

void Sizes(benchmark::internal::Benchmark* b) {
  for (int level = 6; level <= 9; ++level) {
    for (SolverKind k : {SolverKind::ldlt, SolverKind::cg_ichol, SolverKind::cholmod, SolverKind::amg})
      b->Args({level, static_cast<long>(k)});
  }
}
BENCHMARK(BM_AssembleAndSolve)->Apply(Sizes)->Unit(benchmark::kSecond)->Iterations(1);

// Loop-basis elements against P2 with as many unknowns (P2 one level coarser), sphere-peak on
// the icosahedron's uniform levels: each side's whole solve (space or FE mesh, assembly,
// solve, estimate), in one process, and their H1 errors.
void BM_UniformLoopAgainstP2(benchmark::State& state) {
  const int level = static_cast<int>(state.range(0));
  const Problem problem = sphere_peak();
  const TriangleMeshData ico = icosahedron();
  const Projection sphere(project_to_unit_sphere);
  double loop_seconds = 0, p2_seconds = 0, loop_h1 = 0, p2_h1 = 0, dofs = 0;
  double space_seconds = 0, assembly_seconds = 0, solve_seconds = 0, estimate_seconds = 0;
  for (auto _ : state) {
    RgbMesh fine = RgbMesh::from_triangles(ico.points, ico.triangles), coarse = fine;
    selective_refinement(fine, UniformLevel(level));
    selective_refinement(coarse, UniformLevel(level - 1));
    auto t0 = std::chrono::steady_clock::now();
    const LoopSpace space = build_loop_space(fine, sphere);
    space_seconds += seconds_since(t0);
    const Solution loop = solve_loop(space, problem);
    assembly_seconds += loop.assembly_seconds;
    solve_seconds += loop.solve_seconds;
    const auto t_estimate = std::chrono::steady_clock::now();
    const Estimate loop_estimate = loop_residual_estimate(space, problem, loop.u);
    estimate_seconds += seconds_since(t_estimate);
    loop_seconds += seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    const SurfaceMesh p2 = build_surface_mesh(coarse, sphere, 2);
    const Solution quadratic = solve(p2, problem);
    const Estimate p2_estimate = ResidualEstimator().estimate(p2, problem, quadratic.u, {});
    p2_seconds += seconds_since(t0);
    benchmark::DoNotOptimize(loop_estimate.total + p2_estimate.total);
    loop_h1 = loop_error_norms(space, loop.u, *problem.exact).h1;
    p2_h1 = error_norms(p2, quadratic.u, *problem.exact).h1;
    dofs = static_cast<double>(space.num_dofs());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["dofs"] = dofs;
  state.counters["loop_s"] = loop_seconds / n;
  state.counters["p2_s"] = p2_seconds / n;
  state.counters["time_loop_over_p2"] = loop_seconds / p2_seconds;
  // Where Loop's time goes: the space (patches, quadrature tables), assembly, solve, estimate.
  state.counters["loop_space_s"] = space_seconds / n;
  state.counters["loop_assembly_s"] = assembly_seconds / n;
  state.counters["loop_solve_s"] = solve_seconds / n;
  state.counters["loop_estimate_s"] = estimate_seconds / n;
  state.counters["loop_h1"] = loop_h1;
  state.counters["p2_h1"] = p2_h1;
}
BENCHMARK(BM_UniformLoopAgainstP2)->DenseRange(4, 7)->Unit(benchmark::kSecond)->Iterations(1);

// Adaptive sphere-peak from the icosahedron on the unit sphere, until about `target` unknowns.
adapt::AdaptRun sphere_peak_run(std::size_t target, bool resumable) {
  const TriangleMeshData ico = icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  adapt::AdaptOptions o;
  o.projection = Projection(project_to_unit_sphere);
  o.max_cycles = 60;
  o.max_dofs = target;
  o.control.resumable = resumable;
  return adapt::run_cycles(mesh, sphere_peak(), o);
}

// The whole adaptive cycle (mesh update + solve + estimate) for sphere-peak, run until the
// mesh reaches about N unknowns: the last cycle's cost per unknown, and the share of it spent
// adapting the mesh (marking, refining and coarsening through the queues, transfer).
void BM_AdaptiveCycle(benchmark::State& state) {
  const auto target = static_cast<std::size_t>(state.range(0));
  adapt::CycleReport last;
  for (auto _ : state) {
    const auto run = sphere_peak_run(target, false);
    last = run.cycles.back();  // it solved, estimated and adapted (to the mesh past the target)
  }
  state.counters["dofs"] = static_cast<double>(last.dofs);
  state.counters["cycle_s"] = last.seconds;
  state.counters["us_per_dof"] = 1e6 * last.seconds / static_cast<double>(last.dofs);
  state.counters["adapt_share"] = last.adapt_seconds / last.seconds;
  state.counters["solve_share"] = last.solve_seconds / last.seconds;
}
BENCHMARK(BM_AdaptiveCycle)->Arg(10000)->Arg(30000)->Arg(100000)->Unit(benchmark::kSecond)->Iterations(1);

// An exactly resumable run (what the tool does: each cycle carries its RGB state, so that a
// run resumed from a cycle file repeats the uninterrupted one) against a plain run of the same
// problem to about N unknowns: compare the two rows' times. (Exactness comes from the canonical
// order of every stage and of the unknowns, not from a rebuild: the rows should be equal.)
void BM_AdaptiveRun(benchmark::State& state) {
  const auto target = static_cast<std::size_t>(state.range(0));
  const bool resumable = state.range(1) != 0;
  std::size_t cycles = 0, dofs = 0;
  for (auto _ : state) {
    const auto run = sphere_peak_run(target, resumable);
    cycles = run.cycles.size();
    dofs = run.cycles.back().dofs;
  }
  state.counters["cycles"] = static_cast<double>(cycles);
  state.counters["dofs"] = static_cast<double>(dofs);
  state.SetLabel(resumable ? "resumable" : "plain");
}
BENCHMARK(BM_AdaptiveRun)
    ->Args({30000, 0})
    ->Args({30000, 1})
    ->Args({100000, 0})
    ->Args({100000, 1})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
