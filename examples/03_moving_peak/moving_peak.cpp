// Example 03: a moving peak, followed by refining ahead and coarsening behind.
//
// The peak of example 02 travels a quarter of a great circle in 24 time steps. The mesh is
// first adapted to the peak where it starts; the estimate reached there becomes the target.
// At each step the mesh is then adapted twice to the peak's new place by equidistribution:
// every triangle whose indicator exceeds an equal share of the target, target / sqrt(N), is
// refined, and every vertex whose largest indicator over its star is below a quarter of that
// share is removed through the RGB coarsening queue (section V of the paper). Refinement and
// coarsening measure against the same share, so the fine patch leaves behind as much as it
// gains ahead: the number of triangles stays constant and the finest triangles stay centred
// on the peak. This is the continuous level of detail the RGB operators were designed for,
// here driven by a finite-element error.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

int main(int argc, char** argv) {
  CLI::App app{"Example 03: a moving peak on the unit sphere, followed by refining ahead and coarsening behind."};
  std::string out_dir = "out/03_moving_peak";
  app.add_option("OUT", out_dir, "Output folder (one .vtp per step and moving_peak.pvd)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  const std::filesystem::path out = out_dir;
  std::filesystem::create_directories(out);

  const TriangleMeshData ico = icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  selective_refinement(mesh, UniformLevel(1));

  adapt::AdaptOptions options;
  options.projection = fem::Projection(fem::project_to_unit_sphere);
  options.marking =
      std::make_shared<adapt::EquidistributionMarking>();  // target: the estimate reached at the start
  options.coarsen_below = 0.25;
  adapt::DynamicOptions dynamic;  // 24 steps, 2 adaptations per step, 8 cycles for the start
  dynamic.on_started = [](const std::vector<adapt::CycleReport>& start, double target) {
    std::printf("adapted to the start in %zu cycles (%zu unknowns); target estimate %.3e\n", start.size(),
                start.back().dofs, target);
  };

  std::vector<std::pair<double, std::string>> series;
  std::printf(" step   time  triangles  inserted  removed    error_H1\n");
  adapt::run_dynamic(
      mesh, [](double t) { return adapt::moving_peak(t); }, options, dynamic, [&](const adapt::CycleState& s) {
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
