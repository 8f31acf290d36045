// rgbmesh.Problem, rgbmesh.solve and rgbmesh.adapt: the finite-element loop of rgbmesh::fem and
// rgbmesh::adapt on a Mesh, with sources written as numpy functions of the points (one call per
// assembly or estimate: fem::PointValues), the GIL released while C++ works and Ctrl-C let
// through between the steps of a cycle.

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/fem/estimators.hpp"
#include "rgbmesh/fem/loop_adaptive.hpp"
#include "rgbmesh/fem/problem.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace py = pybind11;

namespace rgbmesh::python {

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles: points go to numpy by memcpy");

// A Python callable shared by the copies of a std::function; released with the GIL held,
// whichever thread drops the last copy.
struct Callable {
  py::object f;
  explicit Callable(py::object function) : f(std::move(function)) {}
  ~Callable() {
    py::gil_scoped_acquire gil;
    f = py::object();
  }
};

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// A numpy function of the points, f(points (n, 3)) -> values (n,), as fem::PointValues. What it
// returns is checked: one finite number per point (or one number for all), else InputError
// naming the function and the first bad point.
fem::PointValues point_function(py::object f, const std::string& what) {
  if (!PyCallable_Check(f.ptr())) throw InputError(what + ": must be callable, f(points) -> values");
  auto callable = std::make_shared<Callable>(std::move(f));
  return [callable, what](const Vec3* x, std::size_t n, double* values) {
    py::gil_scoped_acquire gil;
    throw_if_interrupted();
    py::array_t<double> points({static_cast<py::ssize_t>(n), py::ssize_t{3}});
    std::memcpy(points.mutable_data(), x, n * sizeof(Vec3));
    const py::object result = callable->f(points);
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(result);
    if (!a) throw InputError(what + ": returned " + std::string(py::str(py::type::of(result).attr("__name__"))) +
                             ", not an array of numbers");
    const bool scalar = a.size() == 1 && a.ndim() <= 1 && n != 1;
    if (!scalar && !(static_cast<std::size_t>(a.size()) == n && (a.ndim() == 1 || (a.ndim() == 2 && a.shape(1) == 1))))
      throw InputError(what + ": returned an array of shape " + shape_of(a) +
                       " for " + std::to_string(n) + " points (one value per row of points is needed)");
    const double* v = a.data();
    for (std::size_t i = 0; i < n; ++i) {
      values[i] = scalar ? v[0] : v[i];
      if (!std::isfinite(values[i]))
        throw InputError(what + ": not finite at point (" + std::to_string(x[i].x) + ", " + std::to_string(x[i].y) +
                         ", " + std::to_string(x[i].z) + ")");
    }
  };
}

// A problem and what its geometry must be.
struct PyProblem {
  fem::Problem problem;
  bool on_unit_sphere = false;  // its exact solution holds on the unit sphere (built-in problems)
};

PyProblem python_problem(py::object source, double c, py::object dirichlet, const std::string& name) {
  if (!(c >= 0) || !std::isfinite(c)) throw InputError("c: must be finite and >= 0, got " + std::to_string(c));
  PyProblem p;
  p.problem.name = name;
  p.problem.c = c;
  if (!source.is_none()) p.problem.source_values = point_function(std::move(source), "source");
  if (!dirichlet.is_none()) p.problem.dirichlet_values = point_function(std::move(dirichlet), "dirichlet");
  return p;
}

// What solve and adapt both settle: the geometry and the solver.
struct Setup {
  std::optional<fem::Projection> projection;
  fem::SolverKind solver = fem::SolverKind::automatic;
};

Setup settle(const RgbMesh& mesh, const PyProblem& p, int order, const std::optional<std::string>& geometry_option,
             const std::string& solver) {
  if (order != 1 && order != 2) throw InputError("order " + std::to_string(order) + ": 1 or 2");
  const std::string geometry = geometry_option.value_or(p.on_unit_sphere ? "sphere" : "loop");
  const fem::Projection& projection = named_row(fem::geometry_table(), geometry, "geometry").value;
  // As the tool: an exact solution on the unit sphere is not one on a Loop limit surface, and
  // projecting a surface that is not the unit sphere onto it would change the user's problem.
  if (p.on_unit_sphere && geometry == "loop")
    throw InputError("geometry 'loop': problem '" + p.problem.name +
                     "' has its exact solution on the unit sphere, and a Loop limit surface is not that sphere");
  if (geometry == "sphere") {
    for (const VertexHandle v : mesh.vertices()) {
      if (mesh.level(v) != 0) continue;
      const double r = norm(mesh.insertion_point(v));
      if (!(std::abs(r - 1.0) <= 1e-3))
        throw InputError("geometry 'sphere' projects the vertices onto the unit sphere, but base vertex " +
                         std::to_string(v.idx) + " is at distance " + std::to_string(r) + " from the origin");
    }
  }
  Setup s;
  if (projection) s.projection = projection;
  s.solver = fem::parse_solver(solver);
  return s;
}

// The picture of the smooth solution that adapt(element='loop') keeps per cycle: each triangle
// split in 16 (as rgbmesh adapt --element loop writes).
constexpr int kCycleViewLevels = 2;

// A solved mesh, kept after the call that made it: the finite-element mesh, the solution, the
// estimate, and for a cycle its report and marks.
struct Solution {
  std::shared_ptr<const fem::Problem> problem;
  fem::SurfaceMesh fe;
  Eigen::VectorXd u;
  fem::Estimate estimate;
  std::vector<char> marked;  // per triangle (a cycle's marks; all 0 for solve())
  adapt::SolvedMesh solved;
  adapt::CycleReport report;
  bool is_cycle = false;
  std::string element = "p1";  // "p1", "p2" or "loop"
  // Loop elements: the cells and their control values, for pictures finer than the mesh (solve);
  // a cycle of adapt keeps the picture the cycle made instead (AdaptOptions::loop_view_levels).
  std::shared_ptr<const fem::LoopSpace> loop_space;
  Eigen::VectorXd loop_coefficients;
  std::shared_ptr<const MeshSnapshot> loop_view;
  bool loop_view_kept = false;  // a cycle of adapt(element='loop'), whose picture is loop_view

