// Sharp features (creases, corners, semi-sharp and Chaikin creases) against OpenSubdiv, whose
// Far::TopologyRefiner takes the same tags (Far::TopologyDescriptor's creases and corners):
//  * OpenSubdiv's own Loop regression shapes with their tags, read from their OBJ text by our
//    reader (scripts/fetch-test-data.sh cuts them out of opensubdiv-tools): uniform levels,
//    any order of operations, selective meshes and coarsening back equal OpenSubdiv's Loop
//    meshes, control points and limit positions (where its Limit() is exact);
//  * meshes of our own: a cube whose 12 edges are creases stays exactly the cube; darts
//    converge to the limit we compute (not to OpenSubdiv's Limit(), which uses the smooth mask
//    there); every vertex rule and the sharpness of every edge match OpenSubdiv's.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "loop_reference.hpp"
#include "public_data.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

using testing::BaseMesh;
using testing::expect_loop_control_points;
using testing::expect_loop_level;
using testing::LoopReference;
using testing::graded_icosahedron;
using testing::octahedron_with_darts;
using testing::sharp_cube;

BaseMesh opensubdiv_shape(const std::string& name) {
  const TriangleMeshData data = read_mesh(testing::public_data("opensubdiv/" + name + ".obj"));
  return {name, data.points, data.triangles, data.sharp};
}

const char* const kShapes[] = {"loop_cube_creases0",  "loop_cube_creases1", "loop_cubes_infsharp",
                               "loop_cubes_semisharp", "loop_chaikin0",      "loop_chaikin1",
                               "loop_icos_infsharp",   "loop_icos_semisharp"};

std::vector<BaseMesh> sharp_meshes() {
  std::vector<BaseMesh> meshes;
  for (const char* name : kShapes) meshes.push_back(opensubdiv_shape(name));
  meshes.push_back(sharp_cube());
  meshes.push_back(octahedron_with_darts());
  meshes.push_back(graded_icosahedron(CreaseMethod::uniform));
  meshes.push_back(graded_icosahedron(CreaseMethod::chaikin));
  return meshes;
}

class SharpGeometry : public ::testing::TestWithParam<BaseMesh> {};

TEST_P(SharpGeometry, TagsAreRead) {
  const BaseMesh& base = GetParam();
  ASSERT_FALSE(base.sharp.empty()) << base.name;
  const RgbMesh m = base.build();
  EXPECT_TRUE(m.has_sharp_features());
  EXPECT_EQ(m.sharp_features().method, base.sharp.method);
}

TEST_P(SharpGeometry, UniformLevelsAreLoopSubdivisionWithCreases) {
  const BaseMesh& base = GetParam();
  constexpr int kLevels = 4;
  const LoopReference ref(base, kLevels);
  RgbMesh m = base.build();
  int rules = 0;
  for (int k = 1; k <= kLevels; ++k) {
    selective_refinement(m, UniformLevel(k));
    ASSERT_EQ(m.validate(true), "");
    expect_loop_level(m, ref, k, base.name + " level " + std::to_string(k));
    // The rules and the edges' sharpness are OpenSubdiv's.
    const auto& level = ref.level(k);
    const std::vector<int> osd = ref.indices_at(m, k);
    for (VertexHandle v : m.vertices()) {
      const int expected = static_cast<int>(level.GetVertexRule(osd[v.idx]));  // 1 smooth, 2 dart, 4 crease, 8 corner
      EXPECT_EQ(1 << static_cast<int>(m.vertex_rule(v)), expected) << base.name << " " << to_string(m.vertex_rule(v));
      rules += m.vertex_rule(v) != VertexRule::smooth;
    }
    for (EdgeHandle e : m.edges()) {
      const auto& ends = m.edge_vertices(e);
      const int f = level.FindEdge(osd[ends[0].idx], osd[ends[1].idx]);
      ASSERT_GE(f, 0);
      const float theirs = level.IsEdgeBoundary(f) ? kInfiniteSharpness : level.GetEdgeSharpness(f);
      EXPECT_EQ(m.sharpness(e), theirs) << base.name;
    }
  }
  EXPECT_GT(rules, 0);
}

