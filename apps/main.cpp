// rgbmesh: the command-line tool.
//
//   rgbmesh                      the main job on an embedded default problem
//   rgbmesh info MESH            statistics of a mesh
//   rgbmesh convert IN OUT       format conversion (through the RGB mesh checks)
//   rgbmesh refine IN OUT ...    selective refinement stages, in the order given
//
// Exit codes: 0 success, 1 an output could not be written, 2 bad input or arguments, 3 out of
// resources (memory) or an internal failure (rgbmesh/errors.hpp).

#include <sys/resource.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "adapt_command.hpp"
#include "fit_command.hpp"
#include "json.hpp"
#include "one_line.hpp"
#include "processes.hpp"
#include "resources.hpp"
#include "rgbmesh/fit/base.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/repair/repair.hpp"
#include "rgbmesh/soup.hpp"
#include "rgbmesh/statistics.hpp"
#include "rgbmesh/timing.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "stages.hpp"
#include "write_progress.hpp"

namespace fs = std::filesystem;
using namespace rgbmesh;
using namespace rgbmesh::cli;

namespace {

using rgbmesh::seconds_since;

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// A .vtp or .vtu that rgbmesh wrote comes back with its RGB state (levels, colours, parents),
// so that info reports it and refine continues from it; any other file is a base mesh, repaired
// first when asked.
RgbMesh load_mesh(const std::string& path, bool triangulate, bool repair) {
  RgbMeshFile file = read_rgb_mesh(path, repair::soup_options(triangulate, repair));
  for (const auto& note : file.notes) std::cerr << "rgbmesh: note: " << one_line(path + ": " + note) << "\n";
  return std::move(file.mesh);
}

// Rejects an output path before any work is done: unknown format or missing directory.
void check_output_path(const std::string& out) {
  if (out == "-") return;
  std::string ext = fs::path(out).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  static const char* const known[] = {".obj", ".ply", ".off", ".stl", ".vtp", ".vtu"};
  if (std::find(std::begin(known), std::end(known), ext) == std::end(known))
    throw InputError(out + ": unknown output format '" + ext +
                     "' (supported: " + supported_output_extensions() + ")");
  const fs::path dir = fs::path(out).parent_path();
  if (!dir.empty() && !fs::is_directory(dir))
    throw OutputError(out + ": cannot write: the folder " + dir.string() + " does not exist");
}

// A CLI11 check that a path option names something: an empty value (an unset shell variable,
// `--resume "$RUN"`) would otherwise be taken as "not given" and, for --resume, start a new run
// over the folder's previous one.
const CLI::Validator kNonEmptyPath(
    [](std::string& value) -> std::string {
      return value.empty() ? "must name a file or folder, got an empty string (an unset shell variable?)" : "";
    },
    "");

// A CLI11 check that the option's value is a number accepted by `ok`; the message names what
// is expected and what was given ("--theta: must be a number in (0, 1], got 0").
CLI::Validator number_in(const std::string& what, bool (*ok)(double)) {
  return CLI::Validator(
      [what, ok](std::string& value) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(value.c_str(), &end);
        if (value.empty() || end != value.c_str() + value.size() || !ok(x))
          return "must be " + what + ", got '" + value + "'";
        return "";
      },
      what);
}

// The names of a library's table (marking_table, estimator_table) for an option's help.
template <class Row>
std::string choices_help(const std::vector<Row>& table) {
  std::string help;
  for (std::size_t i = 0; i < table.size(); ++i)
    help += (i == 0                  ? ""
             : i + 1 == table.size() ? " or "
                                     : ", ") +
            std::string(table[i].name) + " (" + table[i].description + ")";
  return help;
}

std::string vec_json(const Vec3& p) {
  std::ostringstream o;
  o.precision(17);
  o << "[" << p.x << ", " << p.y << ", " << p.z << "]";
  return o.str();
}

