// Vertex names and canonical diagonals (canonical.hpp): the same vertices inserted in other
// orders give other trapezoid diagonals; after canonical_diagonals, the same triangles.

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/fem/surface_mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

namespace {

using namespace rgbmesh;
using rgbmesh::testing::named_triangles;

// The vertices of `m` inserted into its base mesh again, parents first, in a shuffled order
// within each level: split_edge on the edge between the parents (forced splits may have
// inserted a vertex already). Helpers that split_edge inserts for a Loop stencil and that `m`
// does not have are removed again at the end, finest first (as restore_state does).
RgbMesh reinserted(const rgbmesh::testing::BaseMesh& base, const RgbMesh& m, std::uint64_t seed) {
  const std::vector<VertexName> name = vertex_names(m);
  std::vector<std::vector<std::array<VertexName, 3>>> by_level;  // (name, parents' names)
  for (const VertexHandle v : m.vertices()) {
    const int l = m.level(v);
    if (l == 0) continue;
    if (by_level.size() <= static_cast<std::size_t>(l)) by_level.resize(static_cast<std::size_t>(l) + 1);
    const auto& p = m.parents(v);
    by_level[static_cast<std::size_t>(l)].push_back({name[v.idx], name[p[0].idx], name[p[1].idx]});
  }
  std::mt19937_64 rng(seed);
  RgbMesh b = base.build();
  for (auto& level : by_level) {
    std::shuffle(level.begin(), level.end(), rng);
    for (const auto& [child, pa, pb] : level) {
      std::map<VertexName, VertexHandle> at;
      const std::vector<VertexName> now = vertex_names(b);
      for (const VertexHandle v : b.vertices()) at[now[v.idx]] = v;
      if (at.count(child)) continue;
      const EdgeHandle e = b.find_edge(at.at(pa), at.at(pb));
      EXPECT_TRUE(e.valid() && !b.is_red(e));
      if (!e.valid() || b.is_red(e)) return b;
      b.split_edge(e);
    }
  }
  std::set<VertexName> wanted(name.begin(), name.end());
  for (bool removed = true; removed;) {
    removed = false;
    const std::vector<VertexName> now = vertex_names(b);
    std::vector<VertexHandle> extra;
    for (const VertexHandle v : b.vertices())
      if (!wanted.count(now[v.idx])) extra.push_back(v);
    std::sort(extra.begin(), extra.end(), [&b](VertexHandle x, VertexHandle y) { return b.level(x) > b.level(y); });
    for (const VertexHandle v : extra)
      if (b.alive(v) && b.is_removable(v)) {
        b.remove_vertex(v);
        removed = true;
      }
  }
  return b;
}

TEST(Canonical, NamesDependOnAncestryOnly) {
  EXPECT_EQ(child_name(3, 7), child_name(7, 3));
  EXPECT_NE(child_name(3, 7), child_name(3, 8));
  EXPECT_NE(child_name(3, 7) >> 63, 0u);  // never a base vertex's name
  RgbMesh m = rgbmesh::testing::icosahedron().build();
  const std::vector<VertexName> before = vertex_names(m);
  for (const VertexHandle v : m.vertices()) EXPECT_EQ(before[v.idx], static_cast<VertexName>(v.idx));
}

class CanonicalOnBases : public ::testing::TestWithParam<rgbmesh::testing::BaseMesh> {};

TEST_P(CanonicalOnBases, OtherInsertionOrdersGiveTheSameTriangles) {
  const rgbmesh::testing::BaseMesh& base = GetParam();
  std::size_t differed = 0;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    RgbMesh m = base.build();
    RandomWalkOptions o;
    o.max_level = 4;
    o.split_probability = 0.8;
    random_walk(m, 300, seed, o);
    RgbMesh b = reinserted(base, m, seed + 100);
    ASSERT_EQ(b.num_vertices(), m.num_vertices()) << "seed " << seed;
    if (named_triangles(b) != named_triangles(m)) ++differed;
    canonical_diagonals(m);
    canonical_diagonals(b);
    EXPECT_NO_THROW(m.validate()) << "seed " << seed;
    EXPECT_NO_THROW(b.validate()) << "seed " << seed;
    EXPECT_EQ(named_triangles(b), named_triangles(m)) << "seed " << seed;
    EXPECT_EQ(canonical_diagonals(m), 0u) << "a second pass changes nothing";
    // Still an RGB mesh that refines and coarsens as before.
    random_walk(m, 200, seed + 7, o);
    EXPECT_NO_THROW(m.validate());
  }
  RecordProperty("orders_that_differed_before", static_cast<int>(differed));
}

INSTANTIATE_TEST_SUITE_P(Bases, CanonicalOnBases,
                         ::testing::Values(rgbmesh::testing::icosahedron(), rgbmesh::testing::grid_with_holes(6, 2), rgbmesh::testing::torus(6, 5),
                                           rgbmesh::testing::fan_disk(7)),
                         [](const ::testing::TestParamInfo<rgbmesh::testing::BaseMesh>& p) { return p.param.name; });

