// Adaptive cycles: adaptivity beats uniform refinement on a peak at the optimal rate, every
// mesh stays valid, the mesh follows a moving feature at a steady size while coarsening, and
// the solution is carried through refinement exactly where it is linear.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"
#include "test_meshes.hpp"
#include "test_rates.hpp"

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
  const auto uniform = run_cycles(uniform_mesh, peak, sphere_options(Strategy::uniform)).cycles;
  RgbMesh adaptive_mesh = icosphere();
  int invalid = 0;
  const auto adaptive = run_cycles(adaptive_mesh, peak, sphere_options(Strategy::adaptive), [&](const CycleState& s) {
    if (!s.mesh.validate(true).empty()) ++invalid;
  }).cycles;
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

// Adaptive P2 (residual estimator, isoparametric elements on the sphere) on the peak: the optimal
// rate N^-1 in H1, every mesh valid, and at 5·10^4 unknowns an H1 error at least 5 times
// below adaptive P1's at the same size (issue 12).
TEST(Adapt, QuadraticElementsReachTheirRateAndBeatLinearOnesAtEqualUnknowns) {
  const fem::Problem peak = fem::sphere_peak();
  AdaptOptions o = sphere_options(Strategy::adaptive);
  o.max_dofs = 60000;
  o.estimator = std::make_shared<fem::ResidualEstimator>();
  o.order = 2;
  RgbMesh quadratic_mesh = icosphere();
  int invalid = 0;
  const auto quadratic = run_cycles(quadratic_mesh, peak, o, [&](const CycleState& s) {
    if (!s.mesh.validate(true).empty()) ++invalid;
    if (s.fe.order != 2) ++invalid;
  }).cycles;
  EXPECT_EQ(invalid, 0);
  ASSERT_GE(quadratic.back().dofs, 30000u);
  std::vector<double> dofs, h1;
  for (const auto& r : quadratic) {
    if (r.dofs < 3000) continue;
    dofs.push_back(double(r.dofs));
    h1.push_back(*r.error_h1);
  }
  ASSERT_GE(dofs.size(), 4u);
  EXPECT_NEAR(testing::log_log_slope(dofs, h1), -1.0, 0.15) << ::testing::PrintToString(h1);

  AdaptOptions linear_options = sphere_options(Strategy::adaptive);
  linear_options.max_dofs = 60000;
  RgbMesh linear_mesh = icosphere();
  const auto linear = run_cycles(linear_mesh, peak, linear_options).cycles;
  // P1's error at P2's last size, from P1's last two cycles (its rate there is about -1/2).
  const auto& a = linear[linear.size() - 2];
  const auto& b = linear.back();
  const double slope = std::log(*b.error_h1 / *a.error_h1) / std::log(double(b.dofs) / double(a.dofs));
  const double n = double(quadratic.back().dofs);
  const double linear_at_n = *b.error_h1 * std::pow(n / double(b.dofs), slope);
  EXPECT_LT(*quadratic.back().error_h1 * 5, linear_at_n)
      << "P2 " << *quadratic.back().error_h1 << " vs P1 " << linear_at_n << " at " << n << " unknowns";
}

// Adaptive P2 on a Loop limit surface (no projection: the edge nodes come from split_limits)
// with a Gaussian source on a torus: the marks reach the triangles they were made for, so the
// refinement gathers at the source and the estimate keeps falling (the mesh was refined in the
// wrong places, and the estimate stalled, while the elements named stale triangle handles).
TEST(Adapt, QuadraticElementsOnALoopSurfaceRefineWhereTheyMark) {
  RgbMesh mesh = testing::torus(8, 5).build();
  selective_refinement(mesh, UniformLevel(1));
  mesh.compute_limits();
  const Vec3 source = mesh.limit_position(*mesh.vertices().begin());
  AdaptOptions o;
  o.order = 2;
  o.max_cycles = 8;
  o.max_dofs = 200000;
  double near_share = 0;
  const auto run = run_cycles(mesh, fem::gaussian_source(source, 0.15), o, [&](const CycleState& s) {
    // The share of the finest triangles within 0.5 of the source (its width is 0.15).
    const auto& level = s.solved->triangle_level;  // the solved mesh's (s.mesh is adapted already)
    const int finest = *std::max_element(level.begin(), level.end());
    std::size_t near = 0, all = 0;
    for (std::size_t i = 0; i < s.fe.triangles.size(); ++i) {
      if (level[i] != finest) continue;
      ++all;
      if (norm(s.fe.points[s.fe.triangles[i][0]] - source) < 0.5) ++near;
    }
    near_share = double(near) / double(all);
  }).cycles;
  ASSERT_EQ(run.size(), 8u);
  EXPECT_LT(run.back().estimate * 8, run.front().estimate)
      << run.front().estimate << " -> " << run.back().estimate;
  EXPECT_GT(near_share, 0.9);
}

