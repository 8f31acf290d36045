#include "stages.hpp"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "rgbmesh/errors.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/soup.hpp"

namespace rgbmesh::cli {

namespace {

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> parts;
  std::string cur;
  std::istringstream in(s);
  while (std::getline(in, cur, ',')) parts.push_back(cur);
  if (!s.empty() && s.back() == ',') parts.emplace_back();
  return parts;
}

double to_double(const std::string& option, const std::string& s) {
  char* end = nullptr;
  const double x = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(x))
    throw InputError(option + ": '" + s + "' is not a finite number");
  return x;
}

std::int64_t to_integer(const std::string& option, const std::string& s, std::int64_t lo, std::int64_t hi) {
  std::int64_t x = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size())
    throw InputError(option + ": '" + s + "' is not an integer");
  if (x < lo || x > hi)
    throw InputError(option + ": " + s + " is out of range [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "]");
  return x;
}

std::vector<std::string> fields(const std::string& option, const std::string& value, std::size_t n,
                                const char* form) {
  auto parts = split_commas(value);
  if (parts.size() != n)
    throw InputError(option + ": expected " + form + " (" + std::to_string(n) +
                     " values separated by commas), got '" + value + "'");
  return parts;
}

// Progress on stderr for stages that take more than a second: rewritten in place on a
// terminal, one line every few seconds otherwise.
class Progress {
 public:
  explicit Progress(std::string label) : label_(std::move(label)), start_(clock::now()), tty_(isatty(2)) {}
  ~Progress() {
    if (printed_ && tty_) std::fputc('\n', stderr);
  }
  void update(std::uint64_t operations, std::size_t pending) {
    const double t = seconds();
    if (t < 1.0 || t < next_) return;
    next_ = t + (tty_ ? 0.25 : 5.0);
    std::fprintf(stderr, "%srgbmesh: %s: %llu operations, %zu queued, %.1f s%s", tty_ ? "\r" : "",
                 label_.c_str(), static_cast<unsigned long long>(operations), pending, t, tty_ ? "" : "\n");
    std::fflush(stderr);
    printed_ = true;
  }
  double seconds() const { return std::chrono::duration<double>(clock::now() - start_).count(); }

 private:
  using clock = std::chrono::steady_clock;
  std::string label_;
  clock::time_point start_;
  bool tty_;
  bool printed_ = false;
  double next_ = 0;
};

// Why a stage changed nothing, for the warning: the user may have mistyped a value.
std::string why_nothing_changed(const RgbMesh& mesh, const Stage& s, int cap, std::size_t triangles_before) {
  const std::string capped = " (or --max-level " + std::to_string(cap) + " stops it)";
  switch (s.kind) {
    case Stage::uniform:
      return "the mesh is already at level " + std::to_string(s.level) + " everywhere" +
             (s.level > cap ? capped : std::string());
    case Stage::ball: {
      double nearest = std::numeric_limits<double>::infinity();
      for (TriangleHandle t : mesh.triangles()) {
        const auto c = mesh.triangle_vertices(t);
        nearest = std::min(nearest, point_triangle_distance(Vec3(s.x, s.y, s.z), mesh.control_point(c[0]),
                                                            mesh.control_point(c[1]), mesh.control_point(c[2])));
      }
      if (nearest > s.radius) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "the ball misses the surface: its nearest point is %.6g away, radius %.6g",
                      nearest, s.radius);
        return std::string(buf) + " (`rgbmesh info` prints the bounding box)";
      }
      return "every triangle that meets the ball is already at level " + std::to_string(s.level) + " or finer" +
             (s.level > cap ? capped : std::string());
    }
    case Stage::max_edge:
      return "no edge is longer than " + s.text.substr(s.text.find(' ') + 1) + capped;
    case Stage::geometric_tol:
      return "the surface is already resolved to " + s.text.substr(s.text.find(' ') + 1) + capped;
    case Stage::budget:
      return triangles_before >= s.count ? "the mesh already has " + std::to_string(triangles_before) +
                                               " triangles, at least the budget of " + std::to_string(s.count)
                                         : "no edge could be split" + capped;
    case Stage::coarsen_all:
      return "the mesh is already its base mesh";
    case Stage::random_walk:
      return s.count == 0 ? "it has no steps" : "no operation was possible";
    case Stage::max_level:
      break;
  }
  return "";
}

}  // namespace