// ---- stages in canonical order (issue 24) ---------------------------------------------------
// A stage's result depends on the mesh (its named vertices and diagonals) and the stage's
// input, never on slots: the same stage on a mesh and on a copy rebuilt in a shuffled order
// gives the same mesh, down to the last bit of every limit position.

// A deterministic value in [0, 1) from a name: external fields that follow the vertices.
double unit_value(VertexName n) {
  n ^= n >> 33;
  n *= 0xff51afd7ed558ccdull;
  n ^= n >> 33;
  return static_cast<double>(n >> 11) * 0x1.0p-53;
}

// A field criterion whose values come from the corners' names, as an error indicator computed
// on the mesh would (indexed by slot, as FieldCriterion wants).
FieldCriterion named_field(const RgbMesh& m, double refine_above, double coarsen_below) {
  const std::vector<VertexName> name = vertex_names(m);
  std::vector<double> tv(static_cast<std::size_t>(m.triangle_slots()), 0.0), vv(static_cast<std::size_t>(m.vertex_slots()), 1.0);
  for (const TriangleHandle t : m.triangles()) {
    const auto c = m.triangle_vertices(t);
    tv[t.idx] = unit_value(name[c[0].idx] ^ name[c[1].idx] ^ name[c[2].idx]);
  }
  for (const VertexHandle v : m.vertices()) vv[v.idx] = unit_value(name[v.idx] + 1);
  return FieldCriterion(std::move(tv), refine_above, std::move(vv), coarsen_below);
}

// Every limit position by name (bit for bit).
std::map<VertexName, std::array<double, 3>> named_limits(RgbMesh& m) {
  m.compute_limits();
  const std::vector<VertexName> name = vertex_names(m);
  std::map<VertexName, std::array<double, 3>> out;
  for (const VertexHandle v : m.vertices()) {
    const Vec3 p = m.limit_position(v);
    out[name[v.idx]] = {p.x, p.y, p.z};
  }
  return out;
}

// canonical_vertex_order and canonical_triangle_order: permutations of the live elements,
// parents before children, and the same sequence of names on both meshes.
void expect_same_order(const RgbMesh& m, const RgbMesh& b) {
  const std::vector<VertexName> nm = vertex_names(m), nb = vertex_names(b);
  const auto named = [](const RgbMesh& x, const std::vector<VertexName>& name) {
    const std::vector<VertexHandle> order = canonical_vertex_order(x);
    EXPECT_EQ(order.size(), x.num_vertices());
    std::vector<char> seen(static_cast<std::size_t>(x.vertex_slots()), 0);
    std::vector<VertexName> names;
    for (const VertexHandle v : order) {
      EXPECT_TRUE(x.alive(v));
      EXPECT_FALSE(seen[v.idx]) << "listed twice";
      if (x.level(v) > 0) {
        EXPECT_TRUE(seen[x.parents(v)[0].idx] && seen[x.parents(v)[1].idx]) << "a child before its parents";
      }
      seen[v.idx] = 1;
      names.push_back(name[v.idx]);
    }
    std::vector<std::array<VertexName, 3>> triangles;
    for (const TriangleHandle t : canonical_triangle_order(x, order)) {
      const auto c = x.triangle_vertices(t);
      triangles.push_back({name[c[0].idx], name[c[1].idx], name[c[2].idx]});
    }
    EXPECT_EQ(triangles.size(), x.num_triangles());
    return std::pair(names, triangles);
  };
  const auto [vm, tm] = named(m, nm);
  const auto [vb, tb] = named(b, nb);
  EXPECT_EQ(vm, vb);
  // A triangle's corners may come rotated (each mesh keeps its own first corner): compare
  // the sets per position in the order.
  ASSERT_EQ(tm.size(), tb.size());
  for (std::size_t i = 0; i < tm.size(); ++i) {
    std::array<VertexName, 3> x = tm[i], y = tb[i];
    std::rotate(x.begin(), std::min_element(x.begin(), x.end()), x.end());
    std::rotate(y.begin(), std::min_element(y.begin(), y.end()), y.end());
    ASSERT_EQ(x, y) << "triangle " << i;
  }
}