// Adaptive P2 on a CAD tessellation (a pillbox whose ends are fans of needles and caps of
// nearly 180°; the Gaussian source at its first vertex, where the fan meets the rim's crease,
// as `rgbmesh adapt --mesh` places it). The loop used to stall on such meshes: folded curved
// elements and slivers weighed by their length carried the estimate, one or two triangles were
// marked per cycle and the estimate jumped (on this mesh 378 -> 1,306 unknowns in 20 cycles,
// the estimate up to 170 times its start). Now every cycle adds unknowns in proportion and the
// run reaches max_dofs, the estimate falling at close to P2's N^-1 (measured -0.82 from 4,000
// to 34,000 unknowns; -0.93 over the last three cycles).
TEST(Adapt, QuadraticElementsDoNotStallOnSlivers) {
  const testing::BaseMesh base = testing::cad_pillbox(48, 0.3);
  RgbMesh mesh = base.build();
  mesh.compute_limits();
  const double width = bounding_box_diagonal(base.points) / 20;
  AdaptOptions o;
  o.order = 2;
  o.max_cycles = 20;
  o.max_dofs = 40000;
  const AdaptRun run = run_cycles(mesh, fem::gaussian_source(mesh.limit_position(VertexHandle(0)), width), o);
  EXPECT_EQ(run.stopped, StopReason::max_dofs) << run.cycles.size() << " cycles";
  ASSERT_GE(run.cycles.size(), 10u);
  std::vector<double> dofs, estimate;
  for (std::size_t i = 0; i < run.cycles.size(); ++i) {
    const CycleReport& c = run.cycles[i];
    if (i > 0) {
      EXPECT_GT(c.dofs, 1.1 * run.cycles[i - 1].dofs) << "cycle " << i;
    }
    if (c.dofs < 4000) continue;
    dofs.push_back(static_cast<double>(c.dofs));
    estimate.push_back(c.estimate);
  }
  ASSERT_GE(dofs.size(), 4u);
  EXPECT_NEAR(testing::log_log_slope(dofs, estimate), -1.0, 0.3) << ::testing::PrintToString(estimate);
  EXPECT_LT(run.cycles.back().estimate * 10, run.cycles.front().estimate);
}

// The direction of the area-weighted centroid of the finest-level triangles, and how many.
std::pair<Vec3, std::size_t> finest_patch(const CycleState& s) {
  int finest = 0;
  for (TriangleHandle t : s.fe.triangle) finest = std::max(finest, s.mesh.level(t));
  Vec3 sum;
  std::size_t n = 0;
  for (std::size_t i = 0; i < s.fe.triangles.size(); ++i) {
    if (s.mesh.level(s.fe.triangle[i]) != finest) continue;
    const auto& t = s.fe.triangles[i];
    const Vec3 &a = s.fe.points[t[0]], &b = s.fe.points[t[1]], &c = s.fe.points[t[2]];
    sum += (0.5 * norm(cross(b - a, c - a)) / 3.0) * (a + b + c);
    ++n;
  }
  return {sum * (1.0 / norm(sum)), n};
}

