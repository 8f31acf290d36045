// Example 09: adaptive refinement with smooth (Loop-basis) elements.
//
// Sphere-peak: -Δu + u = f on the unit sphere with the sharp solution u = exp(100 (x·d - 1)).
// The unknowns are one coefficient per vertex of the RGB mesh: the base vertices' control
// values, and at every inserted vertex a detail added to what Loop's rules give it. Each cycle
//   1. builds the hierarchical Loop space of the mesh as it is (build_adaptive_loop_space):
//      its integration cells, the triangles of the Loop hierarchy that the finer functions
//      require, and the sparse map from coefficients to the cells' control values,
//   2. solves (solve_loop: the cells' matrices, then Eᵀ K E for the coefficients),
//   3. measures the error against the exact solution and estimates it per cell
//      (loop_residual_estimate on the cells' control values),
//   4. moves the indicators onto the RGB triangles (loop_indicators_on_triangles), marks them
//      by Dörfler's rule and refines the marked triangles one level (FieldCriterion).
// With --out, the last cycle's smooth solution is written for ParaView, 16 exact pieces per cell.

#include <CLI/CLI.hpp>
#include <cstdio>

#include "../exit_codes.hpp"
#include "rgbmesh/adapt/marking.hpp"
#include "rgbmesh/fem/loop_adaptive.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

int main(int argc, char** argv) {
  CLI::App app("Example 09: adaptive sphere-peak with smooth Loop-basis elements");
  std::size_t max_dofs = 20000;
  double theta = 0.5;
  std::string out;
  app.add_option("--max-dofs", max_dofs, "stop once a mesh has more unknowns than this")
      ->check(CLI::Range(std::size_t{12}, std::size_t{200000}));
  app.add_option("--theta", theta, "Dörfler's fraction of the estimate to mark")
      ->check(CLI::Range(0.05, 1.0));
  app.add_option("--out", out, "write the last cycle's smooth solution here (.vtp)");
  CLI11_PARSE(app, argc, argv);
  return examples::run_reporting_errors([&] {
    const fem::Problem problem = fem::sphere_peak();
    const fem::Projection sphere(fem::project_to_unit_sphere);
    const TriangleMeshData ico = icosahedron();
    RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
    const adapt::DorflerMarking marking(theta);
    std::printf("cycle   unknowns     cells  levels        H1 error    estimate   estimate/error\n");
    for (int cycle = 0;; ++cycle) {
      const fem::AdaptiveLoopSpace space = fem::build_adaptive_loop_space(mesh, sphere);
      const fem::Solution solution = fem::solve_loop(space, problem);
      const Eigen::VectorXd control = space.control_values(solution.u);
      const fem::ErrorNorms error = fem::loop_error_norms(space.cells, control, *problem.exact);
      const fem::Estimate estimate = fem::loop_residual_estimate(space.cells, problem, control);
      int deepest = 0;
      for (const int level : space.cell_level) deepest = std::max(deepest, level);
      std::printf("%5d %10zu %9zu %7d    %.4e  %.4e   %6.2f\n", cycle, space.num_dofs(),
                  space.cells.elements.size(), deepest, error.h1, estimate.total, estimate.total / error.h1);
      if (space.num_dofs() > max_dofs) {
        if (!out.empty()) {
          write_mesh(out, fem::loop_refined_view(space.cells, control, 2));
          std::printf("wrote %s: the solution (point data \"solution\"), 16 pieces per cell\n", out.c_str());
        }
        break;
      }
      // Marking on the RGB mesh: one indicator per triangle (by slot), Dörfler over them.
      const std::vector<double> by_slot = fem::loop_indicators_on_triangles(space, mesh, estimate.eta);
      std::vector<TriangleHandle> triangles;
      std::vector<double> eta;
      for (const TriangleHandle t : mesh.triangles()) {
        triangles.push_back(t);
        eta.push_back(by_slot[static_cast<std::size_t>(t.idx)]);
      }
      const std::vector<char> marked = marking.mark(adapt::Indicators(eta));
      std::vector<double> raise(static_cast<std::size_t>(mesh.triangle_slots()), 0.0);
      for (std::size_t i = 0; i < triangles.size(); ++i)
        if (marked[i]) raise[static_cast<std::size_t>(triangles[i].idx)] = 1.0;
      selective_refinement(mesh, FieldCriterion(std::move(raise), 0.5, {}, 0.0));
    }
  });
}
