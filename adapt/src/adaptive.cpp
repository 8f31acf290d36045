#include "rgbmesh/adapt/adaptive.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>

#include "rgbmesh/adapt/solution_transfer.hpp"
#include "rgbmesh/canonical.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/fem/loop_adaptive.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/rgb_state.hpp"
#include "rgbmesh/timing.hpp"

namespace rgbmesh::adapt {

namespace {

// Whether a solve's errors against the exact solution are read: a moving feature's inner
// solves (and its settling ones) feed only the next adaptation, and their report is not kept,
// so the norms (a tenth of a serial step) are not computed there.
enum class ErrorsWanted { reported, not_read };

struct SolvedCycle {
  fem::SurfaceMesh fe;
  fem::Solution solution;
  fem::Estimate estimate;
  CycleReport report;
  std::vector<std::int32_t> triangle_part;  ///< with AdaptOptions::partition
  /// A distributed mesh: the whole mesh's vertices, edges and triangles (each counted by the
  /// lowest part holding it), and whether its unknowns passed max_dofs (then not solved).
  std::size_t vertices = 0, edges = 0;
  bool over_max_dofs = false;
  std::shared_ptr<const MeshSnapshot> loop_view;  ///< Loop elements: the refined picture, if asked
  /// Loop elements: per FE vertex, what removing it costs (its detail's energy, |u_i|
  /// sqrt(a(φ_i, φ_i)); infinite for base vertices), which coarsening compares instead of the
  /// indicators around it.
  std::vector<double> removal_cost;
};

// A distributed mesh's counts (SolvedCycle::vertices, edges; the report's triangles and
// unknowns): each process counts the vertices, edges and triangles of its own triangles whose
// lowest part is its own, and the counts are added up. (The neighbours of own triangles are
// exact in the view, so their parts are known.)
void count_over_parts(SolvedCycle& c, const RgbMesh& mesh, const AdaptOptions& options) {
  const fem::SurfaceMesh& fe = c.fe;
  const std::vector<std::int32_t>& part = c.triangle_part;
  const std::int32_t me = options.distribution.share.process;
  // Each triangle's part by slot, for the edges' neighbours (-1: none or unknown).
  std::vector<std::int32_t> part_of_slot(static_cast<std::size_t>(mesh.triangle_slots()), -1);
  for (std::size_t t = 0; t < fe.triangles.size(); ++t) part_of_slot[static_cast<std::size_t>(fe.triangle[t].idx)] = part[t];
  std::vector<std::int32_t> lowest(fe.vertex.size(), std::numeric_limits<std::int32_t>::max());
  for (std::size_t t = 0; t < fe.triangles.size(); ++t) {
    if (part[t] < 0) continue;
    for (const std::int32_t v : fe.triangles[t]) lowest[static_cast<std::size_t>(v)] = std::min(lowest[static_cast<std::size_t>(v)], part[t]);
  }
  double counts[3] = {0, 0, 0};  // vertices, edges, triangles
  for (std::size_t t = 0; t < fe.triangles.size(); ++t) {
    if (part[t] != me) continue;
    counts[2] += 1;
    for (const std::int32_t v : fe.triangles[t])
      if (lowest[static_cast<std::size_t>(v)] == me) {
        counts[0] += 1;
        lowest[static_cast<std::size_t>(v)] = -1;  // counted once
      }
    // An edge is counted by the lower part beside it; between two own triangles, from the one
    // in the lower slot.
    const TriangleHandle h = fe.triangle[t];
    for (const EdgeHandle e : mesh.triangle_edges(h)) {
      const TriangleHandle other = mesh.other_triangle(e, h);
      const std::int32_t q = other.valid() ? part_of_slot[static_cast<std::size_t>(other.idx)] : -1;
      if (q < 0 || q > me || (q == me && h.idx < other.idx)) counts[1] += 1;
    }
  }
  options.distribution.share.sum(counts, 3);
  c.vertices = static_cast<std::size_t>(counts[0]);
  c.edges = static_cast<std::size_t>(counts[1]);
  c.report.triangles = static_cast<std::size_t>(counts[2]);
  c.report.dofs = options.order == 2 ? c.vertices + c.edges : c.vertices;
}

// Whether a mesh's unknowns are known only when its cycle is solved: a distributed mesh's once
// its parts are decided, the truncated hierarchical Loop basis's once its space is built (its
// functions are not the vertices). Such runs stop at the solve that would pass max_dofs.
bool unknowns_known_at_solve(const AdaptOptions& options) {
  return options.distribution.distributed_mesh ||
         (options.element == AdaptOptions::Element::loop &&
          options.loop_basis == fem::LoopBasisKind::truncated_hierarchical);
}

// A cycle with Loop elements: the solve on the Loop space; what the cycle keeps (the P1 mesh
// of the limit positions, the values there, the indicators per triangle) as for P1.
SolvedCycle solve_loop_cycle(RgbMesh& mesh, const fem::Problem& problem, const AdaptOptions& options,
                             const SolutionTransfer& transfer, ErrorsWanted errors, bool check_max_dofs) {
  SolvedCycle c;
  const auto t_mesh = std::chrono::steady_clock::now();
  c.fe = fem::build_surface_mesh(mesh, options.projection, 1);
  // The hierarchical space of the RGB mesh (on a uniform mesh, build_loop_space's space in
  // another basis): its cells are integrated, its coefficients solved for.
  const fem::AdaptiveLoopSpace space = fem::build_adaptive_loop_space(mesh, options.projection, {}, options.loop_basis);
  c.report.mesh_seconds = seconds_since(t_mesh);
  if (check_max_dofs && space.num_dofs() > options.max_dofs) {
    c.over_max_dofs = true;
    c.report.dofs = space.num_dofs();
    return c;
  }
  if (options.control.interruption_point) options.control.interruption_point();
  // The last solution's values, carried to this mesh's vertices, seed an iterative solve: a
  // function's coefficient is its control value at its level, close to the limit value at its
  // vertex (the details basis takes them as details of those values).
  fem::SolveOptions solve = options.solve;
  Eigen::VectorXd guess = transfer.at(space.vertex);
  if (guess.size() > 0) {
    if (space.basis == fem::LoopBasisKind::details) guess = space.hierarchical_coefficients(guess);
    solve.initial_guess = &guess;
  }
  Eigen::VectorXd energies;
  const fem::Solution loop = fem::solve_loop(space, problem, solve, energies);
  if (options.control.interruption_point) options.control.interruption_point();
  const Eigen::VectorXd control = space.control_values(loop.u);
  const std::vector<double> removal_cost = fem::loop_removal_costs(space, mesh, loop.u, energies);
  for (const VertexHandle v : c.fe.vertex) c.removal_cost.push_back(removal_cost[static_cast<std::size_t>(v.idx)]);
  c.solution = loop;
  c.solution.u = fem::loop_values_on(space, loop.u, c.fe);
  int levels = options.loop_view_levels;
  while (levels > 0 && (space.cells.elements.size() << (2 * levels)) > 3000000) --levels;
  if (levels > 0)
    c.loop_view = std::make_shared<const MeshSnapshot>(fem::loop_refined_view(space.cells, control, levels));
  const auto t_estimate = std::chrono::steady_clock::now();
  const fem::Estimate estimate = fem::loop_residual_estimate(space.cells, problem, control);
  c.estimate.total = estimate.total;
  // Per RGB triangle, for marking and output (Σ η_T² is the estimate's).
  const std::vector<double> by_slot = fem::loop_indicators_on_triangles(space, mesh, estimate.eta);
  c.estimate.eta.clear();
  for (const TriangleHandle t : c.fe.triangle)
    c.estimate.eta.push_back(by_slot[static_cast<std::size_t>(t.idx)]);
  c.estimate.geometric.assign(c.estimate.eta.size(), 0.0);
  c.report.note = loop_singular_note(space, estimate.eta);
  c.report.estimate_seconds = seconds_since(t_estimate);
  c.report.triangles = c.fe.triangles.size();
  c.report.dofs = space.num_dofs();
  c.report.estimate = c.estimate.total;
  c.report.solve_seconds = loop.assembly_seconds + loop.solve_seconds;
  c.report.assembly_seconds = loop.assembly_seconds;
  c.report.solver = fem::to_string(loop.solver);
  c.report.solver_iterations = loop.iterations;
  if (problem.exact && errors == ErrorsWanted::reported) {
    const auto t_errors = std::chrono::steady_clock::now();
    const fem::ErrorNorms e = fem::loop_error_norms(space.cells, control, *problem.exact, loop.zero_mean);
    c.report.error_l2 = e.l2;
    c.report.error_h1 = e.h1;
    c.report.error_seconds = seconds_since(t_errors);
  }
  return c;
}

SolvedCycle solve_and_estimate_now(RgbMesh& mesh, const fem::Problem& problem, const AdaptOptions& options,
                                   SolutionTransfer& transfer, bool check_max_dofs, ErrorsWanted errors) {
  if (!options.distribution.prepare_mesh && !options.distribution.partition &&
      mesh.live_fraction() < options.compact_below)
    mesh.compact();
  if (options.element == AdaptOptions::Element::loop) {
    SolvedCycle loop = solve_loop_cycle(mesh, problem, options, transfer, errors,
                                        check_max_dofs && unknowns_known_at_solve(options));
    loop.report.mesh_bytes = mesh.memory_bytes();
    return loop;
  }
  SolvedCycle c;
  c.report.mesh_bytes = mesh.memory_bytes();
  if (options.distribution.prepare_mesh) {
    const auto t_prepare = std::chrono::steady_clock::now();
    options.distribution.prepare_mesh(mesh);
    c.report.exchange_seconds = seconds_since(t_prepare);
  }
  const auto t_mesh = std::chrono::steady_clock::now();
  c.fe = fem::build_surface_mesh(mesh, options.projection, options.order);
  c.report.mesh_seconds = seconds_since(t_mesh);
  if (options.control.interruption_point) options.control.interruption_point();
  // On several processes, each assembles and computes the estimator's and the norms' terms of
  // its part's triangles.
  fem::WorkShare share;
  if (options.distribution.partition) {
    const auto t_part = std::chrono::steady_clock::now();
    c.triangle_part = options.distribution.partition(mesh, c.fe);
    c.report.partition_seconds = seconds_since(t_part);
    if (options.distribution.share.sum && options.distribution.share.gather) {
      share = options.distribution.share;
      share.part = c.triangle_part;
    }
  }
  if (options.distribution.distributed_mesh) {
    count_over_parts(c, mesh, options);
    if (check_max_dofs && c.report.dofs > options.max_dofs) {
      c.over_max_dofs = true;
      return c;
    }
  }
  fem::SolveOptions so = options.solve;
  const Eigen::VectorXd guess = transfer.on(c.fe);
  if (guess.size() > 0) so.initial_guess = &guess;
  if (so.shared_solver) so.share = share;
  c.solution = fem::solve(c.fe, problem, so);
  if (options.control.interruption_point) options.control.interruption_point();
  const auto t0 = std::chrono::steady_clock::now();
  c.estimate = options.estimator->estimate(c.fe, problem, c.solution.u, share);
  c.report.estimate_seconds = seconds_since(t0);
  if (options.distribution.distributed_mesh) {
    // Each process has its own triangles' indicators: the total over all.
    double squares = 0;
    for (std::size_t t = 0; t < c.fe.triangles.size(); ++t)
      if (share.computes(t)) squares += c.estimate.eta[t] * c.estimate.eta[t];
    options.distribution.share.sum(&squares, 1);
    c.estimate.total = std::sqrt(squares);
  } else {
    c.report.triangles = c.fe.triangles.size();
    c.report.dofs = c.fe.num_dofs();
  }
  c.report.estimate = c.estimate.total;
  c.report.solve_seconds = c.solution.assembly_seconds + c.solution.solve_seconds;
  c.report.assembly_seconds = c.solution.assembly_seconds;
  c.report.solver = fem::to_string(c.solution.solver);
  c.report.solver_iterations = c.solution.iterations;
  if (problem.exact && errors == ErrorsWanted::reported) {
    const auto t_errors = std::chrono::steady_clock::now();
    const fem::ErrorNorms e = fem::error_norms(c.fe, c.solution.u, *problem.exact, c.solution.zero_mean, share);
    c.report.error_l2 = e.l2;
    c.report.error_h1 = e.h1;
    c.report.error_seconds = seconds_since(t_errors);
  }
  return c;
}

SolvedCycle solve_and_estimate(RgbMesh& mesh, const fem::Problem& problem, const AdaptOptions& options,
                               SolutionTransfer& transfer, bool check_max_dofs = false,
                               ErrorsWanted errors = ErrorsWanted::reported) {
  SolvedCycle c = solve_and_estimate_now(mesh, problem, options, transfer, check_max_dofs, errors);
  // The assembly's, the solver's and the estimator's transients are freed by now.
  if (options.control.release_free_memory) options.control.release_free_memory();
  return c;
}

// A moving feature's step solves several times: its report's stage times are the sums.
void add_stage_seconds(CycleReport& into, const CycleReport& from) {
  into.mesh_seconds += from.mesh_seconds;
  into.solve_seconds += from.solve_seconds;
  into.assembly_seconds += from.assembly_seconds;
  into.estimate_seconds += from.estimate_seconds;
  into.error_seconds += from.error_seconds;
  into.partition_seconds += from.partition_seconds;
  into.exchange_seconds += from.exchange_seconds;
}

void count_traffic(CycleReport& report, const AdaptOptions& options) {
  // The rounds first: their check's sum then belongs to this cycle's bytes.
  if (options.distribution.rounds) {
    const std::array<std::uint64_t, 2> rounds = options.distribution.rounds();
    report.coarsening_rounds = rounds[0];
    report.exchanges = rounds[1];
  }
  if (!options.distribution.bytes_sent) return;
  const std::array<std::uint64_t, 2> sent = options.distribution.bytes_sent();
  report.bytes_sent = sent[0];
  report.bytes_sent_largest = sent[1];
}

// The levels and colours of the mesh a solution lives on, and its RGB state if asked: taken
// before the mesh is adapted.
// piece >= 0 (a distributed mesh): also the state of that part's piece (SolvedMesh::piece_state).
SolvedMesh describe(const RgbMesh& mesh, const SolvedCycle& c, bool with_state, std::int32_t piece = -1) {
  const fem::SurfaceMesh& fe = c.fe;
  SolvedMesh m;
  m.vertex_level.reserve(fe.vertex.size());
  for (const VertexHandle v : fe.vertex) m.vertex_level.push_back(static_cast<std::uint8_t>(mesh.level(v)));
  m.triangle_level.reserve(fe.triangle.size());
  m.triangle_color.reserve(fe.triangle.size());
  for (const TriangleHandle t : fe.triangle) {
    m.triangle_level.push_back(static_cast<std::uint8_t>(mesh.level(t)));
    m.triangle_color.push_back(mesh.color(t));
  }
  if (with_state) {
    MeshSnapshot points;  // save_state names the points by their vertices only
    points.vertex_handle = fe.vertex;
    m.state = save_state(mesh, points);
  }
  m.triangle_part = c.triangle_part;
  if (piece >= 0 && !c.triangle_part.empty()) {
    // The piece's points as snapshot_piece orders them: by their first use among its triangles.
    const CellPiece<3> cells = cell_piece(fe.triangles, fe.vertex.size(), c.triangle_part, piece);
    std::vector<VertexHandle> points;
    points.reserve(cells.point_rows.size());
    for (const std::size_t row : cells.point_rows) points.push_back(fe.vertex[row]);
    m.piece_state = save_piece_state(mesh, points);
  }
  return m;
}

// The unknowns of elements of the given order on the mesh: its vertices (P1), and its edges
// too (P2).
std::size_t unknowns(const RgbMesh& mesh, int order) {
  return order == 2 ? mesh.num_vertices() + mesh.num_edges() : mesh.num_vertices();
}

// The unknowns after one more uniform level: every green edge of the finest level gains a
// vertex (V' = V + E) and splits in two while every triangle gains three edges (E' = 2E + 3T).
// Exact for a uniform mesh; for a selectively refined one, a lower bound.
// (A distributed mesh: the whole mesh's counts, from the solved cycle.)
std::size_t unknowns_after_uniform_level(const RgbMesh& mesh, const SolvedCycle& c, const AdaptOptions& options) {
  const bool whole = options.distribution.distributed_mesh;
  const std::size_t vertices = whole ? c.vertices : mesh.num_vertices(), edges = whole ? c.edges : mesh.num_edges(),
                    triangles = whole ? c.report.triangles : mesh.num_triangles();
  const std::size_t v = vertices + edges;
  return options.order == 2 ? v + 2 * edges + 3 * triangles : v;
}

// A distributed mesh: per FE triangle, whether it is this process's own. Empty otherwise.
std::vector<char> own_triangles(const SolvedCycle& c, const AdaptOptions& options) {
  std::vector<char> own;
  if (!options.distribution.distributed_mesh) return own;
  own.resize(c.fe.triangles.size());
  for (std::size_t i = 0; i < own.size(); ++i)
    own[i] = c.triangle_part[i] == options.distribution.share.process ? 1 : 0;
  return own;
}

// The indicators as the marking sees them; on a distributed mesh, with the own triangles'
// flags and the sums over the processes.
Indicators indicators_of(const SolvedCycle& c, const AdaptOptions& options, const std::vector<char>& own) {
  if (!options.distribution.distributed_mesh) return Indicators(c.estimate.eta, options.target_estimate);
  return Indicators(c.estimate.eta, options.target_estimate, own, options.distribution.share.sum);
}

// Marks, then refines and coarsens the mesh through the queues; returns the marks per FE
// triangle and counts the operations in the report.
std::vector<char> adapt_mesh(RgbMesh& mesh, const SolvedCycle& c, const AdaptOptions& options, CycleReport& report) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<char> marked(c.fe.triangles.size(), 0);
  RefinementOptions ro;
  ro.max_level = options.max_level;
  if (options.control.memory_headroom)
    ro.max_mesh_bytes = mesh.memory_bytes() + options.control.memory_headroom();
  if (options.control.interruption_point)
    ro.progress = [&options](std::uint64_t, std::size_t) { options.control.interruption_point(); };
  RefinementResult r;
  // A distributed mesh: this process's own triangles, marked against thresholds found with
  // the other processes.
  const std::vector<char> own = own_triangles(c, options);
  if (options.strategy == Strategy::uniform && options.distribution.distributed_mesh) {
    // Its own triangles one level up: the next uniform level once every process has its own
    // and the interfaces' splits.
    marked = own;
    std::vector<double> triangle_values(static_cast<std::size_t>(mesh.triangle_slots()), 0.0);
    for (std::size_t i = 0; i < marked.size(); ++i)
      if (marked[i] && mesh.level(c.fe.triangle[i]) < options.max_level) triangle_values[c.fe.triangle[i].idx] = 1.0;
    r = selective_refinement(mesh, FieldCriterion(std::move(triangle_values), 0.5, {}, 0.0), ro);
  } else if (options.strategy == Strategy::uniform) {
    std::fill(marked.begin(), marked.end(), 1);
    r = selective_refinement(mesh, UniformLevel(std::min(mesh.max_level() + 1, options.max_level)), ro);
  } else {
    const Indicators indicators = indicators_of(c, options, own);
    marked = options.marking->mark(indicators);
    if (options.element == AdaptOptions::Element::loop &&
        options.loop_basis == fem::LoopBasisKind::truncated_hierarchical)
      mark_admissible(mesh, c.fe.triangle, marked, options.loop_admissible_levels);
    std::vector<double> triangle_values(static_cast<std::size_t>(mesh.triangle_slots()), 0.0);
    for (std::size_t i = 0; i < marked.size(); ++i) {
      if (marked[i]) triangle_values[c.fe.triangle[i].idx] = 1.0;
    }
    std::vector<double> vertex_values;
    double threshold = 0;
    if (options.coarsen_below > 0) {
      // Each vertex's largest indicator over its star, against the refinement threshold.
      // (A distributed mesh: over the own triangles, and coarsen_mesh asks the processes
      // around each interface vertex.)
      std::vector<double> star(c.fe.vertex.size(), 0.0);
      std::vector<char> next_to_marked(c.fe.vertex.size(), 0);
      for (std::size_t i = 0; i < c.fe.triangles.size(); ++i) {
        if (options.distribution.distributed_mesh && !own[i]) continue;
        for (std::int32_t v : c.fe.triangles[i]) {
          star[v] = std::max(star[v], c.estimate.eta[i]);
          if (marked[i]) next_to_marked[static_cast<std::size_t>(v)] = 1;
        }
      }
      if (options.distribution.distributed_mesh) ro.coarsen = options.distribution.coarsen_mesh;
      vertex_values.assign(static_cast<std::size_t>(mesh.vertex_slots()), 1e300);
      for (std::size_t v = 0; v < star.size(); ++v) {
        // Vertices at or below the floor stay (their removal would coarsen below it). Loop
        // elements compare what removing the vertex's detail costs instead: their indicators
        // fall as h³ where the solution is resolved, and whole resolved regions went by them
        // and came back (sphere-peak, coarsen_below 0.2: 2,188 unknowns, then 827, then 410).
        const double value = c.removal_cost.empty() ? star[v]
                             : next_to_marked[v]    ? std::numeric_limits<double>::infinity()
                                                    : c.removal_cost[v];
        if (mesh.level(c.fe.vertex[v]) > options.min_level) vertex_values[c.fe.vertex[v].idx] = value;
      }
      threshold = options.coarsen_below * options.marking->refinement_threshold(indicators, marked);
    }
    r = selective_refinement(mesh, FieldCriterion(std::move(triangle_values), 0.5, std::move(vertex_values), threshold),
                             ro);
  }
  // The trapezoids' diagonals chosen by the vertices' names, not by the order of the splits:
  // the mesh is then a function of its vertices, the same however (and on however many
  // processes) they were inserted.
  canonical_diagonals(mesh);
  double exchange = 0;
  if (options.distribution.after_adaptation) {
    const auto t_exchange = std::chrono::steady_clock::now();
    options.distribution.after_adaptation(mesh);
    exchange = seconds_since(t_exchange);
    report.exchange_seconds += exchange;
  }
  report.memory_limit_reached = r.stopped_at_memory_limit;
  double counts[3] = {static_cast<double>(std::count(marked.begin(), marked.end(), 1)), static_cast<double>(r.splits),
                      static_cast<double>(r.removals)};
  // (A distributed mesh: over all processes; a split that processes on both sides of an
  // interface make counts on each.)
  if (options.distribution.distributed_mesh) options.distribution.share.sum(counts, 3);
  report.marked = static_cast<std::size_t>(counts[0]);
  report.splits += static_cast<std::size_t>(counts[1]);
  report.removals += static_cast<std::size_t>(counts[2]);
  report.adapt_seconds += seconds_since(t0) - exchange;
  return marked;
}

// AdaptOptions::min_level: the whole mesh at that level at least before anything is solved (a
// mesh that already is, a resumed run's, is left as it is).
void refine_to_floor(RgbMesh& mesh, const AdaptOptions& options) {
  if (options.min_level < 0 || options.min_level > options.max_level)
    throw std::invalid_argument("adapt: min_level " + std::to_string(options.min_level) + " is not in [0, max_level " +
                                std::to_string(options.max_level) + "]");
  if (options.min_level > 0) {
    RefinementOptions ro;
    if (options.control.interruption_point)
      ro.progress = [&options](std::uint64_t, std::size_t) { options.control.interruption_point(); };
    selective_refinement(mesh, AtLeastLevel(options.min_level), ro);
  }
}

// Whether a cycle on the mesh as it is now fits under the memory ceiling: the unknowns added
// since the last solve each need the element's bytes per unknown more.
bool next_cycle_fits(const RgbMesh& mesh, const AdaptOptions& options, std::size_t solved_dofs) {
  if (!options.control.memory_headroom) return true;
  const double added = static_cast<double>(unknowns(mesh, options.order)) - static_cast<double>(solved_dofs);
  const double per_dof =
      options.element == AdaptOptions::Element::loop ? kLoopSolveBytesPerDof : kSolveBytesPerDof;
  return added * per_dof <= static_cast<double>(options.control.memory_headroom());
}

}  // namespace

