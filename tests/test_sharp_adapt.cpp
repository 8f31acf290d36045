// Finite elements and adaptivity on surfaces with sharp edges (issue 42): the unit cube whose 12
// edges are creases is exactly the Loop limit surface of its 12 triangles, and u = cos(π x) is
// the exact solution of -Δu + u = f there (fem::cube_cosine). P1 and P2 reach their optimal
// uniform rates across the creases, adaptive refinement beats uniform (the faces x = 0, 1,
// where u is constant, stay coarse), every mesh stays valid, and a CAD part with detected
// creases adapts as well.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "public_data.hpp"
#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "test_rates.hpp"

namespace rgbmesh::adapt {
namespace {

RgbMesh cube() {
  const TriangleMeshData c = sharp_unit_cube();
  RgbMesh m = RgbMesh::from_triangles(c.points, c.triangles, c.sharp);
  selective_refinement(m, UniformLevel(1));
  return m;
}

std::vector<CycleReport> cube_run(Strategy strategy, int order, std::size_t max_dofs) {
  AdaptOptions o;
  o.strategy = strategy;
  o.order = order;
  o.max_cycles = 30;
  o.max_dofs = max_dofs;
  RgbMesh mesh = cube();
  int invalid = 0;
  const auto cycles = run_cycles(mesh, fem::cube_cosine(), o, [&](const CycleState& s) {
                        if (!s.mesh.validate(true).empty()) ++invalid;
                      }).cycles;
  EXPECT_EQ(invalid, 0);
  return cycles;
}

double slope(const std::vector<CycleReport>& cycles, std::size_t from_dofs, bool h1) {
  std::vector<double> n, e;
  for (const auto& r : cycles) {
    if (r.dofs < from_dofs) continue;
    n.push_back(double(r.dofs));
    e.push_back(h1 ? *r.error_h1 : *r.error_l2);
  }
  EXPECT_GE(n.size(), 3u);
  return testing::log_log_slope(n, e);
}

TEST(CubeCosine, TheCubeIsItsOwnLimitSurface) {
  RgbMesh m = cube();
  selective_refinement(m, UniformLevel(3));
  m.compute_limits();
  for (VertexHandle v : m.vertices()) {
    const Vec3 p = m.limit_position(v);
    const double to_face = std::min({std::abs(p.x), std::abs(p.y), std::abs(p.z), std::abs(1 - p.x),
                                     std::abs(1 - p.y), std::abs(1 - p.z)});
    ASSERT_LE(to_face, 1e-14);
  }
}

TEST(CubeCosine, LinearElementsReachTheirUniformRates) {
  const auto cycles = cube_run(Strategy::uniform, 1, 30000);
  EXPECT_NEAR(slope(cycles, 300, true), -0.5, 0.05);
  EXPECT_NEAR(slope(cycles, 300, false), -1.0, 0.1);
}

TEST(CubeCosine, QuadraticElementsReachTheirUniformRates) {
  const auto cycles = cube_run(Strategy::uniform, 2, 40000);
  EXPECT_NEAR(slope(cycles, 300, true), -1.0, 0.1);
  EXPECT_NEAR(slope(cycles, 300, false), -1.5, 0.15);
}

TEST(CubeCosine, AdaptiveRefinementBeatsUniform) {
  for (const int order : {1, 2}) {
    const auto uniform = cube_run(Strategy::uniform, order, 20000);
    const auto adaptive = cube_run(Strategy::adaptive, order, 20000);
    // Uniform refinement's H1 error at the adaptive run's last size, from its last two meshes.
    const auto& a = uniform[uniform.size() - 2];
    const auto& b = uniform.back();
    const double rate = std::log(*b.error_h1 / *a.error_h1) / std::log(double(b.dofs) / double(a.dofs));
    const double n = double(adaptive.back().dofs);
    const double uniform_at_n = *b.error_h1 * std::pow(n / double(b.dofs), rate);
    std::printf("P%d at %.0f unknowns: adaptive H1 %.3e, uniform %.3e\n", order, n, *adaptive.back().error_h1,
                uniform_at_n);
    EXPECT_LT(*adaptive.back().error_h1, 0.9 * uniform_at_n) << "P" << order;
    EXPECT_NEAR(slope(adaptive, 1000, true), order == 1 ? -0.5 : -1.0, 0.15) << "P" << order;
  }
}

TEST(SharpAdapt, ACadPartWithDetectedCreasesAdapts) {
  // CGAL's fandisk with its edges kept (30 degrees): a Gaussian source, P1 and P2 adaptive,
  // every mesh valid and the estimate falling.
  SoupOptions read;
  read.sharp_angle = 30;
  const TriangleMeshData part = read_mesh(testing::public_data("fandisk.off"), read);
  ASSERT_GT(part.sharp.edges.size(), 50u);
  for (const int order : {1, 2}) {
    RgbMesh mesh = RgbMesh::from_triangles(part.points, part.triangles, part.sharp);
    AdaptOptions o;
    o.order = order;
    o.max_cycles = 6;
    o.max_dofs = order == 1 ? 40000 : 90000;
    int invalid = 0;
    const auto cycles =
        run_cycles(mesh, fem::gaussian_source(part.points[0], 0.05 * bounding_box_diagonal(part.points)), o,
                   [&](const CycleState& s) {
                     if (!s.mesh.validate(true).empty()) ++invalid;
                   })
            .cycles;
    EXPECT_EQ(invalid, 0);
    ASSERT_GE(cycles.size(), 5u);
    EXPECT_LT(cycles.back().estimate, 0.4 * cycles.front().estimate) << "P" << order;
  }
}

}  // namespace
}  // namespace rgbmesh::adapt
