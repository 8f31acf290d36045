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

#include "opensubdiv_refiner.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

using namespace OpenSubdiv;

struct Point {
  double p[3];
  void Clear() { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const Point& o, double w) {
    for (int i = 0; i < 3; ++i) p[i] += w * o.p[i];
  }
  Vec3 vec() const { return {p[0], p[1], p[2]}; }
};

// OpenSubdiv's uniform Loop refinement of a base mesh: control points at every level and the
// limit positions of the finest level's vertices.
class LoopReference {
 public:
  LoopReference(const testing::BaseMesh& base, int levels) : levels_(levels) {
    refiner_ = testing::loop_refiner(base);
    Far::TopologyRefiner::UniformOptions uniform(levels);
    uniform.fullTopologyInLastLevel = true;
    refiner_->RefineUniform(uniform);

    points_.resize(static_cast<std::size_t>(levels) + 1);
    for (const auto& q : base.points) points_[0].push_back({{q.x, q.y, q.z}});
    Far::PrimvarRefinerReal<double> primvar(*refiner_);
    for (int k = 1; k <= levels; ++k) {
      points_[k].resize(static_cast<std::size_t>(refiner_->GetLevel(k).GetNumVertices()));
      primvar.Interpolate(k, points_[k - 1], points_[k]);
    }
    limit_.resize(points_[levels].size());
    primvar.Limit(points_[levels], limit_);

    tolerance_ = 1e-12 * bounding_box_diagonal(base.points);
  }

  int levels() const { return levels_; }
  double tolerance() const { return tolerance_; }
  const Far::TopologyLevel& level(int k) const { return refiner_->GetLevel(k); }
  Vec3 point(int k, int index) const { return points_[k][static_cast<std::size_t>(index)].vec(); }
  Vec3 limit(int index) const { return limit_[static_cast<std::size_t>(index)].vec(); }

  // OpenSubdiv's index at level k of every live RGB vertex (level(v) <= k), found through the
  // parent relation: vertex children of vertices, edge children of the edge a vertex split.
  std::vector<int> indices_at(const RgbMesh& m, int k) const {
    std::vector<std::vector<int>> at(static_cast<std::size_t>(k) + 1,
                                     std::vector<int>(static_cast<std::size_t>(m.vertex_slots()), -1));
    for (int j = 0; j <= k; ++j) {
      for (VertexHandle v : m.vertices()) {
        if (m.level(v) > j) continue;
        int& out = at[j][v.idx];
        if (j == 0) {
          out = v.idx;  // base vertices keep their indices
        } else if (m.level(v) < j) {
          out = level(j - 1).GetVertexChildVertex(at[j - 1][v.idx]);
        } else {
          const auto& p = m.parents(v);
          const int e = level(j - 1).FindEdge(at[j - 1][p[0].idx], at[j - 1][p[1].idx]);
          out = e < 0 ? -1 : level(j - 1).GetEdgeChildVertex(e);
        }
      }
    }
    return at[k];
  }

 private:
  int levels_;
  std::unique_ptr<Far::TopologyRefiner> refiner_;
  std::vector<std::vector<Point>> points_;
  std::vector<Point> limit_;
  double tolerance_ = 0;
};

// The RGB mesh is uniform at level k: same vertices, same oriented triangles and the same
// control points as OpenSubdiv's level k.
void expect_loop_level(const RgbMesh& m, const LoopReference& ref, int k, const std::string& what) {
  const auto& level = ref.level(k);
  ASSERT_EQ(static_cast<int>(m.num_vertices()), level.GetNumVertices()) << what;
  ASSERT_EQ(static_cast<int>(m.num_triangles()), level.GetNumFaces()) << what;
  ASSERT_EQ(static_cast<int>(m.num_edges()), level.GetNumEdges()) << what;
  const std::vector<int> osd = ref.indices_at(m, k);
  std::set<int> used;
  double worst = 0;
  for (VertexHandle v : m.vertices()) {
    ASSERT_GE(osd[v.idx], 0) << what;
    EXPECT_TRUE(used.insert(osd[v.idx]).second) << what;
    worst = std::max(worst, distance(m.control_point(v), ref.point(k, osd[v.idx])));
  }
  EXPECT_LE(worst, ref.tolerance()) << what << ": control points differ from OpenSubdiv's";
  auto canonical = [](std::array<int, 3> x) {
    std::rotate(x.begin(), std::min_element(x.begin(), x.end()), x.end());
    return x;
  };
  std::set<std::array<int, 3>> ours, theirs;
  for (TriangleHandle t : m.triangles()) {
    const auto c = m.triangle_vertices(t);
    ours.insert(canonical({osd[c[0].idx], osd[c[1].idx], osd[c[2].idx]}));
  }
  for (int f = 0; f < level.GetNumFaces(); ++f) {
    const auto fv = level.GetFaceVertices(f);
    ASSERT_EQ(fv.size(), 3);
    theirs.insert(canonical({fv[0], fv[1], fv[2]}));
  }
  EXPECT_EQ(ours, theirs) << what << ": triangles differ from OpenSubdiv's";
}

// Every vertex of a (selectively refined) mesh shows the Loop control point of its shown
// level, and its limit position is OpenSubdiv's.
void expect_loop_control_points(RgbMesh& m, const LoopReference& ref, const std::string& what) {
  ASSERT_LE(m.max_level(), ref.levels());
  std::vector<std::vector<int>> osd(static_cast<std::size_t>(ref.levels()) + 1);
  for (int k = 0; k <= ref.levels(); ++k) osd[k] = ref.indices_at(m, k);
  double worst = 0, worst_limit = 0;
  for (VertexHandle v : m.vertices()) {
    const int k = m.shown_level(v);
    ASSERT_LE(k, ref.levels());
    worst = std::max(worst, distance(m.control_point(v), ref.point(k, osd[k][v.idx])));
  }
  EXPECT_LE(worst, ref.tolerance()) << what << ": shown control points differ from OpenSubdiv's";
  const std::vector<std::array<std::int32_t, 3>> before = testing::canonical_triangles(m);
  const std::size_t vertices = m.num_vertices();
  m.compute_limits();
  EXPECT_EQ(m.num_vertices(), vertices) << what << ": compute_limits changed the mesh";
  EXPECT_EQ(testing::canonical_triangles(m), before) << what << ": compute_limits changed the mesh";
  for (VertexHandle v : m.vertices()) {
    worst_limit = std::max(worst_limit, distance(m.limit_position(v), ref.limit(osd[ref.levels()][v.idx])));
  }
  EXPECT_LE(worst_limit, ref.tolerance()) << what << ": limit positions differ from OpenSubdiv's";
}

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
