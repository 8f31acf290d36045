#include "adapt_command.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "json.hpp"
#include "json_read.hpp"
#include "mesh_commands.hpp"
#include "one_line.hpp"
#include "output_dir.hpp"
#include "resources.hpp"
#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/repair/repair.hpp"
#include "rgbmesh/rgb_state.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "run_lock.hpp"
#include "write_progress.hpp"

#ifndef RGBMESH_VERSION
#define RGBMESH_VERSION "unknown"
#endif

namespace rgbmesh::cli {

namespace {

namespace fs = std::filesystem;

// Exactly the double, as JSON (the JSON helper rounds to 6 digits): a resumed run continues
// from the report's figures, and runs are compared through them.
std::string exact(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::string cycles_json(const std::vector<adapt::CycleReport>& reports, bool dynamic) {
  std::string out = "[";
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const auto& r = reports[i];
    JsonObject o;
    o.add("cycle", r.cycle);
    if (dynamic) o.raw("time", exact(r.time));
    o.add("triangles", static_cast<std::uint64_t>(r.triangles))
        .add("dofs", static_cast<std::uint64_t>(r.dofs))
        .raw("estimate", exact(r.estimate));
    if (r.error_l2) o.raw("error_l2", exact(*r.error_l2));
    if (r.error_h1) o.raw("error_h1", exact(*r.error_h1));
    o.add("seconds", r.seconds)
        .add("mesh_seconds", r.mesh_seconds)
        .add("solve_seconds", r.solve_seconds)
        .add("estimate_seconds", r.estimate_seconds)
        .add("error_seconds", r.error_seconds)
        .add("adapt_seconds", r.adapt_seconds)
        .add("assembly_seconds", r.assembly_seconds)
        .add("partition_seconds", r.partition_seconds)
        .add("exchange_seconds", r.exchange_seconds)
        .add("output_seconds", r.output_seconds)
        .add("bytes_sent", static_cast<std::uint64_t>(r.bytes_sent))
        .add("bytes_sent_largest", static_cast<std::uint64_t>(r.bytes_sent_largest))
        .add("coarsening_rounds", static_cast<std::uint64_t>(r.coarsening_rounds))
        .add("exchanges", static_cast<std::uint64_t>(r.exchanges))
        .add("marked", static_cast<std::uint64_t>(r.marked))
        .add("splits", static_cast<std::uint64_t>(r.splits))
        .add("removals", static_cast<std::uint64_t>(r.removals))
        .add("solver", r.solver)
        .add("solver_iterations", r.solver_iterations)
        .add("mesh_mb", static_cast<double>(r.mesh_bytes) / 1048576.0);
    if (r.resident_bytes > 0) o.add("resident_mb", static_cast<double>(r.resident_bytes) / 1048576.0);
    if (!r.note.empty()) o.add("note", r.note);
    out += (i ? ", " : "") + o.str();
  }
  return out + "]";
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
  std::string problem, marking, estimator, geometry, mesh_name;
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
  s.options.control.memory_headroom = [ceiling = s.ceiling] { return ceiling.headroom(); };
  s.options.control.resident_bytes = [] { return resident_memory_bytes(); };
  s.options.control.release_free_memory = [] { release_free_memory(); };
  s.options.compact_below = a.compact_below;
  s.problem = !a.problem.empty() ? a.problem : (a.mesh.empty() ? "sphere-peak" : "gaussian");
  s.mesh_name = !a.mesh.empty()                 ? a.mesh
                : s.problem == "cube-cosine" ? "unit cube with sharp edges (embedded)"
                                             : "icosahedron (embedded)";
  // What the problem is posed on: the unit sphere (with an exact solution) or the user's mesh
  // (cube-cosine: the unit cube with sharp edges it embeds, exactly the Loop limit surface).
  static const std::vector<Named<bool>> problems = {{"sphere-harmonic", true},
                                                    {"sphere-peak", true},
                                                    {"moving-peak", true},
                                                    {"gaussian", false},
                                                    {"cube-cosine", false}};
  if (s.problem == "cube-cosine") {
    if (a.given.count("--mesh"))
      throw InputError("--mesh: cube-cosine is posed on the unit cube with sharp edges that it embeds");
    if (a.given.count("--geometry") && a.geometry != "loop")
      throw InputError("--geometry " + a.geometry +
                       ": cube-cosine's surface is the cube, which is the Loop limit surface of its creased base");
  }
  s.moving = s.problem == "moving-peak";
  s.on_sphere = named_row(problems, s.problem, "--problem").value;
  s.geometry = !a.geometry.empty() ? a.geometry : (s.on_sphere ? "sphere" : "loop");
  const fem::Projection& projection = named_row(fem::geometry_table(), s.geometry, "--geometry").value;
  adapt::AdaptOptions& o = s.options;
  o.strategy = named_row(adapt::strategy_table(), a.strategy, "--strategy").value;
  s.marking = !a.marking.empty() ? a.marking : (s.moving ? "equidistribution" : "dorfler");
  o.marking = named_row(adapt::marking_table(), s.marking, "--marking").make(a.theta);
  if (a.order != 1 && a.order != 2) throw InputError("--order " + std::to_string(a.order) + ": 1 or 2");
  o.order = a.order;
  if (a.element == "loop") {
    // Loop-basis elements: the hierarchical space of the RGB mesh (Loop's boundary rules and
    // Nitsche's Dirichlet terms on open meshes), on one process.
    o.element = adapt::AdaptOptions::Element::loop;
    o.loop_view_levels = 2;  // cycle_NNN_smooth.vtp, which the series lists
    if (a.processes > 1) throw InputError("--element loop: runs on one process for now");
    if (a.given.count("--estimator") && a.estimator != "residual")
      throw InputError("--estimator " + a.estimator + ": Loop elements have the residual estimator only");
    o.loop_basis = a.loop_basis == "thb" ? fem::LoopBasisKind::truncated_hierarchical : fem::LoopBasisKind::details;
  } else if (a.given.count("--loop-basis")) {
    throw InputError("--loop-basis " + a.loop_basis + ": for --element loop only");
  }
  o.min_level = a.min_level;
  s.estimator = a.estimator;
  o.estimator = named_row(fem::estimator_table(), s.estimator, "--estimator").make();
  o.solve.solver = fem::parse_solver(a.solver);
  // Several processes solve together with CG and BoomerAMG across them: another solver would be
  // ignored without a word.
  if (a.processes > 1 && a.given.count("--solver") && a.solver != "auto" && a.solver != "amg")
    throw InputError("--solver " + a.solver + ": a run on " + std::to_string(a.processes) +
                     " processes solves with amg (CG with BoomerAMG across the processes); give --solver amg or "
                     "auto, or run on one process");

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
  if (projection) o.projection = projection;

  // Options that belong to one problem or strategy only.
  if (!s.moving) refuse(a, {"--steps"}, "to " + s.problem + " (only moving-peak has time steps)");
  if (s.problem != "gaussian") refuse(a, {"--center", "--width"}, "to " + s.problem + " (only to gaussian)");
  if (o.strategy == adapt::Strategy::uniform)
    refuse(a, {"--marking", "--theta", "--coarsen"}, "to --strategy uniform (every triangle is refined)");
  if (o.marking->marks_by_target() && !s.moving) {
    if (!(a.target_error > 0))
      throw InputError("--marking equidistribution: needs --target-error E (it refines every triangle whose "
                       "indicator exceeds E / sqrt(number of triangles))");
    refuse(a, {"--theta"}, "to --marking equidistribution (it marks by --target-error)");
  }

  o.target_estimate = a.target_error;
  o.max_dofs = static_cast<std::size_t>(a.max_dofs);
  // Coarsening by default only where marking keeps a steady size (equidistribution towards a
  // target). Dörfler or fixed-fraction marking marks only the largest indicators, so a quarter of
  // the smallest marked one lies above most of the mesh: coarsening to it took a moving peak's
  // mesh down to 70 triangles and an H1 error of 0.9 within three steps.
  o.coarsen_below =
      a.coarsen >= 0
          ? a.coarsen
          : (s.moving && o.strategy == adapt::Strategy::adaptive && o.marking->marks_by_target() ? 0.25
                                                                                                 : 0.0);
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
    case adapt::StopReason::requested:
      return "the run was asked to stop";
  }
  return "";
}

// ---- --resume ---------------------------------------------------------------------------

std::string cycle_file(bool moving, int cycle) {
  return (moving ? "step_" : "cycle_") + number(cycle, "%03.0f") + ".vtp";
}

// The file of a cycle that the .pvd lists: the cycle's .vtp, or for P2 its quadratic
// triangles (cycle_NNN_p2.vtu), which ParaView draws curved; for Loop elements (order 0 here)
// the refined picture of the smooth solution (cycle_NNN_smooth.vtp).
// On several processes, the summary of the processes' pieces (cycle_NNN.pvtp, cycle_NNN_p2.pvtu).
std::string series_file(bool moving, int cycle, int order, bool pieces = false) {
  const std::string stem = (moving ? "step_" : "cycle_") + number(cycle, "%03.0f");
  if (order == 0) return stem + "_smooth.vtp";
  if (order == 2) return stem + (pieces ? "_p2.pvtu" : "_p2.vtu");
  if (pieces) return stem + ".pvtp";
  return cycle_file(moving, cycle);
}

// A process's piece of a cycle (runs on several processes): cycle_NNN_rK.vtp, or for P2
// cycle_NNN_p2_rK.vtu.
std::string piece_file(bool moving, int cycle, int rank, int order = 1) {
  return (moving ? "step_" : "cycle_") + number(cycle, "%03.0f") + (order == 2 ? "_p2_r" : "_r") + std::to_string(rank) +
         (order == 2 ? ".vtu" : ".vtp");
}

// A run folder read back for --resume: the settings and cycles of its report, the last
// cycle's mesh restored from its file.
struct PriorRun {
  fs::path dir;
  AdaptArgs args;  // the run's settings, as its report gives them
  bool moving = false;
  std::string mesh_name, command, stopped;
  std::vector<std::string> resumed;  // the command lines that resumed it before
  adapt::AdaptRun done;              // its cycles (steps), start cycles and target estimate
  RgbMesh mesh;                      // the mesh of its last cycle
};

[[noreturn]] void damaged(const fs::path& file, const std::string& what) {
  throw InputError(file.string() + ": cannot resume from this run: " + what);
}

const JsonValue& member(const JsonValue& o, const char* key, JsonValue::Kind kind, const fs::path& file) {
  const JsonValue* v = o.find(key);
  if (v == nullptr || v->kind != kind) damaged(file, std::string("'") + key + "' is missing or has the wrong type");
  return *v;
}
double real(const JsonValue& o, const char* key, const fs::path& file) {
  return member(o, key, JsonValue::Kind::number, file).number;
}
std::int64_t count(const JsonValue& o, const char* key, const fs::path& file) {
  const double x = real(o, key, file);
  if (!(x >= 0 && x <= 1e15) || x != std::floor(x)) damaged(file, std::string("'") + key + "' is not a count");
  return static_cast<std::int64_t>(x);
}
std::string text(const JsonValue& o, const char* key, const fs::path& file) {
  return member(o, key, JsonValue::Kind::string, file).string;
}

std::vector<adapt::CycleReport> cycles_from(const JsonValue& list, const fs::path& file) {
  std::vector<adapt::CycleReport> out;
  for (const JsonValue& c : list.array) {
    if (c.kind != JsonValue::Kind::object) damaged(file, "a cycle is not an object");
    adapt::CycleReport r;
    r.cycle = static_cast<int>(count(c, "cycle", file));
    if (c.find("time")) r.time = real(c, "time", file);
    r.triangles = static_cast<std::size_t>(count(c, "triangles", file));
    r.dofs = static_cast<std::size_t>(count(c, "dofs", file));
    r.estimate = real(c, "estimate", file);
    if (c.find("error_l2")) r.error_l2 = real(c, "error_l2", file);
    if (c.find("error_h1")) r.error_h1 = real(c, "error_h1", file);
    r.seconds = real(c, "seconds", file);
    r.solve_seconds = real(c, "solve_seconds", file);
    r.adapt_seconds = real(c, "adapt_seconds", file);
    // Reports written before these fields existed have none.
    for (auto [key, field] : {std::pair{"mesh_seconds", &r.mesh_seconds}, std::pair{"estimate_seconds", &r.estimate_seconds},
                              std::pair{"error_seconds", &r.error_seconds},
                              std::pair{"partition_seconds", &r.partition_seconds},
                              std::pair{"exchange_seconds", &r.exchange_seconds},
                              std::pair{"assembly_seconds", &r.assembly_seconds},
                              std::pair{"output_seconds", &r.output_seconds}})
      if (c.find(key)) *field = real(c, key, file);
    r.marked = static_cast<std::size_t>(count(c, "marked", file));
    r.splits = static_cast<std::size_t>(count(c, "splits", file));
    r.removals = static_cast<std::size_t>(count(c, "removals", file));
    r.solver = text(c, "solver", file);
    // Reports written before the field existed have none.
    if (c.find("solver_iterations")) r.solver_iterations = static_cast<int>(count(c, "solver_iterations", file));
    if (c.find("note")) r.note = text(c, "note", file);
    if (c.find("bytes_sent")) r.bytes_sent = count(c, "bytes_sent", file);
    if (c.find("bytes_sent_largest")) r.bytes_sent_largest = count(c, "bytes_sent_largest", file);
    if (c.find("coarsening_rounds")) r.coarsening_rounds = count(c, "coarsening_rounds", file);
    if (c.find("exchanges")) r.exchanges = count(c, "exchanges", file);
    out.push_back(std::move(r));
  }
  return out;
}

PriorRun read_prior_run(const std::string& folder) {
  PriorRun p;
  p.dir = folder;
  std::error_code ec;
  if (!fs::is_directory(p.dir, ec)) throw InputError("--resume " + folder + ": no such folder");
  const fs::path file = p.dir / "report.json";
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw InputError(file.string() + ": missing: " + folder +
                     " is not the folder of an adapt run (or of one from before runs could be resumed)");
  std::stringstream contents;
  contents << in.rdbuf();
  JsonValue root;
  try {
    root = JsonReader::parse(contents.str());
  } catch (const std::runtime_error& e) {
    damaged(file, std::string("not valid JSON (") + e.what() + ")");
  }
  if (root.kind != JsonValue::Kind::object) damaged(file, "not a JSON object");
  AdaptArgs& a = p.args;
  a.problem = text(root, "problem", file);
  a.strategy = text(root, "strategy", file);
  a.marking = text(root, "marking", file);
  a.estimator = text(root, "estimator", file);
  a.order = root.find("order") ? static_cast<int>(count(root, "order", file)) : 1;  // reports before --order: P1
  a.element = root.find("element") ? text(root, "element", file) : (a.order == 2 ? "p2" : "p1");
  a.loop_basis = root.find("loop_basis") ? text(root, "loop_basis", file) : "details";  // reports before it: details
  if (a.loop_basis != "details" && a.loop_basis != "thb")
    damaged(file, "loop_basis '" + a.loop_basis + "' is neither details nor thb");
  a.solver = text(root, "solver", file);
  a.geometry = text(root, "geometry", file);
  a.theta = real(root, "theta", file);
  a.coarsen = real(root, "coarsen", file);
  a.min_level = root.find("min_level") ? static_cast<int>(count(root, "min_level", file)) : 0;  // reports before it: 0
  a.cycles = static_cast<int>(count(root, "max_cycles", file));
  a.target_error = real(root, "target_error", file);
  a.max_dofs = count(root, "max_dofs", file);
  p.moving = a.problem == "moving-peak";
  if (p.moving) {
    a.steps = static_cast<int>(count(root, "steps", file));
    p.done.target_estimate = real(root, "target_estimate", file);
    p.done.start = cycles_from(member(root, "start_cycles", JsonValue::Kind::array, file), file);
  }
  if (a.problem == "gaussian") {
    for (const JsonValue& x : member(root, "center", JsonValue::Kind::array, file).array) {
      if (x.kind != JsonValue::Kind::number) damaged(file, "'center' is not three numbers");
      a.center.push_back(x.number);
    }
    if (a.center.size() != 3) damaged(file, "'center' is not three numbers");
    a.width = real(root, "width", file);
  }
  p.mesh_name = text(root, "mesh", file);
  p.command = text(root, "command", file);
  if (const JsonValue* r = root.find("resumed"); r != nullptr && r->kind == JsonValue::Kind::array)
    for (const JsonValue& line : r->array) p.resumed.push_back(line.string);
  if (const JsonValue* s = root.find("stopped"); s != nullptr && s->kind == JsonValue::Kind::string) p.stopped = s->string;
  p.done.cycles = cycles_from(member(root, "cycles", JsonValue::Kind::array, file), file);
  if (p.done.cycles.empty())
    throw InputError(folder + ": the run completed no " + (p.moving ? "time step" : "cycle") +
                     ", so there is nothing to resume from (start it again)");
  for (std::size_t i = 0; i < p.done.cycles.size(); ++i) {
    if (p.done.cycles[i].cycle != static_cast<int>(i))
      damaged(file, "its cycle " + std::to_string(i) + " is numbered " + std::to_string(p.done.cycles[i].cycle));
    // (A run with the mesh distributed over processes wrote its cycles as pieces only.)
    const fs::path f = p.dir / cycle_file(p.moving, p.done.cycles[i].cycle);
    const fs::path summary = p.dir / series_file(p.moving, p.done.cycles[i].cycle, 1, true);
    if (!fs::is_regular_file(f, ec) && !fs::is_regular_file(summary, ec))
      throw InputError(f.string() + ": missing (the run's report lists it): cannot resume");
  }
  const adapt::CycleReport& last = p.done.cycles.back();
  fs::path last_file = p.dir / cycle_file(p.moving, last.cycle);
  const bool pieces = !fs::is_regular_file(last_file, ec);
  if (pieces) last_file = p.dir / series_file(p.moving, last.cycle, 1, true);
  RgbMeshFile saved = pieces ? read_rgb_pieces(last_file) : read_rgb_mesh(last_file);
  if (!saved.restored)
    throw InputError(last_file.string() + ": carries no RGB state (written before adapt saved it?): cannot resume from it");
  // The report counts unknowns: the vertices, and the edges too for P2 (the truncated
  // hierarchical Loop basis's are known once its space is built: the triangles are compared).
  const bool thb = p.args.element == "loop" && p.args.loop_basis == "thb";
  const std::size_t unknowns =
      saved.mesh.num_vertices() + (p.args.order == 2 ? saved.mesh.num_edges() : std::size_t{0});
  if ((!thb && unknowns != last.dofs) || saved.mesh.num_triangles() != last.triangles)
    damaged(last_file, "it has " + std::to_string(unknowns) + (p.args.order == 2 ? " P2 unknowns" : " vertices") + " and " +
                           std::to_string(saved.mesh.num_triangles()) + " triangles, the report says " +
                           std::to_string(last.dofs) + " and " + std::to_string(last.triangles));
  p.mesh = std::move(saved.mesh);
  return p;
}

bool same_path(const fs::path& a, const fs::path& b) {
  std::error_code ec1, ec2;
  const fs::path x = fs::weakly_canonical(a, ec1), y = fs::weakly_canonical(b, ec2);
  return !ec1 && !ec2 && x == y;
}

// The settings of a resumed run: the run's own, with what the command line may change
// (--cycles and --max-dofs to extend it, --target-error where it only stops the run, where
// and how the outputs are written). Any other setting given must be the run's; InputError
// otherwise, and when nothing would be left to do.
AdaptArgs resumed_args(const AdaptArgs& given, const PriorRun& p) {
  AdaptArgs r = p.args;
  r.resume = given.resume;
  r.out = p.dir.string();
  r.report = given.report;
  r.compression = given.compression;
  r.memory_limit = given.memory_limit;
  r.command_line = given.command_line;
  // The processes this run has (mpirun), which need not be the resumed run's.
  r.writes = given.writes;
  r.processes = given.processes;
  r.rank = given.rank;
  r.distribute = given.distribute;
  const auto has = [&](const char* option) { return given.given.count(option) > 0; };
  const std::string last_file = (p.dir / cycle_file(p.moving, p.done.cycles.back().cycle)).string();
  for (const char* option : {"--mesh", "--triangulate"})
    if (has(option))
      throw InputError(std::string(option) + ": does not apply with --resume (the mesh is the run's last; for a new run "
                       "from it: adapt --mesh " + last_file + ")");
  if (has("--out") && !same_path(given.out, p.dir))
    throw InputError("--out " + given.out + ": --resume writes into the run's own folder " + p.dir.string());
  const auto conflict = [](const char* option, const std::string& value, const std::string& saved) {
    throw InputError(std::string(option) + " " + value + ": conflicts with the resumed run's " + saved +
                     " (a resumed run keeps its settings; --cycles, --max-dofs and --target-error may change)");
  };
  for (const auto& [option, value, saved] :
       {std::tuple{"--problem", given.problem, r.problem},
        {"--strategy", given.strategy, r.strategy},
        {"--marking", given.marking, r.marking},
        {"--estimator", given.estimator, r.estimator},
        {"--order", std::to_string(given.order), std::to_string(r.order)},
        {"--element", given.element, r.element},
        {"--loop-basis", given.loop_basis, r.loop_basis},
        {"--min-level", std::to_string(given.min_level), std::to_string(r.min_level)},
        {"--solver", given.solver, r.solver},
        {"--geometry", given.geometry, r.geometry}})
    if (has(option) && value != saved) conflict(option, value, saved);
  for (const auto& [option, value, saved] : {std::tuple{"--theta", given.theta, r.theta},
                                             {"--coarsen", given.coarsen, r.coarsen},
                                             {"--width", given.width, r.width},
                                             {"--steps", static_cast<double>(given.steps), static_cast<double>(r.steps)}})
    if (has(option) && value != saved) conflict(option, number(value, "%.10g"), number(saved, "%.10g"));
  if (has("--center") && given.center != r.center) conflict("--center", "", "centre");
  // The target drives the marking of equidistribution and every step of moving-peak.
  const bool target_marks = p.moving || (r.marking == "equidistribution" && r.strategy == "adaptive");
  if (has("--target-error")) {
    if (target_marks && given.target_error != r.target_error)
      conflict("--target-error", number(given.target_error, "%.10g"), number(r.target_error, "%.10g"));
    r.target_error = given.target_error;
  }
  if (has("--cycles")) {
    if (p.moving && given.cycles != r.cycles)
      conflict("--cycles", std::to_string(given.cycles), std::to_string(r.cycles) + " start cycles (done)");
    r.cycles = given.cycles;
  }
  if (has("--max-dofs")) r.max_dofs = given.max_dofs;

  // Something left to do.
  const adapt::CycleReport& last = p.done.cycles.back();
  const std::string stopped = p.dir.string() + ": nothing to resume: ";
  if (p.moving && last.cycle >= r.steps)
    throw InputError(stopped + "all " + std::to_string(r.steps) +
                     " time steps are done (a moving-peak run cannot be extended: its steps divide one quarter turn)");
  if (!p.moving && last.cycle + 1 >= r.cycles)
    throw InputError(stopped + "the run has done " + std::to_string(last.cycle + 1) + " cycles of --cycles " +
                     std::to_string(r.cycles) + " (give a larger --cycles to extend it)");
  if (!p.moving && r.target_error > 0 && last.estimate <= r.target_error)
    throw InputError(stopped + "its estimate " + number(last.estimate, "%.4g") + " reached --target-error " +
                     number(r.target_error, "%.4g") + " (give a smaller one to extend it)");
  if (p.stopped == "max-dofs" && !(r.max_dofs > p.args.max_dofs))
    throw InputError(stopped + "the run stopped at --max-dofs " + std::to_string(p.args.max_dofs) +
                     " (give a larger --max-dofs to extend it)");
  return r;
}

// The base mesh of an RGB mesh, for the checks that a new run makes on its input.
TriangleMeshData base_of(const RgbMesh& mesh) {
  TriangleMeshData base;
  for (std::size_t b = 0; b < mesh.num_base_vertices(); ++b)
    base.points.push_back(mesh.insertion_point(VertexHandle(static_cast<std::int32_t>(b))));
  base.triangles = mesh.base_triangles();
  base.sharp = mesh.sharp_features();
  return base;
}

// The mesh of a new run's first solve, counted before anything is built or solved: the
// starting mesh refined to the --min-level floor (as run_cycles does first), and its unknowns
// for the order (P1 its vertices, P2 its vertices and edges).
struct FirstMesh {
  double vertices = 0, edges = 0;
  bool at_least = false;  // a lower bound (it already passes --max-dofs, so no need to build it)
  double unknowns(int order) const { return order == 2 ? vertices + edges : vertices; }
};

std::string count_text(double n) { return number(n, n < 1e15 ? "%.0f" : "%.3g"); }

FirstMesh first_mesh(const RgbMesh& mesh, int min_level, int order, double max_dofs) {
  int lowest = kMaxLevel, highest = 0;
  for (const TriangleHandle t : mesh.triangles()) {
    lowest = std::min(lowest, mesh.level(t));
    highest = std::max(highest, mesh.level(t));
  }
  if (lowest >= min_level) return {static_cast<double>(mesh.num_vertices()), static_cast<double>(mesh.num_edges())};
  // The floor holds the base mesh's uniform level min_level (each of its triangles lies inside
  // one of that level's), so that level's counts bound it from below, and are its counts when
  // the mesh is uniform (a base mesh): Loop's invariants, each level splitting every edge
  // (V + E vertices) into two and adding three edges per triangle. In floating point: a floor
  // of level 30 has more than 2^64 triangles.
  FirstMesh lower;
  std::set<std::pair<std::int32_t, std::int32_t>> edges;
  for (const auto& t : mesh.base_triangles())
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
  lower.vertices = static_cast<double>(mesh.num_base_vertices());
  lower.edges = static_cast<double>(edges.size());
  double triangles = static_cast<double>(mesh.base_triangles().size());
  for (int level = 0; level < min_level; ++level) {
    lower.vertices += lower.edges;
    lower.edges = 2 * lower.edges + 3 * triangles;
    triangles *= 4;
  }
  if (lowest == highest) return lower;
  lower.at_least = true;
  if (lower.unknowns(order) > max_dofs) return lower;
  // Within the limit: the exact count needs the floor itself (of a mesh refined in places, a
  // saved cycle's); at most about max_dofs unknowns more than the mesh has.
  RgbMesh floor = mesh;
  selective_refinement(floor, AtLeastLevel(min_level));
  return {static_cast<double>(floor.num_vertices()), static_cast<double>(floor.num_edges())};
}

// A new run whose first mesh already has more unknowns than --max-dofs would solve it anyway
// (the limit stops refinement, after a solve): an InputError before anything is solved or
// written.
void refuse_first_mesh_above_max_dofs(const RgbMesh& mesh, const AdaptArgs& a) {
  const double max_dofs = static_cast<double>(a.max_dofs);
  const FirstMesh first = first_mesh(mesh, a.min_level, a.order, max_dofs);
  if (first.unknowns(a.order) <= max_dofs) return;
  throw InputError(
      "--max-dofs " + std::to_string(a.max_dofs) + ": the starting mesh" +
      (a.min_level > 0 ? " refined to --min-level " + std::to_string(a.min_level) : std::string()) +
      (first.at_least ? " has at least " : " has ") + count_text(first.unknowns(a.order)) + " unknowns for " +
      (a.element == "loop" ? std::string("--element loop") : "--order " + std::to_string(a.order)) +
      (a.order == 2
           ? " (" + count_text(first.vertices) + " vertices and " + count_text(first.edges) + " edges)"
           : " (its vertices)") +
      "; nothing was solved");
}

bool is_vtk_xml(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".vtp" || ext == ".vtu";
}

}  // namespace

