#include "mesh_commands.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "json.hpp"
#include "one_line.hpp"
#include "rgbmesh/fit/base.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/repair/repair.hpp"
#include "rgbmesh/statistics.hpp"
#include "rgbmesh/timing.hpp"
#include "write_progress.hpp"

namespace rgbmesh::cli {

namespace fs = std::filesystem;

namespace {

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace

// A .vtp or .vtu that rgbmesh wrote comes back with its RGB state (levels, colours, parents),
// so that info reports it and refine continues from it; any other file is a base mesh, repaired
// first when asked.
RgbMesh load_mesh(const std::string& path, bool triangulate, bool repair, double sharp_angle) {
  SoupOptions options = repair::soup_options(triangulate, repair);
  options.sharp_angle = sharp_angle;
  RgbMeshFile file = read_rgb_mesh(path, options);
  for (const auto& note : file.notes) std::cerr << "rgbmesh: note: " << one_line(path + ": " + note) << "\n";
  if (!file.restored) note_rounded_edges(path, file.mesh, sharp_angle);
  return std::move(file.mesh);
}

void note_rounded_edges(const std::string& path, const RgbMesh& mesh, double sharp_angle) {
  // A CAD part read without its edges becomes a rounded blob: say so once, with the figure.
  if (sharp_angle > 0.0 || mesh.has_sharp_features()) return;  // the user chose the features
  const LimitDeviation d = limit_deviation(mesh);
  std::vector<Vec3> base(mesh.num_base_vertices());
  for (std::size_t i = 0; i < base.size(); ++i) base[i] = mesh.insertion_point(VertexHandle(static_cast<std::int32_t>(i)));
  const double diagonal = bounding_box_diagonal(base);
  if (!(diagonal > 0.0) || d.distance <= 0.01 * diagonal) return;
  std::ostringstream note;
  note << path << ": the Loop limit surface lies " << std::setprecision(2) << 100.0 * d.distance / diagonal
       << "% of the bounding-box diagonal from vertex " << d.vertex.idx
       << " of the input: its edges and corners are rounded; --sharp-angle 30 keeps the edges sharper than 30 degrees";
  std::cerr << "rgbmesh: note: " << one_line(note.str()) << "\n";
}

namespace {

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

// A VTK XML output of a mesh with sharp edges gets them beside it as lines (part.creases.vtp),
// for ParaView to draw over the surface.
void write_sharp_edges_beside(const std::string& out, const RgbMesh& mesh, bool limit, Compression compression) {
  std::string ext = fs::path(out).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".vtp" && ext != ".vtu") return;
  const fs::path lines = sharp_edges_path(out);
  write_sharp_edges(lines, mesh, limit, output_options(lines.string(), compression));
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
                     .add("sharp_edges", static_cast<std::uint64_t>(s.sharp_edges))
                     .add("semi_sharp_edges", static_cast<std::uint64_t>(s.semi_sharp_edges))
                     .add("darts", static_cast<std::uint64_t>(s.darts))
                     .add("crease_vertices", static_cast<std::uint64_t>(s.crease_vertices))
                     .add("corners", static_cast<std::uint64_t>(s.corners))
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
            << "bounding box:         (" << s.bbox_min.x << ", " << s.bbox_min.y << ", " << s.bbox_min.z
            << ") .. (" << s.bbox_max.x << ", " << s.bbox_max.y << ", " << s.bbox_max.z << "), diagonal "
            << s.bbox_diagonal << "\n"
            << "valence histogram:   ";
  const auto sharp_text = [&] {
    std::ostringstream o;
    o << s.sharp_edges << " (" << s.semi_sharp_edges << " semi-sharp); vertices: " << s.darts << " darts, "
      << s.crease_vertices << " creases, " << s.corners << " corners";
    return o.str();
  };
  for (const auto& [v, n] : s.valence_histogram) std::cout << " " << v << ":" << n;
  std::cout << "\nvertices per level:  ";
  for (const auto& [l, n] : s.vertices_per_level) std::cout << " " << l << ":" << n;
  std::cout << "\ntriangles per level (green/red/blue):\n";
  for (const auto& [l, c] : s.triangles_per_level)
    std::cout << "  level " << std::setw(2) << l << ": " << c[0] << " / " << c[1] << " / " << c[2] << "\n";
  std::cout << "red edges:            " << s.red_edges << "\n";
  if (mesh.has_sharp_features())
    std::cout << "sharp edges:          " << sharp_text() << " (" << to_string(mesh.sharp_features().method)
              << " creasing)\n";
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
            << (cloud.normals.empty() ? "without" : "with") << " normals), no faces: rgbmesh fit --target "
            << name << " fits a surface to it\n"
            << "bounding box:         (" << lo.x << ", " << lo.y << ", " << lo.z << ") .. (" << hi.x << ", "
            << hi.y << ", " << hi.z << "), diagonal " << norm(hi - lo) << "\n";
}

void run_info(const std::string& path, bool json, bool triangulate, bool repair, double sharp_angle) {
  RgbMesh mesh;
  try {
    mesh = load_mesh(path, triangulate, repair, sharp_angle);
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
      .add("bytes_per_vertex",
           rss * 1048576.0 / static_cast<double>(std::max<std::size_t>(1, mesh.num_vertices())))
      .raw("stages", stages_json(t))
      .str();
}

}  // namespace

void InfoCommand::add(CLI::App& tool) {
  app = tool.add_subcommand("info",
                            "Print the statistics of a mesh: counts, boundary loops, Euler "
                            "characteristic, genus, valences, levels and colors");
  app->add_option("MESH", path,
                  "Input mesh (" + supported_input_extensions() +
                      "), or a point cloud (.xyz, .pwn, a file without faces)")
      ->required()
      ->check(kNonEmptyPath);
  app->add_flag("--json", json, "Print one JSON object instead of text");
  app->add_flag("--triangulate", triangulate, "Split polygons into triangles (fans for planar convex ones, ears for the others)");
  app->add_flag("--repair", repair, kRepairHelp);
  add_sharp_angle(app, sharp_angle);
}

void InfoCommand::run() const { run_info(path, json, triangulate, repair, sharp_angle); }

void ConvertCommand::add(CLI::App& tool, CompressionOption& compression) {
  app = tool.add_subcommand("convert", "Convert a mesh between formats (checked like any input)");
  app->add_option("IN", in, "Input mesh (" + supported_input_extensions() + ")")
      ->required()
      ->check(kNonEmptyPath);
  app->add_option("OUT", out, "Output mesh (" + supported_output_extensions() + ")")
      ->required()
      ->check(kNonEmptyPath);
  app->add_flag("--triangulate", triangulate, "Split polygons into triangles (fans for planar convex ones, ears for the others)");
  app->add_flag("--repair", repair, kRepairHelp);
  add_sharp_angle(app, sharp_angle);
  compression.add_to(*app);
}

void ConvertCommand::run(Compression compression) const {
  check_output_path(out);
  RgbMesh mesh = load_mesh(in, triangulate, repair, sharp_angle);
  write_rgb_mesh(out, mesh, output_options(out, compression));
  write_sharp_edges_beside(out, mesh, false, compression);
}

void RefineCommand::add(CLI::App& tool, CompressionOption& compression) {
  app = tool.add_subcommand("refine",
                            "Selective refinement: apply the stages in the order given, then write OUT.\n"
                            "Stages may repeat; --max-level caps the stages after it.");
  app->add_option("IN", in, "Input (base) mesh (" + supported_input_extensions() + ")")
      ->required()
      ->check(kNonEmptyPath);
  app->add_option("OUT", out, "Output mesh (" + supported_output_extensions() + "), or - for none")
      ->check(kNonEmptyPath)
      ->required();
  struct Declared {
    const char* name;
    const char* help;
    const char* type;
    Stage (*parse)(const std::string&);
  };
  static const Declared declared[] = {
      {"--uniform", "Every part at exactly level K (refines and coarsens)", "K", parse_uniform},
      {"--ball", "At least level K on the triangles that meet the ball", "X,Y,Z,R,K", parse_ball},
      {"--max-edge", "Split until no edge is longer than L", "L", parse_max_edge},
      {"--geometric-tol", "Split where a new control point would lie farther than T from the edge midpoint",
       "T", parse_geometric_tol},
      {"--budget", "Split the longest edges first until N triangles", "N", parse_budget},
      {"--max-level", "Cap the level of the stages after this one", "K", parse_max_level},
      {"--random-walk", "N random split/remove operations, reproducible from SEED (a testing aid)", "N,SEED",
       parse_random_walk},
  };
  stage_options_.reserve(std::size(declared));
  for (const Declared& d : declared) {
    stage_options_.push_back({nullptr, {}, d.parse});
    StageOption& so = stage_options_.back();
    so.option = app->add_option(d.name, so.values, d.help)->type_name(d.type);
    so.option->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  }
  coarsen_all_ = app->add_flag("--coarsen-all", "Remove every vertex not in the base mesh")
                     ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app->add_flag("--stats", stats,
                "Print one JSON object with counts, timings and peak memory as the last line");
  app->add_flag("--triangulate", triangulate, "Split polygons into triangles (fans for planar convex ones, ears for the others)");
  app->add_flag("--repair", repair, kRepairHelp);
  add_sharp_angle(app, sharp_angle);
  app->add_flag("--limit", limit,
                "Write the vertices at their Loop limit positions instead of their control points");
  compression.add_to(*app);
}

// Stages in command-line order: walk CLI11's parse order, taking each option's values one by one.
std::vector<Stage> RefineCommand::stages() const {
  std::vector<Stage> stages;
  std::map<const CLI::Option*, std::size_t> used;
  for (const CLI::Option* opt : app->parse_order()) {
    if (opt == coarsen_all_) {
      stages.push_back(parse_coarsen_all());
      continue;
    }
    for (const StageOption& so : stage_options_) {
      if (so.option == opt) stages.push_back(so.parse(so.values[used[opt]++]));
    }
  }
  return stages;
}

void RefineCommand::run(Compression compression, const MemoryCeiling& ceiling) const {
  check_output_path(out);
  const std::vector<Stage> stage_list = stages();
  auto t0 = std::chrono::steady_clock::now();
  RgbMesh mesh = load_mesh(in, triangulate, repair, sharp_angle);
  const double read_s = seconds_since(t0);
  const StageTotals totals = run_stages(mesh, stage_list, ceiling, output_bytes_per_vertex(out));
  t0 = std::chrono::steady_clock::now();
  if (out != "-") {
    check_output_memory(mesh, out, ceiling);
    write_rgb_mesh(out, mesh, output_options(out, compression), limit);
    write_sharp_edges_beside(out, mesh, limit, compression);
  }
  const double write_s = seconds_since(t0);
  if (stats) std::cout << stats_json(mesh, totals, read_s, write_s) << "\n";
}

}  // namespace rgbmesh::cli
