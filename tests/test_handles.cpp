// Handles and their lifetime (mesh.hpp, "Handles and their lifetime"): which operations keep
// which handles, the in-place reuse of edge slots, properties of reused slots, and, in builds
// with checked handles, that dead, out-of-range and stale handles are caught instead of
// reading another element's data.

#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

constexpr bool kChecked = RGBMESH_CHECKED_HANDLES != 0;

EdgeHandle first_green_edge(const RgbMesh& m) {
  for (EdgeHandle e : m.edges())
    if (!m.is_red(e)) return e;
  return EdgeHandle();
}

// A vertex whose slot is free, and a new vertex inserted into that very slot. Removing the
// last inserted vertex frees its slot; the next insertion reuses it (free lists are LIFO).
struct ReusedSlot {
  RgbMesh mesh;
  VertexHandle removed, reinserted;
};

ReusedSlot reused_slot() {
  ReusedSlot r{testing::octahedron().build(), {}, {}};
  RgbMesh& m = r.mesh;
  const EdgeHandle e = first_green_edge(m);
  const auto ends = m.edge_vertices(e);
  r.removed = m.split_edge(e);
  m.remove_vertex(r.removed);
  // Another edge, so that the new vertex is a different one (other parents).
  EdgeHandle other;
  for (EdgeHandle f : m.edges()) {
    const auto& fe = m.edge_vertices(f);
    if (fe[0] != ends[0] && fe[0] != ends[1] && fe[1] != ends[0] && fe[1] != ends[1]) other = f;
  }
  r.reinserted = m.split_edge(other);
  return r;
}

TEST(Handles, ReleaseHandlesAreBareIndices) {
  // The checks cost nothing where they are off: a handle is its index.
  EXPECT_EQ(sizeof(VertexHandle), kChecked ? 2 * sizeof(std::int32_t) : sizeof(std::int32_t));
}

TEST(HandleLifetime, InsertionsKeepEveryVertexHandle) {
  RgbMesh m = testing::icosahedron().build();
  selective_refinement(m, BallLevel({0, 1.6, 0.3}, 0.5, 3));
  struct Seen {
    int level;
    Vec3 point;
    std::array<VertexHandle, 2> parents;
  };
  std::map<VertexHandle, Seen> before;
  for (VertexHandle v : m.vertices()) before[v] = {m.level(v), m.insertion_point(v), m.parents(v)};
  // Only insertions: uniform refinement to the ball's level, a ball elsewhere, limits.
  selective_refinement(m, UniformLevel(3));
  selective_refinement(m, BallLevel({0, -1.6, -0.3}, 0.5, 4));
  m.compute_limits();
  for (const auto& [v, seen] : before) {
    ASSERT_TRUE(m.alive(v)) << v.idx;
    EXPECT_EQ(m.level(v), seen.level);
    EXPECT_EQ(m.insertion_point(v), seen.point);
    EXPECT_EQ(m.parents(v), seen.parents);
  }
}

TEST(HandleLifetime, RemovalEndsOnlyTheRemovedVertex) {
  RgbMesh m = testing::torus(6, 5).build();
  selective_refinement(m, UniformLevel(2));
  std::vector<VertexHandle> all(m.vertices().begin(), m.vertices().end());
  VertexHandle victim;
  for (VertexHandle v : all)
    if (m.is_removable(v)) victim = v;
  ASSERT_TRUE(victim.valid());
  m.remove_vertex(victim);
  for (VertexHandle v : all) EXPECT_EQ(m.alive(v), v != victim) << v.idx;
  EXPECT_THROW(m.remove_vertex(victim), PreconditionError);
  EXPECT_EQ(m.validate(true), "");
}

TEST(HandleLifetime, SplitLeavesTheFirstHalfInTheEdgeSlot) {
  RgbMesh m = testing::diamond().build();
  const EdgeHandle e = m.find_edge(VertexHandle(0), VertexHandle(1));
  const auto ends = m.edge_vertices(e);
  const VertexHandle mid = m.split_edge(e);
  ASSERT_TRUE(m.alive(e));
  EXPECT_EQ(m.edge_vertices(e), (std::array<VertexHandle, 2>{ends[0], mid}));
  EXPECT_EQ(m.find_edge(ends[1], mid).valid(), true);
  // A merge leaves the restored edge in the slot of the half at the first parent.
  ASSERT_EQ(m.parents(mid)[0], ends[0]);
  const EdgeHandle restored = m.merge(mid);
  EXPECT_EQ(restored, e);
  EXPECT_EQ(m.edge_vertices(restored), ends);
}