// The finite-element system numbers its unknowns in canonical order: the same mesh with other
// handles gives the same points, triangles and solution, bit for bit (what lets a resumed
// adaptive run repeat the original without rebuilding its mesh).
void expect_same_fe_system(RgbMesh& m, RgbMesh& b) {
  {  // Not vacuous: numbered in the order of the handles, the two systems differ.
    const fem::SurfaceMesh fm = fem::build_surface_mesh(m, std::nullopt, 1, fem::DofOrder::mesh),
                           fb = fem::build_surface_mesh(b, std::nullopt, 1, fem::DofOrder::mesh);
    EXPECT_NE(fm.triangles, fb.triangles);
  }
  fem::Problem problem;
  problem.c = 1;
  problem.source = [](const Vec3& x) { return x.x + 2 * x.y - x.z * x.z; };
  for (const int order : {1, 2}) {
    const fem::SurfaceMesh fm = fem::build_surface_mesh(m, std::nullopt, order), fb = fem::build_surface_mesh(b, std::nullopt, order);
    ASSERT_EQ(fm.points.size(), fb.points.size());
    for (std::size_t i = 0; i < fm.points.size(); ++i) {
      ASSERT_EQ(fm.points[i].x, fb.points[i].x) << "point " << i;
      ASSERT_EQ(fm.points[i].y, fb.points[i].y) << "point " << i;
      ASSERT_EQ(fm.points[i].z, fb.points[i].z) << "point " << i;
    }
    ASSERT_EQ(fm.triangles, fb.triangles);
    ASSERT_EQ(fm.edge_nodes, fb.edge_nodes);
    const fem::Solution um = fem::solve(fm, problem), ub = fem::solve(fb, problem);
    ASSERT_EQ(um.u.size(), ub.u.size());
    for (Eigen::Index i = 0; i < um.u.size(); ++i) ASSERT_EQ(um.u[i], ub.u[i]) << "order " << order << " unknown " << i;
  }
}

class CanonicalStages : public ::testing::TestWithParam<rgbmesh::testing::BaseMesh> {};

TEST_P(CanonicalStages, StagesOnAShuffledCopyGiveTheSameMesh) {
  const rgbmesh::testing::BaseMesh& base = GetParam();
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    RgbMesh m = base.build();
    RandomWalkOptions o;
    o.max_level = 4;
    o.split_probability = 0.7;
    random_walk(m, 400, seed, o);
    RgbMesh b = reinserted(base, m, seed + 100);
    canonical_diagonals(m);
    canonical_diagonals(b);
    ASSERT_EQ(named_triangles(b), named_triangles(m)) << "seed " << seed;
    // The mesh's extent, for balls and lengths that cut through it.
    m.compute_limits();
    Vec3 lo = m.limit_position(*m.vertices().begin()), hi = lo, center;
    for (const VertexHandle v : m.vertices()) {
      const Vec3 p = m.limit_position(v);
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    center = 0.5 * (lo + hi);
    const double size = distance(lo, hi);
    const auto apply = [&](RgbMesh& x, int stage) {
      switch (stage) {
        case 0: return selective_refinement(x, BallLevel(center + Vec3{0.1 * size, 0, 0}, 0.3 * size, 5));
        case 1: return selective_refinement(x, MaxEdgeLength(0.08 * size));
        case 2: return selective_refinement(x, GeometricTolerance(2e-3 * size));
        case 3: return selective_refinement(x, TriangleBudget(3 * x.num_triangles() + 7));
        case 4: return selective_refinement(x, named_field(x, 0.7, 0.5));
        default: return selective_refinement(x, named_field(x, 0.9, 0.95));
      }
    };
    for (int stage = 0; stage < 6; ++stage) {
      const RefinementResult rm = apply(m, stage), rb = apply(b, stage);
      EXPECT_EQ(rm.splits, rb.splits) << "seed " << seed << " stage " << stage;
      EXPECT_EQ(rm.removals, rb.removals) << "seed " << seed << " stage " << stage;
      EXPECT_NO_THROW(m.validate());
      EXPECT_NO_THROW(b.validate());
      ASSERT_EQ(named_triangles(b), named_triangles(m)) << "seed " << seed << " stage " << stage;
      ASSERT_EQ(named_limits(b), named_limits(m)) << "seed " << seed << " stage " << stage;
      expect_same_order(m, b);
    }
    expect_same_fe_system(m, b);
  }
}

INSTANTIATE_TEST_SUITE_P(Bases, CanonicalStages,
                         ::testing::Values(rgbmesh::testing::icosahedron(), rgbmesh::testing::grid_with_holes(6, 2),
                                           rgbmesh::testing::torus(6, 5), rgbmesh::testing::double_torus(),
                                           rgbmesh::testing::fan_disk(7)),
                         [](const ::testing::TestParamInfo<rgbmesh::testing::BaseMesh>& p) { return p.param.name; });

// Without the canonical choice the orders do give other meshes somewhere: the test above is
// not vacuous.
TEST(Canonical, InsertionOrderChangesDiagonalsWithoutIt) {
  std::size_t differed = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const rgbmesh::testing::BaseMesh base = rgbmesh::testing::icosahedron();
    RgbMesh m = base.build();
    RandomWalkOptions o;
    o.max_level = 4;
    o.split_probability = 0.8;
    random_walk(m, 300, seed, o);
    if (named_triangles(reinserted(base, m, seed + 100)) != named_triangles(m)) ++differed;
  }
  EXPECT_GT(differed, 0u);
}

}  // namespace
