#pragma once
/// \file
/// Error-driven adaptive cycles: solve, estimate, mark, refine and coarsen through the RGB
/// queues (paper section V), carry the solution over, repeat.

#include <Eigen/Core>
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rgbmesh/adapt/marking.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/fem/estimators.hpp"
#include "rgbmesh/fem/loop_basis_kind.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/snapshot.hpp"

namespace rgbmesh::fem {
struct AdaptiveLoopSpace;
}

namespace rgbmesh::adapt {

enum class Strategy { adaptive, uniform };
/// The strategies by name ("adaptive", "uniform"), for the tool and Python (named_row).
const std::vector<Named<Strategy>>& strategy_table();

struct CycleReport;

/// How a run is shared among processes: rgbmesh::parallel's distribute and distribute_mesh set
/// these hooks, and a run on one process leaves them empty. Nothing here needs MPI: the serial
/// loop calls the hooks where they are set.
struct Distribution {
  /// Output in pieces (a run on several processes): the part of every triangle of a solved
  /// mesh, per FE triangle, taken before the mesh is adapted (SolvedMesh::triangle_part, the
  /// snapshot's "rank" cell array). Empty: none.
  std::function<std::vector<std::int32_t>(const RgbMesh&, const fem::SurfaceMesh&)> partition;
  /// With partition: this process (share.process), the sum across processes and the gather of
  /// per-triangle values. Each process then computes the estimator's and the error norms'
  /// terms of its own part's triangles only, and receives the others'. (share.part is
  /// ignored: each cycle's comes from partition.)
  fem::WorkShare share;
  /// On several processes: called by every process at the end of each cycle, returns the
  /// bytes all processes sent since the previous call, in all and the most by one process
  /// (CycleReport::bytes_sent, bytes_sent_largest).
  std::function<std::array<std::uint64_t, 2>()> bytes_sent;
  /// A distributed mesh: called by every process at the end of each cycle, returns what the
  /// distributed mesh did since the previous call that grows with the processes apart from
  /// the bytes: its coarsening rounds and its all-to-all exchanges (CycleReport::
  /// coarsening_rounds, exchanges), the same on every process.
  std::function<std::array<std::uint64_t, 2>()> rounds;
  /// A distributed mesh (rgbmesh::parallel::distribute_mesh): the mesh passed to run_cycles
  /// is this process's view of the whole (its part exact, the rest coarser), partition gives
  /// the parts of the view's triangles (-1 where it is coarser than the whole mesh), and the
  /// counts, the total estimate and the marks are the whole mesh's (sums over the parts; each
  /// process marks its own triangles against thresholds found together). prepare_mesh is
  /// called at the start of every cycle, before the finite-element mesh is built (the parts
  /// are decided anew and the view brought to its new part), after_adaptation after every
  /// adaptation (the splits of the other processes that reach this one's part). Adaptive and
  /// uniform refinement of run_cycles, and coarsening: coarsen_mesh carries out the removals
  /// (RefinementOptions::coarsen), each vertex's value being the largest indicator over the
  /// own triangles around it.
  bool distributed_mesh = false;
  std::function<void(RgbMesh&)> prepare_mesh, after_adaptation;
  std::function<std::uint64_t(RgbMesh&, const LodCriterion&)> coarsen_mesh;
};

/// When a run stops early, how it is interrupted, and what it keeps for a later run.
struct RunControl {
  /// Memory: when set, returns the bytes still free under the caller's ceiling. A cycle whose
  /// mesh would need more (solve_bytes_per_dof per new unknown, the refinement's arrays) is not
  /// run: the run stops with StopReason::memory, its results so far intact.
  std::function<std::size_t()> memory_headroom;
  /// run_cycles: asked after each cycle's solve and estimate, before the mesh is adapted;
  /// true ends the run with that cycle (StopReason::requested), the mesh staying the one
  /// solved, as at the other stops. Empty: never.
  std::function<bool(const CycleReport&)> stop;
  /// Called between the steps of a cycle and every 65,536 operations of an adaptation. It may
  /// throw to abandon the run (how the Python package lets Ctrl-C through): the exception
  /// leaves run_cycles or run_dynamic with the mesh valid, though perhaps partly adapted.
  std::function<void()> interruption_point;
  /// When set, asked at the end of each cycle for the process's resident memory
  /// (CycleReport::resident_bytes).
  std::function<std::size_t()> resident_bytes;
  /// When set, called after each solve (with its estimate and errors), once the assembly's,
  /// the solver's and the estimator's transients are freed: the tool hands the allocator's
  /// free pages back to the system there (malloc_trim). Without it a run whose mesh shrank
  /// keeps the pages of its largest solve resident (the moving peak settled at 1.45 times a
  /// new run's resident memory on the same mesh, all of it free heap).
  std::function<void()> release_free_memory;
  /// Resumable runs: each cycle's CycleState carries the mesh's RGB state
  /// (SolvedMesh::state), so that snapshot() gives a file that read_rgb_mesh restores. A run
  /// continued from such a file (first_cycle, DynamicOptions::first_step) repeats the
  /// uninterrupted run exactly: every stage of the adaptation and the numbering of the unknowns
  /// depend on the mesh alone (canonical.hpp), not on its handles, so the restored mesh, whose
  /// handles differ, is solved and adapted as the original was.
  bool resumable = false;
  /// Resuming (run_cycles): the mesh is the one solved in cycle first_cycle - 1 of an earlier
  /// run (e.g. restored from that cycle's file). That cycle is solved again, without a report
  /// or callback, and marked and adapted as the earlier run did; the run goes on with cycle
  /// first_cycle (max_cycles counts the earlier cycles too). 0: a new run.
  int first_cycle = 0;
};

/// The adaptive algorithm and its stops, plus how the run is distributed and controlled.
struct AdaptOptions {
  Strategy strategy = Strategy::adaptive;
  /// Which triangles a cycle refines (marking.hpp: built-in strategies, or your own).
  std::shared_ptr<const MarkingStrategy> marking = std::make_shared<DorflerMarking>(0.5);
  /// The per-triangle indicators (fem::ErrorEstimator: built-in estimators, or your own).
  std::shared_ptr<const fem::ErrorEstimator> estimator = std::make_shared<fem::ResidualEstimator>();
  /// Coarsening, in [0, 1): removable vertices whose largest indicator over their star is below
  /// coarsen_below times the refinement threshold (MarkingStrategy::refinement_threshold: the
  /// smallest indicator marked for refinement; with equidistribution the limit
  /// target_estimate / sqrt(N)) are removed. The same scale for both halves puts the coarsest
  /// fine triangles where refinement would stop, so that a moving feature leaves as much
  /// refinement behind as it finds ahead. (Loop elements compare their details' cost instead
  /// of the indicators: see `element`.) 0: none.
  double coarsen_below = 0.0;
  /// Stops: after max_cycles, when the estimate is at most target_estimate, or when the mesh
  /// would exceed max_dofs (uniform refinement predicts the next size and stops before it;
  /// adaptive refinement stops once a refined mesh has more, before solving on it).
  int max_cycles = 10;
  double target_estimate = 0.0;
  std::size_t max_dofs = 1000000;
  int max_level = kMaxLevel;
  /// A floor: no triangle coarser than this level. The mesh is refined to it before the first
  /// solve (AtLeastLevel) and coarsening never removes a vertex of this level or below, so
  /// every triangle of every cycle lies inside one triangle of the uniform level-min_level mesh
  /// (the unit a distributed run partitions).
  int min_level = 0;
  fem::SolveOptions solve;
  std::optional<fem::Projection> projection;  ///< exact-geometry mode (e.g. the unit sphere)
  /// Finite elements: 1 (P1) or 2 (isoparametric P2, fem::build_surface_mesh). Order 2 counts
  /// unknowns as vertices + edges, carries the solution's vertex and edge values through the
  /// adaptation (SolutionTransfer) as the next solve's initial guess, and writes each cycle's
  /// solution at the vertices (quadratic_snapshot: every node).
  int order = 1;
  /// lagrange: P1 or P2 by `order`. loop: Loop-basis elements in the hierarchical space of the
  /// RGB mesh (fem/loop_adaptive.hpp) in the basis `loop_basis` (order 1), each cycle's solution
  /// written as its values at the limit positions and estimated by fem::loop_residual_estimate
  /// per cell, the indicators moved onto the RGB triangles for marking
  /// (fem::loop_indicators_on_triangles); coarsening compares what removing a vertex's detail
  /// costs (fem::loop_removal_costs) instead of the indicators around it, and keeps the
  /// vertices of marked triangles. On one process.
  enum class Element { lagrange, loop } element = Element::lagrange;
  /// Loop elements: the basis of the space (fem::LoopBasisKind). The truncated hierarchical
  /// basis has rows as narrow as the uniform space's and its unknowns are counted when its space
  /// is built (a run stops at the solve that would pass max_dofs); the details have one unknown
  /// per vertex.
  fem::LoopBasisKind loop_basis = fem::LoopBasisKind::details;
  /// The truncated hierarchical basis: the marks are extended so that at most this many levels
  /// of functions meet on a cell (mark_admissible); below 2, not.
  int loop_admissible_levels = 2;
  /// Loop elements: also a picture of each cycle's solution finer than the mesh
  /// (fem::loop_refined_view with this many levels, CycleState::loop_view); 0 for none. Reduced
  /// on large meshes to stay within 3·10^6 pieces.
  int loop_view_levels = 0;
  /// Memory back after coarsening: a cycle starts by compacting the mesh (RgbMesh::compact)
  /// when fewer than this share of its vertex slots hold a vertex. Results are the same
  /// (numberings are canonical, the solution transfer is told the new slots); 0: never. A
  /// distributed run compacts each process's view instead, after it has been coarsened away
  /// from its part.
  double compact_below = 0.5;
  Distribution distribution;  ///< several processes (rgbmesh::parallel); empty on one
  RunControl control;
};

/// Why a run ended.
enum class StopReason {
  cycles,        ///< max_cycles done
  target_error,  ///< the estimate reached target_estimate
  max_dofs,      ///< the next mesh would exceed max_dofs
  steps,         ///< every time step done (run_dynamic)
  memory,        ///< the next cycle would pass the memory ceiling (RunControl::memory_headroom)
  requested,     ///< RunControl::stop said so
};

/// Peak memory of one cycle per unknown (mesh, finite-element mesh, assembly, CHOLMOD's factor,
/// estimate, output) with Lagrange elements, measured: 1.25 GB at 655,362 unknowns (1.9 kB
/// each) for uniform sphere-peak; with a margin.
inline constexpr double kSolveBytesPerDof = 2500.0;
/// The same for Loop-basis elements: their rows couple 37 unknowns rather than about 7 on a
/// uniform mesh, more in the hierarchical basis of an adaptive one (a coarse function overlaps
/// every finer one in its support), and the cells keep 12 functions at 16 points each.
/// Measured: 1.2 GB at 163,842 unknowns (7.3 kB each) for uniform sphere-peak, 773 MB at
/// 48,164 (16 kB each) for adaptive sphere-peak; with a margin over the larger.
inline constexpr double kLoopSolveBytesPerDof = 18000.0;
/// "cycles", "target-error", "max-dofs", "steps", "memory", "requested".
const char* to_string(StopReason reason);

struct CycleReport {
  int cycle = 0;
  double time = 0;  ///< the time of the step, for dynamic problems
  std::size_t triangles = 0, dofs = 0;
  std::size_t mesh_bytes = 0;      ///< the RgbMesh's arrays when the cycle's mesh was solved
  std::size_t resident_bytes = 0;  ///< RunControl::resident_bytes at the cycle's end (0: not asked)
  double estimate = 0;
  std::optional<double> error_l2, error_h1;
  /// The whole cycle. A dynamic problem's step (run_dynamic): the whole step, and each
  /// stage's seconds below are the sums over all of its solves and adaptations.
  double seconds = 0;
  double mesh_seconds = 0;   ///< the finite-element mesh (limit positions, P2 edge nodes)
  double solve_seconds = 0;  ///< assembly + solve
  double assembly_seconds = 0;  ///< of solve_seconds, the assembly
  double estimate_seconds = 0;
  /// The errors against the exact solution, where it is known (a dynamic step computes them
  /// at its last solve only: the others' are not reported).
  double error_seconds = 0;
  double adapt_seconds = 0;  ///< marking + mesh update + solution transfer
  double partition_seconds = 0;  ///< with Distribution::partition: the triangles' parts
  /// A distributed mesh: the parts decided and the views migrated (prepare_mesh), and the
  /// interface splits exchanged after the adaptation (after_adaptation); not in adapt_seconds.
  double exchange_seconds = 0;
  /// Writing the cycle's files, for the caller that writes them (the tool sets it in its
  /// report); not part of `seconds`.
  double output_seconds = 0;
  /// With Distribution::bytes_sent: the bytes the processes sent during the cycle, in all and
  /// the most by one of them.
  std::uint64_t bytes_sent = 0, bytes_sent_largest = 0;
  /// With Distribution::rounds (a distributed mesh): the rounds of the cycle's coarsening,
  /// each one an exchange of the processes' removals and the ghost layers made exact again,
  /// over all of the cycle's adaptations (a moving feature's step has several); and the
  /// distributed mesh's all-to-all exchanges (each a message to and from every process). 0 on
  /// one process.
  std::uint64_t coarsening_rounds = 0, exchanges = 0;
  std::size_t marked = 0, splits = 0, removals = 0;
  bool memory_limit_reached = false;  ///< the adaptation stopped at the memory ceiling
  std::string solver;
  /// Something the user should know about this cycle's result, in one line (empty: nothing).
  /// Loop elements: most of the estimate lies where the limit surface's parametrization is
  /// nearly singular (fem::loop_singular_estimate), where refinement converges slowly.
  std::string note;
  int solver_iterations = 0;  ///< CG and AMG: the iterations of the cycle's solve (0 for direct solvers)
};

/// What the mesh of a cycle's solution was, per FE point and triangle, taken before the mesh
/// is adapted (the callback comes after the adaptation, when the FE handles may name other
/// elements or none).
struct SolvedMesh {
  std::vector<std::uint8_t> vertex_level, triangle_level;
  std::vector<Color> triangle_color;
  std::optional<RgbState> state;            ///< with RunControl::resumable; point i is FE point i
  std::vector<std::int32_t> triangle_part;  ///< with Distribution::partition, per FE triangle
  /// A distributed mesh: the state of this process's piece (save_piece_state; its points in
  /// the order snapshot_piece gives them), which a resumed run joins with the others'.
  std::optional<RgbState> piece_state;
};

/// Everything about one cycle, for output. `mesh` is the mesh after the cycle's adaptation
/// (the next cycle's mesh); the cycle's own mesh is `fe` and `solved`.
struct CycleState {
  const CycleReport& report;
  const RgbMesh& mesh;
  const fem::SurfaceMesh& fe;
  const fem::Problem& problem;
  const Eigen::VectorXd& u;
  const fem::Estimate& estimate;
  const std::vector<char>& marked;  ///< per FE triangle
  const SolvedMesh* solved = nullptr;  ///< set by run_cycles and run_dynamic
  /// Loop elements with loop_view_levels > 0: the picture (shared: a callback may keep it);
  /// its levels may be fewer than asked on large meshes, none past 3 million pieces.
  std::shared_ptr<const MeshSnapshot> loop_view;
};
using CycleCallback = std::function<void(const CycleState&)>;

/// The cycles of a run and why it ended.
struct AdaptRun {
  std::vector<CycleReport> cycles;  ///< one per cycle (run_cycles) or time step (run_dynamic)
  std::vector<CycleReport> start;   ///< run_dynamic: the cycles that adapted to the start
  StopReason stopped = StopReason::cycles;
  double target_estimate = 0;       ///< run_dynamic: the equidistribution target used
};

/// Loop elements: the note (CycleReport::note) for an estimate whose indicators per cell of
/// the space are `eta`: empty unless half of it or more lies on cells where the limit
/// surface's parametrization is nearly singular (fem::loop_singular_estimate below 1e-5).
std::string loop_singular_note(const fem::AdaptiveLoopSpace& space, const std::vector<double>& eta);

/// Runs adaptive (or uniform) cycles on the mesh for a stationary problem. The last solved
/// mesh stays as it is, except when the run stops at max_dofs after adaptive refinement: the
/// mesh is then the refined one that was not solved.
AdaptRun run_cycles(RgbMesh& mesh, const fem::Problem& problem, const AdaptOptions& options,
                    const CycleCallback& on_cycle = {});

struct DynamicOptions {
  int steps = 24;           ///< time steps t = 0, 1/steps, ..., 1 (steps + 1 solves)
  int cycles_per_step = 2;  ///< adaptations to each new time before it is solved and reported
  int start_cycles = 8;     ///< cycles that adapt the mesh to the problem at t = 0 first
  /// Resuming: the mesh is the one solved at step first_step - 1 of an earlier run with the
  /// same steps. The start is skipped (with equidistribution marking, options.target_estimate
  /// must be the earlier run's target), that step is solved again for the transferred values,
  /// and the steps go on from first_step. 0: a new run.
  int first_step = 0;
  /// Called once the start is adapted, with its cycles and the target of the steps.
  std::function<void(const std::vector<CycleReport>& start, double target_estimate)> on_started;
};

/// A moving source: problem_at(t) gives the problem at time t. The mesh is first adapted to
/// the problem at t = 0 (start_cycles cycles with the options' strategy; equidistribution
/// starts with Dörfler marking unless a target is given); then each time step adapts
/// cycles_per_step times to the problem at its time (refining where the feature is, coarsening
/// where it was), solves and reports. With equidistribution marking and no target_estimate,
/// the target is the estimate reached at the start, which keeps the mesh at a steady size
/// (the start is then settled under that marking, so the size is steady from the first step);
/// Dörfler and fixed-fraction marking refine at every step, until max_dofs. The uniform
/// strategy refines at the start only and keeps that mesh. The run stops early if an
/// adaptation would exceed max_dofs.
AdaptRun run_dynamic(RgbMesh& mesh, const std::function<fem::Problem(double)>& problem_at,
                     const AdaptOptions& options, const DynamicOptions& dynamic, const CycleCallback& on_step = {});

/// The peak of fem::sphere_peak moving along a great circle by a quarter turn as t goes from
/// 0 to 1, with c = 1 (the moving-peak problem).
fem::Problem moving_peak(double t, double kappa = 100.0);

/// The cycle's mesh for output: the finite-element geometry (limit or projected positions)
/// with point data "solution", and "exact_solution" and "error" where the exact solution is
/// known, plus the insertion level; cell data "error_indicator", "marked", "level", "color";
/// and the RGB state when the cycle carries one (RunControl::resumable); "rank" (each
/// triangle's part) with Distribution::partition.
MeshSnapshot snapshot(const CycleState& state);

/// A P2 cycle's elements for output as quadratic triangles (vtk_io's
/// write_quadratic_triangles): every node (corners, then edge nodes), six per triangle, with
/// point data "solution", "exact_solution" and "error" (where the exact solution is known) at
/// every node, and cell data "error_indicator", "marked" and "level". Empty for P1.
struct QuadraticSnapshot {
  std::vector<Vec3> points;
  std::vector<std::array<std::int32_t, 6>> cells;
  std::vector<NamedArray> point_data, cell_data;
};
QuadraticSnapshot quadratic_snapshot(const CycleState& state);
/// One process's piece of it (runs on several processes): the cells whose `part` is `which`,
/// the nodes they use (in their order), and every array restricted alike.
QuadraticSnapshot quadratic_piece(const QuadraticSnapshot& whole, const std::vector<std::int32_t>& part, std::int32_t which);

}  // namespace rgbmesh::adapt