void print_statistics(const std::string& name, const RgbMesh& mesh, bool json) {
  const MeshStatistics s = compute_statistics(mesh);
  if (json) {
    auto histogram = [](const std::map<int, std::size_t>& h) {
      JsonObject o;
      for (const auto& [k, n] : h) o.add(std::to_string(k), static_cast<std::uint64_t>(n));
      return o.str();
    };
    JsonObject levels;
    for (const auto& [l, c] : s.triangles_per_level) {
      levels.raw(std::to_string(l), JsonObject()
                                        .add("green", static_cast<std::uint64_t>(c[0]))
                                        .add("red", static_cast<std::uint64_t>(c[1]))
                                        .add("blue", static_cast<std::uint64_t>(c[2]))
                                        .str());
    }
    std::cout << JsonObject()
                     .add("mesh", name)
                     .add("vertices", static_cast<std::uint64_t>(s.vertices))
                     .add("edges", static_cast<std::uint64_t>(s.edges))
                     .add("triangles", static_cast<std::uint64_t>(s.triangles))
                     .add("components", s.components)
                     .add("boundary_loops", s.boundary_loops)
                     .add("euler_characteristic", static_cast<std::int64_t>(s.euler_characteristic))
                     .add("genus", s.genus)
                     .add("max_level", s.max_level)
                     .add("red_edges", static_cast<std::uint64_t>(s.red_edges))
                     .add("shortest_edge", s.shortest_edge)
                     .raw("bbox_min", vec_json(s.bbox_min))
                     .raw("bbox_max", vec_json(s.bbox_max))
                     .add("bbox_diagonal", s.bbox_diagonal)
                     .add("longest_edge", s.longest_edge)
                     .raw("valence_histogram", histogram(s.valence_histogram))
                     .raw("vertices_per_level", histogram(s.vertices_per_level))
                     .raw("triangles_per_level", levels.str())
                     .str()
              << "\n";
    return;
  }
  std::cout << "mesh:                 " << name << "\n"
            << "vertices:             " << s.vertices << "\n"
            << "edges:                " << s.edges << "\n"
            << "triangles:            " << s.triangles << "\n"
            << "components:           " << s.components << "\n"
            << "boundary loops:       " << s.boundary_loops << "\n"
            << "Euler characteristic: " << s.euler_characteristic << "\n"
            << "genus:                " << s.genus << "\n"
            << "edge length:          " << s.shortest_edge << " .. " << s.longest_edge << "\n"
            << "bounding box:         (" << s.bbox_min.x << ", " << s.bbox_min.y << ", " << s.bbox_min.z << ") .. ("
            << s.bbox_max.x << ", " << s.bbox_max.y << ", " << s.bbox_max.z << "), diagonal " << s.bbox_diagonal << "\n"
            << "valence histogram:   ";
  for (const auto& [v, n] : s.valence_histogram) std::cout << " " << v << ":" << n;
  std::cout << "\nvertices per level:  ";
  for (const auto& [l, n] : s.vertices_per_level) std::cout << " " << l << ":" << n;
  std::cout << "\ntriangles per level (green/red/blue):\n";
  for (const auto& [l, c] : s.triangles_per_level)
    std::cout << "  level " << std::setw(2) << l << ": " << c[0] << " / " << c[1] << " / " << c[2] << "\n";
  std::cout << "red edges:            " << s.red_edges << "\n";
}

// A file with points and no faces (.xyz, .pwn, or a mesh format without them) for info: what it
// is and what to do with it, instead of "the mesh is empty". The file is read as a point cloud
// only once reading it as a mesh has failed, so meshes are read once.
std::optional<PointCloud> point_cloud_instead(const std::string& path) {
  try {
    PointCloud cloud = read_point_cloud(path);
    if (cloud.faces.empty()) return cloud;
  } catch (const InputError&) {
  }
  return std::nullopt;
}

