// Vertex removal (section IV-D, Fig. 11). A removable vertex m splits an edge (p0, p1); on each
// side, the parent triangle (p0, p1, apex) is subdivided by one of seven patterns that contain
// m, seen from m as the colors of its triangles between p0 and p1:
//   RR                 only (p0, p1) split
//   GB / BG            one more edge split first, then (p0, p1)   (mergeable as is)
//   GBR / RBG          (p0, p1) split first, then one more edge  (one RB-swap)
//   GGG                all three edges split, stable             (one GG-swap)
//   GBBG               all three split, unstable                 (BB-swap, then GG-swap)
// Interior vertices pair two sides: 7 x 7 ordered pairs, 28 up to a half-turn around m
// (18 up to mirroring as well, the figure's count). Boundary vertices have one side: 7.

#include <gtest/gtest.h>

#include <set>

#include "rgbmesh/mesh.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

enum class Side { rr, first0, first1, after0, after1, all_stable, all_unstable };
constexpr Side kSides[] = {Side::rr,     Side::first0,     Side::first1,      Side::after0,
                           Side::after1, Side::all_stable, Side::all_unstable};

// Swaps remove_vertex needs on one side.
struct Swaps {
  std::uint64_t bb = 0, gg = 0, rb = 0;
};
Swaps expected_swaps(Side s) {
  switch (s) {
    case Side::after0:
    case Side::after1:
      return {0, 0, 1};
    case Side::all_stable:
      return {0, 1, 0};
    case Side::all_unstable:
      return {1, 1, 0};
    default:
      return {};
  }
}

EdgeHandle edge(const RgbMesh& m, VertexHandle a, VertexHandle b) {
  const EdgeHandle e = m.find_edge(a, b);
  EXPECT_TRUE(e.valid());
  return e;
}

struct Built {
  RgbMesh mesh;
  VertexHandle m;
};

// Builds the configuration around the midpoint of edge (0, 1): one side per apex (2 and, for
// an interior edge, 3). With refine_corner, the green corner child at the apex of an
// all-split side is refined further (a grey zone of Fig. 11 that the removal must keep).
Built build(const testing::BaseMesh& base, const std::vector<Side>& sides, bool refine_corner = false) {
  Built b{base.build(), VertexHandle()};
  RgbMesh& m = b.mesh;
  const VertexHandle p0(0), p1(1);
  const VertexHandle apex[2] = {VertexHandle(2), VertexHandle(3)};
  // Edges split before (p0, p1).
  for (std::size_t i = 0; i < sides.size(); ++i) {
    if (sides[i] == Side::first0) m.split_refinable(edge(m, apex[i], p0));
    if (sides[i] == Side::first1) m.split_refinable(edge(m, apex[i], p1));
  }
  b.m = m.split_refinable(edge(m, p0, p1));
  for (std::size_t i = 0; i < sides.size(); ++i) {
    const Side s = sides[i];
    if (s == Side::after0 || s == Side::all_stable || s == Side::all_unstable)
      m.split_refinable(edge(m, apex[i], p0));
    if (s == Side::after1 || s == Side::all_stable || s == Side::all_unstable)
      m.split_refinable(edge(m, apex[i], p1));
    if (s == Side::all_stable) {
      // The two blue triangles on the red edge (apex, m): BB-swap to the 1-to-4 split.
      m.swap_bb(edge(m, apex[i], b.m));
      if (refine_corner) {
        // The corner child at the apex: split its edge along (apex, p0), a boundary half.
        const VertexHandle n0 = [&] {
          for (VertexHandle v : m.star(apex[i]).neighbors)
            if (m.level(v) == 1 && (m.parents(v)[0] == p0 || m.parents(v)[1] == p0)) return v;
          return VertexHandle();
        }();
        m.split_edge(edge(m, apex[i], n0));
      }
    }
  }
  return b;
}

std::vector<VertexHandle> sorted_vertices(const RgbMesh& m) {
  std::vector<VertexHandle> v(m.vertices().begin(), m.vertices().end());
  return v;
}