// An adapt run's files in its folder: each cycle's mesh (whole, or this process's piece and the
// summary joining them), the .pvd series and the report, written after every cycle so that
// ParaView and --resume can use them while the run goes on; and the row printed per cycle.
class RunFiles {
 public:
  // A resumed run goes on with its folder's series and report.
  RunFiles(const AdaptArgs& a, const Settings& s, const PriorRun* prior)
      : a_(a), s_(s), prior_(prior), dir_(a.out) {
    if (!prior) return;
    progress_ = prior->done;
    for (const auto& r : progress_.cycles) {
      // The earlier run's pieces' summary where it was run on several processes.
      const std::string summary = series_file(s.moving, r.cycle, a.order, true);
      const bool in_pieces = fs::exists(dir_ / summary);
      series_.emplace_back(s.moving ? r.time : r.cycle,
                           in_pieces ? summary : series_file(s.moving, r.cycle, listed_order()));
    }
    for (const auto& r : progress_.cycles) {
      const fs::path creases = sharp_edges_path(cycle_file(s.moving, r.cycle));
      if (fs::exists(dir_ / creases)) crease_series_.emplace_back(s.moving ? r.time : r.cycle, creases.string());
    }
    resumed_ = prior->resumed;
    resumed_.push_back(a.command_line);
  }