TEST(HandleLifetime, GreenEdgesKeepTheirSlotWhileOthersSplit) {
  RgbMesh m = testing::icosahedron().build();
  std::map<EdgeHandle, std::array<VertexHandle, 2>> green;
  for (EdgeHandle e : m.edges()) green[e] = m.edge_vertices(e);
  // Refine around one corner of the surface, its limit point (the control point lies 0.56
  // from it, and finer levels leave a ball of 0.5 around the control point): forced splits and
  // BB-swaps, which leave these edges alone unless they are split themselves.
  selective_refinement(m, BallLevel(m.limit_position(VertexHandle(0)), 0.5, 6));
  ASSERT_GT(m.counters().swaps_bb, 0u) << m.counters().splits << " splits";
  int kept = 0;
  for (const auto& [e, ends] : green) {
    if (m.find_edge(ends[0], ends[1]).valid()) {
      EXPECT_EQ(m.edge_vertices(e), ends);  // not split: same slot, same edge
      ++kept;
    }
  }
  EXPECT_GT(kept, 0);
  EXPECT_LT(kept, static_cast<int>(green.size()));
}

TEST(HandleLifetime, SwapLeavesTheNewDiagonalInTheSlot) {
  RgbMesh m = testing::single_triangle().build();
  m.split_g_boundary(m.find_edge(VertexHandle(0), VertexHandle(1)));
  m.split_r_boundary(m.find_edge(VertexHandle(1), VertexHandle(2)));
  EdgeHandle red;
  for (EdgeHandle e : m.edges())
    if (m.is_red(e)) red = e;
  const auto before = m.edge_vertices(red);
  const EdgeHandle swapped = m.swap_rb(red);
  EXPECT_EQ(swapped, red);
  EXPECT_NE(m.edge_vertices(swapped), before);
  EXPECT_TRUE(m.alive(red));
}

TEST(HandleLifetime, AReusedSlotStartsWithTheDefaultProperty) {
  RgbMesh m = testing::octahedron().build();
  VertexProperty<int> mark = m.add_vertex_property<int>(-1);
  const EdgeHandle e = first_green_edge(m);
  const auto ends = m.edge_vertices(e);
  const VertexHandle v = m.split_edge(e);
  mark[v] = 42;
  m.remove_vertex(v);
  const VertexHandle w = m.split_edge(m.find_edge(ends[0], ends[1]));
  ASSERT_EQ(w.idx, v.idx);  // the slot was reused
  EXPECT_EQ(mark[w], -1);
}

TEST(HandleLifetime, ParentsIdentifyAVertexAcrossRemovalAndReinsertion) {
  RgbMesh m = testing::icosahedron().build();
  const EdgeHandle e = first_green_edge(m);
  const auto ends = m.edge_vertices(e);
  const VertexHandle v = m.split_edge(e);
  const Vec3 point = m.insertion_point(v);
  // Other vertices come and go; then v is removed and its edge split again.
  random_walk(m, 200, 3);
  if (m.alive(v) && m.is_removable(v)) m.remove_vertex(v);
  selective_refinement(m, CoarsenAll());
  const VertexHandle again = m.split_edge(m.find_edge(ends[0], ends[1]));
  EXPECT_EQ(m.parents(again), (std::array<VertexHandle, 2>{ends[0], ends[1]}));
  EXPECT_EQ(m.insertion_point(again), point);
}

// ---- checked builds: stale and dead handles are caught ------------------------------------

TEST(CheckedHandles, AStaleVertexHandleIsNotAlive) {
  if (!kChecked) GTEST_SKIP() << "stale handles are detected in builds with checked handles (Debug)";
  ReusedSlot r = reused_slot();
  ASSERT_EQ(r.removed.idx, r.reinserted.idx);  // same slot, another vertex
  EXPECT_FALSE(r.mesh.alive(r.removed));
  EXPECT_TRUE(r.mesh.alive(r.reinserted));
  // A handle made from a bare index has no generation: checked for liveness only.
  EXPECT_TRUE(r.mesh.alive(VertexHandle(r.removed.idx)));
}