double degrees_between(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(dot(a, b) / (norm(a) * norm(b)), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

// The peak's direction at time t (moving_peak: a quarter turn from (0.6, 0, 0.8) towards y).
Vec3 peak_at(double t) {
  const double phi = 0.5 * 3.14159265358979323846 * t;
  return std::cos(phi) * Vec3(0.6, 0.0, 0.8) + std::sin(phi) * Vec3(0.0, 1.0, 0.0);
}

// With P1 and with Loop elements (which coarsen by their details' energies): measured, P1
// keeps about 1,100 unknowns at H1 0.11, Loop 570-740 at H1 3e-3 (the first with 16
// quadrature points a cell, the second with the 12-point rule, whose indicators on the first
// coarse meshes differ and so the estimate the run keeps to).
class MovingPeak : public ::testing::TestWithParam<AdaptOptions::Element> {};

TEST_P(MovingPeak, MeshFollowsItAtASteadySizeCentredOnIt) {
  RgbMesh mesh = icosphere();
  AdaptOptions o = sphere_options(Strategy::adaptive);
  o.element = GetParam();
  o.coarsen_below = 0.25;
  o.marking = std::make_shared<EquidistributionMarking>();  // towards the estimate reached at the start
  DynamicOptions d;                       // 24 steps of 3.75 degrees
  int invalid = 0;
  std::vector<double> offset;
  const AdaptRun run = run_dynamic(
      mesh, [](double t) { return moving_peak(t); }, o, d, [&](const CycleState& s) {
        if (!s.mesh.validate(true).empty()) ++invalid;
        offset.push_back(degrees_between(finest_patch(s).first, peak_at(s.report.time)));
      });
  EXPECT_EQ(invalid, 0);
  EXPECT_EQ(run.stopped, StopReason::steps);
  const auto& steps = run.cycles;
  ASSERT_EQ(steps.size(), 25u);
  EXPECT_GT(run.target_estimate, 0);
  // Once the wake of intermediate levels behind the peak has formed (five steps, about three
  // widths of the peak), the size stays in a band.
  std::size_t lo = steps[5].triangles, hi = lo;
  for (std::size_t k = 1; k < steps.size(); ++k) {
    EXPECT_GT(steps[k].removals, 0u) << "step " << k << " coarsened nothing";
    EXPECT_GT(steps[k].splits, 0u) << "step " << k << " refined nothing";
    if (k >= 5) {
      lo = std::min(lo, steps[k].triangles);
      hi = std::max(hi, steps[k].triangles);
    }
    // The error stays controlled as the peak moves (no drift to a coarse, wrong mesh).
    EXPECT_LT(*steps[k].error_h1, 1.5 * *steps[0].error_h1);
    // The finest patch sits on the peak, not behind it: well within half a step's travel
    // (1.875 degrees). Coarsening on the refinement's own scale leaves behind as much fine
    // mesh as refinement creates ahead.
    // Loop elements' indicators follow the solution's fourth derivatives, largest on a ring
    // around the peak's top: their finest patch stays within the peak's width (1/sqrt(100)
    // rad, 5.7 degrees) or a little beyond (measured at most 4.85 with 16 quadrature points a
    // cell, 5.85 with 12) instead.
    const bool smooth = GetParam() == AdaptOptions::Element::loop;
    EXPECT_LT(offset[k], smooth ? 6.5 : 0.75)
        << "step " << k << ": the finest patch is " << offset[k] << " degrees off the peak";
  }
  const bool loop = GetParam() == AdaptOptions::Element::loop;
  double worst_h1 = 0;
  for (const CycleReport& step : steps) worst_h1 = std::max(worst_h1, *step.error_h1);
  std::printf("  finest patch at most %.2f degrees off the peak; triangles %zu to %zu; last step %zu "
              "unknowns; H1 at most %.2e\n",
              *std::max_element(offset.begin() + 1, offset.end()), lo, hi, steps.back().dofs, worst_h1);
  EXPECT_LT(double(hi) / double(lo), loop ? 1.4 : 1.3) << "triangles between " << lo << " and " << hi;
  for (const CycleReport& step : steps) EXPECT_LT(*step.error_h1, loop ? 5e-3 : 0.15);
  EXPECT_LT(steps.back().dofs, loop ? 850u : 1400u);
}

INSTANTIATE_TEST_SUITE_P(Adapt, MovingPeak,
                         ::testing::Values(AdaptOptions::Element::lagrange, AdaptOptions::Element::loop),
                         [](const ::testing::TestParamInfo<AdaptOptions::Element>& p) {
                           return std::string(p.param == AdaptOptions::Element::loop ? "Loop" : "P1");
                         });

// Compaction (RgbMesh::compact at the start of a cycle, issue 44) changes slot numbers only:
// a moving peak with P2 elements, coarsening and an iterative solver (whose start is the
// carried solution, so the transfer's renumbering counts) gives the same unknowns, estimates,
// errors and solutions, bit for bit, compacting at every cycle or never; the compacted mesh
// ends with as many slots as vertices.
TEST(Adapt, CompactingTheMeshChangesNoResult) {
  AdaptOptions o = sphere_options(Strategy::adaptive);
  o.order = 2;
  o.coarsen_below = 0.25;
  o.marking = std::make_shared<EquidistributionMarking>();
  o.solve.solver = fem::SolverKind::cg_ichol;
  DynamicOptions d;
  d.steps = 6;
  d.start_cycles = 5;
  struct Run {
    std::vector<CycleReport> cycles;
    std::vector<Eigen::VectorXd> solutions;
    std::int32_t slots = 0;
    std::size_t vertices = 0;
  };
  const auto run = [&](double compact_below) {
    RgbMesh mesh = icosphere();
    o.compact_below = compact_below;
    Run r;
    const AdaptRun a = run_dynamic(mesh, [](double t) { return moving_peak(t); }, o, d,
                                   [&](const CycleState& s) { r.solutions.push_back(s.u); });
    r.cycles = a.cycles;
    r.slots = mesh.vertex_slots();
    r.vertices = mesh.num_vertices();
    return r;
  };
  const Run never = run(0.0), always = run(1.0);
  ASSERT_EQ(never.cycles.size(), always.cycles.size());
  std::uint64_t removals = 0;
  for (std::size_t k = 0; k < never.cycles.size(); ++k) {
    EXPECT_EQ(never.cycles[k].dofs, always.cycles[k].dofs) << "step " << k;
    EXPECT_EQ(never.cycles[k].estimate, always.cycles[k].estimate) << "step " << k;
    EXPECT_EQ(never.cycles[k].error_h1, always.cycles[k].error_h1) << "step " << k;
    EXPECT_EQ(never.cycles[k].solver_iterations, always.cycles[k].solver_iterations) << "step " << k;
    removals += never.cycles[k].removals;
  }
  EXPECT_GT(removals, 100u) << "the peak left no wake to coarsen";
  ASSERT_EQ(never.solutions.size(), always.solutions.size());
  for (std::size_t k = 0; k < never.solutions.size(); ++k)
    EXPECT_TRUE(never.solutions[k] == always.solutions[k]) << "cycle " << k;
  EXPECT_GT(never.slots, static_cast<std::int32_t>(never.vertices));
  std::cout << "moving peak, P2: " << never.vertices << " vertices in " << never.slots << " slots uncompacted, "
            << always.slots << " compacted\n";
}

TEST(Adapt, UniformStrategyOnAMovingPeakKeepsOneMeshWithinMaxDofs) {
  RgbMesh mesh = icosphere();
  AdaptOptions o = sphere_options(Strategy::uniform);
  o.max_dofs = 5000;  // levels: 42, 162, 642, 2562, then 10242 would exceed
  DynamicOptions d;
  d.steps = 3;
  d.start_cycles = 20;
  const AdaptRun run = run_dynamic(mesh, [](double t) { return moving_peak(t); }, o, d);
  ASSERT_EQ(run.cycles.size(), 4u);
  for (const auto& r : run.cycles) {
    EXPECT_EQ(r.dofs, 2562u);
    EXPECT_EQ(r.splits + r.removals, 0u);
  }
}

// A floor under adaptivity (min_level): the first mesh is the uniform level-2 mesh, and a
// moving peak with coarsening never takes a triangle below level 2, while it does coarsen.
TEST(Adapt, NoTriangleFallsBelowTheMinimumLevel) {
  const TriangleMeshData ico = icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  AdaptOptions o = sphere_options(Strategy::adaptive);
  o.coarsen_below = 0.25;
  o.marking = std::make_shared<EquidistributionMarking>();
  o.min_level = 2;
  DynamicOptions d;
  d.steps = 8;
  d.start_cycles = 6;
  int below = 0;
  const AdaptRun run = run_dynamic(mesh, [](double t) { return moving_peak(t); }, o, d, [&](const CycleState& s) {
    for (const std::uint8_t level : s.solved->triangle_level) below += level < 2;
  });
  ASSERT_EQ(run.start.size(), 6u);
  EXPECT_EQ(run.start.front().dofs, 162u);  // the icosahedron's level 2
  std::uint64_t removals = 0;
  for (const auto& r : run.cycles) removals += r.removals;
  EXPECT_GT(removals, 100u);
  EXPECT_EQ(below, 0);
  // The same coarsening without the floor takes triangles below level 2 (the peak's wake
  // returns to the base), so the floor is what holds them.
  RgbMesh free_mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  o.min_level = 0;
  int coarser = 0;
  run_dynamic(free_mesh, [](double t) { return moving_peak(t); }, o, d, [&](const CycleState& s) {
    for (const std::uint8_t level : s.solved->triangle_level) coarser += level < 2;
  });
  EXPECT_GT(coarser, 0);
  o.min_level = o.max_level + 1;
  EXPECT_THROW(run_cycles(free_mesh, fem::sphere_peak(), o), std::invalid_argument);
}

TEST(Adapt, RunsStopAtMaxDofsAndSayWhy) {
  // Uniform refinement predicts the next level and never builds it.
  RgbMesh uniform_mesh = icosphere();
  AdaptOptions o = sphere_options(Strategy::uniform);
  o.max_dofs = 1000;
  const AdaptRun u = run_cycles(uniform_mesh, fem::sphere_peak(), o);
  EXPECT_EQ(u.stopped, StopReason::max_dofs);
  EXPECT_EQ(u.cycles.back().dofs, 642u);
  EXPECT_EQ(uniform_mesh.num_vertices(), 642u);
  // Adaptive refinement stops before solving a mesh above the limit.
  RgbMesh adaptive_mesh = icosphere();
  o.strategy = Strategy::adaptive;
  const AdaptRun a = run_cycles(adaptive_mesh, fem::sphere_peak(), o);
  EXPECT_EQ(a.stopped, StopReason::max_dofs);
  for (const auto& r : a.cycles) EXPECT_LE(r.dofs, 1000u);
  // The target error.
  RgbMesh target_mesh = icosphere();
  o.max_dofs = 100000;
  o.target_estimate = 2.0;
  const AdaptRun t = run_cycles(target_mesh, fem::sphere_peak(), o);
  EXPECT_EQ(t.stopped, StopReason::target_error);
  EXPECT_LE(t.cycles.back().estimate, 2.0);
  EXPECT_GT(t.cycles[t.cycles.size() - 2].estimate, 2.0);
  // A moving run whose target needs more than max_dofs stops at the step that would exceed.
  RgbMesh moving_mesh = icosphere();
  AdaptOptions m = sphere_options(Strategy::adaptive);
  m.marking = std::make_shared<EquidistributionMarking>();
  m.target_estimate = 0.05;
  m.max_dofs = 3000;
  const AdaptRun mv = run_dynamic(moving_mesh, [](double time) { return moving_peak(time); }, m, DynamicOptions{});
  EXPECT_EQ(mv.stopped, StopReason::max_dofs);
  EXPECT_LT(mv.cycles.size(), 25u);
  for (const auto& r : mv.cycles) EXPECT_LE(r.dofs, 3000u);
}

// The memory ceiling reserves what a cycle's new unknowns will take with the element chosen:
// Loop-basis elements need several times what linear ones do, so under the same ceiling their
// run stops a level earlier (12 MB: 7,680 new linear unknowns need 19 MB, 1,920 new Loop
// unknowns 35 MB).
// Loop elements coarsen by what removing a vertex's detail costs (|u_i| sqrt(a(φ_i, φ_i))), not
// by the indicators, which fall as h³ where the solution is resolved: by them whole resolved
// regions went and came back (the error up 50 times). Coarsened this way the error falls at
// every cycle, and at least as fast per unknown as without coarsening (measured: 7.5e-4 at
// 1,261 unknowns, against 8.5e-4 at 1,291 without).
TEST(Adapt, LoopElementsCoarsenByTheirDetails) {
  RgbMesh mesh = icosphere();
  AdaptOptions o = sphere_options(Strategy::adaptive);
  o.element = AdaptOptions::Element::loop;
  o.coarsen_below = 0.2;
  o.max_dofs = 1500;
  const AdaptRun run = run_cycles(mesh, fem::sphere_peak(), o);
  std::size_t removals = 0;
  for (std::size_t i = 1; i < run.cycles.size(); ++i) {
    removals += run.cycles[i - 1].removals;
    EXPECT_LT(*run.cycles[i].error_h1, 1.02 * *run.cycles[i - 1].error_h1) << "cycle " << i;
  }
  const CycleReport& last = run.cycles.back();
  std::printf("  %zu cycles, %zu removals; last: %zu unknowns, H1 %.3e\n", run.cycles.size(), removals,
              last.dofs, *last.error_h1);
  EXPECT_GT(removals, 300u);
  EXPECT_LT(last.dofs, 1500u);
  EXPECT_LT(*last.error_h1, 8e-4);
  RgbMesh plain = icosphere();
  o.coarsen_below = 0;
  const AdaptRun uncoarsened = run_cycles(plain, fem::sphere_peak(), o);
  std::printf("  without coarsening: %zu unknowns, H1 %.3e\n", uncoarsened.cycles.back().dofs,
              *uncoarsened.cycles.back().error_h1);
  EXPECT_LT(*last.error_h1, *uncoarsened.cycles.back().error_h1);
  EXPECT_LT(last.dofs, uncoarsened.cycles.back().dofs + 50);
}

// Issue 26's first target, in one process: on the adaptive sphere-peak, Loop elements reach at
// equal unknowns an H1 error far below adaptive P2's (bench_vs_dealii measures P2 at 1.1–1.2
// times deal.II's Q2 and Loop at 0.004–0.011 times Q2 from 10^4 to 5·10^4 unknowns; here P2's
// error at Loop's last size, from P2's last two cycles: measured ratio 0.01 at ~10^4). Loop's
// adaptive rate over its last five cycles is the cubics' N^-1.5 or better (measured 1.74).
TEST(Adapt, LoopElementsBeatQuadraticsAtEqualUnknownsOnThePeak) {
  const fem::Problem peak = fem::sphere_peak();
  AdaptOptions o = sphere_options(Strategy::adaptive);
  o.max_dofs = 10000;
  o.element = AdaptOptions::Element::loop;
  RgbMesh loop_mesh = icosphere();
  const auto loop = run_cycles(loop_mesh, peak, o).cycles;
  o.element = AdaptOptions::Element::lagrange;
  o.order = 2;
  o.estimator = std::make_shared<fem::ResidualEstimator>();
  o.max_dofs = 20000;
  RgbMesh quadratic_mesh = icosphere();
  const auto quadratic = run_cycles(quadratic_mesh, peak, o).cycles;
  ASSERT_GE(loop.back().dofs, 5000u);
  ASSERT_GE(quadratic.back().dofs, loop.back().dofs);
  std::size_t k = 1;
  while (quadratic[k].dofs < loop.back().dofs) ++k;
  const auto& a = quadratic[k - 1];
  const auto& b = quadratic[k];
  const double slope = std::log(*b.error_h1 / *a.error_h1) / std::log(double(b.dofs) / double(a.dofs));
  const double n = double(loop.back().dofs);
  const double quadratic_at_n = *a.error_h1 * std::pow(n / double(a.dofs), slope);
  std::printf("  at %.0f unknowns: Loop H1 %.3e, P2 H1 %.3e (ratio %.4f)\n", n, *loop.back().error_h1,
              quadratic_at_n, *loop.back().error_h1 / quadratic_at_n);
  EXPECT_LT(*loop.back().error_h1 * 20, quadratic_at_n);
  std::vector<double> dofs, h1;
  for (std::size_t i = loop.size() >= 5 ? loop.size() - 5 : 0; i < loop.size(); ++i) {
    dofs.push_back(double(loop[i].dofs));
    h1.push_back(*loop[i].error_h1);
  }
  const double rate = -testing::log_log_slope(dofs, h1);
  std::printf("  Loop's H1 rate over its last %zu cycles: N^-%.2f\n", dofs.size(), rate);
  EXPECT_GT(rate, 1.3);
}

// Loop elements on an open mesh (a flat square under Loop's boundary rules, its corners
// rounded; Dirichlet data by Nitsche's method) with a boundary layer in the solution. Next to
// the boundary the space reproduces linear functions only (the boundary rules' ghosts are
// g = a + b - t), so uniform refinement converges as h^1.5 in H1 (N^-0.75; measured 0.74);
// adaptive refinement grades towards the boundary and the layer and recovers most of the
// cubics' N^-1.5 (measured N^-1.29 over the last five cycles), the estimate staying 4 times
// the error.
TEST(Adapt, LoopElementsOnAnOpenMesh) {
  fem::Problem layer;
  layer.name = "layer";
  const auto u = [](const Vec3& x) { return std::exp(-8 * x.x) + std::sin(x.y); };
  layer.source = [](const Vec3& x) { return -64 * std::exp(-8 * x.x) + std::sin(x.y); };
  layer.dirichlet = u;
  layer.exact = fem::ExactSolution{u, [](const Vec3& x) {
                                     return Vec3{-8 * std::exp(-8 * x.x), std::cos(x.y), 0};
                                   }};
  for (const Strategy strategy : {Strategy::uniform, Strategy::adaptive}) {
    const TriangleMeshData square = square_lattice(4, 1, 0);
    RgbMesh mesh = RgbMesh::from_triangles(square.points, square.triangles);
    AdaptOptions o;
    o.strategy = strategy;
    o.element = AdaptOptions::Element::loop;
    o.max_cycles = 40;
    o.max_dofs = 6000;
    const AdaptRun run = run_cycles(mesh, layer, o);
    std::printf("  %s:\n", strategy == Strategy::uniform ? "uniform" : "adaptive");
    std::vector<double> dofs, errors;
    for (const CycleReport& c : run.cycles) {
      std::printf("    %6zu unknowns: H1 %.3e, estimate %.3e\n", c.dofs, *c.error_h1, c.estimate);
      dofs.push_back(static_cast<double>(c.dofs));
      errors.push_back(*c.error_h1);
      EXPECT_GT(c.estimate, 2 * *c.error_h1);
      EXPECT_LT(c.estimate, 8 * *c.error_h1);
    }
    const std::size_t last = std::min<std::size_t>(5, dofs.size());
    const double rate =
        -testing::log_log_slope({dofs.end() - static_cast<std::ptrdiff_t>(last), dofs.end()},
                                {errors.end() - static_cast<std::ptrdiff_t>(last), errors.end()});
    std::printf("    rate N^-%.2f over the last %zu cycles\n", rate, last);
    if (strategy == Strategy::uniform) {
      EXPECT_GT(rate, 0.7);
      EXPECT_LT(rate, 0.8);  // the boundary's h^1.5, not the cubics' h^3
    } else {
      EXPECT_GT(rate, 1.15);
      EXPECT_LT(errors.back(), 1.2e-3);  // uniform: 1.4e-2 at 4,225 unknowns
    }
  }
}

TEST(Adapt, MemoryCeilingKnowsTheElement) {
  for (const bool loop : {false, true}) {
    RgbMesh mesh = icosphere();
    AdaptOptions o = sphere_options(Strategy::uniform);
    o.max_dofs = 100000;
    if (loop) o.element = AdaptOptions::Element::loop;
    o.control.memory_headroom = [] { return std::size_t{12} << 20; };
    const AdaptRun run = run_cycles(mesh, fem::sphere_peak(), o);
    EXPECT_EQ(run.stopped, StopReason::memory) << loop;
    EXPECT_EQ(run.cycles.back().dofs, loop ? 642u : 2562u) << loop;
  }
}

TEST(Adapt, ARunStopsWhenAskedAndCanBeAbandonedWithAValidMesh) {
  // The stop predicate ends the run with the cycle it accepts, on the mesh that cycle solved.
  RgbMesh mesh = icosphere();
  AdaptOptions o = sphere_options(Strategy::adaptive);
  std::vector<std::size_t> asked;
  o.control.stop = [&](const CycleReport& r) {
    asked.push_back(r.dofs);
    return r.dofs > 500;
  };
  const AdaptRun run = run_cycles(mesh, fem::sphere_peak(), o);
  EXPECT_EQ(run.stopped, StopReason::requested);
  EXPECT_STREQ(to_string(run.stopped), "requested");
  ASSERT_GE(run.cycles.size(), 2u);
  EXPECT_EQ(asked.size(), run.cycles.size());
  EXPECT_GT(run.cycles.back().dofs, 500u);
  EXPECT_LE(run.cycles[run.cycles.size() - 2].dofs, 500u);
  EXPECT_EQ(mesh.num_vertices(), run.cycles.back().dofs);  // not adapted after the last solve
  EXPECT_EQ(mesh.validate(), "");
  // An exception from the interruption point abandons the run, wherever it comes from (here
  // from inside the third cycle's adaptation), and leaves a valid mesh.
  for (const int throw_at : {1, 7, 12}) {
    RgbMesh m = icosphere();
    AdaptOptions a = sphere_options(Strategy::adaptive);
    int calls = 0;
    a.control.interruption_point = [&] {
      if (++calls == throw_at) throw std::runtime_error("interrupted");
    };
    EXPECT_THROW(run_cycles(m, fem::sphere_peak(), a), std::runtime_error) << throw_at;
    EXPECT_EQ(calls, throw_at);
    EXPECT_EQ(m.validate(), "") << throw_at;
  }
}

TEST(Adapt, FreeMemoryIsHandedBackAfterEverySolve) {
  // The hook runs once per solve, after it and before the cycle is reported, with P1, P2 and
  // Loop elements (the Loop cycle is solved apart), and in every step of a moving feature.
  for (const int kind : {1, 2, 3}) {
    RgbMesh mesh = icosphere();
    AdaptOptions o = sphere_options(Strategy::adaptive);
    o.max_cycles = 4;
    if (kind == 2) o.order = 2;
    if (kind == 3) o.element = AdaptOptions::Element::loop;
    std::string events;
    o.control.release_free_memory = [&] { events += 'r'; };
    const AdaptRun run = run_cycles(mesh, fem::sphere_peak(), o, [&](const CycleState&) { events += 'c'; });
    ASSERT_EQ(run.cycles.size(), 4u) << kind;
    EXPECT_EQ(events, "rcrcrcrc") << kind;
  }
  RgbMesh mesh = icosphere();
  AdaptOptions o = sphere_options(Strategy::adaptive);
  o.coarsen_below = 0.25;
  DynamicOptions d;
  d.steps = 3;
  d.start_cycles = 3;
  d.cycles_per_step = 2;
  std::size_t released = 0, before_step = 0;
  std::vector<std::size_t> per_step;
  o.control.release_free_memory = [&] { ++released; };
  const AdaptRun run = run_dynamic(mesh, [](double t) { return moving_peak(t); }, o, d, [&](const CycleState&) {
    per_step.push_back(released - before_step);
    before_step = released;
  });
  EXPECT_EQ(run.stopped, StopReason::steps);
  ASSERT_EQ(per_step.size(), 4u);
  // Each step after the first solves once per adaptation cycle and once more for its report.
  for (std::size_t k = 1; k < per_step.size(); ++k) EXPECT_EQ(per_step[k], 3u) << "step " << k;
}

TEST(Adapt, SphereHarmonicAdaptsWithItsZeroMeanSource) {
  // c = 0 on the closed sphere: the source has zero mean on the sphere, but its discrete load
  // on an adaptive mesh of flat triangles does not; the run must not refuse it.
  RgbMesh mesh = icosphere();
  AdaptOptions o = sphere_options(Strategy::adaptive);
  o.max_dofs = 5000;
  const AdaptRun run = run_cycles(mesh, fem::sphere_harmonic(), o);
  ASSERT_GE(run.cycles.size(), 5u);
  EXPECT_LT(*run.cycles.back().error_h1, 0.5 * *run.cycles.front().error_h1);
}

TEST(Adapt, MarkingTakesTheBulkOrTheFraction) {
  const std::vector<double> eta = {1, 4, 2, 3, 0.5};  // squares 1, 16, 4, 9, 0.25: total 30.25
  // Dörfler, θ = 0.5: 16 alone is 53%.
  const Indicators in(eta);
  EXPECT_EQ(DorflerMarking(0.5).mark(in), (std::vector<char>{0, 1, 0, 0, 0}));
  // θ = 0.8: 16 + 9 = 25 is 83%.
  EXPECT_EQ(DorflerMarking(0.8).mark(in), (std::vector<char>{0, 1, 0, 1, 0}));
  EXPECT_EQ(FixedFractionMarking(0.4).mark(in), (std::vector<char>{0, 1, 0, 1, 0}));
  // Equidistribution towards a total of 10: every η above 10 / sqrt(5) = 4.47; towards 5, above 2.24.
  EXPECT_EQ(EquidistributionMarking().mark(Indicators(eta, 10.0)), (std::vector<char>{0, 0, 0, 0, 0}));
  EXPECT_EQ(EquidistributionMarking().mark(Indicators(eta, 5.0)), (std::vector<char>{0, 1, 0, 1, 0}));
  // The tables of names give these strategies and refuse others, naming the choices.
  EXPECT_EQ(make_marking("fraction", 0.4)->mark(in), (std::vector<char>{0, 1, 0, 1, 0}));
  EXPECT_TRUE(make_marking("equidistribution", 0.5)->marks_by_target());
  EXPECT_THROW(make_marking("bulk", 0.5), InputError);
  EXPECT_THROW(make_marking("dorfler", 0), InputError);
  EXPECT_THROW(fem::make_estimator("kelly"), InputError);
}

}  // namespace
}  // namespace rgbmesh::adapt