  const fs::path& dir() const { return dir_; }
  // Which of a cycle's files the series lists (series_file's order; 0: the Loop picture).
  int listed_order() const { return a_.element == "loop" ? 0 : a_.order; }
  std::size_t files() const { return series_.size(); }
  // What has been computed so far, for the report.
  adapt::AdaptRun& progress() { return progress_; }

  void write_cycle(const adapt::CycleState& c) {
    const auto t_output = std::chrono::steady_clock::now();
    const auto& r = c.report;
    const std::string file = cycle_file(s_.moving, r.cycle);
    const bool pieces = a_.processes > 1 && c.solved && !c.solved->triangle_part.empty();
    const MeshSnapshot snapshot = adapt::snapshot(c);
    // The whole mesh with its RGB state (what --resume reads), by rank 0; on several
    // processes also each process's piece and the summary that joins them for ParaView.
    // (A distributed mesh: no process has the whole, only pieces are written.)
    if (a_.writes && !s_.options.distribution.distributed_mesh)
      write_mesh(dir_ / file, snapshot, output_options((dir_ / file).string(), a_.compression));
    // (P2 too: its pieces' states are what --resume reads.)
    if (pieces && (a_.order == 1 || s_.options.distribution.distributed_mesh)) {
      const std::string mine = piece_file(s_.moving, r.cycle, a_.rank);
      MeshSnapshot piece = snapshot_piece(snapshot, c.solved->triangle_part, a_.rank);
      piece.piece_state = c.solved->piece_state;
      write_mesh(dir_ / mine, piece, output_options((dir_ / mine).string(), a_.compression));
      if (a_.writes) {
        std::vector<std::string> all;
        for (int q = 0; q < a_.processes; ++q) all.push_back(piece_file(s_.moving, r.cycle, q));
        write_pvtp(dir_ / series_file(s_.moving, r.cycle, 1, true), snapshot, all);
      }
    }
    if (a_.order == 2 && pieces) {
      // P2 on several processes: each process its piece, rank 0 the summary.
      const adapt::QuadraticSnapshot q = adapt::quadratic_snapshot(c);
      const adapt::QuadraticSnapshot piece = adapt::quadratic_piece(q, c.solved->triangle_part, a_.rank);
      const std::string mine = piece_file(s_.moving, r.cycle, a_.rank, 2);
      write_quadratic_triangles(dir_ / mine, piece.points, piece.cells, piece.point_data, piece.cell_data,
                                output_options((dir_ / mine).string(), a_.compression));
      if (a_.writes) {
        std::vector<std::string> all;
        for (int k = 0; k < a_.processes; ++k) all.push_back(piece_file(s_.moving, r.cycle, k, 2));
        write_quadratic_pvtu(dir_ / series_file(s_.moving, r.cycle, 2, true), q.point_data, q.cell_data, all);
      }
    } else if (a_.order == 2 && a_.writes) {
      const std::string p2 = series_file(s_.moving, r.cycle, 2);
      const adapt::QuadraticSnapshot q = adapt::quadratic_snapshot(c);
      write_quadratic_triangles(dir_ / p2, q.points, q.cells, q.point_data, q.cell_data,
                                output_options((dir_ / p2).string(), a_.compression));
    }
    if (c.loop_view && a_.writes) {
      const std::string smooth = series_file(s_.moving, r.cycle, 0);
      write_mesh(dir_ / smooth, *c.loop_view, output_options((dir_ / smooth).string(), a_.compression));
    }
    series_.emplace_back(s_.moving ? r.time : r.cycle,
                         series_file(s_.moving, r.cycle, listed_order(), pieces));
    // The sharp edges as lines, part 1 of the cycle in the series (ParaView draws both).
    const fs::path creases = sharp_edges_path(dir_ / file);
    // (A distributed mesh has no whole snapshot on any process: its pieces carry vertex_rule.)
    if (a_.writes && !s_.options.distribution.distributed_mesh &&
        write_sharp_edges(creases, snapshot, output_options(creases.string(), a_.compression)))
      crease_series_.emplace_back(s_.moving ? r.time : r.cycle, creases.filename().string());
    if (a_.writes) write_series();  // after every cycle: usable while running
    progress_.cycles.push_back(r);
    progress_.cycles.back().output_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_output).count();
    write_report(report_json("running", "", ""));
    std::cout << number(r.cycle, "%5.0f") << (s_.moving ? number(r.time, "%7.3f") : "")
              << number(static_cast<double>(r.triangles), "%11.0f")
              << number(static_cast<double>(r.dofs), "%10.0f") << number(r.estimate, "%12.4e")
              << (r.error_l2 ? number(*r.error_l2, "%12.4e") : std::string(12, ' '))
              << (r.error_h1 ? number(*r.error_h1, "%12.4e") : std::string(12, ' '))
              << number(r.seconds, "%9.3f") << std::endl;
    // A cycle's note once per run (the next cycles usually repeat it), on rank 0.
    if (!r.note.empty() && !noted_ && a_.writes) {
      std::cerr << "rgbmesh: note: cycle " << r.cycle << ": " << one_line(r.note) << "\n";
      noted_ = true;
    }
  }

  void finished(const adapt::AdaptRun& run, const std::string& message) {
    progress_ = run;
    write_report(report_json("finished", adapt::to_string(run.stopped), message));
  }

  // A failure while the run works (a full disk, the memory) would leave the last report saying
  // "running": it says "failed" and why, where the report can still be written (a failed large
  // write has removed its temporary).
  void failed(const std::string& why) noexcept {
    try {
      write_report(report_json("failed", "error", why));
    } catch (const std::exception&) {
    }
  }

 private:
  std::string report_json(const char* status, const std::string& stopped, const std::string& message) const {
    JsonObject j;
    j.add("version", RGBMESH_VERSION)
        .add("command", prior_ ? prior_->command : a_.command_line)
        .add("status", status);
    if (!resumed_.empty()) {
      std::string lines;
      for (const auto& line : resumed_) lines += (lines.empty() ? "" : ", ") + JsonObject::quote(line);
      j.raw("resumed", "[" + lines + "]");
    }
    j.raw("stopped", stopped.empty() ? "null" : JsonObject::quote(stopped));
    j.add("stop_message", message);
    j.add("mesh", s_.mesh_name)
        .add("problem", s_.problem)
        .add("strategy", a_.strategy)
        .add("marking", s_.marking);
    j.raw("theta", exact(a_.theta))
        .add("estimator", s_.estimator)
        .add("order", a_.order)
        .add("element", a_.element)
        .add("loop_basis", a_.loop_basis)
        .add("solver", a_.solver)
        .add("geometry", s_.geometry);
    j.raw("coarsen", exact(s_.options.coarsen_below))
        .add("min_level", a_.min_level)
        .add("max_cycles", s_.options.max_cycles);
    j.raw("target_error", exact(a_.target_error)).add("max_dofs", static_cast<std::int64_t>(a_.max_dofs));
    if (s_.moving) j.add("steps", s_.dynamic.steps).add("cycles_per_step", s_.dynamic.cycles_per_step);
    if (s_.problem == "gaussian") {
      j.raw("center", "[" + number(s_.center.x, "%.17g") + ", " + number(s_.center.y, "%.17g") + ", " +
                          number(s_.center.z, "%.17g") + "]");
      j.raw("width", exact(s_.width));
    }
    if (s_.moving) {
      j.raw("target_estimate", exact(progress_.target_estimate));
      j.raw("start_cycles", cycles_json(progress_.start, false));
    }
    j.raw("cycles", cycles_json(progress_.cycles, s_.moving));
    return j.str() + "\n";
  }

  // The report goes into the run's folder (what --resume reads), and to --report FILE.
  void write_report(const std::string& json) const {
    if (!a_.writes) return;
    const fs::path run_report = dir_ / "report.json";
    write_text_atomically(run_report, json);
    if (!a_.report.empty() && !same_path(a_.report, run_report)) write_text_atomically(a_.report, json);
  }

  const AdaptArgs& a_;
  const Settings& s_;
  const PriorRun* prior_;
  fs::path dir_;
  std::vector<std::pair<double, std::string>> series_;
  std::vector<std::pair<double, std::string>> crease_series_;  // sharp edges, where the mesh has them

  void write_series() const {
    std::vector<PvdEntry> entries;
    for (const auto& [time, file] : series_) entries.push_back({time, 0, file});
    for (const auto& [time, file] : crease_series_) entries.push_back({time, 1, file});
    write_pvd(dir_ / "solution.pvd", entries);
  }
  adapt::AdaptRun progress_;
  bool noted_ = false;  // a cycle's note was printed
  std::vector<std::string> resumed_;
};

