// Long random sequences of split_edge / remove_vertex with validate() after every step, on
// closed, open (several boundary loops) and high-valence meshes; then the order-independence
// facts: coarsening everything returns the base mesh exactly, and uniform refinement to K
// gives the same triangulation whatever happened before.
//
// The walks take 10^5 steps in optimised builds. validate() after every step dominates their
// time (0.5 to 3 minutes per mesh in Release); unoptimised code is about 10 times slower and
// ASan+UBSan 30 times: there the walks are shorter, so that the whole suite runs under the
// sanitizers too (RGBMESH_SANITIZE may also be defined by the build).

#include <gtest/gtest.h>

#include <map>
#include <ostream>
#include <set>

#include "rgbmesh/mesh.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(undefined_behavior_sanitizer)
#define RGBMESH_TEST_UNDER_SANITIZER 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(RGBMESH_SANITIZE)
#define RGBMESH_TEST_UNDER_SANITIZER 1
#endif

namespace rgbmesh {
namespace {

// 2,000 steps still reach levels 6 and 7 on every mesh below, with a third of the steps
// removals (measured).
#if defined(RGBMESH_TEST_UNDER_SANITIZER) || !defined(__OPTIMIZE__)
constexpr std::uint64_t kWalkSteps = 2000;
#else
constexpr std::uint64_t kWalkSteps = 100000;
#endif

// Vertex identity independent of handles: a base vertex is its index; an inserted vertex is
// the (unordered) pair of its parents' identities.
class VertexKeys {
 public:
  std::int64_t key(const RgbMesh& m, VertexHandle v) {
    if (m.level(v) == 0) return v.idx;
    const auto& p = m.parents(v);
    std::int64_t a = key(m, p[0]), b = key(m, p[1]);
    if (a > b) std::swap(a, b);
    auto [it, inserted] = ids_.try_emplace({a, b}, next_);
    if (inserted) ++next_;
    return it->second;
  }