// Where most of a Loop estimate sits on cells whose limit surface is nearly singular
// (tangents less than 1e-5 from parallel), the user is told so: there the Loop basis is not
// smooth on the surface, and refinement gathers on those cells and converges slowly.
// Measured (2026-12-05, CGAL's 130 meshes and the openscad and assimp test files): cells
// below 1e-5 occur in 3 meshes and carry most of the estimate in one, openscad's
// bad-stl-wing.stl (ratios to 2e-7, caps across creases), whose Loop solution stays 8-10%
// from adaptive P2's after 48 cycles; cylinder_locally_refined.off's first estimate lies 99.5%
// on cells of ratio 5e-5 to 1e-4, which refinement resolves (Loop and P2 agree to 3e-5).
// Loop's boundary rules also fold a coarse boundary that turns sharply: triangular_hole.off
// refined twice gets the note at cycle 4 (99% on one cell inside the hole's corner), and its
// Loop estimate wanders between 0.5 and 7e3 for 30 cycles where P2's falls to 1.5e-4.
std::string loop_singular_note(const fem::AdaptiveLoopSpace& space, const std::vector<double>& eta) {
  const fem::LoopSingularEstimate s = fem::loop_singular_estimate(space.cells, eta, 1e-5);
  if (s.share < 0.5) return {};
  std::ostringstream text;
  text
      << "Loop elements: " << static_cast<int>(std::floor(100 * s.share)) << "% of the estimate lies on "
      << s.elements << " cell" << (s.elements == 1 ? "" : "s")
      << " where the limit surface's parametrization is nearly singular (tangents " << std::setprecision(1)
      << std::scientific << s.ratio << " from parallel; the first near (" << std::defaultfloat
      << std::setprecision(6) << s.where.x << ", " << s.where.y << ", " << s.where.z
      << ")): the Loop basis converges slowly there, and refinement gathers on them. Usual causes: cap or "
         "needle triangles across a crease of the input, or a boundary of few edges that turns sharply "
         "(Loop's boundary rules fold the surface there). --element p2 copes with such meshes; or remesh the "
         "input finer there";
  return text.str();
}