int run_adapt(const AdaptArgs& args) {
  // One run per folder (run_lock.hpp). A resumed run's folder is locked before its report is
  // read (a run still writing it is refused); a missing one is read_prior_run's to refuse.
  std::optional<RunLock> lock;
  std::error_code ec;
  if (args.writes && !args.resume.empty() && fs::is_directory(args.resume, ec)) lock.emplace(args.resume);
  // Resuming: the run folder's settings and last mesh.
  std::optional<PriorRun> prior;
  if (!args.resume.empty()) prior = read_prior_run(args.resume);
  const AdaptArgs a = prior ? resumed_args(args, *prior) : args;
  // Mesh, then every setting checked before anything is written. A .vtp or .vtu that rgbmesh
  // wrote (a cycle of an earlier run, a refined mesh) comes back with its RGB state.
  SoupOptions read_options = repair::soup_options(a.triangulate, a.repair);
  read_options.sharp_angle = a.sharp_angle;
  TriangleMeshData base;
  RgbMesh mesh;
  if (prior) {
    mesh = std::move(prior->mesh);
    base = base_of(mesh);
  } else if (is_vtk_xml(a.mesh)) {
    RgbMeshFile file = read_rgb_mesh(a.mesh, read_options);
    for (const auto& note : file.notes) std::cerr << "rgbmesh: note: " << one_line(a.mesh + ": " + note) << "\n";
    mesh = std::move(file.mesh);
    base = base_of(mesh);
  } else {
    base = !a.mesh.empty()                ? read_mesh(a.mesh, read_options)
           : a.problem == "cube-cosine" ? sharp_unit_cube()
                                        : icosahedron();
    for (const auto& note : base.notes) std::cerr << "rgbmesh: note: " << one_line(a.mesh + ": " + note) << "\n";
  }
  Settings s = settle(a, base);
  if (prior) {
    s.mesh_name = prior->mesh_name;
  } else if (!is_vtk_xml(a.mesh)) {
    mesh = [&] {
      try {
        return RgbMesh::from_triangles(base.points, base.triangles, base.sharp);
      } catch (const InputError& e) {
        throw InputError(a.mesh + ": " + e.what());
      }
    }();
    if (!a.mesh.empty()) note_rounded_edges(a.mesh, mesh, a.sharp_angle);
    if (a.mesh.empty()) selective_refinement(mesh, UniformLevel(1));  // 42 vertices to start from (the cube: 26)
  }
  s.options.control.resumable = true;  // every cycle's file can be resumed from, exactly
  // Several processes: they share the units above the floor and hold the mesh itself
  // distributed (each process its part: its cycles are written as pieces only, each with its
  // piece's state, which --resume joins).
  if (a.distribute) a.distribute(s.options, true);
  if (prior) {
    const int next = prior->done.cycles.back().cycle + 1;
    if (s.moving) {
      s.dynamic.first_step = next;
      s.options.target_estimate = prior->done.target_estimate;
    } else {
      s.options.control.first_cycle = next;
    }
  }
  if (!prior) refuse_first_mesh_above_max_dofs(mesh, a);
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
  // A resumed run keeps its folder, series and report, and goes on with them.
  const fs::path dir(a.out);
  if (!prior && a.writes) {
    // A new run's folder is locked once every setting is checked (a refused run creates no
    // folder), before the previous run's files are removed.
    create_output_directory(dir);
    lock.emplace(dir);
    prepare_output_directory(dir);
  }
  RunFiles files(a, s, prior ? &*prior : nullptr);
  if (prior)
    std::cout << "rgbmesh adapt: resuming " << dir.string() << " after " << (s.moving ? "step " : "cycle ")
              << prior->done.cycles.back().cycle << "\n";
  std::cout << "rgbmesh adapt: problem " << s.problem << ", " << a.strategy
            << (s.options.strategy == adapt::Strategy::adaptive ? " (" + s.marking + ")" : std::string())
            << ", geometry " << s.geometry
            << (a.element == "loop" ? (a.loop_basis == "thb" ? ", Loop elements (truncated hierarchical basis)"
                                                             : ", Loop elements")
                : a.order == 2      ? ", P2 elements"
                                    : "")
            << ", mesh " << s.mesh_name
            << (a.processes > 1 ? ", on " + std::to_string(a.processes) + " processes" : std::string())
            << "\n"
            << (s.moving ? " step   time" : "cycle")
            << "  triangles      dofs    estimate    error_L2    error_H1  seconds\n";
  const auto on_cycle = [&files](const adapt::CycleState& c) {
    files.write_cycle(c);
    release_free_memory();  // (a cycle's structures are gone; the next may be smaller)
  };
  adapt::AdaptRun run;
  std::string message;
  try {
    if (s.moving) {
      s.dynamic.on_started = [&](const std::vector<adapt::CycleReport>& start, double target) {
        files.progress().start = start;
        files.progress().target_estimate = target;
        std::cout << "  (adapted to the start in " << start.size() << " cycles: " << start.back().dofs
                  << " unknowns, estimate " << number(start.back().estimate, "%.4e");
        if (s.options.marking->marks_by_target())
          std::cout << "; every step adapts " << s.dynamic.cycles_per_step
                    << " times toward each triangle's indicator below " << number(target, "%.4e")
                    << " / sqrt(triangles)";
        std::cout << ")\n";
      };
      run = adapt::run_dynamic(
          mesh, [](double t) { return adapt::moving_peak(t); }, s.options, s.dynamic, on_cycle);
    } else {
      run = adapt::run_cycles(mesh, problem, s.options, on_cycle);
    }
    if (prior) {  // the report lists every cycle of the run
      run.cycles.insert(run.cycles.begin(), prior->done.cycles.begin(), prior->done.cycles.end());
      run.start = prior->done.start;
      run.target_estimate = prior->done.target_estimate;
    }
    // (The times of writing each cycle are the tool's own: measured above.)
    for (std::size_t i = 0; i < run.cycles.size() && i < files.progress().cycles.size(); ++i)
      run.cycles[i].output_seconds = files.progress().cycles[i].output_seconds;
    message = stop_message(run.stopped, s, a, run);
    files.finished(run, message);
  } catch (const std::bad_alloc&) {
    files.failed("out of memory");
    throw;
  } catch (const std::exception& e) {
    files.failed(e.what());
    throw;
  }
  if (a.processes > 1) {
    double sent = 0;
    for (const auto& r : run.cycles) sent += static_cast<double>(r.bytes_sent);
    std::cout << "processes: " << a.processes << ", " << number(sent / 1e6, "%.1f")
              << " MB sent between them in all (bytes_sent in the report, per cycle)\n";
  }
  if (s.moving && s.options.marking->marks_by_target() && run.target_estimate > 0) {
    // The marking's rule bounds every triangle's indicator, so a step whose estimate is above
    // the target did not reach it: the peak moved farther than the step's adaptations followed.
    std::size_t above = 0, worst = 0;
    for (std::size_t i = 0; i < run.cycles.size(); ++i)
      if (run.cycles[i].estimate > run.target_estimate) {
        if (above == 0 || run.cycles[i].estimate > run.cycles[worst].estimate) worst = i;
        ++above;
      }
    if (above > 0)  // (one write: under mpirun, pieces of a line interleave with stdout's)
      std::cerr << "rgbmesh: note: " + std::to_string(above) + " of " + std::to_string(run.cycles.size()) +
                       " steps ended with an estimate above the target " + number(run.target_estimate, "%.4e") +
                       " (the largest " + number(run.cycles[worst].estimate, "%.4e") + ", step " +
                       std::to_string(worst) + "): the peak moved farther than a step's " +
                       std::to_string(s.dynamic.cycles_per_step) +
                       " adaptations follow; more --steps make each move shorter\n";
  }
  std::cout << "stopped: " << message << "\n"
            << "wrote " << files.files() << " files and " << (files.dir() / "solution.pvd").string()
            << (a.element == "loop"
                    ? " (open the .pvd in ParaView: the smooth solution, 16 pieces per integration cell; color by "
                      "'solution'. "
                      "The cycle_NNN.vtp files hold 'error_indicator' and 'level')\n"
                    : " (open the .pvd in ParaView: color by 'solution', 'error_indicator' or 'level')\n");
  if (run.stopped == adapt::StopReason::memory) throw ResourceError("adapt: " + message);
  return 0;
}