  adapt::CycleState state() const {
    static const RgbMesh no_mesh;  // (snapshot() reads the levels from `solved`, not the mesh)
    return {report, no_mesh, fe, *problem, u, estimate, marked, &solved, nullptr};
  }
};

// A result's note (adapt::CycleReport::note) as a UserWarning, which the caller may silence or
// turn into an error; the GIL held.
void warn_note(const std::string& note) {
  if (!note.empty() && PyErr_WarnEx(PyExc_UserWarning, note.c_str(), 1) < 0) throw py::error_already_set();
}

py::dict report_dict(const adapt::CycleReport& r) {
  py::dict d;
  d["cycle"] = r.cycle;
  d["triangles"] = r.triangles;
  d["dofs"] = r.dofs;
  d["estimate"] = r.estimate;
  d["error_l2"] = r.error_l2 ? py::cast(*r.error_l2) : py::none();
  d["error_h1"] = r.error_h1 ? py::cast(*r.error_h1) : py::none();
  d["marked"] = r.marked;
  d["splits"] = r.splits;
  d["removals"] = r.removals;
  d["solver"] = r.solver;
  d["solver_iterations"] = r.solver_iterations;
  d["note"] = r.note;
  d["seconds"] = r.seconds;
  d["mesh_seconds"] = r.mesh_seconds;
  d["solve_seconds"] = r.solve_seconds;
  d["estimate_seconds"] = r.estimate_seconds;
  d["error_seconds"] = r.error_seconds;
  d["adapt_seconds"] = r.adapt_seconds;
  return d;
}

// What a cycle's levels are, per FE point and triangle (solve() has no run to take them from).
adapt::SolvedMesh levels_of(const RgbMesh& mesh, const fem::SurfaceMesh& fe) {
  adapt::SolvedMesh s;
  for (const VertexHandle v : fe.vertex) s.vertex_level.push_back(static_cast<std::uint8_t>(mesh.level(v)));
  for (const TriangleHandle t : fe.triangle) {
    s.triangle_level.push_back(static_cast<std::uint8_t>(mesh.level(t)));
    s.triangle_color.push_back(mesh.color(t));
  }
  return s;
}

// Loop-basis elements: the unknowns are control values; the Solution keeps what the other
// elements' have, on the P1 mesh of the limit positions: the values there, one indicator per
// triangle.
// The basis of Loop elements by its name ('details' or 'thb').
fem::LoopBasisKind loop_basis_named(const std::string& name) {
  static const std::vector<Named<fem::LoopBasisKind>> bases = {
      {"details", fem::LoopBasisKind::details}, {"thb", fem::LoopBasisKind::truncated_hierarchical}};
  return named_row(bases, name, "loop_basis").value;
}

std::shared_ptr<Solution> solve_loop_elements(RgbMesh& mesh, const PyProblem& p, const Setup& setup,
                                              const std::string& estimator, fem::LoopBasisKind basis) {
  if (estimator != "residual")
    throw InputError("estimator '" + estimator + "': Loop elements have the residual estimator only");
  auto s = std::make_shared<Solution>();
  s->problem = std::make_shared<const fem::Problem>(p.problem);
  s->element = "loop";
  py::gil_scoped_release release;
  // The hierarchical space of the mesh as it is (on a uniform mesh, the uniform space).
  fem::AdaptiveLoopSpace space = fem::build_adaptive_loop_space(mesh, setup.projection, {}, basis);
  check_signals();
  fem::SolveOptions o;
  o.solver = setup.solver;
  const fem::Solution solution = fem::solve_loop(space, p.problem, o);
  check_signals();
  s->fe = fem::build_surface_mesh(mesh, setup.projection, 1, fem::DofOrder::mesh);
  s->u = fem::loop_values_on(space, solution.u, s->fe);
  s->loop_coefficients = space.control_values(solution.u);  // the cells' control values
  const fem::Estimate estimate = fem::loop_residual_estimate(space.cells, p.problem, s->loop_coefficients);
  s->estimate.total = estimate.total;
  const std::vector<double> by_slot = fem::loop_indicators_on_triangles(space, mesh, estimate.eta);
  for (const TriangleHandle t : s->fe.triangle)
    s->estimate.eta.push_back(by_slot[static_cast<std::size_t>(t.idx)]);
  s->estimate.geometric.assign(s->estimate.eta.size(), 0.0);
  s->report.note = adapt::loop_singular_note(space, estimate.eta);
  s->report.triangles = s->fe.triangles.size();
  s->report.dofs = space.num_dofs();
  s->report.estimate = estimate.total;
  s->report.solver = fem::to_string(solution.solver);
  s->report.solver_iterations = solution.iterations;
  s->report.solve_seconds = solution.assembly_seconds + solution.solve_seconds;
  if (p.problem.exact) {
    const fem::ErrorNorms e =
        fem::loop_error_norms(space.cells, s->loop_coefficients, *p.problem.exact, solution.zero_mean);
    s->report.error_l2 = e.l2;
    s->report.error_h1 = e.h1;
  }
  s->loop_space = std::make_shared<const fem::LoopSpace>(std::move(space.cells));
  s->solved = levels_of(mesh, s->fe);
  s->marked.assign(s->fe.triangles.size(), 0);
  return s;
}

// element names the space; order (1, 2) stays for the Lagrange elements. Returns whether the
// element is Loop's, and settles order (1 for Loop: its cycles keep a P1 mesh of the vertices).
bool resolve_element(int& order, const std::optional<std::string>& element) {
  static const std::vector<Named<int>> elements = {{"p1", 1}, {"p2", 2}, {"loop", 0}};
  if (!element) return false;
  const int element_order = named_row(elements, *element, "element").value;
  if (order != 1 && order != element_order)
    throw InputError("order " + std::to_string(order) + " and element '" + *element +
                     "' disagree (give one)");
  order = element_order == 0 ? 1 : element_order;
  return element_order == 0;
}

std::shared_ptr<Solution> solve(RgbMesh& mesh, const PyProblem& p, int order,
                                const std::optional<std::string>& element,
                                const std::optional<std::string>& geometry, const std::string& solver,
                                const std::string& estimator, const std::optional<std::string>& loop_basis) {
  const bool loop = resolve_element(order, element);
  if (loop_basis && !loop) throw InputError("loop_basis '" + *loop_basis + "': for element='loop' only");
  if (loop) {
    std::shared_ptr<Solution> s = solve_loop_elements(mesh, p, settle(mesh, p, 1, geometry, solver), estimator,
                                                      loop_basis_named(loop_basis.value_or("details")));
    warn_note(s->report.note);
    return s;
  }
  const Setup setup = settle(mesh, p, order, geometry, solver);
  const std::shared_ptr<const fem::ErrorEstimator> estimate =
      named_row(fem::estimator_table(), estimator, "estimator").make();
  auto s = std::make_shared<Solution>();
  s->problem = std::make_shared<const fem::Problem>(p.problem);
  s->element = order == 2 ? "p2" : "p1";
  {
    py::gil_scoped_release release;
    s->fe = fem::build_surface_mesh(mesh, setup.projection, order, fem::DofOrder::mesh);  // rows as the mesh's arrays
    check_signals();
    fem::SolveOptions o;
    o.solver = setup.solver;
    const fem::Solution solution = fem::solve(s->fe, p.problem, o);
    check_signals();
    s->u = solution.u;
    s->estimate = estimate->estimate(s->fe, p.problem, s->u, {});
    s->report.triangles = s->fe.triangles.size();
    s->report.dofs = s->fe.num_dofs();
    s->report.estimate = s->estimate.total;
    s->report.solver = fem::to_string(solution.solver);
    s->report.solver_iterations = solution.iterations;
    s->report.solve_seconds = solution.assembly_seconds + solution.solve_seconds;
    if (p.problem.exact) {
      const fem::ErrorNorms e = fem::error_norms(s->fe, s->u, *p.problem.exact, solution.zero_mean);
      s->report.error_l2 = e.l2;
      s->report.error_h1 = e.h1;
    }
    s->solved = levels_of(mesh, s->fe);
    s->marked.assign(s->fe.triangles.size(), 0);  // (nothing marked: the files' "marked" array is 0)
  }
  return s;
}

// Builds a Solution from a cycle's state (the callback's copy).
std::shared_ptr<Solution> copy_cycle(const adapt::CycleState& c,
                                     const std::shared_ptr<const fem::Problem>& problem, bool loop) {
  auto s = std::make_shared<Solution>();
  s->problem = problem;
  s->element = loop ? "loop" : (c.fe.order == 2 ? "p2" : "p1");
  s->loop_view = c.loop_view;  // shared, not copied
  s->loop_view_kept = loop;
  s->fe = c.fe;
  s->u = c.u;
  s->estimate = c.estimate;
  s->marked = c.marked;
  if (c.solved) s->solved = *c.solved;
  s->report = c.report;
  s->is_cycle = true;
  return s;
}

py::dict run_adapt(RgbMesh& mesh, const PyProblem& p, const std::string& strategy, const std::string& marking,
                   double theta, const std::string& estimator, int order,
                   const std::optional<std::string>& element, double coarsen, int min_level, int max_level,
                   int cycles, double target_error, std::size_t max_dofs,
                   const std::optional<std::string>& geometry, const std::string& solver,
                   const std::optional<std::string>& loop_basis, py::object callback, py::object stop) {
  const bool loop = resolve_element(order, element);
  if (loop_basis && !loop) throw InputError("loop_basis '" + *loop_basis + "': for element='loop' only");
  if (loop && estimator != "residual")
    throw InputError("estimator '" + estimator + "': Loop elements have the residual estimator only");
  const Setup setup = settle(mesh, p, order, geometry, solver);
  adapt::AdaptOptions o;
  o.strategy = named_row(adapt::strategy_table(), strategy, "strategy").value;
  const adapt::NamedMarking& marking_row = named_row(adapt::marking_table(), marking, "marking");
  if (!(theta > 0 && theta <= 1)) throw InputError("theta: must be in (0, 1], got " + std::to_string(theta));
  o.marking = marking_row.make(theta);
  if (o.marking->marks_by_target() && !(target_error > 0))
    throw InputError("marking '" + marking +
                     "': needs target_error (it refines every triangle whose indicator "
                     "exceeds target_error / sqrt(number of triangles))");
  if (!(coarsen >= 0 && coarsen < 1)) throw InputError("coarsen: must be in [0, 1), got " + std::to_string(coarsen));
  if (max_level < 0 || max_level > kMaxLevel)
    throw InputError("max_level " + std::to_string(max_level) + " is not in [0, " + std::to_string(kMaxLevel) + "]");
  if (min_level < 0 || min_level > max_level)
    throw InputError("min_level " + std::to_string(min_level) + " is not in [0, max_level " + std::to_string(max_level) + "]");
  if (cycles < 1) throw InputError("cycles: at least 1, got " + std::to_string(cycles));
  if (!(target_error >= 0)) throw InputError("target_error: must be >= 0");
  o.estimator = named_row(fem::estimator_table(), estimator, "estimator").make();
  o.order = order;
  if (loop) {  // the hierarchical Loop space of each cycle's mesh (run_cycles)
    o.element = adapt::AdaptOptions::Element::loop;
    o.loop_view_levels = kCycleViewLevels;
    o.loop_basis = loop_basis_named(loop_basis.value_or("details"));
  }
  o.coarsen_below = coarsen;
  o.min_level = min_level;
  o.max_level = max_level;
  o.max_cycles = cycles;
  o.target_estimate = target_error;
  o.max_dofs = max_dofs;
  o.projection = setup.projection;
  o.solve.solver = setup.solver;
  o.control.interruption_point = check_signals;
  const auto problem = std::make_shared<const fem::Problem>(p.problem);
  if (!callback.is_none()) {
    if (!PyCallable_Check(callback.ptr())) throw InputError("callback: must be callable, callback(cycle)");
  }
  if (!stop.is_none()) {
    if (!PyCallable_Check(stop.ptr())) throw InputError("stop: must be callable, stop(report) -> bool");
    auto predicate = std::make_shared<Callable>(stop);
    o.control.stop = [predicate](const adapt::CycleReport& r) {
      py::gil_scoped_acquire gil;
      return predicate->f(report_dict(r)).cast<bool>();
    };
  }
  auto on_cycle = std::make_shared<Callable>(callback);
  adapt::AdaptRun run;
  {
    py::gil_scoped_release release;
    run = adapt::run_cycles(mesh, *problem, o, [&](const adapt::CycleState& c) {
      if (callback.is_none()) return check_signals();
      std::shared_ptr<Solution> copy = copy_cycle(c, problem, loop);
      py::gil_scoped_acquire gil;
      on_cycle->f(std::move(copy));
      throw_if_interrupted();
    });
  }
  py::list reports;
  for (const auto& r : run.cycles) reports.append(report_dict(r));
  // The first note of the run, once (the next cycles usually repeat it; each report keeps its own).
  for (const auto& r : run.cycles)
    if (!r.note.empty()) {
      warn_note("cycle " + std::to_string(r.cycle) + ": " + r.note);
      break;
    }
  py::dict out;
  out["cycles"] = reports;
  out["stopped"] = adapt::to_string(run.stopped);
  return out;
}

WriteOptions write_options(const std::string& compression) {
  WriteOptions o;
  if (!compression_from_name(compression, o.compression))
    throw InputError("compression '" + compression + "': lz4, zlib or none");
  return o;
}

// A Loop solution's picture finer than the mesh (fem::loop_refined_view).
void write_smooth(const Solution& s, const std::filesystem::path& path, int levels,
                  const std::string& compression) {
  if (!s.loop_space && !s.loop_view_kept)
    throw InputError("write_smooth: only for a solution with element='loop'");
  if (levels < 0 || levels > 4) throw InputError("levels: 0 to 4 (each level splits every triangle in four)");
  const WriteOptions o = write_options(compression);
  if (!s.loop_space) {  // a cycle of adapt(): the picture it made, at the levels it could afford
    if (!s.loop_view)
      throw InputError(
          "write_smooth: this cycle kept no picture (past 3 million pieces); solve() the mesh and "
          "write that solution's");
    int made = 0;
    for (std::size_t pieces = std::max<std::size_t>(1, s.fe.triangles.size());
         pieces < s.loop_view->triangles.size(); pieces *= 4)
      ++made;
    if (levels != made)
      throw InputError("write_smooth: this cycle of adapt() kept its picture at levels=" +
                       std::to_string(made) + " (solve() the mesh for another)");
    py::gil_scoped_release release;
    write_mesh(path, *s.loop_view, o);
    return;
  }
  py::gil_scoped_release release;
  write_mesh(path, fem::loop_refined_view(*s.loop_space, s.loop_coefficients, levels), o);
}

void write_solution(const Solution& s, const std::filesystem::path& path, const std::string& compression) {
  const WriteOptions o = write_options(compression);
  py::gil_scoped_release release;
  const adapt::CycleState state = s.state();
  if (s.fe.order == 2 && path.extension() == ".vtu") {
    const adapt::QuadraticSnapshot q = adapt::quadratic_snapshot(state);
    write_quadratic_triangles(path, q.points, q.cells, q.point_data, q.cell_data, o);
  } else {
    write_mesh(path, adapt::snapshot(state), o);
  }
}

}  // namespace