Stage parse_uniform(const std::string& value) {
  Stage s{Stage::uniform, "--uniform " + value};
  s.level = static_cast<int>(to_integer("--uniform", value, 0, kMaxLevel));
  return s;
}

Stage parse_ball(const std::string& value) {
  Stage s{Stage::ball, "--ball " + value};
  const auto f = fields("--ball", value, 5, "X,Y,Z,R,K");
  s.x = to_double("--ball", f[0]);
  s.y = to_double("--ball", f[1]);
  s.z = to_double("--ball", f[2]);
  s.radius = to_double("--ball", f[3]);
  if (s.radius < 0) throw InputError("--ball: the radius must not be negative, got " + f[3]);
  s.level = static_cast<int>(to_integer("--ball", f[4], 0, kMaxLevel));
  return s;
}

Stage parse_max_edge(const std::string& value) {
  Stage s{Stage::max_edge, "--max-edge " + value};
  s.length = to_double("--max-edge", value);
  if (!(s.length > 0)) throw InputError("--max-edge: the length must be positive, got " + value);
  return s;
}

Stage parse_geometric_tol(const std::string& value) {
  Stage s{Stage::geometric_tol, "--geometric-tol " + value};
  s.length = to_double("--geometric-tol", value);
  if (!(s.length > 0)) throw InputError("--geometric-tol: the tolerance must be positive, got " + value);
  return s;
}

Stage parse_budget(const std::string& value) {
  Stage s{Stage::budget, "--budget " + value};
  s.count = static_cast<std::uint64_t>(to_integer("--budget", value, 1, std::int64_t(1) << 40));
  return s;
}

Stage parse_max_level(const std::string& value) {
  Stage s{Stage::max_level, "--max-level " + value};
  s.level = static_cast<int>(to_integer("--max-level", value, 0, kMaxLevel));
  return s;
}

Stage parse_random_walk(const std::string& value) {
  Stage s{Stage::random_walk, "--random-walk " + value};
  const auto f = fields("--random-walk", value, 2, "N,SEED");
  // At about a million steps a second, 10^9 steps take a quarter of an hour: a testing aid
  // needs no more, and a mistyped count must not run for days.
  s.count = static_cast<std::uint64_t>(to_integer("--random-walk", f[0], 0, 1000000000));
  s.seed = static_cast<std::uint64_t>(to_integer("--random-walk", f[1], 0, INT64_MAX));
  return s;
}

Stage parse_coarsen_all() { return Stage{Stage::coarsen_all, "--coarsen-all"}; }

double output_bytes_per_vertex(const std::string& output_path) {
  if (output_path == "-") return 0;
  const bool xml = output_path.size() > 4 && (output_path.substr(output_path.size() - 4) == ".vtp" ||
                                              output_path.substr(output_path.size() - 4) == ".vtu");
  // VTK XML files are written from the mesh itself (write_rgb_mesh): its limit positions (28
  // bytes per vertex where not yet known), the shown levels and, in a mesh with free slots,
  // the numbering (13), a few MB of blocks. Other formats go through a snapshot: points 24,
  // two triangles of 12 bytes, levels and colours, and VTK's copies of points and cells.
  // Measured peaks stay below these figures.
  return xml ? 60.0 : 150.0;
}