void check_removal(Built& b, const std::vector<Side>& sides, const std::string& label) {
  RgbMesh& m = b.mesh;
  ASSERT_EQ(m.validate(false), "") << label;
  ASSERT_TRUE(m.is_removable(b.m)) << label;
  auto vertices_after = sorted_vertices(m);
  vertices_after.erase(std::find(vertices_after.begin(), vertices_after.end(), b.m));
  const std::size_t triangles_before = m.num_triangles();
  const auto [p0, p1] = m.parents(b.m);
  m.reset_counters();
  m.remove_vertex(b.m);
  // After removal: a stable mesh, the same vertices but m, edge (p0, p1) back as a green
  // level-0 edge, two triangles fewer inside (one on the boundary).
  ASSERT_EQ(m.validate(true), "") << label;
  EXPECT_EQ(sorted_vertices(m), vertices_after) << label;
  EXPECT_EQ(m.num_triangles(), triangles_before - sides.size()) << label;
  const EdgeHandle restored = m.find_edge(p0, p1);
  ASSERT_TRUE(restored.valid()) << label;
  EXPECT_FALSE(m.is_red(restored));
  EXPECT_EQ(m.level(restored), 0);
  Swaps want;
  for (Side s : sides) {
    const Swaps w = expected_swaps(s);
    want.bb += w.bb;
    want.gg += w.gg;
    want.rb += w.rb;
  }
  EXPECT_EQ(m.counters().swaps_bb, want.bb) << label;
  EXPECT_EQ(m.counters().swaps_gg, want.gg) << label;
  EXPECT_EQ(m.counters().swaps_rb, want.rb) << label;
  EXPECT_EQ(m.counters().removals, 1u);
}

TEST(Removal, AllTwentyEightInteriorConfigurations) {
  std::set<std::string> configurations;
  int cases = 0;
  for (Side s0 : kSides) {
    for (Side s1 : kSides) {
      const std::vector<Side> sides{s0, s1};
      const std::string label = "sides " + std::to_string(int(s0)) + "," + std::to_string(int(s1));
      Built b = build(testing::diamond(), sides);
      const std::string config = b.mesh.removal_configuration(b.m);
      ASSERT_FALSE(config.empty()) << label;
      configurations.insert(config);
      check_removal(b, sides, label + " (" + config + ")");
      ++cases;
    }
  }
  EXPECT_EQ(cases, 49);
  // The half-turn around m exchanges the sides: 49 ordered pairs give 28 configurations.
  EXPECT_EQ(configurations.size(), 28u);
  for (const std::string side : {"RR", "GB", "BG", "GBR", "RBG", "GGG", "GBBG"}) {
    bool seen = false;
    for (const auto& c : configurations) seen |= c.rfind(side + "|", 0) == 0;
    EXPECT_TRUE(seen) << side;
  }
}

TEST(Removal, AllSevenBoundaryConfigurations) {
  std::set<std::string> configurations;
  for (Side s : kSides) {
    const std::vector<Side> sides{s};
    Built b = build(testing::single_triangle(), sides);
    configurations.insert(b.mesh.removal_configuration(b.m));
    check_removal(b, sides, "boundary side " + std::to_string(int(s)));
  }
  EXPECT_EQ(configurations, (std::set<std::string>{"RR", "GB", "BG", "GBR", "RBG", "GGG", "GBBG"}));
}

TEST(Removal, KeepsRefinedCornerChildren) {
  for (Side other : kSides) {
    const std::vector<Side> sides{Side::all_stable, other};
    Built b = build(testing::diamond(), sides, /*refine_corner=*/true);
    ASSERT_EQ(b.mesh.max_level(), 2);
    check_removal(b, sides, "refined corner, other side " + std::to_string(int(other)));
    EXPECT_EQ(b.mesh.max_level(), 2);  // the level-2 vertex in the corner survived
  }
}

TEST(Removal, RejectsVerticesWithFinerNeighbours) {
  RgbMesh m = testing::octahedron().build();
  const VertexHandle v = m.split_edge(*m.edges().begin());
  ASSERT_TRUE(m.is_removable(v));
  // Refine next to v: v gains a neighbour of level 2.
  EdgeHandle finer;
  for (EdgeHandle f : m.star(v).edges)
    if (!m.is_red(f) && m.level(f) == 1) finer = f;
  m.split_edge(finer);
  EXPECT_FALSE(m.is_removable(v));
  EXPECT_TRUE(m.removal_configuration(v).empty());
  EXPECT_THROW(m.remove_vertex(v), PreconditionError);
  EXPECT_EQ(m.validate(true), "");
}

}  // namespace
}  // namespace rgbmesh
