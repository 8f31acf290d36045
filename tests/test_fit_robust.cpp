// The fit as users' data need it (issue 23): reconstructions that stay bounded and fall back
// instead of hanging, open clouds kept open, sparse clouds refused, normals taken one by one,
// mesh targets sampled on their triangles, distances to the target's surface checked against
// exact values, stages stopped from outside, and the two-sided check's verdicts.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "public_data.hpp"
#include "rgbmesh/fit/base.hpp"
#include "rgbmesh/fit/distances.hpp"
#include "rgbmesh/fit/fit_target.hpp"
#include "rgbmesh/fit/reconstruct.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::fit {
namespace {

bool has_note(const std::vector<std::string>& notes, const std::string& text) {
  for (const std::string& n : notes)
    if (n.find(text) != std::string::npos) return true;
  return false;
}

std::string notes_text(const std::vector<std::string>& notes) {
  std::string all;
  for (const std::string& n : notes) all += n + "\n";
  return all;
}

// Fibonacci points on the unit sphere (only those with z >= min_z): evenly spread.
std::vector<Vec3> sphere_points(int n, double min_z = -2) {
  std::vector<Vec3> points;
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z);
    if (z >= min_z) points.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return points;
}

// A closed cube [0,1]^3 of 12 triangles, outward.
TriangleMeshData unit_cube() {
  TriangleMeshData cube;
  for (int i = 0; i < 8; ++i) cube.points.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  cube.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return cube;
}

double area_of(const TriangleMeshData& m) {
  double a = 0;
  for (const auto& t : m.triangles) a += 0.5 * norm(cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]));
  return a;
}

TEST(Reconstruction, AnOpenCapStaysOpenThroughTheAdvancingFront) {
  // The upper half of a sphere: Poisson would close it with surface no point supports.
  const std::vector<Vec3> cap = sphere_points(8000, 0.0);
  const Reconstruction r = reconstruct_surface(cap, {});
  EXPECT_EQ(r.method, ReconstructionMethod::advancing_front) << notes_text(r.mesh.notes);
  EXPECT_TRUE(has_note(r.mesh.notes, "Poisson: ")) << notes_text(r.mesh.notes);
  const Topology t = topology_of(r.mesh);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(t.boundary_loops, 1);
  // On the hemisphere: its area (2 pi) to a few percent, every vertex on the sphere.
  EXPECT_NEAR(area_of(r.mesh), 2 * M_PI, 0.05 * 2 * M_PI);
  for (const Vec3& p : r.mesh.points) EXPECT_NEAR(norm(p), 1.0, 1e-3);
}

TEST(Reconstruction, AClosedCloudKeepsPoissonAndIsFullySupported) {
  const Reconstruction r = reconstruct_surface(sphere_points(4000), {});
  EXPECT_EQ(r.method, ReconstructionMethod::poisson);
  EXPECT_LT(r.unsupported, 1e-3);
  EXPECT_EQ(topology_of(r.mesh).boundary_loops, 0);
}

TEST(Reconstruction, TooSparseACloudIsRefusedWithWhatToDo) {
  // 49 points over a sphere are 15% of its extent apart: any surface between them is a guess
  // (one came back five times the part's size).
  try {
    reconstruct_surface(sphere_points(49), {});
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("reconstructing a surface from 49 points: the points are too sparse", 0), 0u) << m;
    EXPECT_NE(m.find("--base"), std::string::npos) << m;
  }
}

TEST(Reconstruction, UnusableNormalsLeaveOnlyTheirPointsOut) {
  std::vector<Vec3> points = sphere_points(3000), normals = points;  // outward on the unit sphere
  normals[10] = Vec3(0, 0, 0);
  normals[2000] = Vec3(NAN, 0, 1);
  const Reconstruction r = reconstruct_surface(points, normals);
  EXPECT_TRUE(has_note(r.mesh.notes, "2 of 3,000 normals are zero or not finite: those points are left out"))
      << notes_text(r.mesh.notes);
  EXPECT_FALSE(has_note(r.mesh.notes, "estimated")) << notes_text(r.mesh.notes);
  EXPECT_EQ(r.method, ReconstructionMethod::poisson);
  for (const Vec3& p : r.mesh.points) EXPECT_NEAR(norm(p), 1.0, 0.02);
}

