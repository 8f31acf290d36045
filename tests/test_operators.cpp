// The local operators of section IV: each one and its inverse restore the mesh exactly; the
// preconditions reject the wrong configurations; split_edge composes them as in section V.

#include <gtest/gtest.h>

#include <functional>

#include <map>
#include <tuple>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

using testing::canonical_triangles;

// Everything observable about a mesh, in handle-independent form for edges and triangles.
struct State {
  std::vector<std::array<std::int32_t, 3>> triangles;
  std::map<std::pair<std::int32_t, std::int32_t>, std::pair<int, bool>> edges;  // level, red
  std::map<std::int32_t, std::tuple<int, double, double, double>> vertices;
  bool operator==(const State& o) const {
    return triangles == o.triangles && edges == o.edges && vertices == o.vertices;
  }
  bool operator!=(const State& o) const { return !(*this == o); }
};

State state_of(const RgbMesh& m) {
  State s;
  s.triangles = canonical_triangles(m);
  for (EdgeHandle e : m.edges()) {
    auto [a, b] = m.edge_vertices(e);
    s.edges[{std::min(a.idx, b.idx), std::max(a.idx, b.idx)}] = {m.level(e), m.is_red(e)};
  }
  for (VertexHandle v : m.vertices()) {
    const Vec3& p = m.insertion_point(v);
    s.vertices[v.idx] = {m.level(v), p.x, p.y, p.z};
  }
  return s;
}

EdgeHandle edge(const RgbMesh& m, std::int32_t a, std::int32_t b) {
  const EdgeHandle e = m.find_edge(VertexHandle(a), VertexHandle(b));
  EXPECT_TRUE(e.valid()) << "no edge (" << a << ", " << b << ")";
  return e;
}

// Diamond: T0 = (0, 1, 2) above the shared edge (0, 1), T1 = (1, 0, 3) below it.
class OperatorTest : public ::testing::Test {
 protected:
  RgbMesh diamond = testing::diamond().build();
  RgbMesh triangle = testing::single_triangle().build();
};

TEST_F(OperatorTest, GgSplitAndR4MergeAreInverse) {
  const State before = state_of(diamond);
  const EdgeHandle e = edge(diamond, 0, 1);
  ASSERT_EQ(diamond.split_kind(e), SplitKind::gg);
  const VertexHandle m = diamond.split_gg(e);
  ASSERT_EQ(diamond.validate(true), "");
  EXPECT_EQ(diamond.level(m), 1);
  EXPECT_EQ(diamond.valence(m), 4);
  for (TriangleHandle t : diamond.triangles()) {
    EXPECT_EQ(diamond.color(t), Color::red);
    EXPECT_EQ(diamond.level(t), 0);
  }
  EXPECT_EQ(diamond.merge_kind(m), MergeKind::r4);
  diamond.merge_r4(m);
  ASSERT_EQ(diamond.validate(true), "");
  EXPECT_EQ(state_of(diamond), before);
}

TEST_F(OperatorTest, RgSplitAndR2gbMergeAreInverse) {
  diamond.split_g_boundary(edge(diamond, 1, 2));  // T0 becomes two red triangles
  const State before = state_of(diamond);
  const EdgeHandle e = edge(diamond, 0, 1);
  ASSERT_EQ(diamond.split_kind(e), SplitKind::rg);
  const VertexHandle m = diamond.split_rg(e);
  ASSERT_EQ(diamond.validate(true), "");
  // The red side becomes a blue triangle of level 0 and a green one of level 1 (Fig. 5).
  int blue = 0, green1 = 0;
  for (TriangleHandle t : diamond.triangles()) {
    blue += diamond.color(t) == Color::blue && diamond.level(t) == 0;
    green1 += diamond.color(t) == Color::green && diamond.level(t) == 1;
  }
  EXPECT_EQ(blue, 1);
  EXPECT_EQ(green1, 1);
  EXPECT_EQ(diamond.merge_kind(m), MergeKind::r2gb);
  diamond.merge_r2gb(m);
  EXPECT_EQ(diamond.validate(true), "");
  EXPECT_EQ(state_of(diamond), before);
}

TEST_F(OperatorTest, Rr1SplitAndGbgbMergeAreInverse) {
  // T0's red edge ends at vertex 0 (opposite of edge (1, 2)), T1's at vertex 1 (opposite of
  // edge (0, 3)): the diamond's boundary alternates red and green.
  diamond.split_g_boundary(edge(diamond, 1, 2));
  diamond.split_g_boundary(edge(diamond, 0, 3));
  const State before = state_of(diamond);
  const EdgeHandle e = edge(diamond, 0, 1);
  ASSERT_EQ(diamond.split_kind(e), SplitKind::rr1);
  EXPECT_THROW(diamond.split_rr2(e), PreconditionError);
  const VertexHandle m = diamond.split_rr1(e);
  ASSERT_EQ(diamond.validate(true), "");
  EXPECT_EQ(diamond.merge_kind(m), MergeKind::gbgb);
  diamond.merge_gbgb(m);
  EXPECT_EQ(diamond.validate(true), "");
  EXPECT_EQ(state_of(diamond), before);
}

