// Selective refinement (section V) with the built-in criteria: each run ends in a stable,
// valid mesh that satisfies its criterion, and does not refine where it need not.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <thread>
#include <tuple>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/detail/parallel_for.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

double longest_edge(const RgbMesh& m) {
  double l = 0;
  for (EdgeHandle e : m.edges()) {
    const auto& v = m.edge_vertices(e);
    // Measured as the criterion defines it: in the Loop mesh of the edge's level.
    l = std::max(l, distance(m.level_point(v[0], m.level(e)), m.level_point(v[1], m.level(e))));
  }
  return l;
}

TEST(Geometry, ClosestPointOnTriangleRegions) {
  const Vec3 a{0, 0, 0}, b{2, 0, 0}, c{0, 2, 0};
  EXPECT_EQ(closest_point_on_triangle({0.5, 0.5, 3}, a, b, c), (Vec3{0.5, 0.5, 0}));  // face
  EXPECT_EQ(closest_point_on_triangle({-1, -1, 0}, a, b, c), a);                      // vertex
  EXPECT_EQ(closest_point_on_triangle({3, -1, 1}, a, b, c), b);
  EXPECT_EQ(closest_point_on_triangle({1, -5, 0}, a, b, c), (Vec3{1, 0, 0}));  // edge ab
  EXPECT_EQ(closest_point_on_triangle({2, 2, 0}, a, b, c), (Vec3{1, 1, 0}));   // edge bc
  EXPECT_DOUBLE_EQ(point_triangle_distance({-3, 1, 4}, a, b, c), 5.0);         // edge ca
}

TEST(Uniform, LevelKHasFourToTheKTrianglesAllGreen) {
  for (const auto& base : testing::all_base_meshes()) {
    RgbMesh m = base.build();
    for (int k : {3, 1, 4, 0, 2}) {  // up and down
      selective_refinement(m, UniformLevel(k));
      ASSERT_EQ(m.validate(true), "") << base.name << " k=" << k;
      EXPECT_EQ(m.num_triangles(), base.triangles.size() << (2 * k)) << base.name << " k=" << k;
      for (TriangleHandle t : m.triangles()) {
        ASSERT_EQ(m.color(t), Color::green);
        ASSERT_EQ(m.level(t), k);
      }
    }
  }
}

// Everything a vertex is in the Loop hierarchy, keyed by its name (canonical.hpp): level,
// parents, boundary flag, control point at insertion and limit position, to the last bit.
using VertexRecord =
    std::tuple<int, VertexName, VertexName, bool, double, double, double, double, double, double>;

std::map<VertexName, VertexRecord> vertex_records(RgbMesh m) {
  m.compute_limits();
  const std::vector<VertexName> names = vertex_names(m);
  std::map<VertexName, VertexRecord> out;
  for (VertexHandle v : m.vertices()) {
    const auto& p = m.parents(v);
    const Vec3 c = m.insertion_point(v), x = m.limit_position(v);
    // The parents as a set: which one is first depends on the order of an edge's ends.
    const VertexName a = p[0].valid() ? names[p[0].idx] : 0, b = p[1].valid() ? names[p[1].idx] : 0;
    out[names[v.idx]] = {
        m.level(v), std::min(a, b), std::max(a, b), m.is_boundary_vertex(v), c.x, c.y, c.z, x.x, x.y, x.z};
  }
  return out;
}

using testing::named_triangles;