TEST(CheckedHandles, AStaleHandleCannotRemoveTheVertexInItsSlot) {
  if (!kChecked) GTEST_SKIP() << "stale handles are detected in builds with checked handles (Debug)";
  ReusedSlot r = reused_slot();
  const std::size_t vertices = r.mesh.num_vertices();
  try {
    r.mesh.remove_vertex(r.removed);
    FAIL() << "a stale handle removed the vertex now in its slot";
  } catch (const PreconditionError& e) {
    EXPECT_NE(std::string(e.what()).find("stale"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(r.mesh.alive(r.reinserted));
  EXPECT_EQ(r.mesh.num_vertices(), vertices);
  EXPECT_EQ(r.mesh.validate(true), "");
  r.mesh.remove_vertex(r.reinserted);  // the fresh handle works
  EXPECT_EQ(r.mesh.validate(true), "");
}

TEST(CheckedHandles, HandlesFromTheMeshCarryTheirGeneration) {
  if (!kChecked) GTEST_SKIP() << "generations exist in builds with checked handles (Debug)";
#if RGBMESH_CHECKED_HANDLES
  ReusedSlot r = reused_slot();
  // Every way the mesh hands out handles stamps the current generation.
  for (VertexHandle v : r.mesh.vertices()) EXPECT_NE(v.generation, 0u);
  for (EdgeHandle e : r.mesh.edges()) {
    EXPECT_NE(e.generation, 0u);
    for (VertexHandle v : r.mesh.edge_vertices(e)) EXPECT_NE(v.generation, 0u);
  }
  EXPECT_EQ(r.mesh.star(r.reinserted).neighbors.size(), 4u);
  for (VertexHandle v : r.mesh.star(r.reinserted).neighbors) EXPECT_TRUE(r.mesh.alive(v));
  EXPECT_GT(r.reinserted.generation, 1u);  // its slot was freed once before
  for (VertexHandle v : r.mesh.snapshot().vertex_handle) EXPECT_TRUE(r.mesh.alive(v));
#endif
}

using CheckedHandlesDeathTest = ::testing::Test;

TEST_F(CheckedHandlesDeathTest, AccessorsAbortOnDeadOutOfRangeAndStaleHandles) {
  if (!kChecked) GTEST_SKIP() << "accessors check handles in builds with checked handles (Debug)";
  ReusedSlot r = reused_slot();
  const RgbMesh& m = r.mesh;
  EXPECT_DEATH(m.level(r.removed),
               "level: vertex [0-9]+ \\(stale: removed, and its slot now holds another vertex\\)");
  EXPECT_DEATH(m.control_point(r.removed), "control_point: vertex [0-9]+ \\(stale");
  EXPECT_DEATH(m.control_point(VertexHandle(100000)),
               "control_point: vertex 100000 \\(out of range: 7 vertex slots\\)");
  EXPECT_DEATH(m.edge_vertices(EdgeHandle()), "edge_vertices: edge -1 \\(invalid");
  EXPECT_DEATH(m.insertion_point(VertexHandle(-3)), "insertion_point: vertex -3 \\(invalid");
  EXPECT_DEATH(m.triangle_vertices(TriangleHandle(5000)), "triangle_vertices: triangle 5000 \\(out of range");

  // A dead slot (freed, not reused yet).
  RgbMesh d = testing::octahedron().build();
  const VertexHandle v = d.split_edge(first_green_edge(d));
  d.remove_vertex(v);
  EXPECT_DEATH(d.parents(v), "parents: vertex [0-9]+ \\(not alive: removed\\)");
  EXPECT_DEATH(d.star(v), "star: vertex [0-9]+ \\(not alive");
  VertexProperty<double> p = d.add_vertex_property<double>(0.0);
  EXPECT_DEATH(p[VertexHandle(99)],
               "VertexProperty::operator\\[\\]: vertex 99 is outside the 7 vertex slots");
}

TEST(Operators, ThrowOnDeadHandlesInEveryBuild) {
  RgbMesh m = testing::diamond().build();
  const EdgeHandle e = m.find_edge(VertexHandle(0), VertexHandle(1));
  const VertexHandle mid = m.split_gg(e);
  const EdgeHandle bisector = m.find_edge(mid, VertexHandle(2));
  m.merge_r4(mid);  // frees the bisecting edges and mid
  EXPECT_THROW(m.swap_rb(bisector), PreconditionError);
  EXPECT_THROW(m.merge(mid), PreconditionError);
  EXPECT_THROW(m.complete_limit(mid), PreconditionError);
  EXPECT_THROW(m.split_edge(EdgeHandle(77)), PreconditionError);
  EXPECT_EQ(m.validate(true), "");
}

}  // namespace
}  // namespace rgbmesh
