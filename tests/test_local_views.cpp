// Refining a distributed mesh (issue 13): each process holds a local view of the mesh (its
// part and a ghost layer as the whole mesh has them, the rest coarse: parallel::local_view)
// and refines it with the marks it can see; the splits that reach another process's region
// (forced splits crossing the interface) are then handed to it, round after round, until no
// process changes (a fixpoint; parallel::make_splits, what reconcile_splits does over MPI,
// which mpi_local_views_check runs). Here the processes are simulated in one: with one ghost
// layer the views end with exactly the triangles, and bit for bit the positions, that refining
// the whole mesh gives inside each part; without it they do not. Vertices are named across
// meshes by keys (parallel::vertex_keys): a start vertex by its slot, a new one by its
// parents' keys.

#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "local_views_common.hpp"

namespace rgbmesh::parallel {
namespace {

using testing::Compared;
using testing::View;

struct Outcome {
  std::size_t missing = 0, extra = 0, handed = 0, missing_vertices = 0;
  int rounds = 0;
  double moved = 0;
};

// The four views refined apart, each with the marks on its own triangles (with `ghost_marks`
// also on its ghost triangles); with `exchange`, every split one made is offered to all
// (make_splits makes those inside each one's fine region) until none changes.
Outcome refine_apart(int ghost_layers, bool exchange, bool ghost_marks = false) {
  std::vector<View> views;
  for (int q = 0; q < testing::Setup::kParts; ++q) views.push_back(testing::refined_view(q, ghost_layers, ghost_marks));
  Outcome out;
  for (bool changed = exchange; changed && out.rounds < 20; ++out.rounds) {
    std::map<VertexKey, std::array<VertexKey, 2>> made;
    for (const View& v : views)
      for (const auto& [key, parents] : vertex_keys(v.mesh, v.start).parents) made[key] = parents;
    std::size_t round = 0;
    for (View& v : views) round += make_splits(v.mesh, v.start, v.fine, made);
    out.handed += round;
    changed = round > 0;
  }
  // The diagonals by the vertices' names, as after every adaptation (canonical.hpp).
  for (View& v : views) canonical_diagonals(v.mesh);
  for (std::size_t q = 0; q < views.size(); ++q) {
    EXPECT_EQ(views[q].mesh.validate(), "") << "part " << q;
    const Compared c = testing::compare_inside(views[q]);
    out.missing += c.missing;
    out.extra += c.extra;
    out.missing_vertices += c.missing_vertices;
    out.moved = std::max(out.moved, c.moved);
  }
  std::printf("ghost layers %d, %s marks, %s: %zu vertices and %zu triangles missing, %zu extra, points within %.1e; %zu "
              "splits handed over in %d rounds\n",
              ghost_layers, ghost_marks ? "own and ghost" : "own", exchange ? "exchanging splits" : "no exchange",
              out.missing_vertices, out.missing, out.extra, out.moved, out.handed, out.rounds);
  return out;
}

TEST(LocalViews, RefinedApartAndReconciledTheyAreTheWholeMeshRefined) {
  ASSERT_GT(testing::setup().marked.size(), 200u);
  // One ghost layer, each process marking its own and its ghost triangles, splits exchanged:
  // inside every part the same triangles and bit for bit the same points as the whole mesh
  // refined.
  const Outcome o = refine_apart(1, true, true);
  EXPECT_EQ(o.missing_vertices, 0u);
  EXPECT_EQ(o.missing, 0u);
  EXPECT_EQ(o.extra, 0u);
  EXPECT_EQ(o.moved, 0.0);
  EXPECT_LT(o.rounds, 20) << "no fixpoint";
  EXPECT_GT(o.handed, 0u) << "splits made by one process that others hold";
}

TEST(LocalViews, MarkingOnlyItsOwnTrianglesEachProcessNeedsTheExchange) {
  // Without it, the splits that the neighbours' marks make along and across a part's interface
  // are missing. With it every part has the whole mesh's vertices, at bit for bit its points,
  // and (the trapezoids' diagonals chosen by names, canonical.hpp, not by the order in which
  // each process inserted) the whole mesh's triangles.
  const Outcome alone = refine_apart(1, false);
  EXPECT_GT(alone.missing_vertices, 0u);
  const Outcome o = refine_apart(1, true);
  EXPECT_EQ(o.missing_vertices, 0u);
  EXPECT_EQ(o.moved, 0.0);
  EXPECT_EQ(o.missing, 0u);
  EXPECT_EQ(o.extra, 0u);
}

TEST(LocalViews, WithoutAGhostLayerThePartsInterfacesDiffer) {
  // Each process sees only its own triangles and their marks: the splits its neighbours' marks
  // force in its part are missing, and the configurations along the interface (which diagonal
  // a trapezoid takes, the colours) depend on triangles it does not have; handing over splits
  // alone does not mend the latter.
  const Outcome alone = refine_apart(0, false);
  EXPECT_GT(alone.missing + alone.extra, 0u);
  const Outcome handed = refine_apart(0, true);
  EXPECT_LT(handed.missing + handed.extra, alone.missing + alone.extra);
}

TEST(LocalViews, KeysNameVerticesByTheirParentsWhateverTheOrder) {
  // The same vertices inserted in two orders get the same keys; different parents, different keys.
  EXPECT_EQ(child_key(3, 7), child_key(7, 3));
  EXPECT_NE(child_key(3, 7), child_key(3, 8));
  EXPECT_NE(child_key(3, 7) & ~(VertexKey{1} << 63), VertexKey{0});
  EXPECT_TRUE(child_key(1, 2) >> 63);
  const testing::Setup& s = testing::setup();
  std::set<VertexKey> distinct;
  for (const auto& [slot, key] : s.refined_keys.of_slot) distinct.insert(key);
  EXPECT_EQ(distinct.size(), s.refined.num_vertices()) << "a key names one vertex";
}

}  // namespace
}  // namespace rgbmesh::parallel
