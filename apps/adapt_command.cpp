#include "adapt_command.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <iostream>
#include <sstream>

#include "json.hpp"
#include "output_dir.hpp"
#include "resources.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "write_progress.hpp"

#ifndef RGBMESH_VERSION
#define RGBMESH_VERSION "unknown"
#endif

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
        .add("marked", static_cast<std::uint64_t>(r.marked))
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
  char buf[64];
  std::snprintf(buf, sizeof buf, format, x);
  return buf;
}

// The exact solutions of the sphere problems hold on the unit sphere centred at the origin:
// a mesh whose vertices are elsewhere would be projected onto it, silently changing the
// user's surface. Vertices may be off by a relative 1e-3 (coordinates written with few digits).
void require_unit_sphere(const TriangleMeshData& mesh, const std::string& name, const std::string& why) {
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    const double r = norm(mesh.points[i]);
    if (!(std::abs(r - 1.0) <= 1e-3))
      throw InputError(why + ", but vertex " + std::to_string(i) + " of " + name + " is at distance " +
                       number(r, "%.6g") + " from the origin");
  }
}

// The options given explicitly that `context` does not use: an InputError naming the first.
void refuse(const AdaptArgs& a, std::initializer_list<const char*> options, const std::string& context) {
  for (const char* o : options) {
    if (a.given.count(o)) throw InputError(std::string(o) + ": does not apply " + context);
  }
}

struct Settings {
  MemoryCeiling ceiling;
  std::string problem, marking, geometry, mesh_name;
  bool moving = false, on_sphere = false;
  adapt::AdaptOptions options;
  adapt::DynamicOptions dynamic;
  Vec3 center;
  double width = 0;
};

// Every option checked against the others; the mesh read. InputError on the first conflict.
Settings settle(const AdaptArgs& a, const TriangleMeshData& base) {
  Settings s;
  s.ceiling = MemoryCeiling::from_option(a.memory_limit);
  s.options.memory_headroom = [ceiling = s.ceiling] { return ceiling.headroom(); };
  s.mesh_name = a.mesh.empty() ? "icosahedron (embedded)" : a.mesh;
  s.problem = !a.problem.empty() ? a.problem : (a.mesh.empty() ? "sphere-peak" : "gaussian");
  choose<int>("--problem", s.problem,
              {{"sphere-harmonic", 0}, {"sphere-peak", 0}, {"moving-peak", 0}, {"gaussian", 0}});
  s.moving = s.problem == "moving-peak";
  s.on_sphere = s.problem != "gaussian";
  s.geometry = !a.geometry.empty() ? a.geometry : (s.on_sphere ? "sphere" : "loop");
  choose<int>("--geometry", s.geometry, {{"sphere", 0}, {"loop", 0}});
  adapt::AdaptOptions& o = s.options;
  o.strategy = choose<adapt::Strategy>("--strategy", a.strategy,
                                       {{"adaptive", adapt::Strategy::adaptive}, {"uniform", adapt::Strategy::uniform}});
  s.marking = !a.marking.empty() ? a.marking : (s.moving ? "equidistribution" : "dorfler");
  o.marking = choose<adapt::Marking>("--marking", s.marking,
                                     {{"dorfler", adapt::Marking::dorfler},
                                      {"fraction", adapt::Marking::fixed_fraction},
                                      {"equidistribution", adapt::Marking::equidistribution}});
  o.estimator = choose<adapt::EstimatorKind>(
      "--estimator", a.estimator, {{"residual", adapt::EstimatorKind::residual}, {"zz", adapt::EstimatorKind::zz}});
  o.solve.solver = fem::parse_solver(a.solver);

  // Geometry: the sphere problems' exact solutions hold on the unit sphere only.
  if (s.on_sphere && s.geometry == "loop")
    throw InputError("--geometry loop: " + s.problem +
                     " has its exact solution on the unit sphere, and a Loop limit surface is not that sphere "
                     "(use --geometry sphere, or --problem gaussian for any surface)");
  if (s.on_sphere)
    require_unit_sphere(base, s.mesh_name,
                        "--problem " + s.problem + ": its exact solution holds on the unit sphere (use --problem gaussian for any surface)");
  else if (s.geometry == "sphere")
    require_unit_sphere(base, s.mesh_name, "--geometry sphere projects the vertices onto the unit sphere");
  if (s.geometry == "sphere") o.projection = fem::Projection(fem::project_to_unit_sphere);

  // Options that belong to one problem or strategy only.
  if (!s.moving) refuse(a, {"--steps"}, "to " + s.problem + " (only moving-peak has time steps)");
  if (s.problem != "gaussian") refuse(a, {"--center", "--width"}, "to " + s.problem + " (only to gaussian)");
  if (o.strategy == adapt::Strategy::uniform)
    refuse(a, {"--marking", "--theta", "--coarsen"}, "to --strategy uniform (every triangle is refined)");
  if (o.marking == adapt::Marking::equidistribution && !s.moving) {
    if (!(a.target_error > 0))
      throw InputError("--marking equidistribution: needs --target-error E (it refines every triangle whose "
                       "indicator exceeds E / sqrt(number of triangles))");
    refuse(a, {"--theta"}, "to --marking equidistribution (it marks by --target-error)");
  }

  o.theta = a.theta;
  o.target_estimate = a.target_error;
  o.max_dofs = static_cast<std::size_t>(a.max_dofs);
  o.coarsen_below = a.coarsen >= 0 ? a.coarsen : (s.moving && o.strategy == adapt::Strategy::adaptive ? 0.25 : 0.0);
  const int cycles = a.cycles > 0 ? a.cycles : (s.moving ? 8 : 20);
  if (s.moving) {
    s.dynamic.steps = a.steps;
    s.dynamic.start_cycles = cycles;
    o.max_cycles = cycles;
  } else {
    o.max_cycles = cycles;
  }
  if (s.problem == "gaussian") {
    if (!a.center.empty() && a.center.size() != 3)
      throw InputError("--center: expected X,Y,Z (three numbers), got " + std::to_string(a.center.size()));
    s.width = a.width > 0 ? a.width : bounding_box_diagonal(base.points) / 20.0;
  }
  return s;
}

