#pragma once
// Error-driven adaptive cycles: solve, estimate, mark, refine and coarsen through the RGB
// queues (paper section V), carry the solution over, repeat.

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rgbmesh/fem/estimators.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/mesh.hpp"

namespace rgbmesh::adapt {

enum class Strategy { adaptive, uniform };
enum class Marking {
  dorfler,         // the fewest triangles carrying a fraction θ of Σ η_T² (bulk chasing)
  fixed_fraction,  // the fraction θ of the triangles with the largest η_T
  // every triangle with η_T > target_estimate / sqrt(number of triangles): equidistribution
  // towards a fixed total, which keeps the mesh at a steady size for moving features
  equidistribution,
};
enum class EstimatorKind { residual, zz };

struct AdaptOptions {
  Strategy strategy = Strategy::adaptive;
  Marking marking = Marking::dorfler;
  double theta = 0.5;
  EstimatorKind estimator = EstimatorKind::residual;
  // Coarsening: removable vertices whose star indicator sqrt(Σ η_T² over the star) is below
  // coarsen_below times the mean star indicator are removed (0: no coarsening).
  double coarsen_below = 0.0;
  // Stops: after max_cycles, when the estimate is at most target_estimate, or when the next
  // cycle would exceed max_dofs (checked after each solve).
  int max_cycles = 10;
  double target_estimate = 0.0;
  std::size_t max_dofs = 1000000;
  int max_level = kMaxLevel;
  fem::SolveOptions solve;
  std::optional<fem::Projection> projection;  // exact-geometry mode (e.g. the unit sphere)
};

struct CycleReport {
  int cycle = 0;
  double time = 0;  // the time of the step, for dynamic problems
  std::size_t triangles = 0, dofs = 0;
  double estimate = 0;
  std::optional<double> error_l2, error_h1;
  double seconds = 0;        // the whole cycle
  double solve_seconds = 0;  // assembly + solve
  double estimate_seconds = 0;
  double adapt_seconds = 0;  // marking + mesh update + solution transfer
  std::size_t marked = 0, splits = 0, removals = 0;
  std::string solver;
};

// Everything about one cycle, for output (before the mesh is adapted).
struct CycleState {
  const CycleReport& report;
  const RgbMesh& mesh;
  const fem::SurfaceMesh& fe;
  const fem::Problem& problem;
  const Eigen::VectorXd& u;
  const fem::Estimate& estimate;
  const std::vector<char>& marked;  // per FE triangle
};
using CycleCallback = std::function<void(const CycleState&)>;

// Runs adaptive (or uniform) cycles on the mesh for a stationary problem. The mesh ends as
// adapted after the last cycle's marking only if a further cycle would run: the last cycle's
// solution stays on its mesh.
std::vector<CycleReport> run_cycles(RgbMesh& mesh, const fem::Problem& problem, const AdaptOptions& options,
                                    const CycleCallback& on_cycle = {});

// A moving source: problem_at(t) gives the problem at time t. Each of the `steps` time steps
// t = 0, 1/steps, ... solves and adapts `cycles_per_step` times (refining where the feature
// is and coarsening where it was), and reports its last cycle. With Dörfler or fixed-fraction
// marking the mesh keeps growing; equidistribution towards a fixed target (for instance the
// estimate reached by run_cycles on the first position) keeps its size steady.
std::vector<CycleReport> run_dynamic(RgbMesh& mesh, const std::function<fem::Problem(double)>& problem_at, int steps,
                                     int cycles_per_step, const AdaptOptions& options, const CycleCallback& on_step = {});

// The peak of fem::sphere_peak moving along a great circle by a quarter turn as t goes from
// 0 to 1, with c = 1 (the moving-peak problem).
fem::Problem moving_peak(double t, double kappa = 100.0);

// The cycle's mesh for output: the finite-element geometry (limit or projected positions)
// with point data "solution", and "exact_solution" and "error" where the exact solution is
// known, plus the insertion level; cell data "error_indicator", "marked", "level", "color".
MeshSnapshot snapshot(const CycleState& state);

// Marks triangles (per FE triangle) by the chosen strategy (target: for equidistribution).
std::vector<char> mark(const std::vector<double>& eta, Marking marking, double theta, double target = 0);

}  // namespace rgbmesh::adapt