TEST_P(SharpGeometry, LimitPositionsAreOpenSubdivsWhereItsLimitIsExact) {
  const BaseMesh& base = GetParam();
  constexpr int kLevels = 5;
  const LoopReference ref(base, kLevels);
  RgbMesh m = base.build();
  selective_refinement(m, UniformLevel(kLevels));
  const std::vector<int> osd = ref.indices_at(m, kLevels);
  double worst = 0;
  int exact = 0;
  for (VertexHandle v : m.vertices()) {
    ASSERT_TRUE(m.has_limit(v));
    if (!ref.limit_is_exact(osd[v.idx])) continue;
    ++exact;
    worst = std::max(worst, distance(m.limit_position(v), ref.limit(osd[v.idx])));
  }
  EXPECT_GT(exact, 0);
  EXPECT_LE(worst, ref.tolerance()) << base.name;
}

TEST_P(SharpGeometry, AnyOperationOrderGivesTheSameMesh) {
  const BaseMesh& base = GetParam();
  const LoopReference ref(base, 4);
  for (std::uint64_t seed : {1u, 2u}) {
    RgbMesh m = base.build();
    RandomWalkOptions options;
    options.max_level = 4;
    random_walk(m, 2000, seed, options);
    ASSERT_EQ(m.validate(), "");
    const std::string what = base.name + " seed " + std::to_string(seed);
    selective_refinement(m, UniformLevel(3));
    expect_loop_level(m, ref, 3, what + " then uniform 3");
    random_walk(m, 2000, seed + 100, options);
    ASSERT_EQ(m.validate(), "");
    selective_refinement(m, CoarsenAll());
    ASSERT_EQ(m.num_vertices(), base.points.size());
    for (VertexHandle v : m.vertices())
      EXPECT_EQ(m.control_point(v), base.points[static_cast<std::size_t>(v.idx)]) << what;
  }
}

TEST_P(SharpGeometry, SelectiveMeshesShowLoopControlPoints) {
  const BaseMesh& base = GetParam();
  const LoopReference ref(base, 5);
  RgbMesh ball = base.build();
  const Vec3 corner = base.points.front();
  selective_refinement(ball, BallLevel(corner, 0.3 * distance(corner, base.points.back()), 5));
  ASSERT_EQ(ball.validate(true), "");
  expect_loop_control_points(ball, ref, base.name + " ball");

  RgbMesh walked = base.build();
  RandomWalkOptions options;
  options.max_level = 5;
  random_walk(walked, 3000, 7, options);
  ASSERT_EQ(walked.validate(), "");
  expect_loop_control_points(walked, ref, base.name + " random walk");
}

INSTANTIATE_TEST_SUITE_P(Shapes, SharpGeometry, ::testing::ValuesIn(sharp_meshes()),
                         [](const ::testing::TestParamInfo<BaseMesh>& p) { return p.param.name; });

TEST(SharpCube, StaysExactlyTheCube) {
  // Every limit point lies on the cube's surface: on a face plane, inside the face.
  const BaseMesh base = sharp_cube();
  RgbMesh m = base.build();
  selective_refinement(m, UniformLevel(4));
  m.compute_limits();
  double lo = 1e300, hi = -1e300;
  for (const Vec3& p : base.points)
    for (int i = 0; i < 3; ++i) lo = std::min(lo, p[i]), hi = std::max(hi, p[i]);
  double worst = 0;
  for (VertexHandle v : m.vertices()) {
    const Vec3 p = m.limit_position(v);
    double to_face = 1e300, outside = 0;
    for (int i = 0; i < 3; ++i) {
      to_face = std::min({to_face, std::abs(p[i] - lo), std::abs(p[i] - hi)});
      outside = std::max({outside, lo - p[i], p[i] - hi});
    }
    worst = std::max({worst, to_face, outside});
  }
  EXPECT_LE(worst, 1e-12 * (hi - lo));
}