TEST(Reconstruction, NormalsOfArbitrarySignAreReorientedFirst) {
  // Principal directions, as a CAD tool exports them: right lines, random signs.
  std::vector<Vec3> points = sphere_points(3000), normals = points;
  std::mt19937 random(7);
  for (Vec3& n : normals)
    if (random() % 2) n = -1.0 * n;
  const Reconstruction r = reconstruct_surface(points, normals);
  EXPECT_TRUE(has_note(r.mesh.notes, "not consistently oriented")) << notes_text(r.mesh.notes);
  EXPECT_EQ(r.method, ReconstructionMethod::poisson);
  const Topology t = topology_of(r.mesh);
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(t.boundary_loops, 0);
  for (const Vec3& p : r.mesh.points) EXPECT_NEAR(norm(p), 1.0, 0.02);
}

TEST(Reconstruction, ALevelSetBeyondItsBudgetFallsBackInsteadOfRunningOn) {
  // A budget far below what the sphere needs stands for a level set gone wild.
  ReconstructionOptions options;
  options.max_vertices_per_face = 0.01;
  const Reconstruction r = reconstruct_surface(sphere_points(4000), {}, options);
  EXPECT_EQ(r.method, ReconstructionMethod::advancing_front);
  EXPECT_TRUE(has_note(r.mesh.notes, "Poisson's zero level set needs more than")) << notes_text(r.mesh.notes);
  EXPECT_EQ(topology_of(r.mesh).genus, 0);
  // Asked for Poisson alone, the same is a refusal naming the way out.
  options.method = ReconstructionMethod::poisson;
  try {
    reconstruct_surface(sphere_points(4000), {}, options);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--reconstruction advancing-front"), std::string::npos) << e.what();
  }
}

// A control that throws on its n-th call: every stage must let it through, whatever it holds.
struct StopAfter {
  int calls = 0, limit;
  std::vector<std::string> stages;
  explicit StopAfter(int n) : limit(n) {}
  StageControl control() {
    StageControl c;
    c.on_step = [this](const std::string& stage, double fraction) {
      EXPECT_TRUE(fraction < 0 || (fraction >= 0 && fraction <= 1)) << fraction;
      if (stages.empty() || stages.back() != stage) stages.push_back(stage);
      if (++calls == limit) throw ResourceError("stopped in " + stage);
    };
    return c;
  }
};

TEST(StageControl, EveryStageOfAFitCanBeStoppedFromOutside) {
  // Count the calls of a whole run, then stop runs at calls spread over it: the stop always
  // comes out as the control's exception, naming a stage.
  const std::vector<Vec3> cloud = sphere_points(3000, 0.0);  // Poisson, then the advancing front
  PolygonSoup target;
  target.points = cloud;
  TargetFitOptions options;
  options.base.faces = 300;
  options.fit.levels = 2;
  options.fit.max_iterations = 3;
  StopAfter count(-1);
  TargetFit whole = prepare_target_fit(target, {}, std::nullopt, options, count.control());
  run_target_fit(whole, options, {}, count.control());
  const int total = count.calls;
  ASSERT_GT(total, 10);
  std::string seen;
  for (const std::string& s : count.stages) seen += s + "\n";
  for (const char* stage : {"(Poisson equation)", "(meshing the level set)", "(advancing front", "decimating",
                            "limit stencils", "fitting", "measuring the distances"})
    EXPECT_NE(seen.find(stage), std::string::npos) << stage << " in\n" << seen;
  for (int k = 1; k <= 8; ++k) {
    StopAfter stop(k * total / 9);
    try {
      TargetFit f = prepare_target_fit(target, {}, std::nullopt, options, stop.control());
      run_target_fit(f, options, {}, stop.control());
      FAIL() << "not stopped at call " << stop.limit;
    } catch (const ResourceError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("stopped in ", 0), 0u);
    }
  }
}

