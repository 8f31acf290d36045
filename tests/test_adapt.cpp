// Adaptive cycles: adaptivity beats uniform refinement on a peak at the optimal rate, every
// mesh stays valid, the mesh follows a moving feature at a steady size while coarsening, and
// the solution is carried through refinement exactly where it is linear.

#include <gtest/gtest.h>

#include <cmath>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_rates.hpp"
#include "rgbmesh/shapes.hpp"

namespace rgbmesh::adapt {
namespace {

RgbMesh icosphere() {
  const TriangleMeshData ico = icosahedron();
  RgbMesh m = RgbMesh::from_triangles(ico.points, ico.triangles);
  selective_refinement(m, UniformLevel(1));
  return m;
}

AdaptOptions sphere_options(Strategy strategy) {
  AdaptOptions o;
  o.strategy = strategy;
  o.projection = fem::Projection(fem::project_to_unit_sphere);
  o.max_cycles = 40;
  o.max_dofs = 20000;
  return o;
}

TEST(Adapt, AdaptivityBeatsUniformRefinementOnThePeak) {
  const fem::Problem peak = fem::sphere_peak();
  RgbMesh uniform_mesh = icosphere();
  const auto uniform = run_cycles(uniform_mesh, peak, sphere_options(Strategy::uniform));
  RgbMesh adaptive_mesh = icosphere();
  int invalid = 0;
  const auto adaptive = run_cycles(adaptive_mesh, peak, sphere_options(Strategy::adaptive), [&](const CycleState& s) {
    if (!s.mesh.validate(true).empty()) ++invalid;
  });
  EXPECT_EQ(invalid, 0);
  ASSERT_GE(adaptive.back().dofs, 10000u);
  ASSERT_GE(uniform.back().dofs, 10000u);
  // Uniform refinement's H1 error at the adaptive mesh's size, from its last two meshes (its
  // rate there is -1/2 in the number of unknowns).
  const auto& u1 = uniform[uniform.size() - 2];
  const auto& u2 = uniform.back();
  const double slope = std::log(*u2.error_h1 / *u1.error_h1) / std::log(double(u2.dofs) / double(u1.dofs));
  const double n = static_cast<double>(adaptive.back().dofs);
  const double uniform_at_n = *u2.error_h1 * std::pow(n / double(u2.dofs), slope);
  EXPECT_LT(*adaptive.back().error_h1 * 5, uniform_at_n)
      << "adaptive " << *adaptive.back().error_h1 << " vs uniform " << uniform_at_n << " at " << n << " DOFs";
  // The adaptive rate, from 1,000 unknowns on: N^(-1/2).
  std::vector<double> dofs, h1;
  for (const auto& r : adaptive) {
    if (r.dofs < 1000) continue;
    dofs.push_back(double(r.dofs));
    h1.push_back(*r.error_h1);
  }
  ASSERT_GE(dofs.size(), 4u);
  EXPECT_NEAR(testing::log_log_slope(dofs, h1), -0.5, 0.15);
}

TEST(Adapt, MeshFollowsAMovingPeakAtASteadySize) {
  RgbMesh mesh = icosphere();
  AdaptOptions start = sphere_options(Strategy::adaptive);
  start.max_cycles = 10;
  const auto started = run_cycles(mesh, moving_peak(0), start);
  AdaptOptions o = sphere_options(Strategy::adaptive);
  o.coarsen_below = 0.25;
  o.marking = Marking::equidistribution;
  o.target_estimate = started.back().estimate;
  int invalid = 0;
  const auto steps = run_dynamic(
      mesh, [](double t) { return moving_peak(t); }, 12, 2, o,
      [&](const CycleState& s) {
        if (!s.mesh.validate(true).empty()) ++invalid;
      });
  EXPECT_EQ(invalid, 0);
  ASSERT_EQ(steps.size(), 13u);
  // After the first step, which trims the mesh of the start to the steady balance of
  // refinement ahead and coarsening behind, the size stays in a band.
  std::size_t lo = steps[2].triangles, hi = lo;
  for (std::size_t k = 1; k < steps.size(); ++k) {
    EXPECT_GT(steps[k].removals, 0u) << "step " << k << " coarsened nothing";
    EXPECT_GT(steps[k].splits, 0u) << "step " << k << " refined nothing";
    if (k >= 2) {
      lo = std::min(lo, steps[k].triangles);
      hi = std::max(hi, steps[k].triangles);
    }
    // The error stays controlled as the peak moves (no drift to a coarse, wrong mesh).
    EXPECT_LT(*steps[k].error_h1, 2 * *steps[1].error_h1);
  }
  EXPECT_LT(double(hi) / double(lo), 1.75) << "triangles between " << lo << " and " << hi;
}

TEST(Adapt, MarkingTakesTheBulkOrTheFraction) {
  const std::vector<double> eta = {1, 4, 2, 3, 0.5};  // squares 1, 16, 4, 9, 0.25: total 30.25
  // Dörfler, θ = 0.5: 16 alone is 53%.
  EXPECT_EQ(mark(eta, Marking::dorfler, 0.5), (std::vector<char>{0, 1, 0, 0, 0}));
  // θ = 0.8: 16 + 9 = 25 is 83%.
  EXPECT_EQ(mark(eta, Marking::dorfler, 0.8), (std::vector<char>{0, 1, 0, 1, 0}));
  EXPECT_EQ(mark(eta, Marking::fixed_fraction, 0.4), (std::vector<char>{0, 1, 0, 1, 0}));
}

}  // namespace
}  // namespace rgbmesh::adapt
