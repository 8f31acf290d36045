// Example 03: a moving peak, followed by refining ahead and coarsening behind.
//
// The peak of example 02 travels a quarter of a great circle in 24 time steps. At each step
// the mesh is adapted twice to the peak's new place: the estimator is large where the peak
// has arrived (those triangles are refined) and small where it has left (vertices there are
// removed through the RGB coarsening queue, section V of the paper). The number of triangles
// stays about constant while the refined region moves: the continuous level of detail the
// RGB operators were designed for, here driven by a finite-element error.

#include <cstdio>
#include <filesystem>
#include <string>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

int main(int argc, char** argv) {
  const std::filesystem::path out = argc > 1 ? argv[1] : "out/03_moving_peak";
  std::filesystem::create_directories(out);

  const TriangleMeshData ico = icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  selective_refinement(mesh, UniformLevel(1));

  adapt::AdaptOptions options;
  options.projection = fem::Projection(fem::project_to_unit_sphere);
  options.theta = 0.5;

  // Resolve the peak where it starts (refinement only).
  options.max_cycles = 10;
  options.max_dofs = 20000;
  const auto start = adapt::run_cycles(mesh, adapt::moving_peak(0.0), options);

  // Then follow it: two adaptation cycles per step. Each refines the triangles whose
  // indicator exceeds an equal share of the error reached at the start (equidistribution),
  // and coarsens vertices whose star indicator is below a quarter of the mean.
  options.marking = adapt::Marking::equidistribution;
  options.target_estimate = start.back().estimate;
  options.coarsen_below = 0.25;
  std::vector<std::pair<double, std::string>> series;
  std::printf(" step   time  triangles  inserted  removed    error_H1\n");
  adapt::run_dynamic(
      mesh, [](double t) { return adapt::moving_peak(t); }, 24, 2, options, [&](const adapt::CycleState& s) {
        const auto& r = s.report;
        const std::string file = "step_" + std::to_string(r.cycle) + ".vtp";
        write_mesh(out / file, adapt::snapshot(s));
        series.emplace_back(r.time, file);
        std::printf("%5d  %5.3f  %9zu  %8zu  %7zu  %10.3e\n", r.cycle, r.time, r.triangles, r.splits, r.removals,
                    *r.error_h1);
      });
  write_pvd(out / "moving_peak.pvd", series);
  std::printf("wrote %s\n", (out / "moving_peak.pvd").c_str());
  return 0;
}