TEST(Uniform, AllEdgesAtOnceIsSplittingEveryEdge) {
  // split_all_edges against split_edge on every edge (section V, one operator at a time), on
  // closed, open (several boundary loops), genus-1 and genus-2 bases with extraordinary
  // vertices: the same vertices with the same parents, control points and limit positions to
  // the last bit, the same triangles, and a valid, stable mesh after every level.
  for (const auto& base : testing::all_base_meshes()) {
    RgbMesh at_once = base.build(), one_by_one = base.build();
    std::vector<std::array<VertexHandle, 3>> heard;  // (vertex, parents) from the observer
    at_once.add_insertion_observer([&](VertexHandle v, VertexHandle a, VertexHandle b) {
      heard.push_back({v, a, b});
    });
    for (int level = 0; level < 3; ++level) {
      ASSERT_TRUE(at_once.is_uniform()) << base.name;
      const std::size_t vertices = at_once.num_vertices(), edges = at_once.num_edges();
      heard.clear();
      EXPECT_EQ(at_once.split_all_edges(), edges) << base.name;
      const std::int32_t slots = one_by_one.edge_slots();
      for (std::int32_t i = 0; i < slots; ++i) {
        const EdgeHandle e(i);
        if (one_by_one.alive(e) && !one_by_one.is_red(e) && one_by_one.level(e) == level)
          one_by_one.split_edge(e);
      }
      ASSERT_EQ(at_once.validate(true), "") << base.name << " level " << level + 1;
      EXPECT_EQ(at_once.num_vertices(), vertices + edges);
      EXPECT_EQ(at_once.counters().splits, one_by_one.counters().splits) << base.name;
      EXPECT_EQ(vertex_records(at_once), vertex_records(one_by_one)) << base.name << " level " << level + 1;
      EXPECT_EQ(named_triangles(at_once), named_triangles(one_by_one)) << base.name << " level " << level + 1;
      // Every new vertex heard once, in slot order, with its parents.
      ASSERT_EQ(heard.size(), edges);
      for (std::size_t k = 0; k < heard.size(); ++k) {
        EXPECT_EQ(heard[k][0].idx, static_cast<std::int32_t>(vertices + k));
        EXPECT_EQ(at_once.parents(heard[k][0])[0], heard[k][1]);
        EXPECT_EQ(at_once.parents(heard[k][0])[1], heard[k][2]);
      }
    }
    // And back: coarsening everything returns the base exactly.
    selective_refinement(at_once, CoarsenAll());
    ASSERT_EQ(at_once.validate(true), "") << base.name;
    EXPECT_EQ(named_triangles(at_once), named_triangles(base.build())) << base.name;
  }
}

TEST(Uniform, AllEdgesAtOnceDoesNotDependOnTheThreads) {
  // Each pass writes only its own slots: one thread and every core give the same arrays.
  const testing::BaseMesh base = testing::torus(24, 16);
  const auto refine = [&](unsigned threads) {
    detail::thread_cap = threads;
    RgbMesh m = base.build();
    for (int level = 0; level < 3; ++level) m.split_all_edges();
    detail::thread_cap = 0;
    return m;
  };
  const RgbMesh one = refine(1), all = refine(4);
  ASSERT_EQ(one.vertex_slots(), all.vertex_slots());
  ASSERT_EQ(one.triangle_slots(), all.triangle_slots());
  for (VertexHandle v : one.vertices()) {
    ASSERT_EQ(one.insertion_point(v), all.insertion_point(v));
    ASSERT_EQ(one.vertex_edge(v), all.vertex_edge(v));
  }
  for (TriangleHandle t : one.triangles()) ASSERT_EQ(one.triangle_vertices(t), all.triangle_vertices(t));
}

#if defined(__linux__)
TEST(Threads, NoMoreThreadsThanTheCoresThisThreadMayRunOn) {
  // A launcher that binds a process to one core (mpirun -np 1 does) leaves its loops one
  // thread: more on one core only take turns. Checked on a thread of its own, whose affinity
  // is then set to one core.
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "one core";
  std::size_t bound = 0, counted = 0;
  std::thread([&] {
    cpu_set_t one;
    CPU_ZERO(&one);
    cpu_set_t all;
    ASSERT_EQ(sched_getaffinity(0, sizeof all, &all), 0);
    for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
      if (CPU_ISSET(cpu, &all)) {
        CPU_SET(cpu, &one);
        break;
      }
    ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
    bound = detail::hardware_threads();
    // The loop runs on this thread alone: every index on thread 0.
    detail::parallel_for(100000, 16, detail::hardware_threads(),
                         [&](std::size_t thread, std::size_t) { counted += thread == 0 ? 1 : 0; });
  }).join();
  EXPECT_EQ(bound, 1u);
  EXPECT_EQ(counted, 100000u);
}
#endif

TEST(Uniform, AllEdgesAtOnceNeedsAUniformMesh) {
  RgbMesh m = testing::icosahedron().build();
  EXPECT_TRUE(m.is_uniform());
  m.split_edge(*m.edges().begin());  // red edges now
  EXPECT_FALSE(m.is_uniform());
  EXPECT_THROW(m.split_all_edges(), PreconditionError);
  selective_refinement(m, UniformLevel(1));
  EXPECT_TRUE(m.is_uniform());
  selective_refinement(m, UniformLevel(2));
  RgbMesh partly = m;
  for (VertexHandle v : partly.vertices()) {
    if (partly.is_removable(v)) {
      partly.remove_vertex(v);  // a free slot now
      break;
    }
  }
  ASSERT_LT(partly.num_vertices(), m.num_vertices());
  EXPECT_FALSE(partly.is_uniform());
  // The sweep still reaches the level one split at a time.
  selective_refinement(partly, UniformLevel(2));
  EXPECT_EQ(named_triangles(partly), named_triangles(m));
}

