// Example 04: a heat source on a scanned shape, on the Loop limit surface.
//
// The base mesh is the Stanford bunny (3,674 triangles). There is no exact geometry here:
// the finite-element vertices sit on the Loop limit surface of the bunny (their limit
// positions), so every refinement brings the flat triangles closer to the smooth surface,
// and the residual estimator's geometric term accounts for the remaining distance. We solve
// -Δu + u = f for a narrow Gaussian source f on the bunny's back and let the adaptive loop
// concentrate the mesh around it.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

int main(int argc, char** argv) {
  CLI::App app{"Example 04: adaptive finite elements for a heat source on the bunny's Loop limit surface."};
  std::string input = RGBMESH_EXAMPLE_DATA_DIR "/bunny.obj";  // the repository's copy, wherever we run
  std::string out_dir = "out/04_bunny_source";
  app.add_option("MESH", input, "The bunny (data/bunny.obj in the rgbmesh repository)")->capture_default_str();
  app.add_option("OUT", out_dir, "Output folder (one .vtp per cycle and bunny.pvd)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  const std::filesystem::path out = out_dir;
  if (!std::filesystem::exists(input)) {
    std::fprintf(stderr, "example_04_bunny_source: %s does not exist: give the path of data/bunny.obj of the rgbmesh "
                 "repository as the first argument\n", input.c_str());
    return 2;
  }
  std::filesystem::create_directories(out);

  const TriangleMeshData bunny = read_mesh(input);
  RgbMesh mesh = RgbMesh::from_triangles(bunny.points, bunny.triangles);

  // The source: a Gaussian of width 0.08 (the bunny is about 3 units long) centred on the
  // limit surface at the base vertex with the largest y (the top of the back).
  VertexHandle top(0);
  for (VertexHandle v : mesh.vertices())
    if (mesh.insertion_point(v).y > mesh.insertion_point(top).y) top = v;
  const fem::Problem problem = fem::gaussian_source(mesh.limit_position(top), 0.08);

  adapt::AdaptOptions options;  // Loop geometry: no projection
  options.marking = std::make_shared<adapt::DorflerMarking>(0.5);
  options.max_cycles = 10;
  options.max_dofs = 60000;

  std::vector<std::pair<double, std::string>> series;
  std::printf("cycle  triangles      dofs    estimate   seconds  (adapt)\n");
  adapt::run_cycles(mesh, problem, options, [&](const adapt::CycleState& s) {
    const auto& r = s.report;
    const std::string file = "cycle_" + std::to_string(r.cycle) + ".vtp";
    write_mesh(out / file, adapt::snapshot(s));
    series.emplace_back(r.cycle, file);
    std::printf("%5d  %9zu  %8zu  %10.3e  %8.3f  %7.3f\n", r.cycle, r.triangles, r.dofs, r.estimate, r.seconds,
                r.adapt_seconds);
  });
  write_pvd(out / "bunny.pvd", series);
  std::printf("wrote %s\n", (out / "bunny.pvd").c_str());
  return 0;
}