const std::vector<Named<Strategy>>& strategy_table() {
  static const std::vector<Named<Strategy>> table = {{"adaptive", Strategy::adaptive},
                                                     {"uniform", Strategy::uniform}};
  return table;
}

const char* to_string(StopReason reason) {
  switch (reason) {
    case StopReason::cycles: return "cycles";
    case StopReason::target_error: return "target-error";
    case StopReason::max_dofs: return "max-dofs";
    case StopReason::steps: return "steps";
    case StopReason::memory: return "memory";
    case StopReason::requested: return "requested";
  }
  return "?";
}

AdaptRun run_cycles(RgbMesh& mesh, const fem::Problem& problem, const AdaptOptions& options,
                    const CycleCallback& on_cycle) {
  if (options.element == AdaptOptions::Element::loop &&
      (options.distribution.partition || options.order != 1))
    throw InputError("Loop elements run on one process, with one unknown per vertex (order 1)");
  refine_to_floor(mesh, options);
  SolutionTransfer transfer(mesh);
  AdaptRun run;
  std::size_t solved_dofs = 0;
  for (int cycle = std::max(0, options.control.first_cycle - 1); cycle < options.max_cycles; ++cycle) {
    // Resuming: the earlier run's last cycle, solved again to be adapted as it was.
    const bool replay = cycle < options.control.first_cycle;
    const auto t0 = std::chrono::steady_clock::now();
    if (!next_cycle_fits(mesh, options, solved_dofs)) {
      run.stopped = StopReason::memory;
      break;
    }
    SolvedCycle c = solve_and_estimate(mesh, problem, options, transfer,
                                       cycle > std::max(0, options.control.first_cycle - 1));
    if (c.over_max_dofs) {  // known at the solve (unknowns_known_at_solve)
      run.stopped = StopReason::max_dofs;
      break;
    }
    solved_dofs = c.fe.num_dofs();
    c.report.cycle = cycle;
    const SolvedMesh solved =
        replay ? SolvedMesh{}
               : describe(mesh, c, options.control.resumable,
                          options.distribution.distributed_mesh ? options.distribution.share.process : -1);
    bool last = true;
    if (cycle + 1 == options.max_cycles)
      run.stopped = StopReason::cycles;
    else if (c.estimate.total <= options.target_estimate)
      run.stopped = StopReason::target_error;
    else if (options.strategy == Strategy::uniform && unknowns_after_uniform_level(mesh, c, options) > options.max_dofs)
      run.stopped = StopReason::max_dofs;  // predicted: the next mesh is never built
    else if (!replay && options.control.stop && options.control.stop(c.report))
      run.stopped = StopReason::requested;
    else
      last = false;
    if (options.control.interruption_point) options.control.interruption_point();
    std::vector<char> marked(c.fe.triangles.size(), 0);
    if (!last) {
      transfer.store(c.fe, c.solution.u);
      marked = adapt_mesh(mesh, c, options, c.report);
    }
    c.report.seconds = seconds_since(t0);
    count_traffic(c.report, options);
    if (options.control.resident_bytes) c.report.resident_bytes = options.control.resident_bytes();
    if (!replay) {
      run.cycles.push_back(c.report);
      if (on_cycle)
        on_cycle(
            {run.cycles.back(), mesh, c.fe, problem, c.solution.u, c.estimate, marked, &solved, c.loop_view});
    }
    if (last) break;
    if (c.report.memory_limit_reached) {
      run.stopped = StopReason::memory;
      break;
    }
    if (!unknowns_known_at_solve(options) && unknowns(mesh, options.order) > options.max_dofs) {
      run.stopped = StopReason::max_dofs;
      break;
    }
  }
  return run;
}

