// Saving and restoring the RGB state (rgb_state.hpp), in memory: after random walks of splits
// and removals on closed, open and higher-genus meshes, the restored mesh equals the original
// element by element, identical further operations keep them equal, coarsening everything
// gives the base back, and edited states are refused with a message saying what is wrong.

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/rgb_state.hpp"
#include "test_meshes.hpp"

#if defined(__SANITIZE_ADDRESS__) || defined(RGBMESH_SANITIZE) || !defined(__OPTIMIZE__)
#define RGBMESH_STATE_TEST_SLOW 1
#endif

namespace rgbmesh {
namespace {

// Vertex correspondence between two meshes that undergo the same operations: original slot ->
// restored handle. New vertices are matched by their parents' images.
class Correspondence {
 public:
  Correspondence(RgbMesh& a, RgbMesh& b) : a_(a), b_(b) {
    ida_ = a.add_insertion_observer([this](VertexHandle v, VertexHandle p, VertexHandle q) {
      new_in_a_.push_back({v, {p, q}});
    });
    idb_ = b.add_insertion_observer([this](VertexHandle v, VertexHandle p, VertexHandle q) {
      new_in_b_[key(p, q)] = v;
    });
    rema_ = a.add_removal_observer([this](VertexHandle v) { map_.erase(v.idx); });
  }
  ~Correspondence() {
    a_.remove_observer(ida_);
    a_.remove_observer(rema_);
    b_.remove_observer(idb_);
  }
  void set(VertexHandle a, VertexHandle b) { map_[a.idx] = b; }
  VertexHandle operator()(VertexHandle a) const { return map_.at(a.idx); }
  // Matches the vertices both meshes inserted since the last call; false if one is unmatched.
  bool settle() {
    bool ok = true;
    for (const auto& [v, p] : new_in_a_) {
      if (!a_.alive(v)) continue;
      const auto it = new_in_b_.find(key((*this)(p[0]), (*this)(p[1])));
      if (it == new_in_b_.end()) {
        ok = false;
        continue;
      }
      map_[v.idx] = it->second;
    }
    new_in_a_.clear();
    new_in_b_.clear();
    return ok;
  }