namespace {

// A refusal or a stop at the memory ceiling, with the figures.
[[noreturn]] void out_of_memory(const Stage& s, const std::string& what, const MemoryCeiling& ceiling) {
  throw ResourceError("stage " + s.text + ": " + what + "; the memory limit is " + ceiling.describe());
}

// "740", "4.43 million", "2.1e+21".
std::string millions(double n) {
  char buf[48];
  if (n >= 1e12)
    std::snprintf(buf, sizeof buf, "%.2g", n);
  else if (n >= 1e9)
    std::snprintf(buf, sizeof buf, "%.3g billion", n / 1e9);
  else if (n >= 1e6)
    std::snprintf(buf, sizeof buf, "%.3g million", n / 1e6);
  else
    std::snprintf(buf, sizeof buf, "%.0f", n);
  return buf;
}

// Uniform levels and budgets: the final size is known, so the stage is refused before it
// starts when it cannot fit.
void check_predictable(const RgbMesh& mesh, const Stage& s, int cap, const MemoryCeiling& ceiling,
                       double output_vertex_bytes) {
  MeshCounts counts;
  std::string target;
  if (s.kind == Stage::uniform) {
    const int level = std::min(s.level, cap);
    if (level <= mesh.max_level()) return;
    counts = uniform_level_counts(mesh, level);
    target = "the mesh at level " + std::to_string(level);
  } else if (s.kind == Stage::budget) {
    const auto n = static_cast<double>(s.count);
    if (n <= static_cast<double>(mesh.num_triangles())) return;
    counts.triangles = n;
    counts.edges = 1.5 * n;
    counts.vertices = 0.5 * n;
    target = "a mesh of " + millions(n) + " triangles";
  } else {
    return;
  }
  // The arrays are reserved for the final size while the current ones still exist.
  const double needed = counts.bytes() + static_cast<double>(mesh.memory_bytes()) + counts.vertices * output_vertex_bytes;
  const double free = static_cast<double>(ceiling.headroom()) + static_cast<double>(mesh.memory_bytes());
  if (needed > free)
    out_of_memory(s,
                  target + " would have " + millions(counts.vertices) + " vertices and " + millions(counts.triangles) +
                      " triangles, about " + human_bytes(needed) +
                      (output_vertex_bytes > 0 ? " with its output" : "") + " (" + human_bytes(free) + " free)",
                  ceiling);
}

// Open-ended stages between the refinement's own checks. The refinement weighs the mesh's
// arrays and its queue by their sizes, but the queue is a vector that doubles: for a moment
// the old block and the copy are both resident, 200 MB more for 8 million entries, and a
// stage under --memory-limit 600M reached 623 MB. Every progress report (each 65,536
// operations) weighs what the process really holds and what may come before the next one:
// the growth seen over the last interval, and the larger of the queue's next doubling (when
// the queue may reach its capacity, a power of two, by then) and a mesh array group's growth
// (half the arrays, as the refinement counts it). When that would pass the ceiling, the stage
// stops there (the mesh stays valid; the stage fails as at the refinement's own stop).
class MemoryWatch {
 public:
  struct Stop {};
  MemoryWatch(const RgbMesh& mesh, const MemoryCeiling& ceiling) : mesh_(mesh), ceiling_(ceiling) {}

  void check(std::size_t queued) {
    const double resident = static_cast<double>(resident_memory_bytes());
    if (resident <= 0) return;  // not Linux: the refinement's own checks only
    const double q = static_cast<double>(queued);
    most_queued_ = std::max(most_queued_, q);
    const double capacity = std::exp2(std::ceil(std::log2(std::max(most_queued_, 1.0))));
    const double growth = last_resident_ > 0 ? std::max(0.0, resident - last_resident_) : 0.0;
    const double queue_growth = std::max(0.0, q - last_queued_);
    last_resident_ = resident;
    last_queued_ = q;
    const double doubling = q + queue_growth >= capacity ? capacity * kEntryBytes : 0.0;
    const double arrays = 0.5 * static_cast<double>(mesh_.memory_bytes());
    if (resident + growth + std::max(doubling, arrays) > static_cast<double>(ceiling_.bytes())) throw Stop{};
  }