void bind_fem(py::module_& m) {
  py::class_<PyProblem>(m, "Problem",
                        "-Δu + c u = f on the mesh's surface (Dirichlet data g on its boundary, if any). On a closed "
                        "surface with c = 0 the source must have zero mean; the solution of zero mean is returned.")
      .def(py::init(&python_problem), py::arg("source") = py::none(), py::kw_only(), py::arg("c") = 0.0,
           py::arg("dirichlet") = py::none(), py::arg("name") = "python",
           "source(points) -> values and dirichlet(points) -> values: functions of an (n, 3) array of points on the "
           "surface returning n values (numpy), called once per assembly or estimate with all the points it needs.")
      .def_static(
          "builtin",
          [](const std::string& name) {
            PyProblem p;
            p.problem = fem::builtin_problem(name);
            p.on_unit_sphere = true;
            return p;
          },
          py::arg("name"),
          "A built-in problem with a known exact solution on the unit sphere: 'sphere-peak' or 'sphere-harmonic' "
          "(as rgbmesh adapt --problem); solve() and adapt() then report the L2 and H1 errors.")
      .def_static(
          "gaussian",
          [](const std::array<double, 3>& center, double width) {
            if (!(width > 0)) throw InputError("width: must be positive");
            PyProblem p;
            p.problem = fem::gaussian_source(Vec3(center[0], center[1], center[2]), width);
            return p;
          },
          py::arg("center"), py::arg("width"), "A Gaussian source of this width at this centre, c = 1 (rgbmesh adapt's 'gaussian').")
      .def_property_readonly("name", [](const PyProblem& p) { return p.problem.name; })
      .def_property_readonly("c", [](const PyProblem& p) { return p.problem.c; })
      .def_property_readonly("has_exact_solution", [](const PyProblem& p) { return p.problem.exact.has_value(); });

  py::class_<Solution, std::shared_ptr<Solution>>(
      m, "Solution",
      "A solved mesh: the finite-element nodes, the solution there, the "
      "error indicators per triangle; for a cycle of adapt() also its report and marks.")
      .def_property_readonly(
          "u",
          [](const Solution& s) {
            return array_of<double>(static_cast<std::size_t>(s.u.size()), 1, s.u.data());
          },
          "The solution at the nodes: the vertices in the order of the mesh's point arrays at the "
          "time of the solve (P2: then one node per edge).")
      .def_property_readonly(
          "points",
          [](const Solution& s) { return array_of<double>(s.fe.points.size(), 3, &s.fe.points.data()->x); },
          "The nodes' positions, (n, 3): on the Loop limit surface (or projected with geometry 'sphere').")
      .def_property_readonly(
          "triangles",
          [](const Solution& s) {
            return array_of<std::int32_t>(s.fe.triangles.size(), 3,
                                          s.fe.triangles.empty() ? nullptr : s.fe.triangles[0].data());
          },
          "The triangles, (m, 3) rows of points.")
      .def_property_readonly(
          "edge_nodes",
          [](const Solution& s) -> py::object {
            if (s.fe.order != 2) return py::none();
            return array_of<std::int32_t>(s.fe.edge_nodes.size(), 3,
                                          s.fe.edge_nodes.empty() ? nullptr : s.fe.edge_nodes[0].data());
          },
          "P2: per triangle, the node of edge k (corner k to k + 1); None for P1.")
      .def_property_readonly("order", [](const Solution& s) { return s.fe.order; })
      .def_property_readonly(
          "element", [](const Solution& s) { return s.element; },
          "'p1', 'p2' or 'loop' (Loop-basis elements: u holds the smooth solution's values at the "
          "vertices' limit positions, not its coefficients).")
      .def_property_readonly(
          "estimate",
          [](const Solution& s) { return array_of<double>(s.estimate.eta.size(), 1, s.estimate.eta.data()); },
          "The error indicator η_T of each triangle.")
      .def_property_readonly(
          "total_estimate", [](const Solution& s) { return s.estimate.total; }, "sqrt(Σ η_T²).")
      .def_property_readonly(
          "marked",
          [](const Solution& s) -> py::object {
            if (!s.is_cycle) return py::none();
            return array_of<bool>(s.marked.size(), 1, s.marked.data());
          },
          "A cycle's triangles marked for refinement (None for solve()).")
      .def_property_readonly("vertex_levels",
                             [](const Solution& s) {
                               return array_of<std::uint8_t>(s.solved.vertex_level.size(), 1,
                                                             s.solved.vertex_level.data());
                             })
      .def_property_readonly("triangle_levels",
                             [](const Solution& s) {
                               return array_of<std::uint8_t>(s.solved.triangle_level.size(), 1,
                                                             s.solved.triangle_level.data());
                             })
      .def_property_readonly(
          "report", [](const Solution& s) { return report_dict(s.report); },
          "Counts, estimate, errors (where the exact solution is known), solver and timings.")
      .def("write", &write_solution, py::arg("path"), py::kw_only(), py::arg("compression") = "lz4",
           "Writes the solved mesh as the tool's cycle files: .vtp (or any mesh format) with point data "
           "solution "
           "(exact_solution, error) and cell data error_indicator, marked, level, color; a P2 solution to "
           ".vtu as "
           "quadratic triangles with every node. Atomic; OSError when the path cannot be written.")
      .def(
          "write_smooth", &write_smooth, py::arg("path"), py::kw_only(), py::arg("levels") = 2,
          py::arg("compression") = "lz4",
          "element='loop' only: a picture of the smooth solution finer than the mesh, each triangle split in "
          "4**levels, surface and solution evaluated exactly at the pieces' corners (point data solution).");

  m.def("solve", &solve, py::arg("mesh"), py::arg("problem"), py::kw_only(), py::arg("order") = 1,
        py::arg("element") = py::none(), py::arg("geometry") = py::none(), py::arg("solver") = "auto",
        py::arg("estimator") = "residual", py::arg("loop_basis") = py::none(),
        "Solves the problem on the mesh as it is (P1 or P2 elements, vertices on the Loop limit surface, or "
        "projected "
        "onto the unit sphere with geometry='sphere', the default for built-in problems) and estimates the "
        "error per "
        "triangle ('residual' or 'zz'). element='loop': Loop-basis (smooth) elements, one unknown per "
        "vertex (the hierarchical space of the mesh as refined; on an open mesh Loop's boundary rules, with "
        "the "
        "Dirichlet data imposed weakly), residual estimator; loop_basis='thb' solves in the truncated "
        "hierarchical basis (functions as narrow as their level; 'details', the default, one per vertex). "
        "Returns a Solution.");
  m.def(
      "adapt", &run_adapt, py::arg("mesh"), py::arg("problem"), py::kw_only(),
      py::arg("strategy") = "adaptive", py::arg("marking") = "dorfler", py::arg("theta") = 0.5,
      py::arg("estimator") = "residual", py::arg("order") = 1, py::arg("element") = py::none(),
      py::arg("coarsen") = 0.0, py::arg("min_level") = 0, py::arg("max_level") = kMaxLevel,
      py::arg("cycles") = 20, py::arg("target_error") = 0.0, py::arg("max_dofs") = 100000,
      py::arg("geometry") = py::none(), py::arg("solver") = "auto", py::arg("loop_basis") = py::none(),
      py::arg("callback") = py::none(), py::arg("stop") = py::none(),
      "Adaptive cycles on the mesh, in place, as rgbmesh adapt runs them: solve, estimate, mark, refine (and "
      "coarsen), until cycles, target_error or max_dofs stops them. callback(solution) after each cycle (the "
      "Solution of that cycle; the mesh is already adapted for the next); stop(report) -> True ends the run "
      "with "
      "that cycle. Returns {'cycles': [report, ...], 'stopped': why}. Ctrl-C interrupts between steps. "
      "element='loop': Loop-basis elements (the hierarchical space of the adaptive mesh; loop_basis 'details' "
      "or 'thb', as for solve), "
      "each "
      "cycle's Solution keeping its picture for write_smooth().");
}

}  // namespace rgbmesh::python
