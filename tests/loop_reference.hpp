#pragma once
// OpenSubdiv's uniform Loop refinement of a base mesh (with its creases and corners), and the
// checks that an RGB mesh agrees with it: the reference of test_opensubdiv.cpp and
// test_creases.cpp.

#include <gtest/gtest.h>
#include <opensubdiv/far/primvarRefiner.h>

#include <algorithm>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "opensubdiv_refiner.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/mesh.hpp"
#include "test_meshes.hpp"

namespace rgbmesh::testing {

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
  LoopReference(const BaseMesh& base, int levels) : levels_(levels) {
    refiner_ = loop_refiner(base);
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

    // Sharp features blend masks with single-precision sharpness on both sides: 1e-10.
    tolerance_ = (base.sharp.empty() ? 1e-12 : 1e-10) * bounding_box_diagonal(base.points);
  }

  int levels() const { return levels_; }
  double tolerance() const { return tolerance_; }
  const Far::TopologyLevel& level(int k) const { return refiner_->GetLevel(k); }
  Vec3 point(int k, int index) const { return points_[k][static_cast<std::size_t>(index)].vec(); }
  Vec3 limit(int index) const { return limit_[static_cast<std::size_t>(index)].vec(); }
  // Whether OpenSubdiv's Limit() is the limit at vertex `index` of the finest level: its rules
  // no longer change there (no semi-sharp edge or vertex) and it is no dart (Limit() uses the
  // smooth mask at darts, whose own subdivision converges elsewhere).
  bool limit_is_exact(int index) const {
    const Far::TopologyLevel& last = level(levels_);
    const Sdc::Crease::Rule rule = last.GetVertexRule(index);
    if (rule == Sdc::Crease::RULE_DART || last.IsVertexSemiSharp(index)) return false;
    for (const int e : last.GetVertexEdges(index))
      if (last.IsEdgeSemiSharp(e)) return false;
    return true;
  }

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
inline void expect_loop_level(const RgbMesh& m, const LoopReference& ref, int k, const std::string& what) {
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
inline void expect_loop_control_points(RgbMesh& m, const LoopReference& ref, const std::string& what) {
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
  const std::vector<std::array<std::int32_t, 3>> before = canonical_triangles(m);
  const std::size_t vertices = m.num_vertices();
  m.compute_limits();
  EXPECT_EQ(m.num_vertices(), vertices) << what << ": compute_limits changed the mesh";
  EXPECT_EQ(canonical_triangles(m), before) << what << ": compute_limits changed the mesh";
  for (VertexHandle v : m.vertices()) {
    const int u = osd[ref.levels()][v.idx];
    if (ref.limit_is_exact(u)) worst_limit = std::max(worst_limit, distance(m.limit_position(v), ref.limit(u)));
  }
  EXPECT_LE(worst_limit, ref.tolerance()) << what << ": limit positions differ from OpenSubdiv's";
}

}  // namespace rgbmesh::testing
