// Example 05: a subdivision surface fitted to a scan.
//
// The Stanford bunny's 1,839 scanned points are the targets. The base mesh is the scan
// decimated by VTK's quadric decimation to 1,000 triangles; its own Loop limit surface is
// visibly shrunk (subdivision smooths a coarse net inwards: thin ears, a flat back). The fit
// moves the 502 control points so that the limit surface passes through the scan: footpoints on
// the current surface (a cell locator), point-to-plane residuals through the limit stencils of
// the control points, a Huber loss, a small control-net smoothness term, Ceres.

#include <cstdio>
#include <filesystem>
#include <string>

#include "rgbmesh/fit/fit.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

int main(int argc, char** argv) {
  const std::string input = argc > 1 ? argv[1] : "data/bunny.obj";
  const std::filesystem::path out = argc > 2 ? argv[2] : "out/05_fit_bunny";
  std::filesystem::create_directories(out);

  const TriangleMeshData scan = read_mesh(input);
  const TriangleMeshData base = fit::decimate(scan, 1000);

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