TEST(Uniform, PredictedCountsAreExactFromAnyMeshOfTheBase) {
  // uniform_level_counts, used to refuse work that cannot fit in memory, from a base mesh and
  // from a selectively refined one, on closed, open (several loops) and genus-2 surfaces.
  for (const auto& base : {testing::cube(), testing::grid_with_holes(8, 3), testing::double_torus(),
                           testing::fan_disk(7), testing::single_triangle()}) {
    RgbMesh m = base.build();
    selective_refinement(m, BallLevel(m.control_point(VertexHandle(0)), 0.3, 3));
    for (int level : {0, 1, 3}) {
      const MeshCounts predicted = uniform_level_counts(m, level);
      RgbMesh u = m;
      selective_refinement(u, UniformLevel(level));
      EXPECT_EQ(predicted.vertices, static_cast<double>(u.num_vertices())) << base.name << " level " << level;
      EXPECT_EQ(predicted.edges, static_cast<double>(u.num_edges())) << base.name << " level " << level;
      EXPECT_EQ(predicted.triangles, static_cast<double>(u.num_triangles())) << base.name << " level " << level;
      EXPECT_GE(predicted.bytes(), static_cast<double>(RgbMesh::storage_bytes(u.num_vertices(), u.num_edges(),
                                                                              u.num_triangles())) * 0.99);
    }
  }
  // Levels beyond any integer still give finite, huge figures (the CLI's refusal quotes them).
  RgbMesh small = testing::octahedron().build();
  EXPECT_GT(uniform_level_counts(small, 30).vertices, 1e18);
}

TEST(Ball, AtLeastLevelKOnTrianglesMeetingTheBallOnly) {
  RgbMesh m = testing::icosahedron().build();
  const Vec3 center{0, 1.618, 0.3};
  const double radius = 0.6;
  const int k = 4;
  selective_refinement(m, BallLevel(center, radius, k));
  ASSERT_EQ(m.validate(true), "");
  int inside = 0, far_coarse = 0;
  for (TriangleHandle t : m.triangles()) {
    const auto c = m.triangle_vertices(t);
    const int l = m.level(t);
    const double d = point_triangle_distance(center, m.level_point(c[0], l), m.level_point(c[1], l), m.level_point(c[2], l));
    if (d <= radius) {
      ++inside;
      EXPECT_GE(m.level(t), k);
    }
    if (d > 2.5) far_coarse += m.level(t) == 0;
  }
  EXPECT_GT(inside, 20);
  EXPECT_GT(far_coarse, 0);  // far away the base triangles are untouched
  EXPECT_EQ(m.max_level(), k);
  // Refinement only: a second run changes nothing.
  const std::size_t n = m.num_vertices();
  const auto again = selective_refinement(m, BallLevel(center, radius, k));
  EXPECT_EQ(again.splits, 0u);
  EXPECT_EQ(m.num_vertices(), n);
}

TEST(MaxEdge, NoEdgeLongerThanTheLimit) {
  for (const auto& base : {testing::cube(), testing::grid_with_holes(8, 3), testing::fan_disk(12)}) {
    RgbMesh m = base.build();
    const double limit = 0.3 * longest_edge(m);
    selective_refinement(m, MaxEdgeLength(limit));
    ASSERT_EQ(m.validate(true), "") << base.name;
    EXPECT_LE(longest_edge(m), limit) << base.name;
  }
}

TEST(MaxLevel, CapsTheRefinement) {
  RgbMesh m = testing::octahedron().build();
  RefinementOptions options;
  options.max_level = 2;
  selective_refinement(m, MaxEdgeLength(1e-3), options);
  ASSERT_EQ(m.validate(true), "");
  EXPECT_EQ(m.max_level(), 2);
  EXPECT_EQ(m.num_triangles(), 8u * 16u);
}

TEST(Budget, LongestFirstUntilTheBudget) {
  RgbMesh m = testing::grid_with_holes(8, 3).build();
  const std::size_t budget = 5000;
  selective_refinement(m, TriangleBudget(budget));
  ASSERT_EQ(m.validate(true), "");
  EXPECT_GE(m.num_triangles(), budget);
  EXPECT_LT(m.num_triangles(), budget + 64);  // one split_edge adds a handful at most here
  // Longest first makes the mesh uniform-ish: the longest edge is within a factor 2.5 of the
  // shortest green edge length scale (levels differ by at most one or two).
  int lo = 99, hi = 0;
  for (TriangleHandle t : m.triangles()) {
    lo = std::min(lo, m.level(t));
    hi = std::max(hi, m.level(t));
  }
  EXPECT_LE(hi - lo, 2);
}

