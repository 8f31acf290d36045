// Example 08: the clamped Kirchhoff plate with Loop-basis elements.
//
// A square plate [0, 1]² of rigidity D = 1, clamped on its four sides (w = 0 and ∂w/∂n = 0),
// under a uniform load q = 1: D Δ²w = q. Its centre deflects by 0.001265319 q L⁴ / D
// (Timoshenko's series). Lagrange elements need a mixed method for Δ²; Loop's basis functions
// are smooth (C², and C¹ at extraordinary vertices), so the weak form ∫ Δw Δv = ∫ q v / D is
// used as it stands. For each lattice
//   1. square_lattice builds the square's mesh with one ring of ghost cells around it,
//   2. build_loop_space(..., LoopBoundary::ghost_ring) makes the triangles with three interior
//      corners the elements; the ghost vertices carry control values only,
//   3. solve_clamped_plate assembles ∫ Δw Δv and clamps the sides weakly (Nitsche's method:
//      the box splines cannot be clamped through their control values without locking),
//   4. the centre deflection is read at the centre vertex (the limit of the regular lattice
//      there is the vertex itself) and compared with the series value.
// With --out, the finest plate is written for ParaView, 16 exact pieces per element.

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>

#include "../exit_codes.hpp"
#include "rgbmesh/fem/loop_plate.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

int main(int argc, char** argv) {
  CLI::App app("Example 08: the clamped square plate with Loop-basis elements");
  int finest = 64;
  double penalty = fem::PlateOptions{}.penalty;
  std::string out;
  app.add_option("--cells", finest, "cells a side of the finest lattice (from 4, doubling)")
      ->check(CLI::Range(4, 512));
  app.add_option("--penalty", penalty,
                 "the factor of Nitsche's penalties (3; above 2 is coercive on any mesh)")
      ->check(CLI::Range(2.0, 1e6));
  app.add_option("--out", out, "write the finest plate's deflection here (.vtp)");
  CLI11_PARSE(app, argc, argv);
  return examples::run_reporting_errors([&] {
    fem::PlateOptions options;
    options.penalty = penalty;
    const fem::PlateProblem plate = fem::clamped_square_plate();
    std::printf("  cells   unknowns   centre deflection   relative error   rate\n");
    double previous = 0;
    for (int cells = 4; cells <= finest; cells *= 2) {
      const TriangleMeshData lattice = square_lattice(cells, 1.0);
      RgbMesh mesh = RgbMesh::from_triangles(lattice.points, lattice.triangles);
      const fem::LoopSpace space =
          fem::build_loop_space(mesh, std::nullopt, {}, fem::LoopBoundary::ghost_ring);
      const fem::Solution w = fem::solve_clamped_plate(space, plate, options);
      const Eigen::VectorXd at_vertices = fem::loop_vertex_values(space, w.u);
      double centre = std::nan("");
      for (std::size_t d = 0; d < space.num_dofs(); ++d)
        if (norm(space.control[d] - Vec3{0.5, 0.5, 0}) < 1e-12)
          centre = at_vertices(static_cast<Eigen::Index>(d));
      const double relative = centre / fem::kClampedSquareCentreDeflection - 1;
      std::printf("  %5d %10zu   %.10f      %+.3e", cells, space.num_dofs(), centre, relative);
      if (previous != 0) std::printf("     %5.2f", std::log2(std::abs(previous / relative)));
      std::printf("\n");
      previous = relative;
      if (!out.empty() && 2 * cells > finest) {
        write_mesh(out, fem::loop_refined_view(space, w.u, 2));
        std::printf("wrote %s: the deflection (point data \"solution\") on %d x %d cells, 16 pieces each\n",
                    out.c_str(), cells, cells);
      }
    }
  });
}