 private:
  static constexpr double kEntryBytes = 24;  // an edge's queue entry (the vertices' are smaller)
  const RgbMesh& mesh_;
  const MemoryCeiling& ceiling_;
  double most_queued_ = 0, last_queued_ = 0, last_resident_ = 0;
};

// One stage on the mesh (--max-level only sets the cap of the later ones).
RefinementResult apply(RgbMesh& mesh, const Stage& s, int& cap, const RefinementOptions& options, Progress& progress) {
  switch (s.kind) {
    case Stage::uniform:
      return selective_refinement(mesh, UniformLevel(s.level), options);
    case Stage::ball:
      return selective_refinement(mesh, BallLevel({s.x, s.y, s.z}, s.radius, s.level), options);
    case Stage::max_edge:
      return selective_refinement(mesh, MaxEdgeLength(s.length), options);
    case Stage::geometric_tol:
      return selective_refinement(mesh, GeometricTolerance(s.length), options);
    case Stage::budget:
      return selective_refinement(mesh, TriangleBudget(s.count), options);
    case Stage::coarsen_all:
      return selective_refinement(mesh, CoarsenAll(), options);
    case Stage::max_level:
      cap = s.level;
      break;
    case Stage::random_walk: {
      RandomWalkOptions walk;
      // Random splits concentrate where the mesh is already fine; a level cap keeps the
      // walk spread out (the triangle cap of random_walk bounds the size).
      walk.max_level = std::min(cap, 8);
      std::uint64_t done = 0;
      walk.after_step = [&](std::uint64_t) {
        if ((++done & 4095) == 0) progress.update(done, s.count - done);
      };
      return random_walk(mesh, s.count, s.seed, walk);
    }
  }
  return {};
}

}  // namespace

void check_output_memory(const RgbMesh& mesh, const std::string& output_path, const MemoryCeiling& ceiling) {
  const double needed = output_bytes_per_vertex(output_path) * static_cast<double>(mesh.num_vertices());
  if (needed > static_cast<double>(ceiling.headroom()))
    throw ResourceError(output_path + ": writing " + millions(static_cast<double>(mesh.num_vertices())) +
                        " vertices needs about " + human_bytes(needed) + " more memory (" +
                        human_bytes(static_cast<double>(ceiling.headroom())) + " free); the memory limit is " +
                        ceiling.describe());
}

StageTotals run_stages(RgbMesh& mesh, const std::vector<Stage>& stages, const MemoryCeiling& ceiling,
                       double output_vertex_bytes) {
  StageTotals totals;
  int cap = kMaxLevel;
  const auto start = std::chrono::steady_clock::now();
  double split_seconds = 0, removal_seconds = 0;
  std::uint64_t pure_splits = 0, pure_removals = 0;
  for (std::size_t i = 0; i < stages.size(); ++i) {
    const Stage& s = stages[i];
    const auto stage_start = std::chrono::steady_clock::now();
    const std::size_t triangles_before = mesh.num_triangles();
    Progress progress("stage " + std::to_string(i + 1) + "/" + std::to_string(stages.size()) + " " + s.text);
    check_predictable(mesh, s, cap, ceiling, output_vertex_bytes);
    RefinementOptions options;
    options.max_level = cap;
    options.max_mesh_bytes = mesh.memory_bytes() + ceiling.headroom();
    MemoryWatch watch(mesh, ceiling);
    options.progress = [&progress, &watch](std::uint64_t ops, std::size_t queued) {
      progress.update(ops, queued);
      watch.check(queued);
    };
    RefinementResult r;
    try {
      r = apply(mesh, s, cap, options, progress);
    } catch (const MemoryWatch::Stop&) {
      r.stopped_at_memory_limit = true;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - stage_start).count();
    if (r.stopped_at_memory_limit)
      out_of_memory(s,
                    "stopped at the memory limit with " + millions(static_cast<double>(mesh.num_vertices())) +
                        " vertices, before the mesh was refined as asked (no output written)",
                    ceiling);
    if (s.kind != Stage::max_level && r.splits == 0 && r.removals == 0)
      std::fprintf(stderr, "rgbmesh: warning: stage %s changed nothing: %s\n", s.text.c_str(),
                   why_nothing_changed(mesh, s, cap, triangles_before).c_str());
    totals.splits += r.splits;
    totals.removals += r.removals;
    if (s.kind != Stage::max_level) totals.stages.push_back({s.text, r.splits, r.removals, seconds});
    if (r.splits > 0 && r.removals == 0) {
      pure_splits += r.splits;
      split_seconds += seconds;
    }
    if (r.removals > 0 && r.splits == 0) {
      pure_removals += r.removals;
      removal_seconds += seconds;
    }
  }
  totals.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  totals.splits_per_second = split_seconds > 0 ? static_cast<double>(pure_splits) / split_seconds : 0.0;
  totals.removals_per_second = removal_seconds > 0 ? static_cast<double>(pure_removals) / removal_seconds : 0.0;
  return totals;
}

}  // namespace rgbmesh::cli