AdaptRun run_dynamic(RgbMesh& mesh, const std::function<fem::Problem(double)>& problem_at,
                     const AdaptOptions& options, const DynamicOptions& dynamic, const CycleCallback& on_step) {
  // A distributed mesh knows its size when a cycle is solved (its parts decided), and so does
  // the truncated hierarchical Loop basis (unknowns_known_at_solve): a step whose mesh would
  // pass max_dofs stops the run at its solve instead of after its adaptation.
  const bool distributed = options.distribution.distributed_mesh;
  const bool counted_at_solve = unknowns_known_at_solve(options);
  refine_to_floor(mesh, options);
  AdaptRun run;
  const bool resuming = dynamic.first_step > 0;
  if (resuming && options.marking->marks_by_target() && !(options.target_estimate > 0))
    throw std::invalid_argument("run_dynamic: resuming under equidistribution needs the earlier run's target");
  if (!resuming) {
    // Adapt to the start, refinement only.
    AdaptOptions start = options;
    start.coarsen_below = 0;
    start.max_cycles = std::max(1, dynamic.start_cycles);
    start.control.first_cycle = 0;
    if (start.marking->marks_by_target() && !(start.target_estimate > 0) && start.marking->before_target())
      start.marking = start.marking->before_target();
    AdaptRun started = run_cycles(mesh, problem_at(0.0), start);
    run.start = std::move(started.cycles);
    const bool over = counted_at_solve ? options.strategy != Strategy::uniform
                                  : unknowns(mesh, options.order) > options.max_dofs;
    if ((started.stopped == StopReason::max_dofs && over) || started.stopped == StopReason::memory) {
      run.stopped = started.stopped;  // even the start needs more than max_dofs, or the memory
      return run;
    }
  }
  // After an adaptation: whether the mesh is still within bounds for the next solve.
  std::size_t solved_dofs = run.start.empty() ? unknowns(mesh, options.order) : run.start.back().dofs;
  const auto out_of_bounds = [&](const CycleReport& adapted) {
    if (adapted.memory_limit_reached || !next_cycle_fits(mesh, options, solved_dofs)) {
      run.stopped = StopReason::memory;
      return true;
    }
    if (!counted_at_solve && unknowns(mesh, options.order) > options.max_dofs) {
      run.stopped = StopReason::max_dofs;
      return true;
    }
    return false;
  };
  AdaptOptions o = options;
  if (o.marking->marks_by_target() && !(o.target_estimate > 0)) o.target_estimate = run.start.back().estimate;
  run.target_estimate = o.target_estimate;
  if (dynamic.on_started && !resuming) dynamic.on_started(run.start, run.target_estimate);

  SolutionTransfer transfer(mesh);
  // A solve; false (the run stopped) where a distributed mesh turns out to pass max_dofs.
  const auto solve = [&](const fem::Problem& problem, const AdaptOptions& with, SolvedCycle& c,
                         ErrorsWanted errors) {
    c = solve_and_estimate(mesh, problem, with, transfer, counted_at_solve, errors);
    if (!c.over_max_dofs) return true;
    run.stopped = StopReason::max_dofs;
    return false;
  };
  if (resuming) {
    // The earlier run's last step solved again: its values seed the next solve, as they did.
    const int last = dynamic.first_step - 1;
    const double t = dynamic.steps > 0 ? static_cast<double>(last) / dynamic.steps : 0.0;
    SolvedCycle c = solve_and_estimate(mesh, problem_at(t), o, transfer, false, ErrorsWanted::not_read);
    transfer.store(c.fe, c.solution.u);
    solved_dofs = c.fe.num_dofs();
  } else if (o.strategy == Strategy::adaptive && o.marking->marks_by_target()) {
    // Settle the start under the steps' own marking and coarsening (equidistribution towards a
    // target reached by Dörfler marking is a different balance), so that the size is steady
    // from the first step on: until an adaptation changes the size by less than 2%.
    // (A distributed mesh counts its vertices when solved: the change is seen at the next
    // solve, which then ends the settling unadapted.)
    const fem::Problem problem = problem_at(0.0);
    std::size_t solved_vertices = 0;
    for (int k = 0; k < 10; ++k) {
      SolvedCycle c;
      if (!solve(problem, o, c, ErrorsWanted::not_read)) return run;
      if (distributed && k > 0 &&
          std::abs(static_cast<double>(c.vertices) - static_cast<double>(solved_vertices)) <
              0.02 * static_cast<double>(solved_vertices))
        break;
      transfer.store(c.fe, c.solution.u);
      const std::size_t before = distributed ? c.vertices : mesh.num_vertices();
      solved_vertices = c.vertices;
      solved_dofs = c.fe.num_dofs();
      CycleReport settled;
      adapt_mesh(mesh, c, o, settled);
      if (out_of_bounds(settled)) return run;
      const double change = std::abs(static_cast<double>(mesh.num_vertices()) - static_cast<double>(before));
      if (!distributed && change < 0.02 * static_cast<double>(before)) break;
    }
  }
  run.stopped = StopReason::steps;
  for (int step = std::max(0, dynamic.first_step); step <= dynamic.steps; ++step) {
    const auto t0 = std::chrono::steady_clock::now();
    const double t = dynamic.steps > 0 ? static_cast<double>(step) / dynamic.steps : 0.0;
    const fem::Problem problem = problem_at(t);
    CycleReport adapted;
    // Adapt to the feature where it is now: refine there, coarsen where it was (a uniform
    // mesh stays as the start made it).
    for (int k = 0; o.strategy == Strategy::adaptive && k < dynamic.cycles_per_step; ++k) {
      SolvedCycle c;
      if (!solve(problem, o, c, ErrorsWanted::not_read)) return run;
      solved_dofs = c.fe.num_dofs();
      transfer.store(c.fe, c.solution.u);
      add_stage_seconds(adapted, c.report);
      adapt_mesh(mesh, c, o, adapted);
      if (out_of_bounds(adapted)) return run;
    }
    SolvedCycle c;
    if (!solve(problem, o, c, ErrorsWanted::reported)) return run;
    solved_dofs = c.fe.num_dofs();
    transfer.store(c.fe, c.solution.u);
    c.report.cycle = step;
    c.report.time = t;
    c.report.splits = adapted.splits;
    c.report.removals = adapted.removals;
    c.report.adapt_seconds = adapted.adapt_seconds;
    // The step's stages over all of its solves and adaptations, as its seconds are.
    add_stage_seconds(c.report, adapted);
    c.report.seconds = seconds_since(t0);
    count_traffic(c.report, o);
    if (o.control.resident_bytes) c.report.resident_bytes = o.control.resident_bytes();
    run.cycles.push_back(c.report);
    std::vector<char> marked(c.fe.triangles.size(), 0);
    if (o.strategy == Strategy::adaptive) {
      const std::vector<char> own = own_triangles(c, o);
      marked = o.marking->mark(indicators_of(c, o, own));
    }
    const SolvedMesh solved = describe(mesh, c, o.control.resumable,
                                       o.distribution.distributed_mesh ? o.distribution.share.process : -1);
    if (on_step)
      on_step(
          {run.cycles.back(), mesh, c.fe, problem, c.solution.u, c.estimate, marked, &solved, c.loop_view});
  }
  return run;
}

