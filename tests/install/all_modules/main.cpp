// Uses every installed rgbmesh module once: vtk_io writes the icosahedron refined once and reads
// it back, fem solves the sphere-peak problem on it, adapt runs two adaptive cycles, and fit
// moves a shrunken icosahedron's control points onto the unit sphere, and repair joins an
// icosahedron whose triangles each have their own vertices. Prints one line per step
// for the install test, and exits non-zero when a result is not what it must be. Where the
// installation has rgbmesh::parallel, it partitions the adapted mesh too.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/fem/surface_mesh.hpp"
#include "rgbmesh/fit/fit.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/repair/repair.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/vtk_io.hpp"
#if defined(CONSUMER_HAS_PARALLEL)
#include "rgbmesh/parallel/mpi.hpp"
#include "rgbmesh/parallel/partition.hpp"
#endif

using namespace rgbmesh;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: all_modules_consumer WORK_DIR\n");
    return 2;
  }
  const std::filesystem::path work = argv[1];
  std::filesystem::create_directories(work);

  // vtk_io: write and read back.
  const TriangleMeshData ico = icosahedron();
  RgbMesh written = RgbMesh::from_triangles(ico.points, ico.triangles);
  selective_refinement(written, UniformLevel(1));
  const std::filesystem::path file = work / "sphere.vtp";
  write_mesh(file, snapshot_for_file(written, file));
  const TriangleMeshData read = read_mesh(file);
  RgbMesh mesh = RgbMesh::from_triangles(read.points, read.triangles);
  std::printf("vtk_io: read %zu vertices, %zu triangles, %s\n", mesh.num_vertices(), mesh.num_triangles(),
              mesh.validate().empty() ? "valid" : "INVALID");
  if (mesh.num_triangles() != 80 || !mesh.validate().empty()) return 1;

  // fem: one solve on the sphere, against the exact solution's values at the vertices.
  const fem::Problem problem = fem::sphere_peak(Vec3(0, 0, 1), 4.0);
  const fem::SurfaceMesh fe = fem::build_surface_mesh(mesh, fem::Projection(fem::project_to_unit_sphere));
  const fem::Solution solution = fem::solve(fe, problem);
  double largest = 0;
  for (std::size_t i = 0; i < fe.num_dofs(); ++i)
    largest = std::max(largest, std::abs(solution.u[static_cast<Eigen::Index>(i)] - problem.exact->value(fe.points[i])));
  std::printf("fem: %zu unknowns, solver %s, largest nodal error %.3g\n", fe.num_dofs(), fem::to_string(solution.solver),
              largest);
  if (!(largest < 0.5)) return 1;

  // adapt: two cycles of the adaptive loop.
  adapt::AdaptOptions options;
  options.max_cycles = 2;
  options.projection = fem::Projection(fem::project_to_unit_sphere);
  const adapt::AdaptRun run = adapt::run_cycles(mesh, fem::sphere_peak(), options);
  for (const adapt::CycleReport& r : run.cycles)
    std::printf("adapt: cycle %d, %zu unknowns, estimate %.3g, H1 error %.3g\n", r.cycle, r.dofs, r.estimate, *r.error_h1);
  if (run.cycles.size() != 2 || !(run.cycles[1].dofs > run.cycles[0].dofs) || !mesh.validate().empty()) return 1;

  // fit: the icosahedron shrunk to 0.8 fitted to points of the unit sphere.
  TriangleMeshData base = ico;
  for (Vec3& p : base.points) p = p * 0.8;
  std::vector<Vec3> targets;
  for (const Vec3& p : fit::limit_stencils(ico, 3).evaluate(ico.points)) targets.push_back(fem::project_to_unit_sphere(p));
  fit::FitOptions fit_options;
  fit_options.levels = 2;
  fit_options.max_iterations = 10;
  const fit::FitResult fitted = fit::fit(base, targets, fit_options);
  const double start = fitted.iterations.front().rms / fitted.diagonal, end = fitted.rms / fitted.diagonal;
  std::printf("fit: %zu targets, RMS %.3g -> %.3g of the diagonal\n", targets.size(), start, end);
  if (!(end < 0.01 && end < 0.2 * start)) return 1;

  // repair: every triangle with its own three vertices (60 at 12 positions) becomes the
  // icosahedron again.
  PolygonSoup apart;
  for (const auto& t : ico.triangles) {
    std::vector<std::int64_t> face;
    for (const std::int32_t v : t) {
      face.push_back(static_cast<std::int64_t>(apart.points.size()));
      apart.points.push_back(ico.points[static_cast<std::size_t>(v)]);
    }
    apart.faces.push_back(face);
  }
  const TriangleMeshData joined = prepare_triangle_mesh(apart, repair::soup_options(false, true));
  const RgbMesh repaired = RgbMesh::from_triangles(joined.points, joined.triangles);
  std::printf("repair: %zu vertices, %zu triangles, %s (%s)\n", repaired.num_vertices(), repaired.num_triangles(),
              repaired.validate().empty() ? "valid" : "INVALID", joined.notes.front().c_str());
  if (repaired.num_vertices() != 12 || !repaired.validate().empty()) return 1;

#if defined(CONSUMER_HAS_PARALLEL)
  // parallel: the adapted mesh's triangles in three parts, all of them used, none too heavy.
  const fem::SurfaceMesh adapted = fem::build_surface_mesh(mesh);
  const std::vector<std::int32_t> parts = parallel::triangle_parts(mesh, adapted, 0, 3);
  std::vector<std::size_t> count(3, 0);
  for (const std::int32_t p : parts) ++count[static_cast<std::size_t>(p)];
  const double mean = static_cast<double>(parts.size()) / 3;
  std::printf("parallel: %zu triangles in parts of %zu, %zu, %zu (MPI %s)\n", parts.size(), count[0], count[1], count[2],
              parallel::mpi_available() ? "available" : "not built");
  if (*std::min_element(count.begin(), count.end()) == 0 || *std::max_element(count.begin(), count.end()) > 1.5 * mean)
    return 1;
#endif
  std::printf("checked handles: %d\n", RGBMESH_CHECKED_HANDLES);
  return 0;
}
