#include "fit_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "json.hpp"
#include "one_line.hpp"
#include "output_dir.hpp"
#include "resources.hpp"
#include "rgbmesh/fit/base.hpp"
#include "rgbmesh/fit/distances.hpp"
#include "rgbmesh/fit/fit.hpp"
#include "rgbmesh/fit/fit_target.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/repair/repair.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "run_lock.hpp"
#include "write_progress.hpp"

namespace rgbmesh::cli {
namespace {

namespace fs = std::filesystem;

fit::FitOptions fit_options(const FitArgs& a) {
  fit::FitOptions o;
  if (a.loss == "huber")
    o.loss = fit::Loss::huber;
  else if (a.loss == "cauchy")
    o.loss = fit::Loss::cauchy;
  else if (a.loss == "none")
    o.loss = fit::Loss::none;
  else
    throw InputError("--loss: '" + a.loss + "' is not huber, cauchy or none");
  if (a.levels < 1 || a.levels > 6) throw InputError("--levels: must be in [1, 6], got " + std::to_string(a.levels));
  if (a.iterations < 1) throw InputError("--iterations: must be at least 1");
  if (!(a.smooth >= 0)) throw InputError("--smooth: must be >= 0");
  if (a.base.empty() && a.base_faces < 4) throw InputError("--base-faces: must be at least 4");
  o.levels = a.levels;
  o.smooth = a.smooth;
  o.max_iterations = a.iterations;
  return o;
}

// The control of every stage: the memory ceiling (a ResourceError naming the stage once the
// process holds more) and a progress line for stages that last more than two seconds.
fit::StageControl stage_control(const MemoryCeiling& ceiling) {
  auto line = std::make_shared<std::unique_ptr<ProgressLine>>();
  fit::StageControl control;
  control.on_step = [line, ceiling](const std::string& stage, double fraction) {
    const std::size_t resident = resident_memory_bytes();
    if (resident > ceiling.bytes()) {
      if (*line) (*line)->finish();
      throw ResourceError(stage + ": the process holds " + human_bytes(static_cast<double>(resident)) +
                          ", more than the memory limit of " + ceiling.describe());
    }
    if (!*line || (*line)->task() != stage) {
      if (*line) (*line)->finish();
      *line = std::make_unique<ProgressLine>(stage);
    }
    (*line)->update(fraction);
  };
  return control;
}

// The base given with --base, if any.
std::optional<fit::Base> given_base(const FitArgs& a) {
  if (a.base.empty()) return std::nullopt;
  SoupOptions soup_options = repair::soup_options(a.triangulate, a.repair);
  soup_options.sharp_angle = a.sharp_angle;
  fit::Base base;
  base.mesh = read_mesh(a.base, soup_options);
  for (const std::string& note : base.mesh.notes) base.notes.push_back(a.base + ": " + note);
  base.mesh.notes.clear();
  try {
    base.topology = fit::topology_of(base.mesh);
  } catch (const InputError& e) {
    throw InputError(a.base + ": " + e.what());
  }
  base.source = fit::BaseSource::given;
  return base;
}

fit::TargetFitOptions target_fit_options(const FitArgs& a) {
  fit::TargetFitOptions o;
  o.fit = fit_options(a);
  o.base.faces = a.base_faces;
  o.base.soup = repair::soup_options(a.triangulate, a.repair);
  o.base.soup.sharp_angle = a.sharp_angle;
  o.base.ignore_faces = a.ignore_faces;
  if (!fit::reconstruction_method_from_name(a.reconstruction, o.base.reconstruction.method))
    throw InputError("--reconstruction: '" + a.reconstruction + "' is not automatic, poisson or advancing-front");
  return o;
}

// Exactly the double (the JSON helper rounds to 6 digits): the report's figures must match
// what targets.vtp holds.
std::string exact(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

std::string json_list(const std::vector<std::string>& items) {
  std::string out = "[";
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out + "]";
}

MeshSnapshot limit_snapshot(const fit::LimitStencils& stencils, const std::vector<Vec3>& controls) {
  MeshSnapshot limit;
  limit.points = stencils.evaluate(controls);
  limit.triangles = stencils.triangles;
  limit.vertex_level.assign(limit.points.size(), 0);
  limit.triangle_level.assign(limit.triangles.size(), 0);
  limit.triangle_color.assign(limit.triangles.size(), Color::green);
  return limit;
}

void write_outputs(const FitArgs& a, const fit::TargetFit& f) {
  const fit::Base& base = f.base;
  const fit::FitResult& r = f.result;
  const fs::path dir(a.out);
  // (With the base's creases and corners as OBJ tags, which read_mesh reads back.)
  write_mesh(dir / "base.obj", RgbMesh::from_triangles(base.mesh.points, base.mesh.triangles, base.mesh.sharp).snapshot());
  write_mesh(dir / "fitted_base.obj",
             RgbMesh::from_triangles(r.control_points, base.mesh.triangles, base.mesh.sharp).snapshot());
  MeshSnapshot limit = limit_snapshot(r.stencils, r.control_points);
  fit::TriangleDistances per_triangle = fit::distances_per_triangle(r);
  limit.point_data.push_back({"distance_to_target", 1, f.distances.to_target});
  limit.cell_data.push_back({"targets", 1, std::move(per_triangle.targets)});
  limit.cell_data.push_back({"rms_distance", 1, std::move(per_triangle.rms_distance)});
  const auto vtk_options = [&](const char* file) { return output_options((dir / file).string(), a.compression); };
  write_mesh(dir / "limit_surface.vtp", limit, vtk_options("limit_surface.vtp"));
  // The limit surface of the starting base, for comparison (subdivision shrinks a coarse base).
  write_mesh(dir / "initial_limit_surface.vtp", limit_snapshot(r.stencils, base.mesh.points),
             vtk_options("initial_limit_surface.vtp"));
  write_point_cloud(dir / "targets.vtp", f.targets, {{"distance", 1, r.distance}}, vtk_options("targets.vtp"));
}

std::string distances_json(const fit::TwoSidedDistances& d) {
  return JsonObject()
      .raw("rms", exact(d.to_surface_rms))
      .raw("max", exact(d.to_surface_max))
      .raw("p99", exact(d.to_surface_p99))
      .add("rms_relative", d.to_surface_rms / d.diagonal)
      .add("max_relative", d.to_surface_max / d.diagonal)
      .str();
}

std::string back_json(const fit::TwoSidedDistances& d) {
  return JsonObject()
      .raw("rms", exact(d.to_target_rms))
      .raw("max", exact(d.to_target_max))
      .add("rms_relative", d.to_target_rms / d.diagonal)
      .add("max_relative", d.to_target_max / d.diagonal)
      .str();
}

// One fit of an escalating run: its settings, two-sided figures (relative to the diagonal) and
// verdict.
struct Attempt {
  std::size_t base_faces = 0;  // asked for
  int levels = 0;
  double seconds = 0;
  double rms = 0, max = 0, back_rms = 0, back_max = 0;
  bool accepted = false;
  std::string reason;
  // How far from accepted, to keep the best: the larger of the two maxima.
  double badness() const { return std::max(max, back_max); }
};

Attempt attempt_of(const fit::TargetFit& f, std::size_t faces, int levels, double seconds) {
  Attempt t;
  t.base_faces = faces;
  t.levels = levels;
  t.seconds = seconds;
  const double diagonal = f.result.diagonal;
  t.rms = f.result.rms / diagonal;
  t.max = f.result.max / diagonal;
  t.back_rms = f.distances.to_target_rms / diagonal;
  t.back_max = f.distances.to_target_max / diagonal;
  t.accepted = f.verdict.accepted;
  t.reason = f.verdict.reason;
  return t;
}

std::string describe(const Attempt& t) {
  char text[256];
  std::snprintf(text, sizeof text,
                "base of %s faces, level %d: targets to surface rms %.2f%% max %.2f%%, surface to target rms %.2f%% "
                "max %.2f%% of the diagonal, %.1f s: %s",
                fit::with_thousands(t.base_faces).c_str(), t.levels, 100 * t.rms, 100 * t.max, 100 * t.back_rms,
                100 * t.back_max, t.seconds, t.accepted ? "accepted" : "rejected");
  return text;
}

void write_report(const FitArgs& a, const PointCloud& cloud, const fit::TargetFit& f, double total_seconds,
                  const std::vector<Attempt>& attempts) {
  const fit::Base& base = f.base;
  const fit::FitResult& r = f.result;
  const fit::TwoSidedDistances& two_sided = f.distances;
  const fit::Verdict& verdict = f.verdict;
  std::vector<std::string> iterations, notes;
  for (const fit::IterationReport& it : r.iterations)
    iterations.push_back(
        JsonObject()
            .add("iteration", it.iteration)
            .add("rms", it.rms)
            .add("max", it.max)
            .add("surface_rms", it.surface_rms)
            .add("seconds", it.seconds)
            .str());
  for (const std::string& note : cloud.notes) notes.push_back(JsonObject::quote(note));
  for (const std::string& note : f.target_notes) notes.push_back(JsonObject::quote(a.target + ": " + note));
  for (const std::string& note : f.notes) notes.push_back(JsonObject::quote(note));
  const std::string target_json = JsonObject()
                                      .add("file", a.target)
                                      .add("kind", f.target_is_surface ? "surface" : "points")
                                      .add("points", static_cast<std::uint64_t>(cloud.points.size()))
                                      .add("faces", static_cast<std::uint64_t>(cloud.faces.size()))
                                      .add("fitted_points", static_cast<std::uint64_t>(f.targets.size()))
                                      .raw("normals", cloud.normals.empty() ? "false" : "true")
                                      .str();
  JsonObject base_json;
  base_json.add("source", fit::to_string(base.source));
  if (!a.base.empty()) base_json.add("file", a.base);
  if (a.base.empty()) base_json.add("requested_faces", static_cast<std::uint64_t>(a.base_faces));
  if (base.source == fit::BaseSource::reconstructed)
    base_json.add("reconstruction", fit::to_string(base.reconstruction))
        .add("unsupported_area", base.unsupported)
        .add("trimmed_area", base.trimmed);
  base_json.add("vertices", static_cast<std::uint64_t>(base.mesh.points.size()))
      .add("faces", static_cast<std::uint64_t>(base.mesh.triangles.size()))
      .add("components", base.topology.components)
      .add("genus", base.topology.genus)
      .add("boundary_loops", base.topology.boundary_loops)
      .add("reconstruction_seconds", base.reconstruction_seconds)
      .add("decimation_seconds", base.decimation_seconds);
  JsonObject report;
  report.add("version", RGBMESH_VERSION);
  if (!a.command_line.empty()) report.add("command", a.command_line);
  report.add("status", verdict.accepted ? "accepted" : "rejected");
  if (!verdict.accepted) report.add("reason", verdict.reason);
  report.raw("target", target_json)
      .raw("base", base_json.str())
      .raw("notes", json_list(notes))
      .raw("settings", JsonObject()
                           .add("levels", a.levels)
                           .add("loss", a.loss)
                           .add("smooth", a.smooth)
                           .add("iterations", a.iterations)
                           .add("reconstruction", a.reconstruction)
                           .str())
      .add("smooth_used", r.smooth)
      .raw("iterations", json_list(iterations))
      .raw("rms", exact(r.rms))
      .raw("max", exact(r.max))
      .raw("diagonal", exact(r.diagonal))
      .add("rms_relative", r.rms / r.diagonal)
      .add("max_relative", r.max / r.diagonal)
      .raw("targets_to_surface", distances_json(two_sided))
      .raw("surface_to_target", back_json(two_sided))
      .add("seconds", r.seconds)
      .add("total_seconds", total_seconds);
  std::vector<std::string> tried;
  for (const Attempt& t : attempts)
    tried.push_back(JsonObject()
                        .add("base_faces", static_cast<std::uint64_t>(t.base_faces))
                        .add("levels", t.levels)
                        .add("seconds", t.seconds)
                        .add("rms_relative", t.rms)
                        .add("max_relative", t.max)
                        .add("surface_rms_relative", t.back_rms)
                        .add("surface_max_relative", t.back_max)
                        .add("status", t.accepted ? "accepted" : "rejected")
                        .str());
  report.raw("attempts", json_list(tried));
  write_text_atomically(a.report, report.str() + "\n");
}

}  // namespace

int run_fit(const FitArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  const fit::TargetFitOptions options = target_fit_options(a);
  const MemoryCeiling ceiling = MemoryCeiling::from_option(a.memory_limit);
  const fit::StageControl control = stage_control(ceiling);
  const PointCloud cloud = read_point_cloud(a.target);
  for (const std::string& note : cloud.notes) std::cerr << "rgbmesh: note: " << one_line(note) << "\n";
  const std::optional<fit::Base> given = given_base(a);
  PolygonSoup soup;
  soup.points = cloud.points;
  soup.faces = cloud.faces;
  soup.numbered_vertices = cloud.numbered_vertices;
  fit::TargetFit f;
  try {
    f = fit::prepare_target_fit(soup, cloud.normals, given, options, control);
  } catch (const MeshDefectError& e) {
    // The checks of the target's faces name faces and vertices: the file is named here, and
    // the defect keeps its kind (the tool adds what --repair would do about it).
    throw MeshDefectError(a.target + ": " + e.what(), e.hint());
  } catch (const InputError& e) {
    // The stages' own errors start with the stage.
    const std::string what = e.what();
    if (what.rfind("reconstructing", 0) == 0 || what.rfind("decimating", 0) == 0) throw;
    throw InputError(a.target + ": " + what);
  }
  for (const std::string& note : f.target_notes) std::cerr << "rgbmesh: note: " << one_line(a.target + ": " + note) << "\n";
  for (const std::string& note : f.notes) std::cerr << "rgbmesh: note: " << one_line(note) << "\n";
  const std::size_t notes_before_fit = f.notes.size();
  const double needed = fit::estimated_fit_bytes(f.targets.size(), f.base.mesh.triangles.size(), a.levels);
  if (needed > static_cast<double>(ceiling.headroom()))
    throw ResourceError("fitting " + fit::with_thousands(f.targets.size()) + " targets at level " +
                        std::to_string(a.levels) + " needs about " + human_bytes(needed) + ", more than the " +
                        human_bytes(static_cast<double>(ceiling.headroom())) + " free under the memory limit of " +
                        ceiling.describe() + ": average the points first, or lower --levels or --base-faces");
  // One run per folder (run_lock.hpp): locked before the previous run's files are removed.
  create_output_directory(a.out);
  const RunLock lock(a.out);
  prepare_output_directory(a.out);

  std::printf(
      "rgbmesh fit: %s target points%s; base (%s) %s vertices / %s triangles, %s; limit surface at level "
      "%d\n",
      fit::with_thousands(f.targets.size()).c_str(),
      f.target_is_surface ? (" (the mesh's " + fit::with_thousands(f.target_surface.points.size()) +
                             " vertices and points spread over its " +
                             fit::with_thousands(f.target_surface.triangles.size()) + " triangles)")
                                .c_str()
                          : "",
      fit::to_string(f.base.source), fit::with_thousands(f.base.mesh.points.size()).c_str(),
      fit::with_thousands(f.base.mesh.triangles.size()).c_str(), fit::to_string(f.base.topology).c_str(), a.levels);
  std::printf("iteration         rms         max   rms/diag  back/diag   seconds\n");
  const double diagonal = bounding_box_diagonal(f.targets);
  fit::run_target_fit(
      f, options,
      [&](const fit::IterationReport& it) {
        std::printf("%9d  %10.4e  %10.4e  %9.2e  %9.2e  %8.3f\n", it.iteration, it.rms, it.max, it.rms / diagonal,
                    it.surface_rms / diagonal, it.seconds);
        std::fflush(stdout);
      },
      control);
  for (std::size_t i = notes_before_fit; i < f.notes.size(); ++i)
    std::cerr << "rgbmesh: note: " << one_line(f.notes[i]) << "\n";
  const auto elapsed = [&start] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  std::vector<Attempt> attempts = {attempt_of(f, a.base_faces, a.levels, elapsed())};

  // Escalation: a rejected fit of a base built from the target is tried again with what the
  // rejection would advise, a finer base (twice, then four times the faces) and then one more
  // level, while the attempt's predicted time (the first one's, scaled by faces and by 4 per
  // level) fits in --retry-seconds, its memory under the ceiling and its base in
  // --max-base-faces. The best attempt (accepted, or the smallest of the two maxima) is written.
  FitArgs used = a;
  if (!f.verdict.accepted && a.retry && a.base.empty()) {
    const double first_seconds = attempts.front().seconds;
    const std::size_t faces = a.base_faces;
    const std::vector<std::pair<std::size_t, int>> steps = {
        {2 * faces, a.levels}, {4 * faces, a.levels}, {4 * faces, std::min(a.levels + 1, 6)}};
    const std::size_t total = steps.size() + 1;
    std::optional<fit::Base> last_base;
    std::printf("rgbmesh fit: attempt 1 of %zu: %s\n", total, describe(attempts.front()).c_str());
    std::size_t number = 1;
    for (const auto& [step_faces, step_levels] : steps) {
      ++number;
      const std::string head = "rgbmesh fit: attempt " + std::to_string(number) + " of " + std::to_string(total) + ": ";
      if (step_faces > a.max_base_faces) {
        std::printf("%sskipped: a base of %s faces is beyond --max-base-faces %s\n", head.c_str(),
                    fit::with_thousands(step_faces).c_str(), fit::with_thousands(a.max_base_faces).c_str());
        continue;
      }
      const double predicted = first_seconds * static_cast<double>(step_faces) / static_cast<double>(faces) *
                               std::pow(4.0, step_levels - a.levels);
      if (elapsed() + predicted > a.retry_seconds) {
        std::printf("%sskipped: it would take about %.0f s, beyond --retry-seconds %.0f\n", head.c_str(), predicted,
                    a.retry_seconds);
        break;
      }
      if (fit::estimated_fit_bytes(f.targets.size(), step_faces, step_levels) > static_cast<double>(ceiling.headroom())) {
        std::printf("%sskipped: it would need more than the memory limit of %s\n", head.c_str(),
                    ceiling.describe().c_str());
        break;
      }
      fit::TargetFitOptions retry_options = options;
      retry_options.base.faces = step_faces;
      retry_options.fit.levels = step_levels;
      const double begin = elapsed();
      fit::TargetFit g;
      try {
        // One more level on the same base: the base of the previous attempt, not made again.
        std::optional<fit::Base> same_base;
        if (last_base && attempts.back().base_faces == step_faces) same_base = last_base;
        g = fit::prepare_target_fit(soup, cloud.normals, same_base, retry_options, control);
        if (same_base) g.base.source = last_base->source;
        fit::run_target_fit(g, retry_options, {}, control);
      } catch (const std::exception& e) {
        // An attempt that fails (a reconstruction that CGAL gives up on, the memory ceiling)
        // ends the escalation; the attempts so far stand.
        std::printf("%sfailed, no more attempts: %s\n", head.c_str(), one_line(e.what()).c_str());
        break;
      }
      attempts.push_back(attempt_of(g, step_faces, step_levels, elapsed() - begin));
      last_base = g.base;
      std::printf("%s%s\n", head.c_str(), describe(attempts.back()).c_str());
      std::fflush(stdout);
      const Attempt& best = *std::min_element(attempts.begin(), attempts.end() - 1, [](const Attempt& x, const Attempt& y) {
        return x.badness() < y.badness();
      });
      if (g.verdict.accepted || attempts.back().badness() < best.badness()) {
        f = std::move(g);
        used.base_faces = step_faces;
        used.levels = step_levels;
      }
      if (attempts.back().accepted) break;
    }
    if (f.verdict.accepted || attempts.size() > 1)
      std::printf("rgbmesh fit: kept the base of %s faces at level %d (%s)\n", fit::with_thousands(used.base_faces).c_str(),
                  used.levels, f.verdict.accepted ? "accepted" : "the closest of the attempts");
  }

  write_outputs(used, f);
  const double total_seconds = elapsed();
  if (!a.report.empty()) write_report(used, cloud, f, total_seconds, attempts);
  const fit::FitResult& r = f.result;
  const fit::TwoSidedDistances& d = f.distances;
  std::printf(
      "targets to surface: rms %.3e (%.4f%% of the diagonal), max %.3e (%.4f%%)\n"
      "surface to target:  rms %.3e (%.4f%%), max %.3e (%.4f%%)\n"
      "fit %.2f s, total %.2f s; wrote %s\n",
      r.rms, 100 * r.rms / r.diagonal, r.max, 100 * r.max / r.diagonal, d.to_target_rms,
      100 * d.to_target_rms / r.diagonal, d.to_target_max, 100 * d.to_target_max / r.diagonal, r.seconds,
      total_seconds, a.out.c_str());
  std::fflush(stdout);
  if (!f.verdict.accepted) {
    if (attempts.size() > 1)
      throw InputError(f.verdict.reason + "; " + std::to_string(attempts.size()) + " attempts (finer bases, more levels), " +
                       "the closest written; " + a.out +
                       "/limit_surface.vtp shows where (point data distance_to_target). A base of your own (--base), "
                       "--sharp-angle for a part with edges, or for a cloud more points may fit");
    throw InputError(f.verdict.reason + "; " + a.out +
                     "/limit_surface.vtp shows where (point data distance_to_target). A finer base (--base-faces), "
                     "more levels (--levels) or a base of your own (--base) may fit; for a cloud, more points");
  }
  return 0;
}

void FitCommand::add(CLI::App& tool, CompressionOption& compression) {
  app = tool.add_subcommand(
      "fit",
      "Fit a Loop subdivision surface to points: move the base mesh's control points so that the\n"
      "limit surface passes through the targets (Ceres). Writes base.obj, fitted_base.obj,\n"
      "initial_limit_surface.vtp, limit_surface.vtp and targets.vtp into --out.");
  app->add_option("--target", args.target,
                  "Target points: a point cloud (" + supported_point_cloud_extensions() +
                      ", or a mesh format without faces) or a mesh (its vertices)")
      ->required()
      ->check(kNonEmptyPath);
  auto* fit_base = app->add_option("--base", args.base, "Base mesh (its points are the starting controls)")
                       ->check(kNonEmptyPath);
  app->add_option(
         "--base-faces", args.base_faces,
         "Without --base: triangles of the base built from the target (decimated, or reconstructed from a "
         "cloud and decimated)")
      ->capture_default_str()
      ->check(number_in("an integer in [4, 10^8]", [](double x) { return x >= 4 && x <= 1e8; }))
      ->excludes(fit_base);
  app->add_flag("--triangulate", args.triangulate, "Split polygons of the --target and --base faces into triangles");
  app->add_flag(
      "--ignore-faces", args.ignore_faces,
      "Fit the --target's vertices as a point cloud, whatever its faces (by default a mesh target is "
      "the surface its faces make)");
  app->add_option(
         "--reconstruction", args.reconstruction,
         "How a point cloud's base surface is reconstructed: automatic (Poisson where the points enclose a "
         "volume, else advancing front), poisson (closed) or advancing-front (open where the points are)")
      ->capture_default_str();
  app->add_flag("--repair", args.repair,
                "Repair the --target faces and the --base mesh first (as info --repair)");
  app->add_option("--sharp-angle", args.sharp_angle,
                  "Keep a CAD target's edges: its edges sharper than DEG degrees become creases of the base, "
                  "which decimation keeps and the fitted surface follows (a mesh target or --base)")
      ->type_name("DEG")
      ->check(number_in("a number of degrees in (0, 180)", [](double x) { return x > 0.0 && x < 180.0; }));
  app->add_option("--levels", args.levels, "Uniform level of the limit surface used in the fit")
      ->capture_default_str()
      ->check(number_in("an integer in [1, 6]", [](double x) { return x >= 1 && x <= 6; }));
  app->add_option("--loss", args.loss, "huber, cauchy or none")->capture_default_str();
  app->add_option("--smooth", args.smooth, "Weight of the control-net smoothness term")
      ->capture_default_str()
      ->check(number_in("a finite number >= 0", [](double x) { return x >= 0 && std::isfinite(x); }));
  app->add_option("--iterations", args.iterations, "Maximum outer iterations")
      ->capture_default_str()
      ->check(number_in("an integer in [1, 1000]", [](double x) { return x >= 1 && x <= 1000; }));
  out = app->add_option("--out", args.out, "Output directory")->capture_default_str()->check(kNonEmptyPath);
  app->add_option("--report", args.report, "Write a JSON report to this file")->check(kNonEmptyPath);
  app->add_flag("!--no-retry", args.retry,
                "Without --base, a rejected fit is not tried again with finer bases and one more level");
  app->add_option("--retry-seconds", args.retry_seconds,
                  "Time the attempts after a rejected fit may take, the first one's included (predicted from it)")
      ->capture_default_str()
      ->check(number_in("a number of seconds >= 0", [](double x) { return x >= 0 && std::isfinite(x); }));
  app->add_option("--max-base-faces", args.max_base_faces, "The largest base the attempts after a rejected fit try")
      ->capture_default_str()
      ->check(number_in("an integer in [4, 10^8]", [](double x) { return x >= 4 && x <= 1e8; }));
  compression.add_to(*app);
}

}  // namespace rgbmesh::cli