void AdaptCommand::add(CLI::App& tool, CompressionOption& compression) {
  app = tool.add_subcommand(
      "adapt",
      "Error-driven adaptive finite elements: solve, estimate, mark, refine and coarsen, repeat.\n"
      "Writes one .vtp per cycle (or time step) and a .pvd series for ParaView into --out.\n"
      "Under mpirun -np P the processes share each cycle's work (the same results; each writes its\n"
      "piece, joined by a .pvtp or .pvtu summary) and the mesh itself (each process holds its part;\n"
      "--resume joins the pieces); --min-level K sets the floor whose units they share.");
  // (Empty is refused: an unset shell variable would silently give the icosahedron.)
  app->add_option("--mesh", args.mesh, "Base mesh (default: an embedded icosahedron)")->check(kNonEmptyPath);
  app->add_flag("--triangulate", args.triangulate,
                "Split the mesh's polygons into triangles (fans for planar convex ones, ears for the others)");
  app->add_flag("--repair", args.repair, kRepairHelp);
  add_sharp_angle(app, args.sharp_angle);
  app->add_option(
      "--problem", args.problem,
      "sphere-harmonic, sphere-peak, moving-peak (exact solutions on the unit sphere), cube-cosine (an exact "
      "solution on the unit cube with sharp edges) or gaussian "
      "(a source on any surface) [default: sphere-peak; gaussian with --mesh]");
  app->add_option("--strategy", args.strategy, "adaptive or uniform")->capture_default_str();
  app->add_option(
      "--marking", args.marking,
      choices_help(adapt::marking_table()) +
          " (equidistribution needs --target-error) [default: dorfler; equidistribution for moving-peak]");
  app->add_option("--theta", args.theta, "Marking parameter of dorfler and fraction, in (0, 1]")
      ->capture_default_str()
      ->check(number_in("a number in (0, 1]", [](double x) { return x > 0 && x <= 1; }));
  app->add_option("--estimator", args.estimator, choices_help(fem::estimator_table()))->capture_default_str();
  app->add_option("--order", args.order,
                  "finite elements: 1 (linear) or 2 (quadratic, isoparametric on the surface)")
      ->capture_default_str();
  app->add_option(
         "--element", args.element,
         "finite elements: p1, p2 (as --order 1, 2) or loop (Loop-basis: smooth, one unknown per vertex, on "
         "the Loop limit surface, whose boundary rounds off corners of open meshes; Dirichlet data imposed "
         "weakly; one process)")
      ->check(CLI::IsMember({"p1", "p2", "loop"}));
  app->add_option("--loop-basis", args.loop_basis,
                  "with --element loop: details (one unknown per vertex, a coarse function whole under finer "
                  "levels) or thb (truncated hierarchical: functions as narrow as their level, matrix rows as the "
                  "uniform space's; unknowns where the mesh holds a function's two-ring)")
      ->capture_default_str()
      ->check(CLI::IsMember({"details", "thb"}));
  app->add_option(
         "--coarsen", args.coarsen,
         "Remove vertices whose largest indicator over their star is below this times the refinement "
         "threshold, in [0, 1) [default: 0.25 for moving-peak with equidistribution marking, else 0]")
      ->check(number_in("a number in [0, 1)", [](double x) { return x >= 0 && x < 1; }));
  app->add_option("--compact-below", args.compact_below,
                  "Give memory back after coarsening: a cycle renumbers the mesh's elements without the slots "
                  "of removed ones when fewer than this share of its vertex slots are live (results are the "
                  "same; 0: never)")
      ->capture_default_str()
      ->check(number_in("a number in [0, 1]", [](double x) { return x >= 0 && x <= 1; }));
  app->add_option("--min-level", args.min_level,
                  "A floor: the mesh is refined to this level first and never coarsened below it")
      ->capture_default_str()
      ->check(number_in("an integer in [0, " + std::to_string(kMaxLevel) + "]",
                        [](double x) { return x >= 0 && x <= kMaxLevel; }));
  app->add_option(
         "--cycles", args.cycles,
         "Maximum number of cycles; for moving-peak, the cycles adapting to the start [default: 20; 8]")
      ->check(number_in("an integer in [1, 1000000]", [](double x) { return x >= 1 && x <= 1e6; }));
  app->add_option("--steps", args.steps, "Time steps of moving-peak")
      ->capture_default_str()
      ->check(number_in("an integer in [1, 1000000]", [](double x) { return x >= 1 && x <= 1e6; }));
  app->add_option(
         "--target-error", args.target_error,
         "Stop once the estimate is at most this; for moving-peak and equidistribution, the error every "
         "step is kept at [moving-peak: the estimate reached at the start]")
      ->check(number_in("a finite number >= 0", [](double x) { return x >= 0 && std::isfinite(x); }));
  app->add_option("--max-dofs", args.max_dofs, "Never solve on a mesh with more unknowns")
      ->capture_default_str()
      ->check(number_in("an integer in [1, 2^40]", [](double x) { return x >= 1 && x <= 1099511627776.0; }));
  app->add_option("--geometry", args.geometry,
                  "loop (vertices on the Loop limit surface) or sphere (projected onto the unit sphere) "
                  "[default: sphere for the sphere problems, else loop]");
  app->add_option("--center", args.center, "gaussian: the source's centre [default: the first vertex]")
      ->delimiter(',')
      ->type_name("X,Y,Z")
      ->expected(3);
  app->add_option("--width", args.width, "gaussian: the source's width sigma [default: diagonal / 20]")
      ->check(number_in("a finite number > 0", [](double x) { return x > 0 && std::isfinite(x); }));
  app->add_option(
         "--solver", args.solver,
         "auto, ldlt, cg, cholmod or amg (CG with algebraic multigrid: hypre BoomerAMG through PETSc)")
      ->capture_default_str();
  out = app->add_option("--out", args.out, "Output directory")->capture_default_str()->check(kNonEmptyPath);
  compression.add_to(*app);
  app->add_option("--report", args.report,
                  "Also write the JSON report (settings, cycles, why the run stopped; always written as "
                  "DIR/report.json) to this file, after every cycle")
      ->check(kNonEmptyPath);
  app->add_option("--resume", args.resume,
                  "Continue the run in this folder from its last cycle, with its settings (--cycles and "
                  "--max-dofs may extend it)")
      ->type_name("DIR")
      ->check(kNonEmptyPath);
}

