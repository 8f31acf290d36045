#include "fit_command.hpp"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "json.hpp"
#include "rgbmesh/fit/fit.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::cli {

int run_fit(const FitArgs& a) {
  namespace fs = std::filesystem;
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
  o.levels = a.levels;
  o.smooth = a.smooth;
  o.max_iterations = a.iterations;

  const std::vector<Vec3> targets = fit::read_points(a.target);
  TriangleMeshData base;
  if (!a.base.empty()) {
    base = read_mesh(a.base);
  } else {
    if (a.base_faces < 4) throw InputError("--base-faces: must be at least 4");
    base = fit::decimate(read_mesh(a.target), a.base_faces);
  }
  fs::create_directories(a.out);
  std::printf("rgbmesh fit: %zu target points, base %zu vertices / %zu triangles, limit surface at level %d\n",
              targets.size(), base.points.size(), base.triangles.size(), a.levels);
  std::printf("iteration         rms         max   rms/diag   seconds\n");
  const double diagonal = bounding_box_diagonal(targets);
  const fit::FitResult r = fit::fit(base, targets, o, [&](const fit::IterationReport& it) {
    std::printf("%9d  %10.4e  %10.4e  %9.2e  %8.3f\n", it.iteration, it.rms, it.max, it.rms / diagonal, it.seconds);
    std::fflush(stdout);
  });

  // The fitted base mesh, and the limit surface with each vertex's distance to the targets.
  const RgbMesh fitted = RgbMesh::from_triangles(r.control_points, base.triangles);
  write_mesh(fs::path(a.out) / "fitted_base.obj", fitted.snapshot());
  auto limit_snapshot = [&](const std::vector<Vec3>& controls, std::vector<double> distance) {
    MeshSnapshot limit;
    limit.points = r.stencils.evaluate(controls);
    limit.triangles = r.stencils.triangles;
    limit.vertex_level.assign(limit.points.size(), 0);
    limit.triangle_level.assign(limit.triangles.size(), 0);
    limit.triangle_color.assign(limit.triangles.size(), Color::green);
    if (!distance.empty()) limit.point_data.push_back({"distance", 1, std::move(distance)});
    return limit;
  };
  write_mesh(fs::path(a.out) / "limit_surface.vtp", limit_snapshot(r.control_points, r.distance));
  // The limit surface of the starting base, for comparison (subdivision shrinks a coarse base).
  write_mesh(fs::path(a.out) / "initial_limit_surface.vtp", limit_snapshot(base.points, {}));

  if (!a.report.empty()) {
    std::string its = "[";
    for (std::size_t i = 0; i < r.iterations.size(); ++i)
      its += (i ? ", " : "") + JsonObject()
                                   .add("iteration", r.iterations[i].iteration)
                                   .add("rms", r.iterations[i].rms)
                                   .add("max", r.iterations[i].max)
                                   .add("seconds", r.iterations[i].seconds)
                                   .str();
    its += "]";
    write_text_atomically(a.report, JsonObject()
                                        .raw("iterations", its)
                                        .add("rms_relative", r.rms / r.diagonal)
                                        .add("max_relative", r.max / r.diagonal)
                                        .add("seconds", r.seconds)
                                        .str() +
                                        "\n");
  }
  std::printf("rms %.3e (%.4f%% of the diagonal), max %.3e (%.4f%%), %.2f s; wrote %s and %s\n", r.rms,
              100 * r.rms / r.diagonal, r.max, 100 * r.max / r.diagonal, r.seconds,
              (fs::path(a.out) / "fitted_base.obj").c_str(), (fs::path(a.out) / "limit_surface.vtp").c_str());
  return 0;
}

}  // namespace rgbmesh::cli