// TriangleBudget's rule without its known final size: the refinement then keeps every queued
// edge in its queue (it sets the low priorities aside only for a criterion that says where it
// stops), and is the reference for the set-aside entries' order.
class BudgetWithoutFinalSize final : public LodCriterion {
 public:
  explicit BudgetWithoutFinalSize(std::size_t triangles) : budget_(triangles) {}
  double edge_priority(const RgbMesh& m, EdgeHandle e) const override { return budget_.edge_priority(m, e); }
  bool satisfied(const RgbMesh& m) const override { return budget_.satisfied(m); }

 private:
  TriangleBudget budget_;
};

TEST(Budget, SettingLowPrioritiesAsideSplitsWhatOneQueueSplits) {
  // Bases with many exactly equal lengths (the icosahedron, the grid, the cube) test the order
  // among ties, which the entries set aside and brought back must keep; budgets from a few
  // hundred to 60 times the base bring entries back many times; a second budget on a refined
  // mesh starts with a large first batch.
  const std::vector<testing::BaseMesh> bases = {testing::icosahedron(), testing::grid_with_holes(8, 3),
                                                testing::torus(12, 8), testing::sharp_cube(),
                                                testing::double_torus()};
  for (const auto& base : bases) {
    for (const std::size_t factor : {7u, 60u}) {
      RgbMesh set_aside = base.build(), one_queue = base.build();
      const std::size_t budget = factor * set_aside.num_triangles() + 5;
      const RefinementResult a = selective_refinement(set_aside, TriangleBudget(budget));
      const RefinementResult b = selective_refinement(one_queue, BudgetWithoutFinalSize(budget));
      ASSERT_EQ(set_aside.validate(true), "") << base.name;
      EXPECT_EQ(a.splits, b.splits) << base.name << " x" << factor;
      EXPECT_EQ(a.skipped, b.skipped) << base.name << " x" << factor;
      ASSERT_EQ(set_aside.num_vertices(), one_queue.num_vertices()) << base.name << " x" << factor;
      EXPECT_EQ(testing::canonical_triangles(set_aside), testing::canonical_triangles(one_queue))
          << base.name << " x" << factor;
      for (VertexHandle v : set_aside.vertices())
        ASSERT_EQ(set_aside.insertion_point(v), one_queue.insertion_point(v)) << base.name << " x" << factor;
      // Again from the refined mesh: its edges are the first batch, and new edges tie with
      // some of them (halves of a longer edge as long as an edge of the next level): the newer
      // pops first. Several second budgets stop inside such ties.
      for (const std::size_t more : {budget, budget + 101, budget + 1003, 3 * budget}) {
        RgbMesh again_set_aside = set_aside, again_one_queue = one_queue;
        selective_refinement(again_set_aside, TriangleBudget(budget + more));
        selective_refinement(again_one_queue, BudgetWithoutFinalSize(budget + more));
        EXPECT_EQ(testing::canonical_triangles(again_set_aside), testing::canonical_triangles(again_one_queue))
            << base.name << " x" << factor << " then +" << more;
      }
    }
  }
}

TEST(GeometricTolerance, EveryEdgeWithinToleranceAndFlatPartsStayCoarse) {
  // A flat square (4 x 4 quads) with a bump in the middle of its right half.
  testing::BaseMesh base{"bump", {}, {}};
  const int n = 4;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) base.points.push_back({double(i), double(j), (i == 3 && j == 2) ? 1.0 : 0.0});
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      base.triangles.push_back({a, a + 1, a + n + 2});
      base.triangles.push_back({a, a + n + 2, a + n + 1});
    }
  }
  RgbMesh m = base.build();
  const double tol = 1e-3;
  selective_refinement(m, GeometricTolerance(tol));
  ASSERT_EQ(m.validate(true), "");
  for (EdgeHandle e : m.edges()) {
    if (m.is_refinable(e)) {
      EXPECT_LE(GeometricTolerance::deviation(m, e), tol);
    }
  }
  // The flat left half (x < 1, away from the bump's support and the corners' curvature of the
  // boundary) keeps coarse triangles, while the bump is refined deeply.
  int deepest_near_bump = 0, deepest_left = 0;
  for (TriangleHandle t : m.triangles()) {
    const auto c = m.triangle_vertices(t);
    const double x = (m.control_point(c[0]).x + m.control_point(c[1]).x + m.control_point(c[2]).x) / 3;
    const double y = (m.control_point(c[0]).y + m.control_point(c[1]).y + m.control_point(c[2]).y) / 3;
    if (std::abs(x - 3) < 0.5 && std::abs(y - 2) < 0.5) deepest_near_bump = std::max(deepest_near_bump, m.level(t));
    if (x < 1 && y > 1 && y < 3) deepest_left = std::max(deepest_left, m.level(t));
  }
  EXPECT_GE(deepest_near_bump, 4);
  EXPECT_LE(deepest_left, 1);
}

