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
// With --basis thb, the same space in the truncated hierarchical basis (functions as narrow as
// their level, marking kept admissible), and --svg draws where its functions are.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "../exit_codes.hpp"
#include "rgbmesh/adapt/marking.hpp"
#include "rgbmesh/fem/loop_adaptive.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/vtk_io.hpp"

using namespace rgbmesh;

namespace {

Vec3 unit(const Vec3& v) { return v * (1.0 / norm(v)); }

// The mesh seen from the peak's direction d (the visible half, within `radius` of the peak),
// and the truncated hierarchical basis's functions: a dot at the vertex of each, coloured by
// its level (several at one vertex: the finest), a ring where a vertex has none of its own.
void draw_functions(const std::string& path, RgbMesh& mesh, const fem::AdaptiveLoopSpace& space,
                    const Vec3& d, double radius) {
  mesh.compute_limits();
  // An orthonormal frame (e1, e2) across d.
  const Vec3 e1 = unit(cross(d, std::abs(d.z) < 0.9 ? Vec3(0, 0, 1) : Vec3(1, 0, 0)));
  const Vec3 e2 = cross(d, e1);
  const double size = 640, scale = size / (2 * radius);
  const auto seen = [&](const Vec3& p) { return dot(p, d) > 0 && norm(p - d) < 1.5 * radius; };
  const auto x = [&](const Vec3& p) { return size / 2 + scale * dot(p, e1); };
  const auto y = [&](const Vec3& p) { return size / 2 - scale * dot(p, e2); };
  std::ofstream svg(path);
  if (!svg) throw std::runtime_error("cannot write " + path);
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << size << "\" height=\"" << size + 30
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" "
         "fill=\"white\"/>\n";
  for (const TriangleHandle t : mesh.triangles()) {
    const auto v = mesh.triangle_vertices(t);
    const Vec3 a = mesh.limit_position(v[0]), b = mesh.limit_position(v[1]), c = mesh.limit_position(v[2]);
    if (!seen(a) || !seen(b) || !seen(c)) continue;
    svg << "<polygon points=\"" << x(a) << ',' << y(a) << ' ' << x(b) << ',' << y(b) << ' ' << x(c) << ','
        << y(c) << "\" fill=\"none\" stroke=\"#999\" stroke-width=\"0.4\"/>\n";
  }
  static const char* colour[] = {"#4e79a7", "#59a14f", "#edc948", "#f28e2b",
                                 "#e15759", "#b07aa1", "#76b7b2", "#9c755f"};
  int deepest = 0;
  for (const int l : space.coefficient_level) deepest = std::max(deepest, l);
  for (const VertexHandle v : mesh.vertices()) {
    const Vec3 p = mesh.limit_position(v);
    if (!seen(p)) continue;
    const std::int32_t i = space.coefficient_of_vertex[static_cast<std::size_t>(v.idx)];
    if (i < 0) {
      svg << "<circle cx=\"" << x(p) << "\" cy=\"" << y(p)
          << "\" r=\"2.2\" fill=\"none\" stroke=\"#333\" stroke-width=\"0.6\"/>\n";
    } else {
      const int level = space.coefficient_level[static_cast<std::size_t>(i)];
      svg << "<circle cx=\"" << x(p) << "\" cy=\"" << y(p) << "\" r=\"2.6\" fill=\"" << colour[level % 8]
          << "\"/>\n";
    }
  }
  svg << "<text x=\"8\" y=\"" << size + 20 << "\">functions of level";
  for (int l = 0; l <= deepest; ++l)
    svg << "<tspan fill=\"" << colour[l % 8] << "\"> \u25cf " << l << "</tspan>";
  svg << "<tspan> \u25cb a vertex with no function of its own</tspan></text>\n</svg>\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Example 09: adaptive sphere-peak with smooth Loop-basis elements");
  std::size_t max_dofs = 20000;
  double theta = 0.5;
  std::string out, basis = "details", svg;
  app.add_option("--basis", basis,
                 "the space's basis: details (one function per vertex) or thb (truncated hierarchical)")
      ->check(CLI::IsMember({"details", "thb"}));
  app.add_option("--svg", svg,
                 "with --basis thb: draw the last mesh's functions around the peak here (.svg)");
  app.add_option("--max-dofs", max_dofs, "stop once a mesh has more unknowns than this")
      ->check(CLI::Range(std::size_t{12}, std::size_t{200000}));
  app.add_option("--theta", theta, "Dörfler's fraction of the estimate to mark")
      ->check(CLI::Range(0.05, 1.0));
  app.add_option("--out", out, "write the last cycle's smooth solution here (.vtp)");
  CLI11_PARSE(app, argc, argv);
  return examples::run_reporting_errors([&] {
    const Vec3 peak = unit(Vec3(0.48, 0.6, 0.64));  // sphere_peak's default direction
    const fem::Problem problem = fem::sphere_peak(peak);
    const fem::LoopBasisKind kind =
        basis == "thb" ? fem::LoopBasisKind::truncated_hierarchical : fem::LoopBasisKind::details;
    const fem::Projection sphere(fem::project_to_unit_sphere);
    const TriangleMeshData ico = icosahedron();
    RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
    const adapt::DorflerMarking marking(theta);
    std::printf("cycle   unknowns     cells  levels        H1 error    estimate   estimate/error\n");
    for (int cycle = 0;; ++cycle) {
      const fem::AdaptiveLoopSpace space = fem::build_adaptive_loop_space(mesh, sphere, {}, kind);
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
        if (!svg.empty() && kind == fem::LoopBasisKind::truncated_hierarchical) {
          draw_functions(svg, mesh, space, peak, 0.35);
          std::printf("wrote %s: the functions around the peak, by level\n", svg.c_str());
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
      std::vector<char> marked = marking.mark(adapt::Indicators(eta));
      // The truncated hierarchical basis: at most two levels of functions on a cell.
      if (kind == fem::LoopBasisKind::truncated_hierarchical)
        adapt::mark_admissible(mesh, triangles, marked, 2);
      std::vector<double> raise(static_cast<std::size_t>(mesh.triangle_slots()), 0.0);
      for (std::size_t i = 0; i < triangles.size(); ++i)
        if (marked[i]) raise[static_cast<std::size_t>(triangles[i].idx)] = 1.0;
      selective_refinement(mesh, FieldCriterion(std::move(raise), 0.5, {}, 0.0));
    }
  });
}