std::string stop_message(adapt::StopReason reason, const Settings& s, const AdaptArgs& a, const adapt::AdaptRun& run) {
  switch (reason) {
    case adapt::StopReason::cycles:
      return "the --cycles limit (" + std::to_string(s.options.max_cycles) + ") was reached";
    case adapt::StopReason::target_error:
      return "the estimate " + number(run.cycles.empty() ? 0.0 : run.cycles.back().estimate, "%.4g") +
             " reached --target-error " + number(a.target_error, "%.4g");
    case adapt::StopReason::max_dofs:
      return "the next mesh would have more than --max-dofs " + std::to_string(a.max_dofs) + " unknowns";
    case adapt::StopReason::steps:
      return "all " + std::to_string(s.dynamic.steps) + " time steps done";
    case adapt::StopReason::memory:
      return "the next cycle would pass the memory limit of " + s.ceiling.describe() +
             " (the results so far are written)";
  }
  return "";
}

}  // namespace

int run_adapt(const AdaptArgs& a) {
  // Mesh, then every setting checked before anything is written.
  SoupOptions read_options;
  read_options.triangulate = a.triangulate;
  TriangleMeshData base = a.mesh.empty() ? icosahedron() : read_mesh(a.mesh, read_options);
  for (const auto& note : base.notes) std::cerr << "rgbmesh: note: " << a.mesh << ": " << note << "\n";
  Settings s = settle(a, base);
  RgbMesh mesh = [&] {
    try {
      return RgbMesh::from_triangles(base.points, base.triangles);
    } catch (const InputError& e) {
      throw InputError(a.mesh + ": " + e.what());
    }
  }();
  if (a.mesh.empty()) selective_refinement(mesh, UniformLevel(1));  // 42 vertices to start from
  if (mesh.num_vertices() > s.options.max_dofs)
    throw InputError("--max-dofs " + std::to_string(a.max_dofs) + ": the starting mesh already has " +
                     std::to_string(mesh.num_vertices()) + " vertices");
  fem::Problem problem;
  if (s.problem == "gaussian") {
    // A localized source: by default at the limit position of the first vertex, 1/20 of the
    // mesh's size wide.
    mesh.compute_limits();
    s.center = a.center.empty() ? mesh.limit_position(VertexHandle(0)) : Vec3(a.center[0], a.center[1], a.center[2]);
    problem = fem::gaussian_source(s.center, s.width);
  } else if (!s.moving) {
    problem = fem::builtin_problem(s.problem);
  }

  // Output: the folder, the per-cycle files, the series and the report after every cycle.
  const fs::path dir(a.out);
  prepare_output_directory(dir);
  std::vector<std::pair<double, std::string>> series;
  adapt::AdaptRun progress;  // what has been computed so far, for the report
  auto report_json = [&](const char* status, const std::string& stopped, const std::string& message) {
    JsonObject j;
    j.add("version", RGBMESH_VERSION).add("command", a.command_line).add("status", status);
    j.raw("stopped", stopped.empty() ? "null" : JsonObject::quote(stopped));
    j.add("stop_message", message);
    j.add("mesh", s.mesh_name).add("problem", s.problem).add("strategy", a.strategy).add("marking", s.marking);
    j.add("theta", s.options.theta).add("estimator", a.estimator).add("solver", a.solver).add("geometry", s.geometry);
    j.add("coarsen", s.options.coarsen_below).add("max_cycles", s.options.max_cycles);
    j.add("target_error", a.target_error).add("max_dofs", static_cast<std::int64_t>(a.max_dofs));
    if (s.moving) j.add("steps", s.dynamic.steps).add("cycles_per_step", s.dynamic.cycles_per_step);
    if (s.problem == "gaussian") {
      j.raw("center", "[" + number(s.center.x, "%.17g") + ", " + number(s.center.y, "%.17g") + ", " +
                          number(s.center.z, "%.17g") + "]");
      j.add("width", s.width);
    }
    if (s.moving) {
      j.add("target_estimate", progress.target_estimate);
      j.raw("start_cycles", cycles_json(progress.start, false));
    }
    j.raw("cycles", cycles_json(progress.cycles, s.moving));
    return j.str() + "\n";
  };

  std::cout << "rgbmesh adapt: problem " << s.problem << ", " << a.strategy
            << (s.options.strategy == adapt::Strategy::adaptive ? " (" + s.marking + ")" : std::string())
            << ", geometry " << s.geometry << ", mesh " << s.mesh_name << "\n"
            << (s.moving ? " step   time" : "cycle")
            << "  triangles      dofs    estimate    error_L2    error_H1  seconds\n";
  auto on_cycle = [&](const adapt::CycleState& c) {
    const auto& r = c.report;
    const std::string file = (s.moving ? "step_" : "cycle_") + number(r.cycle, "%03.0f") + ".vtp";
    write_mesh(dir / file, adapt::snapshot(c), output_options((dir / file).string(), a.compression));
    series.emplace_back(s.moving ? r.time : r.cycle, file);
    write_pvd(dir / "solution.pvd", series);  // after every cycle: usable while running
    progress.cycles.push_back(r);
    if (!a.report.empty()) write_text_atomically(a.report, report_json("running", "", ""));
    std::cout << number(r.cycle, "%5.0f") << (s.moving ? number(r.time, "%7.3f") : "")
              << number(static_cast<double>(r.triangles), "%11.0f") << number(static_cast<double>(r.dofs), "%10.0f")
              << number(r.estimate, "%12.4e") << (r.error_l2 ? number(*r.error_l2, "%12.4e") : std::string(12, ' '))
              << (r.error_h1 ? number(*r.error_h1, "%12.4e") : std::string(12, ' ')) << number(r.seconds, "%9.3f")
              << std::endl;
  };
  adapt::AdaptRun run;
  if (s.moving) {
    s.dynamic.on_started = [&](const std::vector<adapt::CycleReport>& start, double target) {
      progress.start = start;
      progress.target_estimate = target;
      std::cout << "  (adapted to the start in " << start.size() << " cycles: " << start.back().dofs
                << " unknowns, estimate " << number(start.back().estimate, "%.4e");
      if (s.options.marking == adapt::Marking::equidistribution)
        std::cout << "; every step keeps each triangle's indicator below " << number(target, "%.4e")
                  << " / sqrt(triangles)";
      std::cout << ")\n";
    };
    run = adapt::run_dynamic(
        mesh, [](double t) { return adapt::moving_peak(t); }, s.options, s.dynamic, on_cycle);
  } else {
    run = adapt::run_cycles(mesh, problem, s.options, on_cycle);
  }
  progress = run;
  const std::string message = stop_message(run.stopped, s, a, run);
  if (!a.report.empty()) write_text_atomically(a.report, report_json("finished", adapt::to_string(run.stopped), message));
  std::cout << "stopped: " << message << "\n"
            << "wrote " << series.size() << " files and " << (dir / "solution.pvd").string()
            << " (open the .pvd in ParaView: color by 'solution', 'error_indicator' or 'level')\n";
  if (run.stopped == adapt::StopReason::memory) throw ResourceError("adapt: " + message);
  return 0;
}

}  // namespace rgbmesh::cli
