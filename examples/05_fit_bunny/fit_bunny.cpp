// Example 05: a subdivision surface fitted to a scan.
//
// The Stanford bunny's 1,839 scanned points are the targets. The base mesh is the scan
// decimated to 1,000 triangles by topology-preserving edge collapse (CGAL's, with quadric
// error metrics and a check of the link condition, so the base is a valid manifold with the
// scan's topology); its own Loop limit surface is visibly shrunk (subdivision smooths a coarse
// net inwards: thin ears, a flat back). The fit moves the 502 control points so that the limit
// surface passes through the scan: footpoints on the current surface, point-to-plane residuals
// through the limit stencils of the control points, a Huber loss, a small control-net
// smoothness term, Ceres.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "rgbmesh/fit/base.hpp"
#include "rgbmesh/fit/fit.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

int main(int argc, char** argv) {
  CLI::App app{"Example 05: a Loop subdivision surface fitted to the Stanford bunny scan."};
  std::string input = RGBMESH_EXAMPLE_DATA_DIR "/bunny.obj";  // the repository's copy, wherever we run
  std::string out_dir = "out/05_fit_bunny";
  app.add_option("MESH", input, "The bunny (data/bunny.obj in the rgbmesh repository)")->capture_default_str();
  app.add_option("OUT", out_dir, "Output folder (base.obj, fitted_base.obj)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  const std::filesystem::path out = out_dir;
  if (!std::filesystem::exists(input)) {
    std::fprintf(stderr, "example_05_fit_bunny: %s does not exist: give the path of data/bunny.obj of the rgbmesh "
                 "repository as the first argument\n", input.c_str());
    return 2;
  }
  std::filesystem::create_directories(out);

  const TriangleMeshData scan = read_mesh(input);
  const TriangleMeshData base = fit::decimate(scan, 1000, "the bunny");
  for (const auto& note : base.notes) std::printf("note: %s\n", note.c_str());

  fit::FitOptions options;  // level 3 limit surface, Huber loss, smoothness 1e-3
  std::printf("iteration          rms          max\n");
  const fit::FitResult r = fit::fit(base, scan.points, options, [](const fit::IterationReport& it) {
    std::printf("%9d   %10.4e   %10.4e\n", it.iteration, it.rms, it.max);
  });
  std::printf("final: rms %.4f%% and max %.4f%% of the bounding-box diagonal, %.2f s\n", 100 * r.rms / r.diagonal,
              100 * r.max / r.diagonal, r.seconds);

  write_mesh(out / "fitted_base.obj", RgbMesh::from_triangles(r.control_points, base.triangles).snapshot());
  write_mesh(out / "base.obj", RgbMesh::from_triangles(base.points, base.triangles).snapshot());
  std::printf("wrote %s and %s\n", (out / "base.obj").c_str(), (out / "fitted_base.obj").c_str());
  return 0;
}