MeshSnapshot snapshot(const CycleState& s) {
  MeshSnapshot out;
  // The vertices (P2: the corner nodes; the edge nodes are not written).
  const std::size_t n = s.fe.vertex.size();
  out.points.assign(s.fe.points.begin(), s.fe.points.begin() + static_cast<std::ptrdiff_t>(n));
  out.triangles = s.fe.triangles;
  out.vertex_handle = s.fe.vertex;
  out.triangle_handle = s.fe.triangle;
  s.mesh.add_sharp_features(out);  // crease lines and vertex rules, where the mesh has them
  NamedArray u{"solution", 1, {}}, exact{"exact_solution", 1, {}}, error{"error", 1, {}};
  if (s.solved) {
    out.vertex_level = s.solved->vertex_level;
    out.triangle_level = s.solved->triangle_level;
    out.triangle_color = s.solved->triangle_color;
    out.state = s.solved->state;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!s.solved) out.vertex_level.push_back(static_cast<std::uint8_t>(s.mesh.level(s.fe.vertex[i])));
    const double uh = s.u[static_cast<Eigen::Index>(i)];
    u.values.push_back(uh);
    if (s.problem.exact) {
      const double ue = s.problem.exact->value(s.fe.lift(s.fe.points[i]));
      exact.values.push_back(ue);
      error.values.push_back(ue - uh);
    }
  }
  out.point_data.push_back(std::move(u));
  if (s.problem.exact) {
    out.point_data.push_back(std::move(exact));
    out.point_data.push_back(std::move(error));
  }
  NamedArray eta{"error_indicator", 1, {}}, marked{"marked", 1, {}};
  for (std::size_t i = 0; i < s.fe.triangles.size(); ++i) {
    if (!s.solved) {
      out.triangle_level.push_back(static_cast<std::uint8_t>(s.mesh.level(s.fe.triangle[i])));
      out.triangle_color.push_back(s.mesh.color(s.fe.triangle[i]));
    }
    eta.values.push_back(s.estimate.eta[i]);
    marked.values.push_back(s.marked[i] ? 1.0 : 0.0);
  }
  out.cell_data.push_back(std::move(eta));
  out.cell_data.push_back(std::move(marked));
  if (s.solved && !s.solved->triangle_part.empty())
    out.cell_data.push_back({"rank", 1, std::vector<double>(s.solved->triangle_part.begin(), s.solved->triangle_part.end())});
  return out;
}

