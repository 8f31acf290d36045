// Example 10: smooth elements up to the boundary, Loop's boundary rules against the completed
// boundary.
//
// The Poisson problem -Δu = f on the unit square with u = g on its sides, exact solution
// u = sin(2x + y) + x y². The mesh is the square itself (no ghost ring around it): Loop's
// boundary rules make its limit surface, whose boundary is the cubic B-spline of the boundary
// vertices (the corners rounded a little), and the exact solution holds on that domain too.
// For each lattice
//   1. square_lattice builds the square's mesh (no ghost cells),
//   2. build_loop_space(..., LoopBoundary::loop_rules) subdivides the functions as the surface
//      (next to the boundary they reproduce linear functions only), and
//      build_loop_space(..., LoopBoundary::completed) adds the functions of ghosts beyond the
//      boundary edges (the mesh completed by a ring of ghost triangles, subdivided by the
//      interior rules), which give the cubics back along the sides,
//   3. solve_loop imposes g by Nitsche's method, loop_error_norms measures the H1 error
//      against the exact solution and loop_residual_estimate the estimate,
//   4. one row per lattice and boundary: unknowns, H1 error, its rate, estimate / error.
// With --out, the finest completed solution is written for ParaView, 16 exact pieces per element.

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>

#include "../exit_codes.hpp"
#include "rgbmesh/fem/loop_elements.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

namespace {

fem::Problem wave() {
  fem::Problem p;
  p.name = "wave";
  p.source = [](const Vec3& x) { return 5 * std::sin(2 * x.x + x.y) - 2 * x.x; };
  p.dirichlet = [](const Vec3& x) { return std::sin(2 * x.x + x.y) + x.x * x.y * x.y; };
  p.exact = fem::ExactSolution{
      [](const Vec3& x) { return std::sin(2 * x.x + x.y) + x.x * x.y * x.y; },
      [](const Vec3& x) {
        return Vec3{2 * std::cos(2 * x.x + x.y) + x.y * x.y, std::cos(2 * x.x + x.y) + 2 * x.x * x.y, 0};
      }};
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Example 10: Loop-basis elements up to the boundary (Loop's rules, completed boundary)");
  int finest = 64;
  std::string out;
  app.add_option("--cells", finest, "cells a side of the finest lattice (from 8, doubling)")
      ->check(CLI::Range(8, 256));
  app.add_option("--out", out, "write the finest completed solution here (.vtp)");
  CLI11_PARSE(app, argc, argv);
  return examples::run_reporting_errors([&] {
    const fem::Problem problem = wave();
    std::printf("  cells   boundary       unknowns   H1 error    rate   estimate / error\n");
    double previous[2] = {0, 0};
    for (int cells = 8; cells <= finest; cells *= 2) {
      const TriangleMeshData lattice = square_lattice(cells, 1.0, 0);
      RgbMesh mesh = RgbMesh::from_triangles(lattice.points, lattice.triangles);
      for (const int k : {0, 1}) {
        const fem::LoopBoundary kind = k == 0 ? fem::LoopBoundary::loop_rules : fem::LoopBoundary::completed;
        const fem::LoopSpace space = fem::build_loop_space(mesh, std::nullopt, {}, kind);
        const fem::Solution u = fem::solve_loop(space, problem);
        const double h1 = fem::loop_error_norms(space, u.u, *problem.exact).h1;
        double estimate = 0;
        for (const double eta : fem::loop_residual_estimate(space, problem, u.u).eta) estimate += eta * eta;
        std::printf("  %5d   %-12s %8zu   %.3e", cells, k == 0 ? "Loop's rules" : "completed",
                    space.num_dofs(), h1);
        if (previous[k] > 0)
          std::printf("   %5.2f", std::log2(previous[k] / h1));
        else
          std::printf("        ");
        std::printf("   %6.1f\n", std::sqrt(estimate) / h1);
        previous[k] = h1;
        if (k == 1 && !out.empty() && 2 * cells > finest) {
          write_mesh(out, fem::loop_refined_view(space, u.u, 2));
          std::printf(
              "wrote %s: the completed solution (point data \"solution\") on %d x %d cells, 16 pieces each\n",
              out.c_str(), cells, cells);
        }
      }
    }
  });
}
