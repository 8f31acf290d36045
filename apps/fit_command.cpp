#include "fit_command.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "json.hpp"
#include "output_dir.hpp"
#include "rgbmesh/fit/base.hpp"
#include "rgbmesh/fit/fit.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/repair/repair.hpp"
#include "rgbmesh/vtk_io.hpp"
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

// The base: --base as given, or built from the target.
fit::Base base_for(const FitArgs& a, const PointCloud& target) {
  const SoupOptions soup_options = repair::soup_options(a.triangulate, a.repair);
  if (!a.base.empty()) {
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
  PolygonSoup soup;
  soup.points = target.points;
  soup.faces = target.faces;
  soup.numbered_vertices = target.numbered_vertices;
  std::vector<std::string> repaired;  // the repair's notes, first among the base's
  if (a.repair && !soup.faces.empty()) soup = repair::repaired_soup(soup, a.triangulate, repaired);
  fit::BaseOptions options;
  options.faces = a.base_faces;
  options.triangulate = a.triangulate;
  // (A repair changes the points: the file's normals then belong to none of them.)
  const bool same_points = soup.points.size() == target.normals.size();
  fit::Base base = fit::make_base(soup, same_points ? target.normals : std::vector<Vec3>{}, options);
  for (auto note = repaired.rbegin(); note != repaired.rend(); ++note)
    base.notes.insert(base.notes.begin(), a.target + ": " + *note);
  return base;
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

}  // namespace

int run_fit(const FitArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  const fit::FitOptions options = fit_options(a);
  const PointCloud target = read_point_cloud(a.target);
  for (const std::string& note : target.notes) std::cerr << "rgbmesh: note: " << note << "\n";
  const fit::Base base = base_for(a, target);
  for (const std::string& note : base.notes) std::cerr << "rgbmesh: note: " << note << "\n";
  prepare_output_directory(a.out);

  std::printf(
      "rgbmesh fit: %s target points%s; base (%s) %s vertices / %s triangles, %s; limit surface at level "
      "%d\n",
      fit::with_thousands(target.points.size()).c_str(), target.faces.empty() ? "" : " (mesh vertices)",
      fit::to_string(base.source), fit::with_thousands(base.mesh.points.size()).c_str(),
      fit::with_thousands(base.mesh.triangles.size()).c_str(), fit::to_string(base.topology).c_str(),
      a.levels);
  std::printf("iteration         rms         max   rms/diag   seconds\n");
  const double diagonal = bounding_box_diagonal(target.points);
  const fit::FitResult r = fit::fit(base.mesh, target.points, options, [&](const fit::IterationReport& it) {
    std::printf("%9d  %10.4e  %10.4e  %9.2e  %8.3f\n", it.iteration, it.rms, it.max, it.rms / diagonal, it.seconds);
    std::fflush(stdout);
  });

  for (const std::string& note : r.notes) std::cerr << "rgbmesh: note: " << note << "\n";

  const fs::path dir(a.out);
  write_mesh(dir / "base.obj", RgbMesh::from_triangles(base.mesh.points, base.mesh.triangles).snapshot());
  write_mesh(dir / "fitted_base.obj",
             RgbMesh::from_triangles(r.control_points, base.mesh.triangles).snapshot());
  MeshSnapshot limit = limit_snapshot(r.stencils, r.control_points);
  fit::TriangleDistances per_triangle = fit::distances_per_triangle(r);
  limit.cell_data.push_back({"targets", 1, std::move(per_triangle.targets)});
  limit.cell_data.push_back({"rms_distance", 1, std::move(per_triangle.rms_distance)});
  const auto vtk_options = [&](const char* file) { return output_options((dir / file).string(), a.compression); };
  write_mesh(dir / "limit_surface.vtp", limit, vtk_options("limit_surface.vtp"));
  // The limit surface of the starting base, for comparison (subdivision shrinks a coarse base).
  write_mesh(dir / "initial_limit_surface.vtp", limit_snapshot(r.stencils, base.mesh.points),
             vtk_options("initial_limit_surface.vtp"));
  write_point_cloud(dir / "targets.vtp", target.points, {{"distance", 1, r.distance}}, vtk_options("targets.vtp"));
  const double total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (!a.report.empty()) {
    std::vector<std::string> iterations, notes;
    for (const fit::IterationReport& it : r.iterations)
      iterations.push_back(JsonObject()
                               .add("iteration", it.iteration)
                               .add("rms", it.rms)
                               .add("max", it.max)
                               .add("seconds", it.seconds)
                               .str());
    for (const std::string& note : target.notes) notes.push_back(JsonObject::quote(note));
    for (const std::string& note : base.notes) notes.push_back(JsonObject::quote(note));
    for (const std::string& note : r.notes) notes.push_back(JsonObject::quote(note));
    const std::string target_json = JsonObject()
                                        .add("file", a.target)
                                        .add("points", static_cast<std::uint64_t>(target.points.size()))
                                        .add("faces", static_cast<std::uint64_t>(target.faces.size()))
                                        .raw("normals", target.normals.empty() ? "false" : "true")
                                        .str();
    JsonObject base_json;
    base_json.add("source", fit::to_string(base.source));
    if (!a.base.empty()) base_json.add("file", a.base);
    if (a.base.empty()) base_json.add("requested_faces", static_cast<std::uint64_t>(a.base_faces));
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
    report.raw("target", target_json)
        .raw("base", base_json.str())
        .raw("notes", json_list(notes))
        .raw("settings", JsonObject()
                             .add("levels", a.levels)
                             .add("loss", a.loss)
                             .add("smooth", a.smooth)
                             .add("iterations", a.iterations)
                             .str())
        .add("smooth_used", r.smooth)
        .raw("iterations", json_list(iterations))
        .raw("rms", exact(r.rms))
        .raw("max", exact(r.max))
        .raw("diagonal", exact(r.diagonal))
        .add("rms_relative", r.rms / r.diagonal)
        .add("max_relative", r.max / r.diagonal)
        .add("seconds", r.seconds)
        .add("total_seconds", total_seconds);
    write_text_atomically(a.report, report.str() + "\n");
  }
  std::printf("rms %.3e (%.4f%% of the diagonal), max %.3e (%.4f%%); fit %.2f s, total %.2f s; wrote %s\n",
              r.rms, 100 * r.rms / r.diagonal, r.max, 100 * r.max / r.diagonal, r.seconds, total_seconds,
              a.out.c_str());
  return 0;
}

}  // namespace rgbmesh::cli