TEST(Darts, ConvergeToTheLimitOfTheirOwnRules) {
  // OpenSubdiv's control points at a dart approach our limit by a constant factor per level,
  // so that Aitken's extrapolation of its last three lands on our limit; its Limit() (the
  // smooth mask) does not.
  const BaseMesh base = octahedron_with_darts();
  constexpr int kLevels = 7;
  const LoopReference ref(base, kLevels);
  RgbMesh m = base.build();
  for (const VertexHandle dart : {VertexHandle(base.sharp.edges[0].a), VertexHandle(base.sharp.edges[0].b)}) {
    ASSERT_EQ(m.vertex_rule(dart, 0), VertexRule::dart);
    const Vec3 limit = m.limit_position(dart);
    std::vector<Vec3> p;
    int u = dart.idx;
    for (int k = 0; k <= kLevels; ++k) {
      EXPECT_LE(distance(m.control_point(dart, k), ref.point(k, u)), ref.tolerance()) << "level " << k;
      p.push_back(ref.point(k, u));
      if (k < kLevels) u = ref.level(k).GetVertexChildVertex(u);
    }
    const double gap = distance(p[kLevels], limit);
    for (int k = 2; k <= kLevels; ++k) EXPECT_LT(distance(p[k], limit), 0.6 * distance(p[k - 1], limit));
    // Aitken's delta-squared, coordinate by coordinate.
    const auto extrapolate = [&](int i) {
      const double a = p[kLevels - 2][i], b = p[kLevels - 1][i], c = p[kLevels][i];
      const double d = (c - b) - (b - a);
      return d == 0.0 ? c : c - (c - b) * (c - b) / d;
    };
    const Vec3 aitken(extrapolate(0), extrapolate(1), extrapolate(2));
    std::printf("dart %d: gap %.3e, aitken %.3e, OpenSubdiv Limit() %.3e\n", dart.idx, gap, distance(aitken, limit),
                distance(ref.limit(u), limit));
    EXPECT_LT(distance(aitken, limit), 0.05 * gap);
    EXPECT_GT(distance(ref.limit(u), limit), 5 * distance(aitken, limit)) << "OpenSubdiv's Limit() at a dart";
  }
}

TEST(SharpFeaturesInput, BadTagsAreNamed) {
  const BaseMesh cube = testing::cube();
  SharpFeatures s;
  s.edges.push_back({0, 0, 1.0f});
  EXPECT_THROW(RgbMesh::from_triangles(cube.points, cube.triangles, s), InputError);
  s.edges = {{0, 99, 1.0f}};
  EXPECT_THROW(RgbMesh::from_triangles(cube.points, cube.triangles, s), InputError);
  s.edges = {{cube.triangles[0][0], cube.triangles[0][1], -1.0f}};
  EXPECT_THROW(RgbMesh::from_triangles(cube.points, cube.triangles, s), InputError);
  s.edges = {{cube.triangles[0][0], cube.triangles[0][1], 0.0f}};
  EXPECT_FALSE(RgbMesh::from_triangles(cube.points, cube.triangles, s).has_sharp_features());
  s.edges = {{cube.triangles[0][0], cube.triangles[0][1], 3.0f}, {cube.triangles[0][1], cube.triangles[0][0], 12.0f}};
  const RgbMesh m = RgbMesh::from_triangles(cube.points, cube.triangles, s);
  ASSERT_EQ(m.sharp_features().edges.size(), 1u);  // the last entry counts, at most 10
  EXPECT_EQ(m.sharp_features().edges[0].sharpness, kInfiniteSharpness);
}

}  // namespace
}  // namespace rgbmesh
