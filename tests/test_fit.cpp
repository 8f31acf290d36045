// Fitting Loop surfaces to points: the stencils are affine and reproduce the limit surface,
// a perturbed base recovers a known surface exactly, robust losses resist gross outliers, the
// Stanford bunny is fitted to a fraction of a percent, and the per-target distances are the
// reported figures. (Point files: test_fit_io; bases: test_fit_base; scans: test_fit_scans.)

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rgbmesh/fit/fit.hpp"
#include "rgbmesh/vtk_io.hpp"
#include "test_meshes.hpp"

namespace rgbmesh::fit {
namespace {

TriangleMeshData torus_base() {
  const testing::BaseMesh t = testing::torus(8, 6);
  return {t.points, t.triangles, {}};
}

TriangleMeshData perturbed(TriangleMeshData m, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, sigma);
  for (Vec3& p : m.points) p += Vec3(g(rng), g(rng), g(rng));
  return m;
}

// The RMS distance from points to the limit surface of a base (no iteration).
double rms_to_surface(const TriangleMeshData& base, const std::vector<Vec3>& points, int levels) {
  FitOptions o;
  o.levels = levels;
  o.max_iterations = 0;
  return fit(base, points, o).rms;
}

TEST(Fit, StencilsAreAffineAndLocal) {
  const TriangleMeshData base = torus_base();
  const LimitStencils st = limit_stencils(base, 3);
  ASSERT_EQ(st.num_vertices(), base.points.size() * 64);  // V grows like T/2: 4^3 times
  for (std::size_t v = 0; v < st.num_vertices(); ++v) {
    double sum = 0;
    for (std::int32_t k = st.offset[v]; k < st.offset[v + 1]; ++k) sum += st.weight[k];
    EXPECT_NEAR(sum, 1.0, 1e-12);  // affine invariance of subdivision
    EXPECT_LE(st.offset[v + 1] - st.offset[v], 20);  // a limit point depends on a few base points
  }
}

TEST(Fit, RecoversAKnownLimitSurfaceFromAPerturbedBase) {
  const TriangleMeshData truth = torus_base();
  const std::vector<Vec3> targets = limit_stencils(truth, 3).evaluate(truth.points);
  FitOptions o;
  o.loss = Loss::none;
  o.smooth = 0;
  o.max_iterations = 40;
  o.min_improvement = 1e-6;
  const FitResult r = fit(perturbed(truth, 0.1, 1), targets, o);
  EXPECT_GT(r.iterations.front().rms, 1e-3 * r.diagonal);  // the start is off
  EXPECT_LT(r.rms, 1e-6 * r.diagonal);
  for (std::size_t j = 0; j < truth.points.size(); ++j)
    EXPECT_LT(distance(r.control_points[j], truth.points[j]), 1e-5 * r.diagonal) << j;
}

TEST(Fit, RobustLossesResistGrossOutliers) {
  const TriangleMeshData truth = torus_base();
  std::vector<Vec3> inliers = limit_stencils(truth, 3).evaluate(truth.points);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.005);  // about 0.07% of the diagonal
  for (Vec3& p : inliers) p += Vec3(noise(rng), noise(rng), noise(rng));
  std::vector<Vec3> all = inliers;
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::size_t k = 0; k < inliers.size() / 20; ++k) {  // 5% gross outliers, about 10% of the diagonal off
    const Vec3& p = inliers[(k * 37) % inliers.size()];
    Vec3 d(u(rng), u(rng), u(rng));
    all.push_back(p + d * (0.7 / norm(d)));
  }
  const TriangleMeshData start = perturbed(truth, 0.05, 3);
  FitOptions o;
  o.smooth = 0;
  o.loss = Loss::none;
  TriangleMeshData clean_fit = truth;
  clean_fit.points = fit(start, inliers, o).control_points;
  const double clean = rms_to_surface(clean_fit, inliers, 3);
  for (Loss loss : {Loss::huber, Loss::cauchy}) {
    o.loss = loss;
    TriangleMeshData fitted = truth;
    fitted.points = fit(start, all, o).control_points;
    const double robust = rms_to_surface(fitted, inliers, 3);
    EXPECT_LT(robust, 1.5 * clean) << (loss == Loss::huber ? "huber" : "cauchy") << ": " << robust << " vs " << clean;
  }
  // Without a robust loss the outliers pull the surface away.
  o.loss = Loss::none;
  TriangleMeshData plain = truth;
  plain.points = fit(start, all, o).control_points;
  EXPECT_GT(rms_to_surface(plain, inliers, 3), 1.5 * clean);
}

TEST(Fit, BunnyWithAThousandFaceBase) {
  const TriangleMeshData bunny = read_mesh(std::string(RGBMESH_DATA_DIR) + "/bunny.obj");
  const TriangleMeshData base = decimate(bunny, 1000);
  EXPECT_NEAR(static_cast<double>(base.triangles.size()), 1000.0, 20.0);
  const FitResult r = fit(base, bunny.points, FitOptions{});
  EXPECT_LT(r.rms, 0.003 * r.diagonal);
  EXPECT_LT(r.rms, 0.3 * r.iterations.front().rms);
  // The figures are those of the per-target distances, and each target's footpoint triangle
  // holds a point at that distance (the triangle's plane is no farther).
  ASSERT_EQ(r.distance.size(), bunny.points.size());
  double sum = 0, max = 0;
  for (const double d : r.distance) {
    sum += d * d;
    max = std::max(max, d);
  }
  EXPECT_DOUBLE_EQ(r.rms, std::sqrt(sum / static_cast<double>(r.distance.size())));
  EXPECT_EQ(r.max, max);
  const std::vector<Vec3> surface = r.stencils.evaluate(r.control_points);
  for (std::size_t i = 0; i < bunny.points.size(); i += 97) {
    const auto& t = r.stencils.triangles[static_cast<std::size_t>(r.footpoint_triangle[i])];
    const Vec3 n = cross(surface[t[1]] - surface[t[0]], surface[t[2]] - surface[t[0]]);
    EXPECT_LE(std::abs(dot(bunny.points[i] - surface[t[0]], n)) / norm(n),
              r.distance[i] * (1 + 1e-9) + 1e-12);
  }
  // Per triangle: every target counted once, RMS of those in the triangle.
  const TriangleDistances per_triangle = distances_per_triangle(r);
  double counted = 0, squares = 0;
  for (std::size_t t = 0; t < per_triangle.targets.size(); ++t) {
    counted += per_triangle.targets[t];
    squares += per_triangle.targets[t] * per_triangle.rms_distance[t] * per_triangle.rms_distance[t];
    if (per_triangle.targets[t] == 0) {
      EXPECT_EQ(per_triangle.rms_distance[t], 0);
    }
  }
  EXPECT_EQ(counted, static_cast<double>(bunny.points.size()));
  EXPECT_NEAR(std::sqrt(squares / counted), r.rms, 1e-12 * r.diagonal);
  std::cout << "bunny: rms " << r.rms / r.diagonal * 100 << "% of the diagonal, max "
            << r.max / r.diagonal * 100 << "%, " << r.seconds << " s\n";
}

}  // namespace
}  // namespace rgbmesh::fit