TEST(SurfaceSamples, SpreadOverTheTrianglesByArea) {
  TriangleMeshData m;  // two triangles of areas 1/2 and 1 in the plane z = 0
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {3, 0, 0}, {3, 1, 0}};
  m.triangles = {{0, 1, 2}, {1, 3, 4}};
  const std::vector<Vec3> s = surface_samples(m, 1005);
  ASSERT_EQ(s.size(), 1005u);
  for (std::size_t i = 0; i < m.points.size(); ++i) EXPECT_EQ(s[i], m.points[i]);  // the vertices first
  std::size_t in_first = 0;
  for (std::size_t i = 5; i < s.size(); ++i) {
    EXPECT_EQ(s[i].z, 0);
    const bool first = s[i].x + s[i].y <= 1 + 1e-12 && s[i].x >= 0 && s[i].y >= 0 && s[i].x <= 1;
    const bool second = s[i].x >= 1 - 1e-12 && s[i].x <= 3 && s[i].y >= 0 && s[i].y <= (s[i].x - 1) / 2 + 1e-12;
    EXPECT_TRUE(first || second) << s[i].x << " " << s[i].y;
    in_first += first;
  }
  EXPECT_NEAR(static_cast<double>(in_first), 1000 / 3.0, 1.0);  // a third of the area
  EXPECT_EQ(surface_samples(m, 1005), s);                         // the same points every time
  EXPECT_EQ(surface_samples(m, 3).size(), 5u);                    // never fewer than the vertices
}

TEST(TargetSurfaceDistances, AMeshIsMeasuredExactly) {
  const TargetSurface cube = TargetSurface::from_mesh(unit_cube());
  const std::vector<double> d = cube.distances({{0.5, 0.5, 2}, {0.25, 0.5, 0.5}, {2, 2, 2}, {0.5, 0.5, 1}});
  EXPECT_NEAR(d[0], 1.0, 1e-12);
  EXPECT_NEAR(d[1], 0.25, 1e-12);  // inside: to the nearest face
  EXPECT_NEAR(d[2], std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(d[3], 0.0, 1e-12);
}

TEST(TargetSurfaceDistances, ACloudIsMeasuredAcrossItsDiscsAndBeyondTheirRims) {
  std::vector<Vec3> grid;  // the square [0, 1]^2 of z = 0 sampled every 0.01
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 100; ++j) grid.emplace_back(i / 100.0, j / 100.0, 0);
  const TargetSurface plane = TargetSurface::from_points(grid);
  const std::vector<double> d = plane.distances({{0.505, 0.505, 0.03}, {0.505, 0.505, 0}, {2, 0.5, 0}, {0.5, 0.5, -0.2}});
  EXPECT_NEAR(d[0], 0.03, 1e-9);  // between points, above the plane: the height, not the gap
  EXPECT_NEAR(d[1], 0.0, 1e-9);
  // Beyond the edge x = 1: the distance past the rim of the last points' discs (their spacing,
  // about 0.0128 for a square grid's 6 nearest there), within that spacing of the true 1.
  EXPECT_NEAR(d[2], 1.0, 0.015);
  EXPECT_LT(d[2], 1.0);
  EXPECT_NEAR(d[3], 0.2, 1e-9);
}