void AdaptCommand::settle_given() {
  for (const char* name :
       {"--mesh",     "--problem", "--strategy",  "--marking", "--theta", "--estimator",    "--order",
        "--element",  "--loop-basis", "--coarsen", "--min-level", "--cycles",  "--steps", "--target-error", "--max-dofs",
        "--geometry", "--center",  "--width",     "--solver",  "--out",   "--triangulate",  "--repair",
        "--sharp-angle"}) {
    if (app->count(name) > 0) args.given.insert(name);
  }
  if (app->parsed() && !args.resume.empty() && args.repair)
    throw InputError(
        "--repair: does not apply with --resume (the mesh is the run's last cycle, restored exactly)");
  if (app->parsed() && !args.resume.empty() && args.sharp_angle > 0)
    throw InputError(
        "--sharp-angle: does not apply with --resume (the mesh is the run's last cycle, with its own sharp "
        "features, restored exactly)");
  // --element p1 or p2 is --order 1 or 2 (loop has one unknown per vertex, as order 1); given
  // both, they must agree.
  if (!args.element.empty()) {
    const int order = args.element == "p2" ? 2 : 1;
    if (args.given.count("--order") && args.order != order)
      throw InputError("--order " + std::to_string(args.order) + ": disagrees with --element " +
                       args.element + " (give one)");
    args.order = order;
  } else if (args.resume.empty()) {
    args.element = args.order == 2 ? "p2" : "p1";
  }
}

}  // namespace rgbmesh::cli
