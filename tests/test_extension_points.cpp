// Extension points of the adaptive loop, used as a library user would: a marking strategy and
// an error estimator defined here, outside the library, in a namespace of their own, plugged
// into adapt::AdaptOptions and run by adapt::run_cycles. Nothing else in the library knows
// them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/geometry.hpp"
#include "rgbmesh/refinement.hpp"
#include "rgbmesh/shapes.hpp"

namespace user {

using namespace rgbmesh;

// An "estimator" that knows where the interesting region is: the height z of the centroid on
// triangles in the polar cap z > 0.8, 0 elsewhere (graded, so that Dörfler marking in its
// place would mark fewer). It counts its calls.
class PolarCapIndicator : public fem::ErrorEstimator {
 public:
  mutable int calls = 0;
  fem::Estimate estimate(const fem::SurfaceMesh& mesh, const fem::Problem&, const Eigen::VectorXd&,
                         const fem::WorkShare&) const override {
    ++calls;
    fem::Estimate e;
    e.eta.resize(mesh.triangles.size());
    e.geometric.assign(mesh.triangles.size(), 0.0);
    double squares = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      const double z = (mesh.points[tri[0]].z + mesh.points[tri[1]].z + mesh.points[tri[2]].z) / 3;
      e.eta[t] = z > 0.8 ? z : 0.0;
      squares += e.eta[t] * e.eta[t];
    }
    e.total = std::sqrt(squares);
    return e;
  }
};

// Marks every own triangle whose indicator reaches half of the largest one this process holds.
class HalfOfLargestMarking : public adapt::MarkingStrategy {
 public:
  std::vector<char> mark(const adapt::Indicators& in) const override {
    double largest = 0;
    for (std::size_t t = 0; t < in.eta.size(); ++t)
      if (in.is_own(t)) largest = std::max(largest, in.eta[t]);
    std::vector<char> marked(in.eta.size(), 0);
    for (std::size_t t = 0; t < in.eta.size(); ++t)
      marked[t] = in.is_own(t) && in.eta[t] >= 0.5 * largest ? 1 : 0;
    return marked;
  }
};

TEST(ExtensionPoints, AUserMarkingAndEstimatorDriveTheAdaptiveLoop) {
  const TriangleMeshData ico = icosahedron();
  RgbMesh mesh = RgbMesh::from_triangles(ico.points, ico.triangles);
  selective_refinement(mesh, UniformLevel(2));
  const int start_level = mesh.max_level();

  auto indicator = std::make_shared<PolarCapIndicator>();
  adapt::AdaptOptions o;
  o.projection = fem::Projection(fem::project_to_unit_sphere);
  o.estimator = indicator;
  o.marking = std::make_shared<HalfOfLargestMarking>();
  o.max_cycles = 4;
  int checked = 0;
  const adapt::AdaptRun run = adapt::run_cycles(mesh, fem::sphere_peak(), o, [&](const adapt::CycleState& s) {
    // The loop reports the user's estimate and refines exactly the user's marks (none after
    // the last solve, which is not adapted).
    const bool adapted = s.report.cycle + 1 < o.max_cycles;
    double squares = 0;
    for (std::size_t t = 0; t < s.fe.triangles.size(); ++t) {
      const auto& tri = s.fe.triangles[t];
      const double z = (s.fe.points[tri[0]].z + s.fe.points[tri[1]].z + s.fe.points[tri[2]].z) / 3;
      ASSERT_EQ(s.marked[t], adapted && z > 0.8 ? 1 : 0) << "cycle " << s.report.cycle << ", triangle " << t;
      squares += z > 0.8 ? z * z : 0;
    }
    EXPECT_DOUBLE_EQ(s.report.estimate, std::sqrt(squares));
    EXPECT_EQ(s.mesh.validate(true), "");
    ++checked;
  });
  ASSERT_EQ(run.cycles.size(), 4u);
  EXPECT_EQ(checked, 4);
  EXPECT_EQ(indicator->calls, 4);
  // Three adaptations refined the cap three levels down; the far side was never touched.
  int finest_in_cap = 0, finest_far = 0;
  for (const TriangleHandle t : mesh.triangles()) {
    const auto v = mesh.triangle_vertices(t);
    const Vec3 centroid = mesh.control_point(v[0]) + mesh.control_point(v[1]) + mesh.control_point(v[2]);
    const double z = centroid.z / norm(centroid);  // the direction's height
    if (z > 0.9) finest_in_cap = std::max(finest_in_cap, mesh.level(t));
    if (z < -0.5) finest_far = std::max(finest_far, mesh.level(t));
  }
  EXPECT_EQ(finest_in_cap, start_level + 3);
  EXPECT_EQ(finest_far, start_level);
  EXPECT_GT(run.cycles.back().triangles, run.cycles.front().triangles);
}

}  // namespace user
