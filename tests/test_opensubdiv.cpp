// Uniform RGB refinement to level K has exactly the topology of K steps of Loop subdivision,
// as computed independently by OpenSubdiv's Far::TopologyRefiner.

#include <gtest/gtest.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <set>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

using namespace OpenSubdiv;

std::unique_ptr<Far::TopologyRefiner> loop_refiner(const testing::BaseMesh& base, int levels) {
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  std::vector<int> counts(base.triangles.size(), 3);
  std::vector<int> indices;
  for (const auto& t : base.triangles) indices.insert(indices.end(), t.begin(), t.end());
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(base.points.size());
  desc.numFaces = static_cast<int>(base.triangles.size());
  desc.numVertsPerFace = counts.data();
  desc.vertIndicesPerFace = indices.data();
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_LOOP, options)));
  Far::TopologyRefiner::UniformOptions uniform(levels);
  uniform.fullTopologyInLastLevel = true;
  refiner->RefineUniform(uniform);
  return refiner;
}

// Linear ("varying") interpolation of the base points: OpenSubdiv's own midpoints.
struct Point {
  double p[3];
  void Clear() { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const Point& o, double w) {
    for (int i = 0; i < 3; ++i) p[i] += w * o.p[i];
  }
};

class OpenSubdivTopology : public ::testing::TestWithParam<testing::BaseMesh> {};

TEST_P(OpenSubdivTopology, UniformLevelsMatchLoopRefinement) {
  const testing::BaseMesh& base = GetParam();
  constexpr int kLevels = 4;
  const auto refiner = loop_refiner(base, kLevels);
  std::vector<std::vector<Point>> varying(kLevels + 1);
  for (const auto& q : base.points) varying[0].push_back({{q.x, q.y, q.z}});
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  for (int k = 1; k <= kLevels; ++k) {
    varying[k].resize(static_cast<std::size_t>(refiner->GetLevel(k).GetNumVertices()));
    primvar.InterpolateVarying(k, varying[k - 1], varying[k]);
  }

  RgbMesh m = base.build();
  for (int k = 1; k <= kLevels; ++k) {
    selective_refinement(m, UniformLevel(k));
    ASSERT_EQ(m.validate(true), "");
    // OpenSubdiv's index of every RGB vertex at level k, found through the parent relation
    // (vertex children of vertices, edge children of the edge a vertex split), level by level.
    std::vector<int> osd(static_cast<std::size_t>(m.vertex_slots()), -1);
    std::function<int(VertexHandle, int)> index_at = [&](VertexHandle v, int level) -> int {
      if (level == 0) return v.idx;  // base vertices keep their indices
      const auto& parent_level = refiner->GetLevel(level - 1);
      if (m.level(v) < level) return parent_level.GetVertexChildVertex(index_at(v, level - 1));
      const auto& p = m.parents(v);
      const int e = parent_level.FindEdge(index_at(p[0], level - 1), index_at(p[1], level - 1));
      EXPECT_GE(e, 0);
      return parent_level.GetEdgeChildVertex(e);
    };
    const auto& level = refiner->GetLevel(k);
    ASSERT_EQ(static_cast<int>(m.num_vertices()), level.GetNumVertices());
    ASSERT_EQ(static_cast<int>(m.num_triangles()), level.GetNumFaces());
    ASSERT_EQ(static_cast<int>(m.num_edges()), level.GetNumEdges());
    std::set<int> used;
    for (VertexHandle v : m.vertices()) {
      osd[v.idx] = index_at(v, k);
      EXPECT_TRUE(used.insert(osd[v.idx]).second);
      // The correspondence is confirmed by positions: RGB midpoints = OpenSubdiv's varying data.
      const Point& q = varying[k][static_cast<std::size_t>(osd[v.idx])];
      EXPECT_NEAR(distance(m.position(v), Vec3{q.p[0], q.p[1], q.p[2]}), 0.0, 1e-12);
    }
    // Same triangles, with the same orientation.
    std::set<std::array<int, 3>> ours, theirs;
    auto canonical = [](std::array<int, 3> x) {
      std::rotate(x.begin(), std::min_element(x.begin(), x.end()), x.end());
      return x;
    };
    for (TriangleHandle t : m.triangles()) {
      const auto c = m.triangle_vertices(t);
      ours.insert(canonical({osd[c[0].idx], osd[c[1].idx], osd[c[2].idx]}));
    }
    for (int f = 0; f < level.GetNumFaces(); ++f) {
      const auto fv = level.GetFaceVertices(f);
      ASSERT_EQ(fv.size(), 3);
      theirs.insert(canonical({fv[0], fv[1], fv[2]}));
    }
    EXPECT_EQ(ours, theirs) << base.name << " level " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Meshes, OpenSubdivTopology, ::testing::ValuesIn(testing::all_base_meshes()),
                         [](const ::testing::TestParamInfo<testing::BaseMesh>& param_info) {
                           return param_info.param.name;
                         });

}  // namespace
}  // namespace rgbmesh