TEST(Verdicts, SurfaceFarFromTheTargetIsRejectedWithTheFigures) {
  TwoSidedDistances d;
  d.diagonal = 100;
  d.to_surface_rms = 0.2;  // 0.2%
  d.to_surface_p99 = 0.6;
  d.to_target_rms = 0.4;
  d.to_target_max = 2.9;
  EXPECT_TRUE(judge(d).accepted);
  d.to_target_rms = 2.4;  // the pinion's case: 0.18% one way, 2.4% the other
  Verdict v = judge(d);
  EXPECT_FALSE(v.accepted);
  EXPECT_NE(v.reason.find("surface-to-target RMS 2.40% of the diagonal"), std::string::npos) << v.reason;
  d.to_target_rms = 0.4;
  d.to_target_max = 3.5;
  v = judge(d);
  EXPECT_FALSE(v.accepted);
  EXPECT_NE(v.reason.find("max 3.50%"), std::string::npos) << v.reason;
  // A noisy cloud: the targets themselves lie 1% from any smooth surface; the other direction
  // may be as far as twice that.
  d.to_surface_rms = 1.0;
  d.to_surface_p99 = 2.6;
  d.to_target_rms = 1.5;
  d.to_target_max = 4.5;
  EXPECT_FALSE(judge(d).accepted);  // unless they were measured noisy
  d.noisy_targets = true;
  EXPECT_TRUE(judge(d).accepted);
  AcceptanceRule exact;  // a mesh target: no allowance
  exact.rms_ratio = exact.max_ratio = 0;
  EXPECT_FALSE(judge(d, exact).accepted);
  // Targets the surface does not reach.
  d.to_surface_p99 = 8;
  v = judge(d);
  EXPECT_FALSE(v.accepted);
  EXPECT_NE(v.reason.find("does not reach the targets"), std::string::npos) << v.reason;
}

TEST(MeshTargets, ACoarseCadMeshIsFittedAsItsSurfaceNotItsVertices) {
  // A cube of 12 triangles: its 8 vertices alone let the surface bulge anywhere between them.
  const TriangleMeshData cube = unit_cube();
  PolygonSoup target;
  target.points = cube.points;
  for (const auto& t : cube.triangles) target.faces.push_back({t[0], t[1], t[2]});
  TargetFitOptions options;
  options.fit.max_iterations = 10;
  TargetFit f = prepare_target_fit(target, {}, std::nullopt, options);
  EXPECT_TRUE(f.target_is_surface);
  EXPECT_EQ(f.base.mesh.triangles.size(), 768u);  // 12 * 4^3, at least half the 1,000 asked for
  EXPECT_NEAR(static_cast<double>(f.targets.size()), 768 * 16, 1.0);  // a quarter of the limit triangles
  run_target_fit(f, options);
  // The distances in both directions are those to the cube itself, measured here apart.
  const std::vector<Vec3> limit = f.result.stencils.evaluate(f.result.control_points);
  double worst = 0;
  for (const Vec3& p : limit) {
    const Vec3 c(std::clamp(p.x, 0.0, 1.0), std::clamp(p.y, 0.0, 1.0), std::clamp(p.z, 0.0, 1.0));
    const double outside = distance(p, c);
    const double inside = std::min({p.x, 1 - p.x, p.y, 1 - p.y, p.z, 1 - p.z});
    worst = std::max(worst, outside > 0 ? outside : inside);
  }
  EXPECT_NEAR(f.distances.to_target_max, worst, 1e-9);
  // A smooth surface rounds the cube's edges: within the tool's bounds (3% of the diagonal).
  EXPECT_LT(worst, 0.03 * std::sqrt(3.0));
  EXPECT_TRUE(f.verdict.accepted) << f.verdict.reason;
}

TEST(MeshTargets, ATargetWhoseFacesAreBrokenIsRefusedNotReconstructed) {
  PolygonSoup target;
  const TriangleMeshData cube = unit_cube();
  target.points = cube.points;
  for (const auto& t : cube.triangles) target.faces.push_back({t[0], t[1], t[2]});
  target.faces.push_back({0, 2, 7});  // a third triangle on edge (0, 2)
  EXPECT_THROW(prepare_target_fit(target, {}, std::nullopt, TargetFitOptions{}), InputError);
}

}  // namespace
}  // namespace rgbmesh::fit
