// RGB subdivision against OpenSubdiv, an independent implementation of Loop subdivision
// (Far::TopologyRefiner with Sdc::SCHEME_LOOP and VTX_BOUNDARY_EDGE_ONLY, positions by
// Far::PrimvarRefinerReal<double>):
//  * uniform RGB refinement to level K has the topology and the control points of K steps of
//    Loop subdivision, and its limit positions are OpenSubdiv's Limit();
//  * the same holds after any random sequence of splits and removals (order independence);
//  * in selectively refined meshes every vertex shows the Loop control point of its level.

#include <gtest/gtest.h>
#include <opensubdiv/far/primvarRefiner.h>

#include <algorithm>
#include <memory>
#include <set>

#include "loop_reference.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

using namespace OpenSubdiv;
using testing::expect_loop_control_points;
using testing::expect_loop_level;
using testing::LoopReference;

std::vector<testing::BaseMesh> geometry_meshes() {
  std::vector<testing::BaseMesh> meshes = testing::all_base_meshes();
  for (int n : {4, 5, 6, 7, 8, 9, 10, 11}) meshes.push_back(testing::bipyramid(n));
  return meshes;
}

class LoopGeometry : public ::testing::TestWithParam<testing::BaseMesh> {};

TEST_P(LoopGeometry, UniformLevelsAreLoopSubdivision) {
  const testing::BaseMesh& base = GetParam();
  const LoopReference ref(base, 5);
  RgbMesh m = base.build();
  for (int k = 1; k <= 5; ++k) {
    selective_refinement(m, UniformLevel(k));
    ASSERT_EQ(m.validate(true), "");
    expect_loop_level(m, ref, k, base.name + " level " + std::to_string(k));
  }
}

TEST_P(LoopGeometry, LimitPositionsAreOpenSubdivsLimit) {
  const testing::BaseMesh& base = GetParam();
  const LoopReference ref(base, 3);
  RgbMesh m = base.build();
  selective_refinement(m, UniformLevel(3));
  const std::vector<int> osd = ref.indices_at(m, 3);
  double worst = 0;
  for (VertexHandle v : m.vertices()) {
    ASSERT_TRUE(m.has_limit(v));  // a uniform mesh has every Loop ring
    worst = std::max(worst, distance(m.limit_position(v), ref.limit(osd[v.idx])));
  }
  EXPECT_LE(worst, ref.tolerance());
}

TEST_P(LoopGeometry, AnyOperationOrderGivesLoopSubdivision) {
  const testing::BaseMesh& base = GetParam();
  const LoopReference ref(base, 4);
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    RgbMesh m = base.build();
    RandomWalkOptions options;
    options.max_level = 4;
    random_walk(m, 3000, seed, options);
    ASSERT_EQ(m.validate(), "");
    const std::string what = base.name + " seed " + std::to_string(seed);
    selective_refinement(m, UniformLevel(3));
    expect_loop_level(m, ref, 3, what + " then uniform 3");
    random_walk(m, 2000, seed + 100, options);
    selective_refinement(m, CoarsenAll());
    ASSERT_EQ(m.num_vertices(), base.points.size());
    for (VertexHandle v : m.vertices()) {
      EXPECT_EQ(m.control_point(v), base.points[static_cast<std::size_t>(v.idx)]) << what;
    }
  }
}

TEST_P(LoopGeometry, SelectiveMeshesShowLoopControlPoints) {
  const testing::BaseMesh& base = GetParam();
  const LoopReference ref(base, 5);
  RgbMesh ball = base.build();
  const Vec3 corner = base.points.front();
  selective_refinement(ball, BallLevel(corner, 0.3 * distance(corner, base.points.back()), 5));
  expect_loop_control_points(ball, ref, base.name + " ball");

  RgbMesh budget = base.build();
  RefinementOptions capped;
  capped.max_level = 5;
  selective_refinement(budget, TriangleBudget(base.triangles.size() * 37), capped);
  expect_loop_control_points(budget, ref, base.name + " budget");

  RgbMesh walked = base.build();
  RandomWalkOptions options;
  options.max_level = 5;
  random_walk(walked, 4000, 7, options);
  expect_loop_control_points(walked, ref, base.name + " random walk");
}

INSTANTIATE_TEST_SUITE_P(Meshes, LoopGeometry, ::testing::ValuesIn(geometry_meshes()),
                         [](const ::testing::TestParamInfo<testing::BaseMesh>& p) { return p.param.name; });

#ifndef RGBMESH_DATA_DIR
#error "RGBMESH_DATA_DIR must name the repository's data directory"
#endif

testing::BaseMesh stanford_bunny() {
  const TriangleMeshData data = read_mesh(std::string(RGBMESH_DATA_DIR) + "/bunny.obj");
  return {"bunny", data.points, data.triangles};
}

TEST(LoopGeometryBunny, UniformLevelsAndLimitAreLoopSubdivision) {
#ifdef NDEBUG
  constexpr int kLevels = 5;  // 3.8 million triangles
#else
  constexpr int kLevels = 3;  // sanitizer and debug builds
#endif
  const testing::BaseMesh base = stanford_bunny();
  ASSERT_EQ(base.triangles.size(), 3674u);
  const LoopReference ref(base, kLevels);
  RgbMesh m = base.build();
  for (int k = 1; k <= kLevels; ++k) {
    selective_refinement(m, UniformLevel(k));
    expect_loop_level(m, ref, k, "bunny level " + std::to_string(k));
  }
  const std::vector<int> osd = ref.indices_at(m, kLevels);
  double worst = 0;
  for (VertexHandle v : m.vertices()) worst = std::max(worst, distance(m.limit_position(v), ref.limit(osd[v.idx])));
  EXPECT_LE(worst, ref.tolerance());
}

TEST(LoopGeometryBunny, SelectiveRefinementShowsLoopControlPoints) {
  const testing::BaseMesh base = stanford_bunny();
  const LoopReference ref(base, 4);
  RgbMesh m = base.build();
  selective_refinement(m, BallLevel(base.points[100], 0.5, 4));
  RandomWalkOptions options;
  options.max_level = 4;
  random_walk(m, 5000, 11, options);
  ASSERT_EQ(m.validate(true), "");
  expect_loop_control_points(m, ref, "bunny");
}

}  // namespace
}  // namespace rgbmesh
