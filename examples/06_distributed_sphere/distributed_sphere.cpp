// Example 06: the adaptive loop of example 02 on several MPI processes.
//
// The same problem as example 02 (-Δu + u = f on the unit sphere, a sharp peak, exact geometry),
// run with `mpirun -np P`. Every process builds the same start mesh and calls the same
// adapt::run_cycles; parallel::distribute gives the loop what it needs to share the work: each
// cycle the triangles above the floor (--min-level) are divided among the processes, each
// process assembles and estimates its own, the linear system is solved on all of them (CG with
// BoomerAMG through PETSc), and the indicators are exchanged so that every process adapts the
// same mesh. The result does not depend on the number of processes; rank 0 prints it.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <vector>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/parallel/adaptive.hpp"
#include "rgbmesh/parallel/mpi.hpp"
#include "rgbmesh/shapes.hpp"

using namespace rgbmesh;

int main(int argc, char** argv) {
  parallel::initialize(&argc, &argv);  // MPI and PETSc, finished at exit
  CLI::App app{"Example 06: adaptive refinement for a sharp peak on the unit sphere, on every process of an MPI run."};
  int cycles = 14, floor = 2;
  app.add_option("--cycles", cycles, "Cycles of the adaptive loop")->capture_default_str()->check(CLI::Range(1, 40));
  app.add_option("--min-level", floor, "The floor: no triangle coarser than this level")
      ->capture_default_str()
      ->check(CLI::Range(0, 5));
  CLI11_PARSE(app, argc, argv);
  const bool speaks = parallel::rank() == 0;

  const TriangleMeshData ico = icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  adapt::AdaptOptions options;
  options.theta = 0.5;
  options.projection = fem::Projection(fem::project_to_unit_sphere);
  options.max_cycles = cycles;
  options.min_level = floor;  // refined to it first: the units the processes share lie above it
  parallel::distribute(options);

  if (speaks)
    std::printf("%d processes\n  cycle      dofs    error_H1    estimate   triangles  most/mean  sent (kB)\n",
                parallel::processes());
  adapt::run_cycles(mesh, fem::sphere_peak(), options, [&](const adapt::CycleState& s) {
    const adapt::CycleReport& r = s.report;
    // How evenly the triangles of the cycle were divided (each FE triangle's process).
    double balance = 1;
    if (s.solved != nullptr && !s.solved->triangle_part.empty()) {
      std::vector<double> count(static_cast<std::size_t>(parallel::processes()), 0.0);
      for (const std::int32_t p : s.solved->triangle_part) count[static_cast<std::size_t>(p)] += 1;
      balance = *std::max_element(count.begin(), count.end()) * static_cast<double>(count.size()) /
                static_cast<double>(s.solved->triangle_part.size());
    }
    if (speaks)
      std::printf("  %5d %9zu  %10.3e  %10.3e  %10zu  %9.3f  %9.1f\n", r.cycle, r.dofs, *r.error_h1, r.estimate,
                  r.triangles, balance, static_cast<double>(r.bytes_sent) / 1e3);
  });
  return 0;
}