TEST_F(OperatorTest, Rr2SplitAndG2b2MergeAreInverse) {
  // Both red edges end at vertex 0: red-red-green-green.
  diamond.split_g_boundary(edge(diamond, 1, 2));
  diamond.split_g_boundary(edge(diamond, 1, 3));
  const State before = state_of(diamond);
  const EdgeHandle e = edge(diamond, 0, 1);
  ASSERT_EQ(diamond.split_kind(e), SplitKind::rr2);
  EXPECT_THROW(diamond.split_rr1(e), PreconditionError);
  const VertexHandle m = diamond.split_rr2(e);
  ASSERT_EQ(diamond.validate(true), "");
  EXPECT_EQ(diamond.merge_kind(m), MergeKind::g2b2);
  diamond.merge_g2b2(m);
  EXPECT_EQ(diamond.validate(true), "");
  EXPECT_EQ(state_of(diamond), before);
}

TEST_F(OperatorTest, BoundarySplitsAndMergesAreInverse) {
  const State s0 = state_of(triangle);
  const VertexHandle m = triangle.split_g_boundary(edge(triangle, 0, 1));
  ASSERT_EQ(triangle.validate(true), "");
  EXPECT_EQ(triangle.merge_kind(m), MergeKind::r2_boundary);
  const State s1 = state_of(triangle);
  const EdgeHandle e = edge(triangle, 1, 2);
  ASSERT_EQ(triangle.split_kind(e), SplitKind::r_boundary);
  EXPECT_THROW(triangle.split_g_boundary(e), PreconditionError);
  const VertexHandle n = triangle.split_r_boundary(e);
  ASSERT_EQ(triangle.validate(true), "");
  EXPECT_EQ(triangle.merge_kind(n), MergeKind::gb_boundary);
  EXPECT_THROW(triangle.merge_r2_boundary(n), PreconditionError);
  triangle.merge_gb_boundary(n);
  EXPECT_EQ(state_of(triangle), s1);
  triangle.merge_r2_boundary(m);
  EXPECT_EQ(state_of(triangle), s0);
}

// Fig. 7: the 1-to-4 split of a green triangle is three edge splits and one BB-swap; the
// GG-swap undoes the BB-swap exactly.
TEST_F(OperatorTest, OneToFourSplitAndBbGgSwaps) {
  triangle.split_g_boundary(edge(triangle, 0, 1));
  triangle.split_refinable(edge(triangle, 1, 2));
  triangle.split_refinable(edge(triangle, 2, 0));
  ASSERT_EQ(triangle.validate(false), "");
  ASSERT_FALSE(triangle.is_stable());
  EdgeHandle red;
  for (EdgeHandle e : triangle.edges())
    if (triangle.is_red(e)) red = e;
  const State unstable = state_of(triangle);
  EXPECT_THROW(triangle.swap_rb(red), PreconditionError);
  const EdgeHandle g = triangle.swap_bb(red);
  ASSERT_EQ(triangle.validate(true), "");
  const State four_green = state_of(triangle);
  ASSERT_EQ(triangle.num_triangles(), 4u);
  for (TriangleHandle t : triangle.triangles()) {
    EXPECT_EQ(triangle.color(t), Color::green);
    EXPECT_EQ(triangle.level(t), 1);
  }
  EXPECT_FALSE(triangle.is_red(g));
  EXPECT_EQ(triangle.level(g), 1);
  triangle.swap_gg(g);
  EXPECT_EQ(state_of(triangle), unstable);

  // split_edge does the same with the forced swap.
  RgbMesh t2 = testing::single_triangle().build();
  t2.split_edge(edge(t2, 0, 1));
  t2.split_edge(edge(t2, 1, 2));
  t2.split_edge(edge(t2, 2, 0));
  EXPECT_EQ(t2.validate(true), "");
  EXPECT_EQ(t2.counters().splits, 3u);
  EXPECT_EQ(t2.counters().swaps_bb, 1u);
  EXPECT_EQ(state_of(t2), four_green);
}

TEST_F(OperatorTest, RbSwapIsItsOwnInverse) {
  triangle.split_g_boundary(edge(triangle, 0, 1));
  triangle.split_r_boundary(edge(triangle, 1, 2));
  const State before = state_of(triangle);
  EdgeHandle red;
  for (EdgeHandle e : triangle.edges())
    if (triangle.is_red(e)) red = e;
  ASSERT_TRUE(red.valid());
  const auto old_ends = triangle.edge_vertices(red);
  const EdgeHandle swapped = triangle.swap_rb(red);
  ASSERT_EQ(triangle.validate(true), "");
  EXPECT_TRUE(triangle.is_red(swapped));
  EXPECT_NE(triangle.edge_vertices(swapped), old_ends);
  EXPECT_NE(state_of(triangle), before);
  triangle.swap_rb(swapped);
  EXPECT_EQ(state_of(triangle), before);
}

