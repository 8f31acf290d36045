#include "adapt_command.hpp"

#include <cstdio>
#include <initializer_list>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "json.hpp"
#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::cli {

namespace {

namespace fs = std::filesystem;

std::string cycles_json(const std::vector<adapt::CycleReport>& reports, bool dynamic) {
  std::string out = "[";
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const auto& r = reports[i];
    JsonObject o;
    o.add("cycle", r.cycle);
    if (dynamic) o.add("time", r.time);
    o.add("triangles", static_cast<std::uint64_t>(r.triangles))
        .add("dofs", static_cast<std::uint64_t>(r.dofs))
        .add("estimate", r.estimate);
    if (r.error_l2) o.add("error_l2", *r.error_l2);
    if (r.error_h1) o.add("error_h1", *r.error_h1);
    o.add("seconds", r.seconds)
        .add("solve_seconds", r.solve_seconds)
        .add("adapt_seconds", r.adapt_seconds)
        .add("splits", static_cast<std::uint64_t>(r.splits))
        .add("removals", static_cast<std::uint64_t>(r.removals))
        .add("solver", r.solver);
    out += (i ? ", " : "") + o.str();
  }
  return out + "]";
}

// The value of a named choice; InputError listing the names otherwise.
template <class T>
T choose(const char* option, const std::string& value, std::initializer_list<std::pair<const char*, T>> names) {
  std::string known;
  for (const auto& [name, v] : names) {
    if (value == name) return v;
    known += (known.empty() ? "" : ", ") + std::string(name);
  }
  throw InputError(std::string(option) + ": '" + value + "' is not one of " + known);
}

std::string number(double x, const char* format) {
  char buf[32];
  std::snprintf(buf, sizeof buf, format, x);
  return buf;
}

}  // namespace

int run_adapt(const AdaptArgs& a) {
  // Problem and geometry.
  const bool moving = a.problem == "moving-peak";
  const bool on_sphere = a.problem == "sphere-harmonic" || a.problem == "sphere-peak" || moving;
  if (!on_sphere && a.problem != "gaussian")
    throw InputError("--problem: unknown problem '" + a.problem +
                     "' (sphere-harmonic, sphere-peak, moving-peak, gaussian)");
  const std::string geometry = a.geometry.empty() ? (on_sphere ? "sphere" : "loop") : a.geometry;
  if (geometry != "sphere" && geometry != "loop")
    throw InputError("--geometry: '" + geometry + "' is neither loop nor sphere");
  adapt::AdaptOptions o;
  o.strategy = choose<adapt::Strategy>("--strategy", a.strategy, {{"adaptive", adapt::Strategy::adaptive}, {"uniform", adapt::Strategy::uniform}});
  o.marking = choose<adapt::Marking>("--marking", a.marking, {{"dorfler", adapt::Marking::dorfler}, {"fraction", adapt::Marking::fixed_fraction}});
  o.estimator =
      choose<adapt::EstimatorKind>("--estimator", a.estimator, {{"residual", adapt::EstimatorKind::residual}, {"zz", adapt::EstimatorKind::zz}});
  if (!(a.theta > 0 && a.theta <= 1)) throw InputError("--theta: must be in (0, 1], got " + std::to_string(a.theta));
  if (a.cycles < 1) throw InputError("--cycles: must be at least 1");
  o.theta = a.theta;
  o.max_cycles = a.cycles;
  o.target_estimate = a.target_error;
  o.max_dofs = a.max_dofs;
  o.solve.solver = fem::parse_solver(a.solver);
  o.coarsen_below = a.coarsen >= 0 ? a.coarsen : (moving ? 0.25 : 0.0);
  if (geometry == "sphere") o.projection = fem::Projection(fem::project_to_unit_sphere);

  // Mesh.
  TriangleMeshData base = a.mesh.empty() ? icosahedron() : read_mesh(a.mesh);
  for (const auto& note : base.notes) std::cerr << "rgbmesh: " << a.mesh << ": " << note << "\n";
  RgbMesh mesh = RgbMesh::from_triangles(base.points, base.triangles);
  if (a.mesh.empty()) selective_refinement(mesh, UniformLevel(1));  // 42 vertices to start from

  // Output.
  const fs::path dir(a.out);
  fs::create_directories(dir);
  std::vector<std::pair<double, std::string>> series;
  if (!a.quiet) {
    std::cout << "rgbmesh adapt: problem " << a.problem << ", " << a.strategy << ", geometry " << geometry
              << ", mesh " << (a.mesh.empty() ? "icosahedron (embedded)" : a.mesh) << "\n"
              << (moving ? " step   time" : "cycle") << "  triangles      dofs    estimate    error_L2    error_H1  seconds\n";
  }
  auto on_cycle = [&](const adapt::CycleState& s) {
    const auto& r = s.report;
    const std::string file = (moving ? "step_" : "cycle_") + number(r.cycle, "%03.0f") + ".vtp";
    write_mesh(dir / file, adapt::snapshot(s));
    series.emplace_back(moving ? r.time : r.cycle, file);
    write_pvd(dir / "solution.pvd", series);  // after every cycle: usable while running
    if (!a.quiet) {
      std::cout << number(r.cycle, "%5.0f") << (moving ? number(r.time, "%7.3f") : "") << number(static_cast<double>(r.triangles), "%11.0f")
                << number(static_cast<double>(r.dofs), "%10.0f") << number(r.estimate, "%12.4e")
                << (r.error_l2 ? number(*r.error_l2, "%12.4e") : std::string(12, ' ') + "")
                << (r.error_h1 ? number(*r.error_h1, "%12.4e") : std::string(12, ' ') + "")
                << number(r.seconds, "%9.3f") << std::endl;
    }
  };
  std::vector<adapt::CycleReport> reports;
  if (moving) {
    // Adapt to the peak's starting place first, then follow it.
    adapt::AdaptOptions start = o;
    start.coarsen_below = 0;
    start.max_cycles = 8;
    start.max_dofs = std::min<std::size_t>(o.max_dofs, 20000);
    const auto started = adapt::run_cycles(mesh, adapt::moving_peak(0.0), start);
    // Equidistribution towards the error reached there keeps the size steady.
    o.marking = adapt::Marking::equidistribution;
    o.target_estimate = started.back().estimate;
    reports = adapt::run_dynamic(
        mesh, [](double t) { return adapt::moving_peak(t); }, a.steps, 2, o, on_cycle);
  } else {
    fem::Problem problem = a.problem == "gaussian" ? fem::Problem() : fem::builtin_problem(a.problem);
    if (a.problem == "gaussian") {
      // A localized source: a Gaussian of width 1/20 of the mesh's size at its first vertex.
      problem = fem::gaussian_source(mesh.limit_position(VertexHandle(0)), bounding_box_diagonal(base.points) / 20.0);
    }
    reports = adapt::run_cycles(mesh, problem, o, on_cycle);
  }
  if (!a.report.empty()) {
    const std::string json = JsonObject()
                                 .add("problem", a.problem)
                                 .add("strategy", a.strategy)
                                 .add("geometry", geometry)
                                 .raw("cycles", cycles_json(reports, moving))
                                 .str();
    write_text_atomically(a.report, json + "\n");
  }
  if (!a.quiet)
    std::cout << "wrote " << series.size() << " files and " << (dir / "solution.pvd").string()
              << " (open the .pvd in ParaView: color by 'solution', 'error_indicator' or 'level')\n";
  return 0;
}

}  // namespace rgbmesh::cli