 private:
  static std::pair<std::int32_t, std::int32_t> key(VertexHandle p, VertexHandle q) {
    return {std::min(p.idx, q.idx), std::max(p.idx, q.idx)};
  }
  RgbMesh& a_;
  RgbMesh& b_;
  int ida_ = 0, idb_ = 0, rema_ = 0;
  std::map<std::int32_t, VertexHandle> map_;
  std::vector<std::pair<VertexHandle, std::array<VertexHandle, 2>>> new_in_a_;
  std::map<std::pair<std::int32_t, std::int32_t>, VertexHandle> new_in_b_;
};

double relative(const Vec3& p, const Vec3& q) { return norm(p - q) / std::max(1.0, norm(q)); }

// Same triangles (through the correspondence), colours, levels, control points and limits.
void expect_same_mesh(RgbMesh& a, RgbMesh& b, const Correspondence& c, const std::string& what) {
  ASSERT_EQ(b.validate(true), "") << what;
  ASSERT_EQ(a.num_vertices(), b.num_vertices()) << what;
  ASSERT_EQ(a.num_triangles(), b.num_triangles()) << what;
  using Key = std::array<std::int32_t, 3>;
  std::map<Key, std::pair<int, Color>> tb;
  for (TriangleHandle t : b.triangles()) {
    auto v = b.triangle_vertices(t);
    Key k{v[0].idx, v[1].idx, v[2].idx};
    std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
    tb[k] = {b.level(t), b.color(t)};
  }
  for (TriangleHandle t : a.triangles()) {
    auto v = a.triangle_vertices(t);
    Key k{c(v[0]).idx, c(v[1]).idx, c(v[2]).idx};
    std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
    const auto it = tb.find(k);
    ASSERT_NE(it, tb.end()) << what << ": a triangle of the original is missing";
    EXPECT_EQ(it->second.first, a.level(t)) << what;
    EXPECT_EQ(it->second.second, a.color(t)) << what;
  }
  a.compute_limits();
  b.compute_limits();
  for (VertexHandle v : a.vertices()) {
    const VertexHandle w = c(v);
    ASSERT_EQ(a.level(v), b.level(w)) << what;
    EXPECT_LE(relative(b.insertion_point(w), a.insertion_point(v)), 1e-12) << what;
    EXPECT_LE(relative(b.control_point(w), a.control_point(v)), 1e-12) << what;
    EXPECT_LE(relative(b.limit_position(w), a.limit_position(v)), 1e-12) << what;
  }
}

RestoreExpectations expectations(const MeshSnapshot& s) {
  RestoreExpectations x;
  x.triangles = s.triangles;
  x.vertex_level = s.vertex_level;
  x.triangle_level = s.triangle_level;
  for (Color c : s.triangle_color) x.triangle_color.push_back(static_cast<std::uint8_t>(c));
  return x;
}

// One random operation keyed by what both meshes share: a green edge of a random triangle
// split, or a random removable vertex removed.
void random_operation(RgbMesh& a, RgbMesh& b, Correspondence& c, std::mt19937_64& rng, int max_level) {
  std::vector<TriangleHandle> ts(a.triangles().begin(), a.triangles().end());
  if (rng() % 2 == 0) {
    const TriangleHandle t = ts[rng() % ts.size()];
    std::vector<EdgeHandle> edges;
    a.raising_edges(t, edges);
    if (edges.empty() || a.level(edges[0]) + 1 >= max_level) return;
    const auto ends = a.edge_vertices(edges[rng() % edges.size()]);
    const EdgeHandle eb = b.find_edge(c(ends[0]), c(ends[1]));
    ASSERT_TRUE(eb.valid());
    a.split_edge(a.find_edge(ends[0], ends[1]));
    b.split_edge(eb);
  } else {
    std::vector<VertexHandle> removable;
    for (VertexHandle v : a.vertices())
      if (a.is_removable(v)) removable.push_back(v);
    if (removable.empty()) return;
    const VertexHandle v = removable[rng() % removable.size()];
    const VertexHandle w = c(v);
    ASSERT_TRUE(b.is_removable(w));
    a.remove_vertex(v);
    b.remove_vertex(w);
  }
  ASSERT_TRUE(c.settle());
}

struct StateCase {
  testing::BaseMesh base;
  std::uint64_t seed;
};
void PrintTo(const StateCase& c, std::ostream* os) { *os << c.base.name << ", seed " << c.seed; }

class StateRoundTrip : public ::testing::TestWithParam<StateCase> {};

#ifdef RGBMESH_STATE_TEST_SLOW
constexpr std::uint64_t kWalk = 600;
constexpr int kFurther = 150;
#else
constexpr std::uint64_t kWalk = 4000;
constexpr int kFurther = 600;
#endif

TEST_P(StateRoundTrip, RestoredMeshIsTheSameAndStaysTheSame) {
  const StateCase& sc = GetParam();
  RgbMesh original = sc.base.build();
  RandomWalkOptions walk;
  walk.max_level = 6;
  const auto walked = random_walk(original, kWalk, sc.seed, walk);
  ASSERT_GT(walked.removals, 0u);
  const MeshSnapshot snap = original.snapshot();
  const RgbState state = save_state(original, snap);
  RestoredMesh restored = restore_state(state, expectations(snap));
  Correspondence c(original, restored.mesh);
  for (std::size_t i = 0; i < snap.vertex_handle.size(); ++i) c.set(snap.vertex_handle[i], restored.vertex[i]);
  expect_same_mesh(original, restored.mesh, c, sc.base.name + " restored");

  std::mt19937_64 rng(sc.seed * 7919);
  for (int k = 0; k < kFurther; ++k) {
    random_operation(original, restored.mesh, c, rng, 7);
    if (::testing::Test::HasFatalFailure()) return;
  }
  expect_same_mesh(original, restored.mesh, c, sc.base.name + " after further operations");

  // Coarsening everything gives exactly the base mesh back.
  selective_refinement(restored.mesh, CoarsenAll());
  ASSERT_EQ(restored.mesh.validate(true), "");
  EXPECT_EQ(testing::canonical_triangles(restored.mesh), testing::canonical_triangles(sc.base.build()));
  std::vector<Vec3> points;
  for (VertexHandle v : restored.mesh.vertices()) points.push_back(restored.mesh.insertion_point(v));
  EXPECT_EQ(points, sc.base.points);
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, StateRoundTrip,
    ::testing::Values(StateCase{testing::icosahedron(), 11}, StateCase{testing::double_torus(), 12},
                      StateCase{testing::grid_with_holes(8, 3), 13}, StateCase{testing::torus(6, 5), 14},
                      StateCase{testing::fan_disk(12), 15}, StateCase{testing::tetrahedron(), 16},
                      StateCase{testing::single_triangle(), 17}),
    [](const ::testing::TestParamInfo<StateCase>& p) { return p.param.base.name; });

// A base mesh saves and restores as itself.
TEST(RgbState, BaseMeshRoundTrip) {
  RgbMesh base = testing::cube().build();
  const MeshSnapshot snap = base.snapshot();
  const RgbState state = save_state(base, snap);
  EXPECT_EQ(state.base_points.size(), base.num_vertices());
  RestoredMesh r = restore_state(state, expectations(snap));
  EXPECT_EQ(testing::canonical_triangles(r.mesh), testing::canonical_triangles(base));
}

// The saved vertices are closed under parents and forced splits; the order of the points
// does not matter (they are restored parents first).
TEST(RgbState, PointOrderDoesNotMatter) {
  RgbMesh m = testing::icosahedron().build();
  random_walk(m, 800, 5);
  MeshSnapshot snap = m.snapshot();
  RgbState state = save_state(m, snap);
  // Reverse the points: every index in the state and the triangles changes.
  const auto n = static_cast<std::int32_t>(state.parents.size());
  const auto flip = [n](std::int32_t i) { return i < 0 ? i : n - 1 - i; };
  RgbState reversed = state;
  RestoreExpectations x = expectations(snap);
  for (std::int32_t i = 0; i < n; ++i) {
    reversed.base_vertex[flip(i)] = state.base_vertex[i];
    reversed.parents[flip(i)] = {flip(state.parents[i][0]), flip(state.parents[i][1])};
    x.vertex_level[flip(i)] = snap.vertex_level[i];
  }
  for (auto& t : x.triangles)
    for (auto& v : t) v = flip(v);
  const RestoredMesh r = restore_state(reversed, x);
  EXPECT_EQ(r.mesh.num_vertices(), m.num_vertices());
}

// Edited states: each refused, with what is wrong.
class EditedState : public ::testing::Test {
 protected:
  void SetUp() override {
    mesh = testing::grid_with_holes(6, 2).build();
    random_walk(mesh, 1500, 21);
    snap = mesh.snapshot();
    state = save_state(mesh, snap);
    x = expectations(snap);
    mesh.compute_limits();
    for (VertexHandle v : snap.vertex_handle) x.control_points.push_back(mesh.control_point(v));
    ASSERT_NO_THROW(restore_state(state, x));
  }
  // The message of the InputError restore_state throws ("" if none).
  std::string refusal() {
    try {
      restore_state(state, x);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  // An inserted point that no other point has as a parent.
  std::int32_t leaf() const {
    std::vector<char> parent(state.parents.size(), 0);
    for (const auto& p : state.parents)
      for (std::int32_t q : p)
        if (q >= 0) parent[q] = 1;
    for (auto i = static_cast<std::int32_t>(state.parents.size()) - 1; i >= 0; --i)
      if (state.base_vertex[i] < 0 && !parent[i]) return i;
    return -1;
  }
  RgbMesh mesh;
  MeshSnapshot snap;
  RgbState state;
  RestoreExpectations x;
};

TEST_F(EditedState, ChangedParent) {
  const std::int32_t k = leaf();
  ASSERT_GE(k, 0);
  state.parents[k][1] = state.parents[k][0] == 0 ? 1 : 0;  // another vertex, not joined or elsewhere
  const std::string m = refusal();
  EXPECT_NE(m.find("inconsistent RGB state"), std::string::npos) << m;
  state.parents[k][1] = static_cast<std::int32_t>(state.parents.size());
  EXPECT_NE(refusal().find("has parent " + std::to_string(state.parents.size())), std::string::npos);
  state.parents[k][1] = k;
  EXPECT_NE(refusal().find("has parent"), std::string::npos);
}

TEST_F(EditedState, ParentCycle) {
  const std::int32_t k = leaf();
  const std::int32_t p = state.parents[k][0];
  ASSERT_EQ(state.base_vertex[p], -1) << "the test needs a parent that is not a base vertex";
  state.parents[p][0] = k;
  const std::string m = refusal();
  EXPECT_TRUE(m.find("among its own ancestors") != std::string::npos || m.find("both split") != std::string::npos)
      << m;
}

TEST_F(EditedState, TwoPointsOnOneEdge) {
  // A leaf given the parents of an earlier inserted point: both would split that edge.
  const std::int32_t k = leaf();
  std::int32_t j = 0;
  while (state.base_vertex[j] >= 0) ++j;
  ASSERT_LT(j, k);
  state.parents[k] = {state.parents[j][1], state.parents[j][0]};
  EXPECT_NE(refusal().find("points " + std::to_string(j) + " and " + std::to_string(k) + " both split the edge"),
            std::string::npos)
      << refusal();
}

TEST_F(EditedState, MissingVertex) {
  // The point is dropped from the state; the file's triangles still name it.
  const std::int32_t k = leaf();
  const auto shift = [k](std::int32_t i) { return i > k ? i - 1 : i; };
  state.parents.erase(state.parents.begin() + k);
  state.base_vertex.erase(state.base_vertex.begin() + k);
  for (auto& p : state.parents)
    for (auto& q : p) q = q < 0 ? q : shift(q);
  x = RestoreExpectations{};
  x.triangles = snap.triangles;
  for (auto& t : x.triangles)
    for (auto& v : t) v = v == k ? 0 : shift(v);
  EXPECT_NE(refusal().find("is not a triangle of the mesh the state describes"), std::string::npos) << refusal();
}

TEST_F(EditedState, MissingForcedVertex) {
  // Dropping a point that a finer one needs makes that one's insertion force it.
  for (VertexHandle v : snap.vertex_handle) {
    if (mesh.level(v) == 0 || mesh.is_removable(v)) continue;
    const auto k = static_cast<std::int32_t>(std::find(snap.vertex_handle.begin(), snap.vertex_handle.end(), v) -
                                             snap.vertex_handle.begin());
    bool is_parent = false;
    for (const auto& p : state.parents) is_parent = is_parent || p[0] == k || p[1] == k;
    if (is_parent) continue;
    // Make it a duplicate of another vertex's identity: its own pair is then missing.
    state.parents.erase(state.parents.begin() + k);
    state.base_vertex.erase(state.base_vertex.begin() + k);
    for (auto& p : state.parents)
      for (auto& q : p) q = q > k ? q - 1 : q;
    x = RestoreExpectations{};
    const std::string m = refusal();
    EXPECT_NE(m.find("which the state does not have"), std::string::npos) << m;
    return;
  }
  GTEST_SKIP() << "no unremovable leaf vertex in this walk";
}

TEST_F(EditedState, ChangedLevel) {
  const std::int32_t k = leaf();
  x.vertex_level[k] = static_cast<std::uint8_t>(x.vertex_level[k] + 1);
  EXPECT_NE(refusal().find("point " + std::to_string(k) + " has level"), std::string::npos) << refusal();
}

TEST_F(EditedState, SwappedTriangle) {
  std::swap(x.triangles[3][0], x.triangles[3][1]);
  EXPECT_NE(refusal().find("triangle 3 "), std::string::npos) << refusal();
  std::swap(x.triangles[3][0], x.triangles[3][1]);
  x.triangle_color[4] = static_cast<std::uint8_t>((x.triangle_color[4] + 1) % 3);
  EXPECT_NE(refusal().find("triangle 4 "), std::string::npos) << refusal();
}

TEST_F(EditedState, ChangedBasePoints) {
  state.base_points[5].z += 0.25;
  EXPECT_NE(refusal().find("edited base points"), std::string::npos) << refusal();
}

TEST_F(EditedState, MissingBaseVertexAndWrongVersion) {
  for (std::size_t i = 0; i < state.base_vertex.size(); ++i)
    if (state.base_vertex[i] == 2) state.base_vertex[i] = 3;
  EXPECT_NE(refusal().find("are both base vertex 3"), std::string::npos) << refusal();
  SetUp();
  state.version = 99;
  EXPECT_NE(refusal().find("version 99 is not supported"), std::string::npos) << refusal();
  SetUp();
  state.base_triangles[0] = {0, 0, 1};
  EXPECT_NE(refusal().find("the base mesh: "), std::string::npos) << refusal();
}

// How long restoring takes against refining to the same mesh is measured by a benchmark
// (bench/bench_rgb_state.cpp), not here: a timed test fails on a loaded machine.

}  // namespace
}  // namespace rgbmesh

namespace rgbmesh {
namespace {

// Pieces (a distributed run's output): each piece's state lists its triangles' corners and
// their ancestors; the pieces joined and restored are the whole mesh, on several bases. The
// pieces are cut by position (x), so each is a patch whose ancestors reach outside it.
class PieceStates : public ::testing::TestWithParam<testing::BaseMesh> {};

TEST_P(PieceStates, JoinedPiecesRestoreTheWholeMesh) {
  RgbMesh m = GetParam().build();
  random_walk(m, 2500, 31);
  const MeshSnapshot snap = m.snapshot();
  // Three pieces by the triangles' centroids' x.
  std::vector<std::int32_t> part(snap.triangles.size());
  double lo = 1e300, hi = -1e300;
  for (const Vec3& p : snap.points) {
    lo = std::min(lo, p.x);
    hi = std::max(hi, p.x);
  }
  for (std::size_t t = 0; t < snap.triangles.size(); ++t) {
    double x = 0;
    for (const std::int32_t v : snap.triangles[t]) x += snap.points[static_cast<std::size_t>(v)].x / 3;
    part[t] = std::min(2, static_cast<std::int32_t>(3 * (x - lo) / std::max(hi - lo, 1e-300)));
  }
  std::vector<RgbState> pieces;
  std::vector<CellPiece<3>> cells;
  std::size_t ancestors_outside = 0;
  for (std::int32_t k = 0; k < 3; ++k) {
    cells.push_back(cell_piece(snap.triangles, snap.points.size(), part, k));
    std::vector<VertexHandle> points;
    for (const std::size_t row : cells.back().point_rows) points.push_back(snap.vertex_handle[row]);
    pieces.push_back(save_piece_state(m, points));
    ASSERT_GE(pieces.back().parents.size(), points.size());
    ancestors_outside += pieces.back().parents.size() - points.size();
    // Each piece's entries are closed under parents.
    for (std::size_t i = 0; i < pieces.back().parents.size(); ++i)
      for (const std::int32_t p : pieces.back().parents[i])
        ASSERT_LT(p, static_cast<std::int32_t>(pieces.back().parents.size()));
  }
  EXPECT_GT(ancestors_outside, 0u) << "the pieces should need ancestors beyond their points";
  std::vector<std::vector<std::int32_t>> entry_of;
  const RgbState whole = join_piece_states(pieces, entry_of);
  EXPECT_EQ(whole.parents.size(), m.num_vertices());
  RestoreExpectations x;
  for (std::size_t k = 0; k < 3; ++k)
    for (const auto& t : cells[k].cells)
      x.triangles.push_back({entry_of[k][static_cast<std::size_t>(t[0])],
                             entry_of[k][static_cast<std::size_t>(t[1])],
                             entry_of[k][static_cast<std::size_t>(t[2])]});
  const RestoredMesh r = restore_state(whole, x);
  EXPECT_EQ(r.mesh.validate(true), "");
  // The same triangles, by their corners' names (handles differ).
  const auto named = [](const RgbMesh& mesh) {
    const std::vector<VertexName> name = vertex_names(mesh);
    std::set<std::array<VertexName, 3>> out;
    for (const TriangleHandle t : mesh.triangles()) {
      std::array<VertexName, 3> c{};
      for (int k = 0; k < 3; ++k)
        c[static_cast<std::size_t>(k)] = name[static_cast<std::size_t>(mesh.triangle_vertices(t)[k].idx)];
      std::sort(c.begin(), c.end());
      out.insert(c);
    }
    return out;
  };
  EXPECT_EQ(named(r.mesh), named(m));
  EXPECT_EQ(r.mesh.num_triangles(), m.num_triangles());
  // Every piece point became the vertex it was.
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t i = 0; i < cells[k].point_rows.size(); ++i)
      EXPECT_EQ(r.mesh.insertion_point(r.vertex[static_cast<std::size_t>(entry_of[k][i])]),
                m.insertion_point(snap.vertex_handle[cells[k].point_rows[i]]));
}

INSTANTIATE_TEST_SUITE_P(Meshes, PieceStates,
                         ::testing::Values(testing::icosahedron(), testing::grid_with_holes(8, 3),
                                           testing::double_torus()),
                         [](const ::testing::TestParamInfo<testing::BaseMesh>& p) { return p.param.name; });

// Damaged pieces: refused with the piece and what is wrong, never looping or crashing.
TEST(PieceStates, DamagedPiecesAreRefused) {
  RgbMesh m = testing::icosahedron().build();
  random_walk(m, 600, 7);
  std::vector<VertexHandle> points;
  for (const VertexHandle v : m.vertices())
    if (m.level(v) >= 2) points.push_back(v);
  ASSERT_GT(points.size(), 3u);
  const RgbState good = save_piece_state(m, points);
  const auto refusal = [&](const RgbState& second) {
    std::vector<std::vector<std::int32_t>> entry_of;
    try {
      join_piece_states({good, second}, entry_of);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(refusal(good), "");
  RgbState cycle = good;  // entry 0 its own ancestor through entry 1
  cycle.parents[1] = {0, cycle.parents[1][1] == 0 ? cycle.parents[1][0] : cycle.parents[1][1]};
  cycle.parents[0] = {1, cycle.parents[0][0] == 1 ? cycle.parents[0][1] : cycle.parents[0][0]};
  EXPECT_NE(refusal(cycle).find("piece 1: entry"), std::string::npos) << refusal(cycle);
  RgbState out_of_range = good;
  out_of_range.parents[0][1] = static_cast<std::int32_t>(good.parents.size());
  EXPECT_NE(refusal(out_of_range).find("piece 1: entry 0 has base index -1 and parents"), std::string::npos);
  RgbState other_base = good;
  other_base.base_points[0].x += 1e-9;
  EXPECT_NE(refusal(other_base).find("piece 1: its base mesh differs"), std::string::npos);
  RgbState sizes = good;
  sizes.base_vertex.pop_back();
  EXPECT_NE(refusal(sizes).find("base indices for"), std::string::npos);
  RgbState base = good;
  base.base_vertex[0] = 999;
  base.parents[0] = {-1, -1};
  EXPECT_NE(refusal(base).find("is base vertex 999"), std::string::npos);
}

}  // namespace
}  // namespace rgbmesh
