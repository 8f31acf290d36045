// The exception guarantees of mesh.hpp ("Exceptions"): observers that throw at the k-th call,
// and allocations that fail at the k-th request, in the middle of split_edge and remove_vertex
// sequences, coarsening and compute_limits. After every exception the mesh is valid and
// stable, every observer was told of exactly the changes that were made, and further
// operations work.

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <new>
#include <stdexcept>
#include <tuple>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

// ---- allocation failure injection ---------------------------------------------------------
// Replaces the global operator new of this test program: once armed with k, the k-th
// allocation throws std::bad_alloc (once).

namespace {
long g_allocations_left = 0;  // 0: disarmed

void* allocate(std::size_t n) {
  if (g_allocations_left > 0 && --g_allocations_left == 0) throw std::bad_alloc();
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace rgbmesh {
namespace {

// Fails the k-th allocation while alive.
class FailingAllocation {
 public:
  explicit FailingAllocation(long k) { g_allocations_left = k; }
  ~FailingAllocation() { g_allocations_left = 0; }
  FailingAllocation(const FailingAllocation&) = delete;
  FailingAllocation& operator=(const FailingAllocation&) = delete;
  bool failed() const { return g_allocations_left == 0; }
};

struct ObserverError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Counts what observers hear; the mesh's vertex count must follow it exactly.
struct Tally {
  std::int64_t inserted = 0, removed = 0;
};

// An insertion or removal observer that throws at its k-th call (and only then).
struct Thrower {
  long calls = 0;
  long throw_at = 0;
  void call() {
    if (++calls == throw_at) throw ObserverError("observer call " + std::to_string(calls));
  }
};

// Everything observable about a mesh, independent of handles for edges and triangles.
using State = std::tuple<std::vector<std::array<std::int32_t, 3>>, std::map<std::int32_t, Vec3>, std::size_t>;
State state_of(const RgbMesh& m) {
  std::map<std::int32_t, Vec3> points;
  for (VertexHandle v : m.vertices()) points[v.idx] = m.insertion_point(v);
  return {testing::canonical_triangles(m), points, m.num_edges()};
}

// Every k up to 64, then about 6% apart: all the early calls (the first forced splits and
// swaps) and a spread over the rest, at a cost that suits unoptimised and sanitizer builds.
long next_k(long k) { return k < 64 ? k + 1 : k + k / 16; }

// A ball around base vertex 0 of the icosahedron, refined to level 5: about 500 insertions,
// most of them forced splits of coarser neighbours, and 300 stabilising BB-swaps.
BallLevel deep_ball(const RgbMesh& icosahedron) {
  return BallLevel(icosahedron.insertion_point(VertexHandle(0)), 0.8, 5);
}

RandomWalkOptions walk_options() {
  RandomWalkOptions o;
  o.max_level = 6;
  o.max_triangles = 800;
  return o;
}

// Runs `operation` on copies of `start` with an observer that throws at its k-th call, for
// k = 1, 2, ... until the operation completes without a throw. After each exception: a valid,
// stable mesh whose vertex count matches what a second observer heard, and further
// operations (a random walk, then coarsening to the base) that work.
template <class Operation>
void each_observer_throw(const RgbMesh& start, bool insertion, Operation operation, const char* what) {
  const auto base = testing::canonical_triangles([&] {
    RgbMesh b = start;
    selective_refinement(b, CoarsenAll());
    return b;
  }());
  int throws = 0;
  for (long k = 1;; k = next_k(k)) {
    RgbMesh m = start;
    Tally tally;
    Thrower thrower;
    thrower.throw_at = k;
    m.add_insertion_observer([&](VertexHandle, VertexHandle, VertexHandle) { ++tally.inserted; });
    m.add_removal_observer([&](VertexHandle) { ++tally.removed; });
    const int id =
        insertion
            ? m.add_insertion_observer([&](VertexHandle, VertexHandle, VertexHandle) { thrower.call(); })
            : m.add_removal_observer([&](VertexHandle) { thrower.call(); });
    const auto vertices = static_cast<std::int64_t>(m.num_vertices());
    bool threw = false;
    try {
      operation(m);
    } catch (const ObserverError&) {
      threw = true;
    }
    ASSERT_EQ(m.validate(true), "") << what << ", observer throwing at call " << k;
    ASSERT_EQ(static_cast<std::int64_t>(m.num_vertices()), vertices + tally.inserted - tally.removed)
        << what << ", observer throwing at call " << k;
    if (!threw) break;
    ++throws;
    ::testing::Test::RecordProperty(what, static_cast<int>(k));
    // Further operations work.
    m.remove_observer(id);
    random_walk(m, 30, static_cast<std::uint64_t>(k), walk_options());
    ASSERT_EQ(m.validate(true), "") << what << " k=" << k;
    selective_refinement(m, CoarsenAll());
    ASSERT_EQ(testing::canonical_triangles(m), base) << what << " k=" << k;
  }
  EXPECT_GT(throws, 5) << what;  // the operation did call the observer
}

TEST(ObserverExceptions, InsertionObserverThrowingDuringSplitEdgeSequences) {
  const RgbMesh start = testing::icosahedron().build();
  // Deep splits at one spot force many coarser splits and stabilising swaps.
  each_observer_throw(
      start, /*insertion=*/true, [](RgbMesh& m) { selective_refinement(m, deep_ball(m)); }, "deep ball");
  each_observer_throw(
      start, true, [](RgbMesh& m) { random_walk(m, 300, 7, walk_options()); }, "random walk, insertions");
}

TEST(ObserverExceptions, RemovalObserverThrowingDuringRemoveVertexSequences) {
  RgbMesh start = testing::grid_with_holes(6, 2).build();
  random_walk(start, 400, 5, walk_options());
  each_observer_throw(
      start, /*insertion=*/false, [](RgbMesh& m) { random_walk(m, 300, 9, walk_options()); },
      "random walk, removals");
}

TEST(ObserverExceptions, RemovalObserverThrowingDuringCoarsening) {
  RgbMesh start = testing::double_torus().build();
  random_walk(start, 1500, 2, walk_options());
  ASSERT_GT(start.max_level(), 3);
  each_observer_throw(
      start, false, [](RgbMesh& m) { selective_refinement(m, CoarsenAll()); }, "coarsen all");
  RgbMesh uniform = testing::cube().build();
  selective_refinement(uniform, UniformLevel(3));
  each_observer_throw(
      uniform, false, [](RgbMesh& m) { selective_refinement(m, UniformLevel(1)); }, "uniform 3 -> 1");
}

TEST(ObserverExceptions, ThrowingSplitKeepsItsVertexAndEveryObserverHearsOfIt) {
  RgbMesh m = testing::diamond().build();
  std::vector<VertexHandle> heard;
  m.add_insertion_observer([](VertexHandle, VertexHandle, VertexHandle) { throw ObserverError("first"); });
  m.add_insertion_observer([&](VertexHandle v, VertexHandle, VertexHandle) { heard.push_back(v); });
  EXPECT_THROW(m.split_gg(m.find_edge(VertexHandle(0), VertexHandle(1))), ObserverError);
  ASSERT_EQ(heard.size(), 1u);  // the second observer was called although the first threw
  EXPECT_TRUE(m.alive(heard[0]));
  EXPECT_EQ(m.num_vertices(), 5u);
  EXPECT_EQ(m.validate(true), "");
}

TEST(ObserverExceptions, ThrowingMergeStillRemovesItsVertex) {
  RgbMesh m = testing::diamond().build();
  const State before = state_of(m);
  const VertexHandle mid = m.split_gg(m.find_edge(VertexHandle(0), VertexHandle(1)));
  m.add_removal_observer([&](VertexHandle v) {
    EXPECT_TRUE(m.alive(v));  // still there while observers run
    throw ObserverError("merge");
  });
  EXPECT_THROW(m.merge_r4(mid), ObserverError);
  EXPECT_FALSE(m.alive(mid));
  EXPECT_EQ(state_of(m), before);
  EXPECT_EQ(m.validate(true), "");
}

TEST(ObserverExceptions, ComputeLimitsUndoesEverythingWhateverThrows) {
  RgbMesh start = testing::bipyramid(7).build();
  selective_refinement(start, BallLevel({0, 0, 1}, 0.2, 5));
  ASSERT_GT(RgbMesh(start).compute_limits(), 0u);  // it does have to insert vertices
  const State before = state_of(start);
  for (const bool insertion : {true, false}) {
    for (long k = 1;; k = next_k(k)) {
      RgbMesh m = start;
      Tally tally;
      m.add_insertion_observer([&](VertexHandle, VertexHandle, VertexHandle) { ++tally.inserted; });
      m.add_removal_observer([&](VertexHandle) { ++tally.removed; });
      Thrower thrower;
      thrower.throw_at = k;
      if (insertion)
        m.add_insertion_observer([&](VertexHandle, VertexHandle, VertexHandle) { thrower.call(); });
      else
        m.add_removal_observer([&](VertexHandle) { thrower.call(); });
      bool threw = false;
      try {
        m.compute_limits();
      } catch (const ObserverError&) {
        threw = true;
      }
      // Strong: the very same mesh (handles included), every helper heard of twice.
      ASSERT_EQ(state_of(m), before) << "insertion observer " << insertion << ", k=" << k;
      ASSERT_EQ(m.validate(true), "");
      ASSERT_EQ(tally.inserted, tally.removed);
      if (!threw) break;
      // Limits computed before the exception stay; the next call completes the rest.
      m.compute_limits();
      for (VertexHandle v : m.vertices()) ASSERT_TRUE(m.has_limit(v));
    }
  }
}

// ---- allocation failures --------------------------------------------------------------------

// Runs `operation` on copies of `start` with the k-th allocation failing, for k = 1, 2, ...
// until it completes. After each std::bad_alloc: a valid, stable mesh, and further operations
// that work. `min_failures`: how many allocations the operation makes at least.
template <class Operation>
void each_allocation_failure(const RgbMesh& start, Operation operation, const char* what,
                             int min_failures = 4) {
  int failures = 0;
  for (long k = 1;; k = next_k(k)) {
    RgbMesh m = start;  // a copy has no spare capacity: the operation must grow the arrays
    bool failed = false;
    try {
      FailingAllocation fail(k);
      operation(m);
      failed = fail.failed();
    } catch (const std::bad_alloc&) {
      failed = true;
    }
    ASSERT_EQ(m.validate(true), "") << what << ", allocation " << k << " failed";
    if (!failed) break;
    ++failures;
    random_walk(m, 20, static_cast<std::uint64_t>(k), walk_options());
    ASSERT_EQ(m.validate(true), "") << what << " k=" << k;
  }
  EXPECT_GE(failures, min_failures) << what;
}

TEST(AllocationFailures, LeaveAValidStableMesh) {
  const RgbMesh ico = testing::icosahedron().build();
  each_allocation_failure(
      ico, [](RgbMesh& m) { selective_refinement(m, UniformLevel(2)); }, "uniform level 2");
  // A vertex property that allocates per value: split_all_edges grows it first, undone if it fails.
  RgbMesh ico_with_lists = ico;
  (void)ico_with_lists.add_vertex_property<std::vector<int>>({1, 2, 3});
  each_allocation_failure(
      ico_with_lists, [](RgbMesh& m) { selective_refinement(m, UniformLevel(2)); },
      "uniform level 2 with a property");
  each_allocation_failure(
      ico, [](RgbMesh& m) { selective_refinement(m, deep_ball(m)); }, "deep ball");
  each_allocation_failure(
      ico, [](RgbMesh& m) { random_walk(m, 150, 4, walk_options()); }, "random walk");
  RgbMesh refined = ico;
  random_walk(refined, 600, 8, walk_options());
  // Removals allocate nothing in optimised builds (the free lists live in the freed slots);
  // Debug builds allocate in their assertions.
  each_allocation_failure(
      refined, [](RgbMesh& m) { selective_refinement(m, CoarsenAll()); }, "coarsen all", /*min_failures=*/0);
  VertexProperty<std::vector<int>> lists = refined.add_vertex_property<std::vector<int>>({1, 2, 3});
  (void)lists;
  each_allocation_failure(
      refined, [](RgbMesh& m) { random_walk(m, 100, 6, walk_options()); }, "random walk with a property");
}

TEST(AllocationFailures, ComputeLimitsLeavesTheMeshAsItWas) {
  RgbMesh start = testing::fan_disk(9).build();
  selective_refinement(start, BallLevel({0, 0, 0.3}, 0.1, 5));
  const State before = state_of(start);
  for (long k = 1;; k = next_k(k)) {
    RgbMesh m = start;
    bool failed = false;
    try {
      FailingAllocation fail(k);
      m.compute_limits();
      failed = fail.failed();
    } catch (const std::bad_alloc&) {
      failed = true;
    }
    ASSERT_EQ(state_of(m), before) << "allocation " << k;
    ASSERT_EQ(m.validate(true), "");
    if (!failed) break;
  }
}

}  // namespace
}  // namespace rgbmesh