void print_point_cloud(const std::string& name, const PointCloud& cloud, bool json) {
  for (const auto& note : cloud.notes) std::cerr << "rgbmesh: note: " << one_line(note) << "\n";
  Vec3 lo = cloud.points.front(), hi = lo;
  for (const Vec3& p : cloud.points) {
    lo = Vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
    hi = Vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
  }
  if (json) {
    std::cout << JsonObject()
                     .add("mesh", name)
                     .raw("point_cloud", "true")
                     .add("points", static_cast<std::uint64_t>(cloud.points.size()))
                     .raw("normals", cloud.normals.empty() ? "false" : "true")
                     .add("triangles", static_cast<std::uint64_t>(0))
                     .raw("bbox_min", vec_json(lo))
                     .raw("bbox_max", vec_json(hi))
                     .add("bbox_diagonal", norm(hi - lo))
                     .str()
              << "\n";
    return;
  }
  std::cout << name << ": a point cloud of " << fit::with_thousands(cloud.points.size()) << " points ("
            << (cloud.normals.empty() ? "without" : "with") << " normals), no faces: rgbmesh fit --target " << name
            << " fits a surface to it\n"
            << "bounding box:         (" << lo.x << ", " << lo.y << ", " << lo.z << ") .. (" << hi.x << ", " << hi.y
            << ", " << hi.z << "), diagonal " << norm(hi - lo) << "\n";
}

// rgbmesh info: a mesh's statistics, or what a point cloud is.
void run_info(const std::string& path, bool json, bool triangulate, bool repair) {
  RgbMesh mesh;
  try {
    mesh = load_mesh(path, triangulate, repair);
  } catch (const InputError&) {
    const std::optional<PointCloud> cloud = point_cloud_instead(path);
    if (!cloud) throw;
    print_point_cloud(path, *cloud, json);
    return;
  }
  print_statistics(path, mesh, json);
}

// [{"stage": "--uniform 4", "splits": N, "removals": N, "seconds": S}, ...]
std::string stages_json(const StageTotals& t) {
  std::string out = "[";
  for (std::size_t i = 0; i < t.stages.size(); ++i) {
    const StageResult& r = t.stages[i];
    out += (i ? ", " : "") + JsonObject()
                                 .add("stage", r.text)
                                 .add("splits", r.splits)
                                 .add("removals", r.removals)
                                 .add("seconds", r.seconds)
                                 .str();
  }
  return out + "]";
}

std::string stats_json(const RgbMesh& mesh, const StageTotals& t, double read_s, double write_s) {
  // Only counts the mesh keeps anyway: a statistics pass would allocate and distort peak_rss_mb.
  const double rss = peak_rss_mb();
  const auto& c = mesh.counters();
  return JsonObject()
      .add("vertices", static_cast<std::uint64_t>(mesh.num_vertices()))
      .add("edges", static_cast<std::uint64_t>(mesh.num_edges()))
      .add("triangles", static_cast<std::uint64_t>(mesh.num_triangles()))
      .add("max_level", mesh.max_level())
      .add("splits", t.splits)
      .add("removals", t.removals)
      .add("swaps", c.swaps_bb + c.swaps_gg + c.swaps_rb)
      .add("refine_seconds", t.seconds)
      .add("splits_per_second", t.splits_per_second)
      .add("removals_per_second", t.removals_per_second)
      .add("read_seconds", read_s)
      .add("write_seconds", write_s)
      .add("peak_rss_mb", rss)
      .add("bytes_per_vertex", rss * 1048576.0 / static_cast<double>(std::max<std::size_t>(1, mesh.num_vertices())))
      .raw("stages", stages_json(t))
      .str();
}

}  // namespace

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // The mesh's arrays grow in a few large steps. A fixed threshold keeps every large block in
  // its own mapping, returned to the system when the array moves; glibc's default raises the
  // threshold after the first such free, after which freed blocks stay in the heap and count
  // in the resident size.
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  // A library loaded with the tool (SuperLU_DIST, through PETSc) switches mappings off
  // (M_MMAP_MAX 0) and heap trimming too before main runs: every block then came from the
  // heap and stayed resident once freed, and a refinement that passed --memory-limit 600M by
  // a quarter held a grown queue's old 200 MB block. glibc's defaults again.
  mallopt(M_MMAP_MAX, 65536);
  mallopt(M_TRIM_THRESHOLD, 128 * 1024);