fem::Problem moving_peak(double t, double kappa) {
  const double pi = 3.14159265358979323846, phi = 0.5 * pi * t;
  const Vec3 a(0.6, 0.0, 0.8), b(0.0, 1.0, 0.0);  // orthonormal: the great circle's plane
  fem::Problem p = fem::sphere_peak(std::cos(phi) * a + std::sin(phi) * b, kappa, 1.0);
  p.name = "moving-peak";
  return p;
}

QuadraticSnapshot quadratic_snapshot(const CycleState& s) {
  QuadraticSnapshot out;
  if (s.fe.order != 2) return out;
  out.points = s.fe.points;
  out.cells.reserve(s.fe.triangles.size());
  for (std::size_t t = 0; t < s.fe.triangles.size(); ++t) {
    const auto& c = s.fe.triangles[t];
    const auto& e = s.fe.edge_nodes[t];
    out.cells.push_back({c[0], c[1], c[2], e[0], e[1], e[2]});
  }
  NamedArray u{"solution", 1, {s.u.data(), s.u.data() + s.u.size()}, false};
  out.point_data.push_back(std::move(u));
  if (s.problem.exact) {
    NamedArray exact{"exact_solution", 1, {}, false}, error{"error", 1, {}, false};
    for (std::size_t i = 0; i < s.fe.num_dofs(); ++i) {
      const double ue = s.problem.exact->value(s.fe.lift(s.fe.points[i]));
      exact.values.push_back(ue);
      error.values.push_back(ue - s.u[static_cast<Eigen::Index>(i)]);
    }
    out.point_data.push_back(std::move(exact));
    out.point_data.push_back(std::move(error));
  }
  NamedArray eta{"error_indicator", 1, {}, false}, marked{"marked", 1, {}, false}, level{"level", 1, {}, false};
  for (std::size_t t = 0; t < s.fe.triangles.size(); ++t) {
    eta.values.push_back(s.estimate.eta[t]);
    marked.values.push_back(s.marked[t] ? 1.0 : 0.0);
    level.values.push_back(s.solved ? s.solved->triangle_level[t] : s.mesh.level(s.fe.triangle[t]));
  }
  out.cell_data.push_back(std::move(eta));
  out.cell_data.push_back(std::move(marked));
  out.cell_data.push_back(std::move(level));
  if (s.solved && !s.solved->triangle_part.empty())
    out.cell_data.push_back({"rank", 1, std::vector<double>(s.solved->triangle_part.begin(), s.solved->triangle_part.end()), false});
  return out;
}

QuadraticSnapshot quadratic_piece(const QuadraticSnapshot& whole, const std::vector<std::int32_t>& part, std::int32_t which) {
  if (part.size() != whole.cells.size()) throw std::invalid_argument("quadratic_piece: one part per cell needed");
  CellPiece<6> cells = cell_piece(whole.cells, whole.points.size(), part, which);
  QuadraticSnapshot piece;
  piece.cells = std::move(cells.cells);
  for (const std::size_t p : cells.point_rows) piece.points.push_back(whole.points[p]);
  piece.point_data = array_rows(whole.point_data, cells.point_rows);
  piece.cell_data = array_rows(whole.cell_data, cells.cell_rows);
  return piece;
}

}  // namespace rgbmesh::adapt
