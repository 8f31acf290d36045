// Example 06: the adaptive loop of example 02 on several MPI processes.
//
// The same problem as example 02 (-Δu + u = f on the unit sphere, a sharp peak, exact geometry),
// run with `mpirun -np P`. Every process builds the same start mesh and calls the same
// adapt::run_cycles; parallel::distribute_mesh gives the loop what it needs to distribute the
// mesh itself: each cycle the triangles above the floor (--min-level) are divided among the
// processes, each process keeps only its part and two layers of neighbours as the whole mesh
// has them (the rest coarse), assembles and estimates its own triangles, the linear system is
// solved on all of them (CG with BoomerAMG through PETSc), and the splits that cross between
// parts are handed over. The result does not depend on the number of processes; rank 0
// prints it.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <vector>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/parallel/distributed_mesh.hpp"
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
  options.marking = std::make_shared<adapt::DorflerMarking>(0.5);
  options.projection = fem::Projection(fem::project_to_unit_sphere);
  options.max_cycles = cycles;
  options.min_level = floor;  // refined to it first: the units the processes share lie above it
  parallel::distribute_mesh(options);

  const int processes = parallel::processes();
  if (speaks)
    std::printf("%d processes\n  cycle      dofs    error_H1    estimate   triangles  most/mean  held/own  sent (kB)\n",
                processes);
  adapt::run_cycles(mesh, fem::sphere_peak(), options, [&](const adapt::CycleState& s) {
    const adapt::CycleReport& r = s.report;
    // How evenly the triangles were divided (the largest part over the mean), and how many
    // triangles the process holding the most held per own triangle (its part, its ghost
    // layers and the coarse rest: its memory beside its share).
    std::vector<double> own(static_cast<std::size_t>(processes), 0.0), held(own);
    const auto me = static_cast<std::size_t>(parallel::rank());
    for (const std::int32_t p : s.solved->triangle_part) own[me] += p == parallel::rank() ? 1 : 0;
    if (s.solved->triangle_part.empty()) own[me] = static_cast<double>(s.fe.triangles.size());  // one process
    held[me] = static_cast<double>(s.fe.triangles.size()) / std::max(1.0, own[me]);
    parallel::sum(own.data(), own.size());
    parallel::sum(held.data(), held.size());
    const double balance = *std::max_element(own.begin(), own.end()) * processes / static_cast<double>(r.triangles);
    const double held_most = *std::max_element(held.begin(), held.end());
    if (speaks)
      std::printf("  %5d %9zu  %10.3e  %10.3e  %10zu  %9.3f  %8.2f  %9.1f\n", r.cycle, r.dofs, *r.error_h1, r.estimate,
                  r.triangles, balance, held_most, static_cast<double>(r.bytes_sent) / 1e3);
  });
  return 0;
}