TEST(Field, RefinesMarkedTrianglesOnceAndCoarsensMarkedVertices) {
  RgbMesh m = testing::torus(6, 5).build();
  selective_refinement(m, UniformLevel(2));
  // Mark the triangles with x > 1 for refinement and vertices with x < -1 for removal.
  std::vector<double> tri(static_cast<std::size_t>(m.triangle_slots()), 0.0);
  std::vector<double> ver(static_cast<std::size_t>(m.vertex_slots()), 1.0);
  int marked = 0;
  for (TriangleHandle t : m.triangles()) {
    const auto c = m.triangle_vertices(t);
    const double x = (m.insertion_point(c[0]).x + m.insertion_point(c[1]).x + m.insertion_point(c[2]).x) / 3;
    if (x > 1) {
      tri[t.idx] = 1.0 + x;
      ++marked;
    }
  }
  for (VertexHandle v : m.vertices())
    if (m.insertion_point(v).x < -1) ver[v.idx] = 0.0;
  ASSERT_GT(marked, 10);
  const auto result = selective_refinement(m, FieldCriterion(tri, 0.5, ver, 0.5));
  ASSERT_EQ(m.validate(true), "");
  EXPECT_GT(result.splits, 0u);
  EXPECT_GT(result.removals, 0u);
  // Marked triangles rose one level (to 3), nothing went beyond.
  EXPECT_EQ(m.max_level(), 3);
  for (VertexHandle v : m.vertices()) {
    if (m.insertion_point(v).x < -1.2) {
      EXPECT_LE(m.level(v), 1);
    }
  }
}

}  // namespace
}  // namespace rgbmesh

namespace rgbmesh {
namespace {

// split_limits: the limit position of the vertex each edge's split would insert, exactly what
// splitting the edge of a copy and computing its limits gives, while the mesh itself is left
// as it was (same triangles, colours, levels; validate()). Red edges get no value.
TEST(SplitLimits, AreWhatSplittingInsertsAndLeaveTheMeshAsItWas) {
  for (const auto& base : {testing::icosahedron(), testing::grid_with_holes(4, 1), testing::double_torus()}) {
    RgbMesh m = base.build();
    selective_refinement(m, UniformLevel(1));
    random_walk(m, 400, 17);
    m.compute_limits();
    std::vector<EdgeHandle> edges;
    for (std::int32_t i = 0; i < m.edge_slots(); ++i)
      if (m.alive(EdgeHandle(i))) edges.push_back(EdgeHandle(i));
    // The triangles by their corners, with their levels and colours.
    const auto described = [](const RgbMesh& mesh) {
      std::vector<std::array<std::int32_t, 5>> out;
      for (TriangleHandle t : mesh.triangles()) {
        auto c = mesh.triangle_vertices(t);
        std::array<std::int32_t, 3> ids{c[0].idx, c[1].idx, c[2].idx};
        std::rotate(ids.begin(), std::min_element(ids.begin(), ids.end()), ids.end());
        out.push_back({ids[0], ids[1], ids[2], mesh.level(t), static_cast<std::int32_t>(mesh.color(t))});
      }
      std::sort(out.begin(), out.end());
      return out;
    };
    const auto before = described(m);
    const std::vector<Vec3> limits = m.split_limits(edges);
    ASSERT_EQ(m.validate(true), "") << base.name;
    EXPECT_EQ(described(m), before) << base.name;
    int red = 0, checked = 0;
    for (std::size_t i = 0; i < edges.size(); ++i) {
      if (m.is_red(edges[i])) {
        EXPECT_TRUE(std::isnan(limits[i].x)) << base.name;
        ++red;
        continue;
      }
      if (i % 7 != 0) continue;  // a sample: each check copies the mesh
      RgbMesh copy = m;
      const VertexHandle v = copy.split_edge(edges[i]);
      copy.compute_limits();
      EXPECT_LE(norm(copy.limit_position(v) - limits[i]), 1e-12 * norm(limits[i])) << base.name << " edge " << i;
      ++checked;
    }
    EXPECT_GT(red, 0) << base.name << ": the walk leaves red edges";
    EXPECT_GT(checked, 20) << base.name;
  }
}

}  // namespace
}  // namespace rgbmesh