#endif
  remove_temporaries_on_signals();
  const Processes processes = start_processes(&argc, &argv);
  CLI::App app{
      "rgbmesh: adaptive RGB subdivision meshes (Puppo & Panozzo, IEEE TVCG 2009),\n"
      "conforming at every step, with the limit surface of Loop subdivision.\n"
      "Without a subcommand, runs the default job (see `rgbmesh --help`)."};
  app.require_subcommand(0, 1);
  app.set_version_flag("--version", "rgbmesh " RGBMESH_VERSION);
  std::string global_out = "out";
  std::string memory_limit;
  app.add_option("--memory-limit", memory_limit,
                 "Memory ceiling of the process: bytes with K/M/G/T, or a percentage of the available memory "
                 "[default: 80%]; larger work is refused or stopped (exit code 3)")
      ->type_name("SIZE");
  // --compression: before the subcommand, or on any subcommand that writes files.
  std::string compression_text = compression_name(WriteOptions().compression);
  const CLI::Validator compression_check(
      [](std::string& value) -> std::string {
        Compression c;
        return compression_from_name(value, c) ? "" : "must be lz4, zlib or none, got '" + value + "'";
      },
      "");
  const std::string compression_help =
      "Compression of VTK XML outputs (.vtp, .vtu): lz4 (the fastest; ParaView 5.6 and later), zlib (smaller, "
      "slower; every VTK reader) or none";
  std::vector<CLI::Option*> compression_options;
  const auto add_compression = [&](CLI::App* where) {
    compression_options.push_back(where->add_option("--compression", compression_text, compression_help)
                                      ->type_name("lz4|zlib|none")
                                      ->check(compression_check));
    return compression_options.back();
  };
  add_compression(&app)->capture_default_str();
  auto* global_out_option =
      app.add_option("--out", global_out,
                     "Output directory of the default job, and of adapt and fit when given before the subcommand")
          ->capture_default_str()
          ->check(kNonEmptyPath);

  const std::string repair_help =
      "Repair the mesh first: merge vertices at equal positions, collapse degenerate and needle triangles, remove "
      "duplicate ones, split non-manifold edges and vertices, orient consistently (a note says what changed; "
      "nothing moves by more than 1e-6 of the bounding-box diagonal)";

  // info
  auto* info = app.add_subcommand("info",
                                  "Print the statistics of a mesh: counts, boundary loops, Euler "
                                  "characteristic, genus, valences, levels and colors");
  std::string info_path;
  bool info_json = false, info_triangulate = false, info_repair = false;
  info->add_option("MESH", info_path,
                   "Input mesh (" + supported_input_extensions() +
                       "), or a point cloud (.xyz, .pwn, a file without faces)")
      ->required()
      ->check(kNonEmptyPath);
  info->add_flag("--json", info_json, "Print one JSON object instead of text");
  info->add_flag("--triangulate", info_triangulate, "Fan-split polygons with more than three vertices");
  info->add_flag("--repair", info_repair, repair_help);

  // convert
  auto* convert = app.add_subcommand("convert", "Convert a mesh between formats (checked like any input)");
  std::string convert_in, convert_out;
  bool convert_triangulate = false, convert_repair = false;
  convert->add_option("IN", convert_in, "Input mesh (" + supported_input_extensions() + ")")
      ->required()
      ->check(kNonEmptyPath);
  convert->add_option("OUT", convert_out, "Output mesh (" + supported_output_extensions() + ")")
      ->required()
      ->check(kNonEmptyPath);
  convert->add_flag("--triangulate", convert_triangulate, "Fan-split polygons with more than three vertices");
  convert->add_flag("--repair", convert_repair, repair_help);
  add_compression(convert);

  // refine
  auto* refine =
      app.add_subcommand("refine",
                         "Selective refinement: apply the stages in the order given, then write OUT.\n"
                         "Stages may repeat; --max-level caps the stages after it.");
  std::string refine_in, refine_out;
  bool refine_stats = false, refine_triangulate = false, refine_limit = false, refine_repair = false;
  refine->add_option("IN", refine_in, "Input (base) mesh (" + supported_input_extensions() + ")")
      ->required()
      ->check(kNonEmptyPath);
  refine->add_option("OUT", refine_out, "Output mesh (" + supported_output_extensions() + "), or - for none")
      ->check(kNonEmptyPath)
      ->required();
  std::vector<std::string> uniform_v, ball_v, max_edge_v, geometric_tol_v, budget_v, max_level_v, walk_v;
  struct StageOption {
    CLI::Option* option;
    std::vector<std::string>* values;
    Stage (*parse)(const std::string&);
  };
  const StageOption stage_options[] = {
      {refine->add_option("--uniform", uniform_v, "Every part at exactly level K (refines and coarsens)")
           ->type_name("K"),
       &uniform_v, parse_uniform},
      {refine->add_option("--ball", ball_v, "At least level K on the triangles that meet the ball")
           ->type_name("X,Y,Z,R,K"),
       &ball_v, parse_ball},
      {refine->add_option("--max-edge", max_edge_v, "Split until no edge is longer than L")->type_name("L"),
       &max_edge_v, parse_max_edge},
      {refine
           ->add_option("--geometric-tol", geometric_tol_v,
                        "Split where a new control point would lie farther than T from the edge midpoint")
           ->type_name("T"),
       &geometric_tol_v, parse_geometric_tol},
      {refine->add_option("--budget", budget_v, "Split the longest edges first until N triangles")
           ->type_name("N"),
       &budget_v, parse_budget},
      {refine->add_option("--max-level", max_level_v, "Cap the level of the stages after this one")
           ->type_name("K"),
       &max_level_v, parse_max_level},
      {refine
           ->add_option("--random-walk", walk_v,
                        "N random split/remove operations, reproducible from SEED (a testing aid)")
           ->type_name("N,SEED"),
       &walk_v, parse_random_walk},
  };
  for (const auto& so : stage_options) so.option->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  auto* coarsen_all = refine->add_flag("--coarsen-all", "Remove every vertex not in the base mesh")
                          ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  refine->add_flag("--stats", refine_stats,
                   "Print one JSON object with counts, timings and peak memory as the last line");
  refine->add_flag("--triangulate", refine_triangulate, "Fan-split polygons with more than three vertices");
  refine->add_flag("--repair", refine_repair, repair_help);
  refine->add_flag("--limit", refine_limit,
                   "Write the vertices at their Loop limit positions instead of their control points");
  add_compression(refine);

  // adapt
  auto* adapt_cmd = app.add_subcommand(
      "adapt",
      "Error-driven adaptive finite elements: solve, estimate, mark, refine and coarsen, repeat.\n"
      "Writes one .vtp per cycle (or time step) and a .pvd series for ParaView into --out.\n"
      "Under mpirun -np P the processes share each cycle's work (the same results; each writes its\n"
      "piece, joined by a .pvtp or .pvtu summary) and the mesh itself (each process holds its part;\n"
      "--resume joins the pieces); --min-level K sets the floor whose units they share.");
  AdaptArgs adapt_args;
  // (Empty is refused: an unset shell variable would silently give the icosahedron.)
  adapt_cmd->add_option("--mesh", adapt_args.mesh, "Base mesh (default: an embedded icosahedron)")->check(kNonEmptyPath);
  adapt_cmd->add_flag("--triangulate", adapt_args.triangulate, "Fan-split the mesh's polygons with more than three vertices");
  adapt_cmd->add_flag("--repair", adapt_args.repair, repair_help);
  adapt_cmd->add_option("--problem", adapt_args.problem,
                        "sphere-harmonic, sphere-peak, moving-peak (exact solutions on the unit sphere) or gaussian "
                        "(a source on any surface) [default: sphere-peak; gaussian with --mesh]");
  adapt_cmd->add_option("--strategy", adapt_args.strategy, "adaptive or uniform")->capture_default_str();
  adapt_cmd->add_option(
      "--marking", adapt_args.marking,
      choices_help(adapt::marking_table()) +
          " (equidistribution needs --target-error) [default: dorfler; equidistribution for moving-peak]");
  adapt_cmd->add_option("--theta", adapt_args.theta, "Marking parameter of dorfler and fraction, in (0, 1]")
      ->capture_default_str()
      ->check(number_in("a number in (0, 1]", [](double x) { return x > 0 && x <= 1; }));
  adapt_cmd->add_option("--estimator", adapt_args.estimator, choices_help(fem::estimator_table()))
      ->capture_default_str();
  adapt_cmd->add_option("--order", adapt_args.order, "finite elements: 1 (linear) or 2 (quadratic, isoparametric on the surface)")
      ->capture_default_str();
  adapt_cmd
      ->add_option("--coarsen", adapt_args.coarsen,
                   "Remove vertices whose largest indicator over their star is below this times the refinement "
                   "threshold, in [0, 1) [default: 0.25 for moving-peak, else 0]")
      ->check(number_in("a number in [0, 1)", [](double x) { return x >= 0 && x < 1; }));
  adapt_cmd
      ->add_option("--min-level", adapt_args.min_level,
                   "A floor: the mesh is refined to this level first and never coarsened below it")
      ->capture_default_str()
      ->check(number_in("an integer in [0, " + std::to_string(kMaxLevel) + "]",
                        [](double x) { return x >= 0 && x <= kMaxLevel; }));
  adapt_cmd
      ->add_option("--cycles", adapt_args.cycles,
                   "Maximum number of cycles; for moving-peak, the cycles adapting to the start [default: 20; 8]")
      ->check(number_in("an integer in [1, 1000000]", [](double x) { return x >= 1 && x <= 1e6; }));
  adapt_cmd->add_option("--steps", adapt_args.steps, "Time steps of moving-peak")
      ->capture_default_str()
      ->check(number_in("an integer in [1, 1000000]", [](double x) { return x >= 1 && x <= 1e6; }));
  adapt_cmd
      ->add_option("--target-error", adapt_args.target_error,
                   "Stop once the estimate is at most this; for moving-peak and equidistribution, the error every "
                   "step is kept at [moving-peak: the estimate reached at the start]")
      ->check(number_in("a finite number >= 0", [](double x) { return x >= 0 && std::isfinite(x); }));
  adapt_cmd->add_option("--max-dofs", adapt_args.max_dofs, "Never solve on a mesh with more unknowns")
      ->capture_default_str()
      ->check(number_in("an integer in [1, 2^40]", [](double x) { return x >= 1 && x <= 1099511627776.0; }));
  adapt_cmd->add_option("--geometry", adapt_args.geometry,
                        "loop (vertices on the Loop limit surface) or sphere (projected onto the unit sphere) "
                        "[default: sphere for the sphere problems, else loop]");
  adapt_cmd->add_option("--center", adapt_args.center, "gaussian: the source's centre [default: the first vertex]")
      ->delimiter(',')
      ->type_name("X,Y,Z")
      ->expected(3);
  adapt_cmd->add_option("--width", adapt_args.width, "gaussian: the source's width sigma [default: diagonal / 20]")
      ->check(number_in("a finite number > 0", [](double x) { return x > 0 && std::isfinite(x); }));
  adapt_cmd->add_option("--solver", adapt_args.solver, "auto, ldlt, cg, cholmod or amg (CG with algebraic multigrid: hypre BoomerAMG through PETSc)")->capture_default_str();
  auto* adapt_out =
      adapt_cmd->add_option("--out", adapt_args.out, "Output directory")->capture_default_str()->check(kNonEmptyPath);
  add_compression(adapt_cmd);
  adapt_cmd->add_option("--report", adapt_args.report,
                        "Also write the JSON report (settings, cycles, why the run stopped; always written as "
                        "DIR/report.json) to this file, after every cycle")
      ->check(kNonEmptyPath);
  adapt_cmd->add_option("--resume", adapt_args.resume,
                        "Continue the run in this folder from its last cycle, with its settings (--cycles and "
                        "--max-dofs may extend it)")
      ->type_name("DIR")
      ->check(kNonEmptyPath);

  // fit
  auto* fit_cmd = app.add_subcommand(
      "fit", "Fit a Loop subdivision surface to points: move the base mesh's control points so that the\n"
             "limit surface passes through the targets (Ceres). Writes base.obj, fitted_base.obj,\n"
             "initial_limit_surface.vtp, limit_surface.vtp and targets.vtp into --out.");
  FitArgs fit_args;
  fit_cmd
      ->add_option("--target", fit_args.target,
                   "Target points: a point cloud (" + supported_point_cloud_extensions() +
                       ", or a mesh format without faces) or a mesh (its vertices)")
      ->required()
      ->check(kNonEmptyPath);
  auto* fit_base = fit_cmd->add_option("--base", fit_args.base, "Base mesh (its points are the starting controls)")
                       ->check(kNonEmptyPath);
  fit_cmd
      ->add_option("--base-faces", fit_args.base_faces,
                   "Without --base: triangles of the base built from the target (decimated, or reconstructed from a "
                   "cloud and decimated)")
      ->capture_default_str()
      ->check(number_in("an integer in [4, 10^8]", [](double x) { return x >= 4 && x <= 1e8; }))
      ->excludes(fit_base);
  fit_cmd->add_flag("--triangulate", fit_args.triangulate, "Fan-split polygons of the --target and --base faces");
  fit_cmd->add_flag("--ignore-faces", fit_args.ignore_faces,
                    "Fit the --target's vertices as a point cloud, whatever its faces (by default a mesh target is "
                    "the surface its faces make)");
  fit_cmd
      ->add_option("--reconstruction", fit_args.reconstruction,
                   "How a point cloud's base surface is reconstructed: automatic (Poisson where the points enclose a "
                   "volume, else advancing front), poisson (closed) or advancing-front (open where the points are)")
      ->capture_default_str();
  fit_cmd->add_flag("--repair", fit_args.repair,
                    "Repair the --target faces and the --base mesh first (as info --repair)");
  fit_cmd->add_option("--levels", fit_args.levels, "Uniform level of the limit surface used in the fit")
      ->capture_default_str()
      ->check(number_in("an integer in [1, 6]", [](double x) { return x >= 1 && x <= 6; }));
  fit_cmd->add_option("--loss", fit_args.loss, "huber, cauchy or none")->capture_default_str();
  fit_cmd->add_option("--smooth", fit_args.smooth, "Weight of the control-net smoothness term")
      ->capture_default_str()
      ->check(number_in("a finite number >= 0", [](double x) { return x >= 0 && std::isfinite(x); }));
  fit_cmd->add_option("--iterations", fit_args.iterations, "Maximum outer iterations")
      ->capture_default_str()
      ->check(number_in("an integer in [1, 1000]", [](double x) { return x >= 1 && x <= 1000; }));
  auto* fit_out =
      fit_cmd->add_option("--out", fit_args.out, "Output directory")->capture_default_str()->check(kNonEmptyPath);
  fit_cmd->add_option("--report", fit_args.report, "Write a JSON report to this file")->check(kNonEmptyPath);
  add_compression(fit_cmd);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::cerr << "rgbmesh: error: " << one_line(e.what()) << " (see --help)\n";
    return 2;
  }
  // Global options work wherever they stand: `rgbmesh --out D adapt` is `rgbmesh adapt --out D`.
  const bool global_out_given = global_out_option->count() > 0;
  if (global_out_given) {
    if (adapt_cmd->parsed() && adapt_out->count() == 0) adapt_args.out = global_out;
    if (fit_cmd->parsed() && fit_out->count() == 0) fit_args.out = global_out;
    for (const CLI::App* sub : {info, convert, refine}) {
      if (sub->parsed()) {
        std::cerr << "rgbmesh: error: --out: " << sub->get_name() << " writes no output folder\n";
        return 2;
      }
    }
  }
  Compression compression = WriteOptions().compression;
  compression_from_name(compression_text, compression);  // checked by the options' validator
  if (info->parsed() && compression_options.front()->count() > 0) {
    std::cerr << "rgbmesh: error: --compression: info writes no file\n";
    return 2;
  }
  adapt_args.compression = compression;
  fit_args.compression = compression;
  for (const char* name : {"--mesh", "--problem", "--strategy", "--marking", "--theta", "--estimator", "--order", "--coarsen", "--min-level",
                           "--cycles", "--steps", "--target-error", "--max-dofs", "--geometry", "--center", "--width",
                           "--solver", "--out", "--triangulate", "--repair"}) {
    if (adapt_cmd->count(name) > 0) adapt_args.given.insert(name);
  }
  if (adapt_cmd->parsed() && !adapt_args.resume.empty() && adapt_args.repair) {
    std::cerr << "rgbmesh: error: --repair: does not apply with --resume (the mesh is the run's last cycle, restored "
                 "exactly)\n";
    return 2;
  }
  {
    std::string line = "rgbmesh";
    for (int i = 1; i < argc; ++i) line += std::string(" ") + argv[i];
    adapt_args.command_line = line;
    fit_args.command_line = line;
  }

  // A failure: one line (rank 0 speaks for the run), and on several processes, an end for all.
  const auto fail = [&processes](int code, const std::string& message) {
    std::cerr << "rgbmesh: " << one_line(message) << "\n";
    return finish(processes, code, message);
  };
  try {
    const MemoryCeiling ceiling = MemoryCeiling::from_option(memory_limit);
    if (!ceiling.note().empty()) std::cerr << "rgbmesh: note: " << one_line(ceiling.note()) << "\n";
    adapt_args.memory_limit = memory_limit;
    fit_args.memory_limit = memory_limit;
    // Only adapt runs on several processes; any other command is rank 0's alone.
    if (processes.rank != 0 && !adapt_cmd->parsed() && (info->parsed() || convert->parsed() || refine->parsed() || fit_cmd->parsed()))
      return 0;
    if (info->parsed()) {
      run_info(info_path, info_json, info_triangulate, info_repair);
      return 0;
    }
    if (convert->parsed()) {
      check_output_path(convert_out);
      RgbMesh mesh = load_mesh(convert_in, convert_triangulate, convert_repair);
      write_rgb_mesh(convert_out, mesh, output_options(convert_out, compression));
      return 0;
    }
    if (refine->parsed()) {
      check_output_path(refine_out);
      // Stages in command-line order: walk CLI11's parse order, taking each option's values
      // one by one.
      std::vector<Stage> stages;
      std::map<const CLI::Option*, std::size_t> used;
      for (const CLI::Option* opt : refine->parse_order()) {
        if (opt == coarsen_all) {
          stages.push_back(parse_coarsen_all());
          continue;
        }
        for (const auto& so : stage_options) {
          if (so.option == opt) stages.push_back(so.parse((*so.values)[used[opt]++]));
        }
      }
      auto t0 = std::chrono::steady_clock::now();
      RgbMesh mesh = load_mesh(refine_in, refine_triangulate, refine_repair);
      const double read_s = seconds_since(t0);
      const StageTotals totals = run_stages(mesh, stages, ceiling, output_bytes_per_vertex(refine_out));
      t0 = std::chrono::steady_clock::now();
      if (refine_out != "-") {
        check_output_memory(mesh, refine_out, ceiling);
        write_rgb_mesh(refine_out, mesh, output_options(refine_out, compression), refine_limit);
      }
      const double write_s = seconds_since(t0);
      if (refine_stats) std::cout << stats_json(mesh, totals, read_s, write_s) << "\n";
      return 0;
    }
    if (adapt_cmd->parsed()) {
      distribute(adapt_args, processes);
      return run_adapt(adapt_args);
    }
    if (fit_cmd->parsed()) return run_fit(fit_args);
    // The main job: rgbmesh adapt with its defaults.
    AdaptArgs defaults;
    defaults.out = global_out;
    defaults.command_line = adapt_args.command_line;
    defaults.memory_limit = memory_limit;
    defaults.compression = compression;
    distribute(defaults, processes);
    return run_adapt(defaults);
  } catch (const MeshDefectError& e) {
    // The one thing to try next: what --repair would do about this defect.
    return fail(2, std::string("error: ") + e.what() + " (--repair " + e.hint() + ")");
  } catch (const InputError& e) {
    return fail(2, std::string("error: ") + e.what());
  } catch (const OutputError& e) {
    return fail(1, std::string("error: ") + e.what());
  } catch (const ResourceError& e) {
    return fail(3, std::string("error: ") + e.what());
  } catch (const std::bad_alloc&) {
    return fail(3, "error: out of memory (the work needs more memory than the machine has; see --memory-limit)");
  } catch (const std::exception& e) {
    return fail(3, std::string("internal error: ") + e.what());
  }
}
