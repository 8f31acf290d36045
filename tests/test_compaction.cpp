// RgbMesh::compact (issue 44): after random walks of splits and removals on every test base
// mesh (closed, open, genus 2, sharp features), the compacted mesh is valid, has no free slot,
// lists the same elements in the same order with the same data (its snapshot is the
// uncompacted one's, array for array), and behaves as the uncompacted mesh under further
// random operations and selective refinement (the same triangles by their vertices' names).

#include <gtest/gtest.h>

#include <initializer_list>
#include <memory>
#include <optional>
#include <set>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

namespace rgbmesh {
namespace {

using testing::BaseMesh;

void expect_same_snapshot(const RgbMesh& a, const RgbMesh& b) {
  const MeshSnapshot x = a.snapshot(RgbMesh::Points::control), y = b.snapshot(RgbMesh::Points::control);
  ASSERT_EQ(x.points.size(), y.points.size());
  for (std::size_t i = 0; i < x.points.size(); ++i) {
    EXPECT_EQ(x.points[i].x, y.points[i].x);
    EXPECT_EQ(x.points[i].y, y.points[i].y);
    EXPECT_EQ(x.points[i].z, y.points[i].z);
  }
  EXPECT_EQ(x.triangles, y.triangles);
  EXPECT_EQ(x.vertex_level, y.vertex_level);
  EXPECT_EQ(x.triangle_level, y.triangle_level);
  EXPECT_EQ(x.triangle_color, y.triangle_color);
  EXPECT_EQ(x.vertex_rule, y.vertex_rule);
}

// Levels, limit positions and names (ancestry), vertex by vertex in slot order.
void expect_same_vertices(const RgbMesh& a, const RgbMesh& b) {
  std::vector<VertexHandle> va, vb;
  for (VertexHandle v : a.vertices()) va.push_back(v);
  for (VertexHandle v : b.vertices()) vb.push_back(v);
  ASSERT_EQ(va.size(), vb.size());
  const std::vector<VertexName> na = vertex_names(a), nb = vertex_names(b);
  for (std::size_t i = 0; i < va.size(); ++i) {
    EXPECT_EQ(a.level(va[i]), b.level(vb[i]));
    // A limit is known, computable from a complete ring, or neither (then both refuse).
    const auto limit = [](const RgbMesh& m, VertexHandle v) -> std::optional<Vec3> {
      try {
        return m.limit_position(v);
      } catch (const PreconditionError&) {
        return std::nullopt;
      }
    };
    const auto la = limit(a, va[i]), lb = limit(b, vb[i]);
    ASSERT_EQ(la.has_value(), lb.has_value()) << "vertex " << i;
    if (la) {
      EXPECT_EQ(la->x, lb->x);
      EXPECT_EQ(la->y, lb->y);
      EXPECT_EQ(la->z, lb->z);
    }
    EXPECT_EQ(na[static_cast<std::size_t>(va[i].idx)], nb[static_cast<std::size_t>(vb[i].idx)]) << "vertex " << i;
  }
}

class Compaction : public ::testing::TestWithParam<BaseMesh> {};

TEST_P(Compaction, KeepsTheMeshAndItsOrderAndGivesTheSlotsBack) {
  RgbMesh mesh = GetParam().build();
  RandomWalkOptions walk;
  walk.max_level = 5;
  walk.split_probability = 0.8;
  random_walk(mesh, 3000, 17, walk);  // grow
  walk.split_probability = 0.2;
  random_walk(mesh, 3000, 18, walk);  // shrink: free slots
  ASSERT_EQ(mesh.validate(), "");
  ASSERT_LT(mesh.live_fraction(), 1.0) << "the walk freed no slot";

  const RgbMesh before = mesh;
  auto tag = mesh.add_vertex_property<std::int64_t>(-1);
  for (VertexHandle v : mesh.vertices()) tag[v] = v.idx;
  RgbMesh::Renumbering told;
  const int id = mesh.add_renumbering_observer([&](const RgbMesh::Renumbering& r) { told = r; });
  const std::size_t bytes_before = mesh.memory_bytes();
  const RgbMesh::Renumbering map = mesh.compact();
  mesh.remove_observer(id);

  EXPECT_EQ(mesh.validate(), "");
  EXPECT_EQ(mesh.live_fraction(), 1.0);
  EXPECT_EQ(mesh.vertex_slots(), static_cast<std::int32_t>(mesh.num_vertices()));
  EXPECT_EQ(mesh.edge_slots(), static_cast<std::int32_t>(mesh.num_edges()));
  EXPECT_EQ(mesh.triangle_slots(), static_cast<std::int32_t>(mesh.num_triangles()));
  EXPECT_LT(mesh.memory_bytes(), bytes_before);
  EXPECT_EQ(told.vertex, map.vertex);
  EXPECT_EQ(told.triangle, map.triangle);
  expect_same_snapshot(before, mesh);
  expect_same_vertices(before, mesh);
  // The maps: live slots move down in order, base vertices stay, free ones map to -1; the
  // property followed its vertices.
  std::int32_t next = 0;
  for (std::size_t i = 0; i < map.vertex.size(); ++i) {
    const VertexHandle old(static_cast<std::int32_t>(i));
    EXPECT_EQ(map.vertex[i] >= 0, before.alive(old));
    if (map.vertex[i] < 0) continue;
    EXPECT_EQ(map.vertex[i], next++);
    if (i < before.num_base_vertices()) {
      EXPECT_EQ(map.vertex[i], static_cast<std::int32_t>(i));
    }
    EXPECT_EQ(tag[VertexHandle(map.vertex[i])], static_cast<std::int64_t>(i));
  }

  // The same further stages give the same mesh (only slots differ: new elements take new
  // slots at the end). Random walks pick elements by slot, so they are not compared.
  RgbMesh uncompacted = before;
  const Vec3 centre = mesh.control_point(VertexHandle(0));
  for (const LodCriterion* stage : std::initializer_list<const LodCriterion*>{
           new BallLevel(centre, 0.5, 6), new UniformLevel(2), new BallLevel(-1.0 * centre, 0.7, 5)}) {
    const std::unique_ptr<const LodCriterion> owned(stage);
    const RefinementResult r1 = selective_refinement(mesh, *stage);
    const RefinementResult r2 = selective_refinement(uncompacted, *stage);
    ASSERT_EQ(mesh.validate(), "");
    EXPECT_EQ(r1.splits, r2.splits);
    EXPECT_EQ(r1.removals, r2.removals);
    EXPECT_EQ(testing::named_triangles(mesh), testing::named_triangles(uncompacted));
  }
  selective_refinement(mesh, CoarsenAll());
  EXPECT_EQ(mesh.num_vertices(), mesh.num_base_vertices());
  EXPECT_EQ(mesh.validate(), "");
}

TEST(CompactionOfAFreshMesh, ChangesNothing) {
  RgbMesh mesh = testing::icosahedron().build();
  selective_refinement(mesh, UniformLevel(2));
  const RgbMesh before = mesh;
  const RgbMesh::Renumbering map = mesh.compact();
  for (std::size_t i = 0; i < map.vertex.size(); ++i) EXPECT_EQ(map.vertex[i], static_cast<std::int32_t>(i));
  expect_same_snapshot(before, mesh);
  EXPECT_TRUE(mesh.is_uniform());
  EXPECT_EQ(mesh.validate(), "");
}

TEST(CompactionOfACoarsenedMesh, MakesItUniformAgainForTheFastSplitter) {
  // is_uniform() wants no free slot: a uniform level reached by coarsening qualifies again.
  RgbMesh mesh = testing::torus(6, 4).build();
  selective_refinement(mesh, UniformLevel(3));
  selective_refinement(mesh, UniformLevel(1));
  EXPECT_FALSE(mesh.is_uniform());
  mesh.compact();
  EXPECT_TRUE(mesh.is_uniform());
  RgbMesh reference = testing::torus(6, 4).build();
  selective_refinement(reference, UniformLevel(1));
  mesh.split_all_edges();
  reference.split_all_edges();
  EXPECT_EQ(mesh.validate(), "");
  EXPECT_EQ(testing::named_triangles(mesh), testing::named_triangles(reference));
}

// Every test mesh, and those with sharp features (rails, vertex histories).
std::vector<BaseMesh> bases() {
  std::vector<BaseMesh> all = testing::all_base_meshes();
  all.push_back(testing::sharp_cube());
  all.push_back(testing::octahedron_with_darts());
  all.push_back(testing::graded_icosahedron(CreaseMethod::chaikin));
  return all;
}

INSTANTIATE_TEST_SUITE_P(AllBases, Compaction, ::testing::ValuesIn(bases()),
                         [](const ::testing::TestParamInfo<BaseMesh>& p) { return p.param.name; });

}  // namespace
}  // namespace rgbmesh