 private:
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> ids_;
  std::int64_t next_ = 1 << 30;
};

std::set<std::array<std::int64_t, 3>> keyed_triangles(const RgbMesh& m, VertexKeys& keys) {
  std::set<std::array<std::int64_t, 3>> out;
  for (TriangleHandle t : m.triangles()) {
    const auto c = m.triangle_vertices(t);
    std::array<std::int64_t, 3> x{keys.key(m, c[0]), keys.key(m, c[1]), keys.key(m, c[2])};
    std::rotate(x.begin(), std::min_element(x.begin(), x.end()), x.end());
    out.insert(x);
  }
  return out;
}

struct WalkCase {
  testing::BaseMesh base;
  std::uint64_t seed;
};

// GoogleTest prints parameters with this (CTest shows it in the test names).
void PrintTo(const WalkCase& c, std::ostream* os) { *os << c.base.name << ", seed " << c.seed; }

class RandomWalk : public ::testing::TestWithParam<WalkCase> {};

TEST_P(RandomWalk, LongWalksStayValid) {
  const WalkCase& wc = GetParam();
  RgbMesh m = wc.base.build();
  const auto base_triangles = testing::canonical_triangles(m);
  std::vector<Vec3> base_points;
  for (VertexHandle v : m.vertices()) base_points.push_back(m.insertion_point(v));

  RandomWalkOptions options;
  options.max_level = 7;
  options.max_triangles = std::max<std::size_t>(600, 12 * m.num_triangles());
  std::string failure;
  std::uint64_t failed_step = 0;
  options.after_step = [&](std::uint64_t step) {
    if (!failure.empty()) return;
    failure = m.validate(true);
    failed_step = step;
  };
  RecordProperty("steps", std::to_string(kWalkSteps));
  const auto result = random_walk(m, kWalkSteps, wc.seed, options);
  ASSERT_EQ(failure, "") << wc.base.name << " at step " << failed_step;
  // A walk that mostly did nothing would prove little: at least 30% of the steps are splits,
  // 30% removals.
  EXPECT_GT(result.splits, 3 * kWalkSteps / 10) << wc.base.name;
  EXPECT_GT(result.removals, 3 * kWalkSteps / 10) << wc.base.name;
  EXPECT_GE(m.max_level(), 5) << wc.base.name;

  // Coarsening everything gives back the base mesh: same triangles, same positions.
  const auto coarse = selective_refinement(m, CoarsenAll());
  EXPECT_GT(coarse.removals, 0u);
  ASSERT_EQ(m.validate(true), "");
  EXPECT_EQ(testing::canonical_triangles(m), base_triangles) << wc.base.name;
  std::vector<Vec3> points;
  for (VertexHandle v : m.vertices()) points.push_back(m.insertion_point(v));
  EXPECT_EQ(points, base_points) << wc.base.name;
  for (TriangleHandle t : m.triangles()) {
    EXPECT_EQ(m.color(t), Color::green);
    EXPECT_EQ(m.level(t), 0);
  }
}

TEST_P(RandomWalk, UniformRefinementIsOrderIndependent) {
  const WalkCase& wc = GetParam();
  for (int k = 1; k <= 3; ++k) {
    RgbMesh reference = wc.base.build();
    selective_refinement(reference, UniformLevel(k));
    RgbMesh walked = wc.base.build();
    RandomWalkOptions options;
    options.max_level = 5;
    random_walk(walked, 3000, wc.seed + static_cast<std::uint64_t>(k), options);
    selective_refinement(walked, UniformLevel(k));
    ASSERT_EQ(walked.validate(true), "");
    VertexKeys keys;
    EXPECT_EQ(keyed_triangles(walked, keys), keyed_triangles(reference, keys))
        << wc.base.name << " level " << k;
    EXPECT_EQ(walked.num_triangles(), wc.base.triangles.size() << (2 * k));
    // The midpoint positions agree too.
    std::map<std::int64_t, Vec3> ref_points;
    for (VertexHandle v : reference.vertices()) ref_points[keys.key(reference, v)] = reference.insertion_point(v);
    for (VertexHandle v : walked.vertices()) {
      const Vec3& p = walked.insertion_point(v);
      const Vec3& q = ref_points.at(keys.key(walked, v));
      EXPECT_NEAR(distance(p, q), 0.0, 1e-12);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, RandomWalk,
    ::testing::Values(WalkCase{testing::icosahedron(), 1}, WalkCase{testing::double_torus(), 2},
                      WalkCase{testing::grid_with_holes(8, 3), 3}, WalkCase{testing::bipyramid(12), 4},
                      WalkCase{testing::fan_disk(12), 5}, WalkCase{testing::tetrahedron(), 6}),
    [](const ::testing::TestParamInfo<WalkCase>& param_info) { return param_info.param.base.name; });

// Stable meshes only ever show the six stable side patterns: 21 configurations up to a
// half-turn. Random walks from a few meshes reach every one of them.
TEST(RandomWalkCoverage, ReachesEveryStableRemovalConfiguration) {
  std::set<std::string> seen;
  for (const auto& base : {testing::icosahedron(), testing::grid_with_holes(8, 3), testing::torus(6, 5)}) {
    RgbMesh m = base.build();
    RandomWalkOptions options;
    options.max_level = 6;
    std::uint64_t n = 0;
    options.after_step = [&](std::uint64_t) {
      // Sample the removable vertices' configurations every few steps.
      if (++n % 7) return;
      for (VertexHandle v : m.vertices()) {
        const std::string c = m.removal_configuration(v);
        if (!c.empty()) seen.insert(c);
      }
    };
    random_walk(m, 4000, 99, options);
  }
  std::set<std::string> interior;
  for (const auto& c : seen)
    if (c.find('|') != std::string::npos) interior.insert(c);
  EXPECT_EQ(interior.size(), 21u);
  // Boundary vertices: the six stable single sides.
  std::set<std::string> boundary;
  for (const auto& c : seen)
    if (c.find('|') == std::string::npos) boundary.insert(c);
  EXPECT_EQ(boundary, (std::set<std::string>{"BG", "GB", "GBR", "GGG", "RBG", "RR"}));
}

}  // namespace
}  // namespace rgbmesh