TEST_F(OperatorTest, PreconditionsRejectWrongConfigurations) {
  const EdgeHandle e = edge(diamond, 0, 1);
  EXPECT_THROW(diamond.split_rg(e), PreconditionError);
  EXPECT_THROW(diamond.split_g_boundary(e), PreconditionError);
  EXPECT_THROW(diamond.swap_gg(e), PreconditionError);              // level 0
  EXPECT_THROW(diamond.swap_bb(e), PreconditionError);              // green
  EXPECT_THROW(diamond.merge(VertexHandle(0)), PreconditionError);  // base vertex
  EXPECT_THROW(diamond.remove_vertex(VertexHandle(0)), PreconditionError);
  const VertexHandle m = diamond.split_gg(e);
  EdgeHandle red;
  for (EdgeHandle f : diamond.edges())
    if (diamond.is_red(f)) red = f;
  EXPECT_THROW(diamond.split_edge(red), PreconditionError);
  EXPECT_THROW(diamond.swap_bb(red), PreconditionError);  // red + red
  EXPECT_THROW(diamond.swap_rb(red), PreconditionError);
  EXPECT_THROW(diamond.merge_r2gb(m), PreconditionError);
  EXPECT_THROW(diamond.split_gg(EdgeHandle(12345)), PreconditionError);
  // A half of the split edge is green at level 1 but its triangles are at level 0.
  const EdgeHandle half = edge(diamond, 0, m.idx);
  EXPECT_FALSE(diamond.is_refinable(half));
  EXPECT_THROW(diamond.split_refinable(half), PreconditionError);
  // Nothing changed by the failed calls.
  EXPECT_EQ(diamond.validate(true), "");
  EXPECT_EQ(diamond.num_vertices(), 5u);
}

// Section V-B: splitting a fine edge forces the splits of coarser neighbours, and the mesh
// stays conforming and stable throughout.
TEST(SplitEdge, ForcesCoarserSplitsAndStaysStable) {
  for (const auto& base : testing::all_base_meshes()) {
    RgbMesh m = base.build();
    EdgeHandle e = *m.edges().begin();
    for (int depth = 0; depth < 8; ++depth) {
      const std::size_t before = m.num_vertices();
      const VertexHandle v = m.split_edge(e);
      ASSERT_EQ(m.validate(true), "") << base.name << " depth " << depth;
      EXPECT_EQ(m.level(v), depth + 1);
      EXPECT_GE(m.num_vertices(), before + 1);
      // Continue with the finest green edge at v that is not on its parent edge.
      EdgeHandle next;
      for (EdgeHandle f : m.star(v).edges) {
        if (!m.is_red(f) && m.level(f) == depth + 1) next = f;
      }
      ASSERT_TRUE(next.valid());
      e = next;
    }
    // Levels rose by 8 in one corner; forced splits were needed (more than 8 insertions).
    EXPECT_GT(m.counters().splits, 8u) << base.name;
    EXPECT_EQ(m.max_level(), 8);
  }
}

TEST(Observers, ReportInsertionsWithParentsAndRemovalsBeforehand) {
  RgbMesh m = testing::icosahedron().build();
  int inserted = 0, removed = 0;
  const int id1 = m.add_insertion_observer([&](VertexHandle v, VertexHandle a, VertexHandle b) {
    ++inserted;
    EXPECT_EQ(m.parents(v)[0], a);
    EXPECT_EQ(m.parents(v)[1], b);
    EXPECT_EQ(m.level(v), std::max(m.level(a), m.level(b)) + 1);
  });
  const int id2 = m.add_removal_observer([&](VertexHandle v) {
    ++removed;
    EXPECT_TRUE(m.alive(v));
    EXPECT_TRUE(m.is_removable(v) || m.merge_kind(v) != MergeKind::not_mergeable);
  });
  // A linear field carried by averaging the parents stays exactly linear in the positions.
  auto f = m.add_vertex_property<double>(0.0);
  auto linear = [](const Vec3& p) { return 1.0 + 2.0 * p.x - 3.0 * p.y + 0.5 * p.z; };
  for (VertexHandle v : m.vertices()) f[v] = linear(m.insertion_point(v));
  const int id3 = m.add_insertion_observer(
      [&](VertexHandle v, VertexHandle a, VertexHandle b) { f[v] = 0.5 * (f[a] + f[b]); });
  const auto result = random_walk(m, 3000, 11);
  EXPECT_EQ(static_cast<std::uint64_t>(inserted), result.splits);
  EXPECT_EQ(static_cast<std::uint64_t>(removed), result.removals);
  EXPECT_GT(removed, 100);
  // The expected value, from the parent relation at the end (not from the observers): the
  // linear field at the base vertices, averaged down the parents.
  std::function<double(VertexHandle)> expected = [&](VertexHandle v) {
    if (m.level(v) == 0) return linear(m.insertion_point(v));
    return 0.5 * (expected(m.parents(v)[0]) + expected(m.parents(v)[1]));
  };
  for (VertexHandle v : m.vertices()) EXPECT_NEAR(f[v], expected(v), 1e-12);
  m.remove_observer(id1);
  m.remove_observer(id2);
  m.remove_observer(id3);
  const int before = inserted;
  selective_refinement(m, UniformLevel(3));
  EXPECT_EQ(inserted, before);
}

}  // namespace
}  // namespace rgbmesh
