// Macro triangles and their partition (rgbmesh::parallel, issue 13): under a floor at level K
// every triangle lies in one triangle of the uniform level-K mesh. Checked by parametric area:
// relative to its macro triangle, a triangle of level l covers 4^-(l-K) if green, half that if
// red (a bisected green one), a quarter if blue (the colours' definitions by their edges'
// levels); the triangles of each macro triangle must cover exactly 1 (dyadic sums, exact in
// floating point). Then METIS's partition: every part holds macro triangles, the weights add
// up, and the balance on a mesh refined around one point stays within 1.2.

#include <gtest/gtest.h>

#include <map>
#include <set>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/parallel/local_view.hpp"
#include "rgbmesh/parallel/partition.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/rgb_state.hpp"
#include "rgbmesh/shapes.hpp"
#include "test_meshes.hpp"

namespace rgbmesh::parallel {
namespace {

double parametric_area(const RgbMesh& m, TriangleHandle t, int macro_level) {
  const double green = std::ldexp(1.0, -2 * (m.level(t) - macro_level));
  switch (m.color(t)) {
    case Color::green: return green;
    case Color::red: return green / 2;
    case Color::blue: return green / 4;
  }
  return 0;
}

// A mesh above a floor at `level`: refined around a point to `deep`, then a random walk (which
// may coarsen anywhere), then the floor again.
RgbMesh floored(const testing::BaseMesh& base, int level, int deep, std::uint64_t seed) {
  RgbMesh m = base.build();
  selective_refinement(m, AtLeastLevel(level));
  m.compute_limits();
  selective_refinement(m, BallLevel(m.limit_position(*m.vertices().begin()), 0.4, deep));
  random_walk(m, 2000, seed);
  selective_refinement(m, AtLeastLevel(level));
  return m;
}

TEST(MacroTriangles, EveryTriangleLiesInOneAndEachIsCoveredOnce) {
  for (const auto& base : {testing::torus(6, 4), testing::grid_with_holes(3, 1), testing::double_torus()}) {
    for (int level : {0, 1, 2}) {
      const RgbMesh m = floored(base, level, level + 3, 11 + level);
      ASSERT_EQ(m.validate(true), "") << base.name;
      const MacroTriangles macro = macro_triangles(m, level);
      EXPECT_DOUBLE_EQ(double(macro.corners.size()), uniform_level_counts(m, level).triangles) << base.name;
      std::vector<double> covered(macro.corners.size(), 0.0);
      std::size_t counted = 0;
      for (const TriangleHandle t : m.triangles()) {
        const std::int32_t f = macro.of_triangle[t.idx];
        ASSERT_GE(f, 0) << base.name;
        covered[static_cast<std::size_t>(f)] += parametric_area(m, t, level);
        ++counted;
      }
      EXPECT_EQ(counted, std::accumulate(macro.triangles.begin(), macro.triangles.end(), std::size_t{0}));
      for (std::size_t f = 0; f < covered.size(); ++f)
        ASSERT_EQ(covered[f], 1.0) << base.name << " level " << level << " macro " << f;
      // The dual graph: neighbours are mutual, and every edge of a closed surface has one.
      for (std::size_t f = 0; f < macro.across.size(); ++f)
        for (int k = 0; k < 3; ++k) {
          const std::int32_t g = macro.across[f][k];
          if (g < 0) continue;
          const auto& back = macro.across[static_cast<std::size_t>(g)];
          EXPECT_NE(std::find(back.begin(), back.end(), static_cast<std::int32_t>(f)), back.end());
        }
    }
  }
}

TEST(MacroTriangles, ATriangleBelowTheLevelIsRefused) {
  RgbMesh m = testing::torus(6, 4).build();
  EXPECT_THROW(macro_triangles(m, 1), std::invalid_argument);
}

// Refinement gathered around one point: at the base's level a single macro triangle holds a
// sixth of the mesh or more; two levels deeper (16 times as many, smaller macro triangles)
// METIS balances every part count within 1.2.
TEST(Partition, BalancesTheTrianglesOfAMeshRefinedAroundOnePoint) {
  const testing::BaseMesh base = testing::torus(12, 8);  // 192 base triangles
  RgbMesh m = base.build();
  m.compute_limits();  // the ball around a point of the surface (smoothing pulls control points in)
  selective_refinement(m, BallLevel(m.limit_position(*m.vertices().begin()), 0.5, 7));
  EXPECT_EQ(macro_level_for(m, 4, 0, 32), 0);  // 192 base triangles >= 4 parts * 32
  EXPECT_EQ(macro_level_for(m, 4, 0, 64), 1);  // 768 at level 1
  selective_refinement(m, AtLeastLevel(2));
  const MacroTriangles coarse = macro_triangles(m, 0), fine = macro_triangles(m, 2);
  const std::size_t heaviest = *std::max_element(coarse.triangles.begin(), coarse.triangles.end());
  EXPECT_GT(6 * heaviest, m.num_triangles()) << "the test needs refinement gathered in few macro triangles";
  for (int parts : {1, 2, 3, 4}) {
    const Partition p = partition(fine, parts);
    EXPECT_EQ(std::accumulate(p.weight.begin(), p.weight.end(), std::size_t{0}), m.num_triangles());
    for (std::size_t w : p.weight) EXPECT_GT(w, 0u);
    EXPECT_LE(p.imbalance, 1.2) << parts << " parts";
    EXPECT_EQ(partition(fine, parts).part_of, p.part_of) << "reproducible";
  }
  EXPECT_THROW(partition(fine, int(fine.corners.size()) + 1), std::invalid_argument);
}

// Adaptive sphere-peak above a floor at level 2 (320 macro triangles of the icosahedron), its
// peak inside a few of them: the final mesh partitioned at the floor's level for 2, 3 and 4
// processes, within 20% unless one macro triangle alone holds more than a part's share (then
// within 5% of what that triangle forces; units finer where the mesh is heavy lift that limit).
// Adaptive runs on the unit sphere from the icosahedron above a floor at level 2.
adapt::AdaptOptions above_level_2() {
  adapt::AdaptOptions o;
  o.projection = fem::Projection(fem::project_to_unit_sphere);
  o.min_level = 2;
  o.max_cycles = 60;
  o.max_dofs = 30000;
  return o;
}
RgbMesh icosahedron_mesh() {
  const TriangleMeshData ico = icosahedron();
  return RgbMesh::from_triangles(ico.points, ico.triangles);
}

TEST(Partition, AnAdaptiveRunAboveAFloorBalancesWithinTwentyPercent) {
  const adapt::AdaptOptions o = above_level_2();
  RgbMesh peak = icosahedron_mesh();
  adapt::run_cycles(peak, fem::sphere_peak(), o);
  const MacroTriangles macro = macro_triangles(peak, 2);
  ASSERT_EQ(macro.corners.size(), 320u);
  // METIS cannot split a macro triangle: the heaviest one bounds the balance from below.
  const std::size_t heaviest = *std::max_element(macro.triangles.begin(), macro.triangles.end());
  for (int parts : {2, 3, 4}) {
    const Partition p = partition(macro, parts);
    const double floor = static_cast<double>(heaviest) * parts / static_cast<double>(peak.num_triangles());
    EXPECT_LE(p.imbalance, std::max(1.2, 1.05 * floor)) << parts << " parts of " << peak.num_triangles() << " triangles";
    std::printf("%d parts: imbalance %.3f (the heaviest macro triangle alone: %.3f)\n", parts, p.imbalance, floor);
  }
}

// A moving peak's wake gathers in a few macro triangles at the floor (1.36 for 3 parts of its
// 96,548 triangles at level 2): units split where heavy spread it, and each unit is covered
// exactly once by its triangles (parametric areas relative to the unit's level add up to 1).
TEST(Partition, UnitsFinerWhereTheMeshIsHeavyBalanceAMovingPeaksWake) {
  adapt::AdaptOptions o = above_level_2();
  o.marking = std::make_shared<adapt::EquidistributionMarking>();
  o.coarsen_below = 0.25;
  adapt::DynamicOptions d;
  d.steps = 6;
  d.start_cycles = 16;
  RgbMesh m = icosahedron_mesh();
  adapt::run_dynamic(m, [](double t) { return adapt::moving_peak(t); }, o, d);
  ASSERT_GT(m.num_triangles(), 50000u);
  const MacroTriangles macro = macro_triangles(m, 2);
  const Partition coarse = partition(macro, 3);
  for (int parts : {2, 3, 4}) {
    const Units u = units(m, 2, parts);
    std::vector<double> covered(u.level.size(), 0.0);
    for (const TriangleHandle t : m.triangles()) {
      const std::int32_t k = u.of_triangle[t.idx];
      ASSERT_GE(k, 0);
      covered[static_cast<std::size_t>(k)] += parametric_area(m, t, u.level[static_cast<std::size_t>(k)]);
    }
    for (std::size_t k = 0; k < covered.size(); ++k) ASSERT_EQ(covered[k], 1.0) << "unit " << k;
    const Partition p = partition(u, parts);
    EXPECT_EQ(std::accumulate(p.weight.begin(), p.weight.end(), std::size_t{0}), m.num_triangles());
    EXPECT_LE(p.imbalance, 1.2) << parts << " parts, " << u.level.size() << " units";
    if (parts == 3) {
      EXPECT_LT(p.imbalance, coarse.imbalance);
    }
    std::printf("%zu triangles, %d parts: %zu units, imbalance %.3f (macro triangles only: %.3f)\n", m.num_triangles(),
                parts, u.level.size(), p.imbalance, partition(macro, parts).imbalance);
  }
}

// Units as groups of triangle slots, whatever their numbering: per triangle slot, the smallest
// slot of its unit and the unit's level.
std::vector<std::array<std::int32_t, 2>> grouping(const Units& u) {
  std::vector<std::int32_t> smallest(u.level.size(), std::numeric_limits<std::int32_t>::max());
  for (std::size_t t = 0; t < u.of_triangle.size(); ++t)
    if (u.of_triangle[t] >= 0)
      smallest[static_cast<std::size_t>(u.of_triangle[t])] =
          std::min(smallest[static_cast<std::size_t>(u.of_triangle[t])], static_cast<std::int32_t>(t));
  std::vector<std::array<std::int32_t, 2>> out(u.of_triangle.size(), {-1, -1});
  for (std::size_t t = 0; t < u.of_triangle.size(); ++t)
    if (u.of_triangle[t] >= 0) {
      const auto k = static_cast<std::size_t>(u.of_triangle[t]);
      out[t] = {smallest[k], u.level[k]};
    }
  return out;
}

// The floor's uniform mesh kept between calls gives the units of a fresh computation (the same
// groups of triangles at the same levels; the units' numbers follow the macro triangles' order,
// which the kept mesh fixes), for the cycles of one run (the same floor vertices) and for
// another mesh or floor (recomputed).
TEST(Partition, TheFloorCacheGivesTheUnitsComputedAfresh) {
  const std::shared_ptr<FloorCache> cache = make_floor_cache();
  adapt::AdaptOptions o = above_level_2();
  o.max_dofs = 3000;
  std::size_t calls = 0;
  RgbMesh peak = icosahedron_mesh();
  adapt::run_cycles(peak, fem::sphere_peak(), o, [&](const adapt::CycleState& s) {
    const Units cached = units(s.mesh, 2, 3, 0.1, cache.get()), fresh = units(s.mesh, 2, 3);
    EXPECT_EQ(grouping(cached), grouping(fresh)) << "cycle " << s.report.cycle;
    ++calls;
  });
  EXPECT_GT(calls, 3u);
  RgbMesh other = icosahedron_mesh();
  selective_refinement(other, UniformLevel(4));
  EXPECT_EQ(grouping(units(other, 2, 3, 0.1, cache.get())), grouping(units(other, 2, 3)));
  EXPECT_EQ(grouping(units(other, 3, 3, 0.1, cache.get())), grouping(units(other, 3, 3)));
}

// What a process of a distributed mesh would hold: for each part of an adaptive mesh, the
// mesh coarsened to the floor away from the part and one ghost layer. Its own triangles are
// exactly the whole mesh's (the same corners, the same control points), the view is valid,
// and it is a fraction of the whole: the memory model of the distributed mesh.
// The corners of the kept triangles.
std::vector<char> kept_vertex_of(const RgbMesh& m, const std::vector<char>& keep) {
  std::vector<char> out(static_cast<std::size_t>(m.vertex_slots()), 0);
  for (const TriangleHandle t : m.triangles())
    if (keep[static_cast<std::size_t>(t.idx)])
      for (const VertexHandle v : m.triangle_vertices(t)) out[static_cast<std::size_t>(v.idx)] = 1;
  return out;
}

// A distributed run's views hold the floor only near their part (coarser than it elsewhere,
// down to the base mesh): the floor cache, made from the whole mesh, places such a view's
// triangles in the whole mesh's units (each kept triangle in its unit, every triangle coarser
// than the floor in none). Without the cache a view below the floor is refused.
TEST(Partition, TheFloorCacheLocatesAViewThatIsCoarserThanTheFloor) {
  RgbMesh whole = icosahedron_mesh();
  adapt::run_cycles(whole, fem::sphere_peak(), above_level_2());
  const std::shared_ptr<FloorCache> cache = make_floor_cache();
  const int parts = 4;
  // (The units as a distributed run has them, which lists the divided cells: one process here.)
  const Collectives one{[](std::uint64_t*, std::size_t) {}, [](const std::vector<std::uint64_t>& v) { return v; }};
  const Units u = shared_units(whole, 2, parts, std::vector<char>(static_cast<std::size_t>(whole.triangle_slots()), 1), one,
                               cache.get());
  const Partition p = partition(u, parts);
  std::map<std::array<std::int32_t, 3>, std::int32_t> unit_of_corners;
  const auto corners = [](const RgbMesh& m, TriangleHandle t) {
    std::array<std::int32_t, 3> c{};
    const auto v = m.triangle_vertices(t);
    for (int k = 0; k < 3; ++k) c[k] = v[k].idx;
    std::sort(c.begin(), c.end());
    return c;
  };
  for (const TriangleHandle t : whole.triangles()) unit_of_corners[corners(whole, t)] = u.of_triangle[t.idx];
  int views_below = 0;
  for (int q = 0; q < parts; ++q) {
    std::vector<char> keep(static_cast<std::size_t>(whole.triangle_slots()), 0);
    std::size_t own = 0;
    for (const TriangleHandle t : whole.triangles()) {
      keep[static_cast<std::size_t>(t.idx)] = p.part_of[static_cast<std::size_t>(u.of_triangle[t.idx])] == q;
      own += keep[static_cast<std::size_t>(t.idx)];
    }
    const RgbMesh view = local_view(whole, keep, 0, 2);
    ASSERT_EQ(view.validate(), "") << "part " << q;
    const std::vector<std::int32_t> located = locate_units(view, 2, u, cache.get());
    std::size_t below = 0, same = 0;
    for (const TriangleHandle t : view.triangles()) {
      const std::int32_t unit = located[static_cast<std::size_t>(t.idx)];
      if (view.level(t) < 2) {
        ++below;
        EXPECT_EQ(unit, -1) << "part " << q << ", triangle " << t.idx;
        continue;
      }
      const auto it = unit_of_corners.find(corners(view, t));
      if (it == unit_of_corners.end()) continue;  // coarser than the whole mesh here
      EXPECT_EQ(unit, it->second) << "part " << q << ", triangle " << t.idx;
      same += unit == it->second;
    }
    EXPECT_GE(same, own) << "part " << q;
    if (below > 0) {
      ++views_below;
      EXPECT_THROW(locate_units(view, 2, u), std::invalid_argument);
    }
    std::printf("part %d: %zu of %zu triangles in the view (%zu below the floor)\n", q, view.num_triangles(),
                whole.num_triangles(), below);
  }
  EXPECT_GE(views_below, 2) << "the views hardly went below the floor";
}

TEST(LocalView, KeepsAPartsTrianglesExactlyAndLittleElse) {
  RgbMesh whole = icosahedron_mesh();
  adapt::run_cycles(whole, fem::sphere_peak(), above_level_2());
  whole.compute_limits();
  const std::size_t n = whole.num_triangles();
  ASSERT_GT(n, 20000u);
  for (int parts : {2, 4, 16}) {
    const Units u = units(whole, 2, parts);
    const Partition p = partition(u, parts);
    double largest = 0;
    for (int q = 0; q < parts; ++q) {
      std::vector<char> keep(static_cast<std::size_t>(whole.triangle_slots()), 0);
      std::size_t own = 0;
      for (const TriangleHandle t : whole.triangles()) {
        const bool mine = p.part_of[static_cast<std::size_t>(u.of_triangle[t.idx])] == q;
        keep[static_cast<std::size_t>(t.idx)] = mine;
        own += mine;
      }
      const RgbMesh view = local_view(whole, keep, 2);
      ASSERT_EQ(view.validate(), "") << parts << " parts, part " << q;
      // The view's triangles by their corners (vertices keep their handles in the copy).
      std::set<std::array<std::int32_t, 3>> in_view;
      for (const TriangleHandle t : view.triangles()) {
        std::array<std::int32_t, 3> c{};
        const auto v = view.triangle_vertices(t);
        for (int k = 0; k < 3; ++k) c[k] = v[k].idx;
        std::sort(c.begin(), c.end());
        in_view.insert(c);
      }
      std::size_t missing = 0, moved = 0;
      for (const TriangleHandle t : whole.triangles()) {
        if (!keep[static_cast<std::size_t>(t.idx)]) continue;
        std::array<std::int32_t, 3> c{};
        const auto v = whole.triangle_vertices(t);
        for (int k = 0; k < 3; ++k) {
          c[k] = v[k].idx;
          moved += !(view.control_point(v[k]) == whole.control_point(v[k]));
        }
        std::sort(c.begin(), c.end());
        missing += in_view.count(c) == 0;
      }
      EXPECT_EQ(missing, 0u) << parts << " parts, part " << q;
      EXPECT_EQ(moved, 0u) << parts << " parts, part " << q;
      if (parts == 4) {
        // Migrated: the view's RGB state rebuilt from its base on another process (positions
        // computed anew by the Loop stencils). The kept vertices come back at the whole mesh's
        // control points and limit positions.
        const MeshSnapshot snap = view.snapshot();
        RestoreExpectations expected;
        expected.triangles = snap.triangles;  // the trapezoids' diagonals
        RestoredMesh moved_to = restore_state(save_state(view, snap), expected);
        moved_to.mesh.compute_limits();
        double control = 0, limit = 0;
        std::size_t compared = 0;
        const std::vector<char> kept = kept_vertex_of(whole, keep);
        for (std::size_t i = 0; i < snap.vertex_handle.size(); ++i) {
          const VertexHandle v = snap.vertex_handle[i], w = moved_to.vertex[i];
          if (!kept[static_cast<std::size_t>(v.idx)]) continue;
          ++compared;
          control = std::max(control, norm(moved_to.mesh.control_point(w) - whole.control_point(v)));
          limit = std::max(limit, norm(moved_to.mesh.limit_position(w) - whole.limit_position(v)));
        }
        EXPECT_GT(compared, own / 3) << "part " << q;
        EXPECT_LE(control, 1e-14) << "part " << q;
        EXPECT_LE(limit, 1e-14) << "part " << q;
        std::printf("part %d migrated: %zu kept vertices, control points within %.1e, limits within %.1e\n", q, compared,
                    control, limit);
      }
      const double share = static_cast<double>(view.num_triangles()) / static_cast<double>(n);
      largest = std::max(largest, share);
      std::printf("%zu triangles, %d parts: part %d owns %zu, its view holds %zu (%.3f of the mesh, %.2f x its own)\n", n,
                  parts, q, own, view.num_triangles(), share,
                  static_cast<double>(view.num_triangles()) / static_cast<double>(own));
    }
    // Each view holds little more than its part: at most 1.5 / parts of the mesh.
    EXPECT_LT(largest, 1.5 / parts) << parts << " parts";
  }
}

}  // namespace
}  // namespace rgbmesh::parallel
